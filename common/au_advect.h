/* au_advect.h - the generic Lie-advection loop (Zou et al. 2011, eq. 19-20), shared by the sphere
 * and the planar domains. A domain supplies two callbacks: one that removes forbidden velocity
 * components (sphere: the normal; disk: the boundary's radial part), one that puts points back on
 * the domain (normalize; radial projection of boundary vertices). */
#ifndef AU_ADVECT_H
#define AU_ADVECT_H

#include "au_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AU_ADVECT_MAX_STEPS 512
#define AU_ANGLE_STEPS_MAX 50 /* the most angle steps (au_advect_opts.angle_steps) the tools offer */

typedef struct au_advect_domain {
  /* Constrain the displacement d[3] of vertex i at position p[3], in place. Required. */
  void (*constrain)(void *ctx, int i, const double *p, double *d);
  /* Put vertex i's position p[3] back onto the domain, in place. Required. */
  void (*retract)(void *ctx, int i, double *p);
  int spherical; /* 1: faces oriented by the triple product p0.(p1 x p2); 0: planar, by the z of the cross product */
  void *ctx;     /* passed to the callbacks */
  double arc_radius; /* planar domains whose boundary slides on circles about the origin (disk, annulus):
                        > 0 moves each vertex along the arc about the origin that its displacement
                        starts on, bent by the fraction min(1, r / arc_radius) at radius r (straight
                        at the origin); 0 (default): straight moves. A boundary vertex sliding along
                        its circle and the interior vertices beside it then turn together, and the
                        long, thin triangles an equal-area disk map must have at a short boundary do
                        not turn over (see au_advect.c, move_vertex) */
  const double *shift; /* per-corner translations, or NULL (every domain but the flat torus): corner k of face f
                          lies at P[F[3f+k]] + shift[9f+3k..9f+3k+2]. A face's geometry (areas, orientation,
                          step control, the step systems) is that of its shifted corners; the shifts stay
                          fixed for the run, so a periodic map is advected with its vertices free to leave
                          the fundamental domain (au_torus.h). The least-shear method only: the Poisson
                          method refuses shifts (AU_E_ARG) */
  /* Optional (NULL: none): called before each move of a step, backtracking tries included, with the
     positions at the step's start P, the step D and each vertex's fraction lim of it (rows of these
     arrays: row[i] for the caller's vertex i, or i when row is NULL). A domain whose constraints have
     unknowns of their own (au_circles_map: each hole's centre and radius) moves them here; retract then
     puts the vertices on the moved constraint. A vertex whose fraction is 0 keeps its position without a
     retract, so such a domain keeps still where any of its vertices does. */
  void (*begin_move)(void *ctx, const int *row, const double *P, const double *D, const double *lim);
} au_advect_domain;

/* How a step's velocity is chosen. */
typedef enum au_advect_method {
  AU_ADVECT_LEAST_SHEAR = 0, /* per-face area targets; of the velocities that realize them, the one that
                                shears least (au_lm.c). Default. */
  AU_ADVECT_POISSON = 1      /* the paper's curl-free velocity grad g, C g = -dA on the vertex cells, then
                                exact Gauss-Newton polish and per-face refinement */
} au_advect_method;

/* A flow's state, recorded by one flow to resume another from: a flow with the lantern (au_advect_opts.
 * lantern > 0) is the same as one without, step for step, up to the first step where the lantern acts
 * (au_advect_report.lantern_steps), so au_sphere_map's lantern retry starts from the first flow's state
 * there instead of repeating those steps. The two flows must run on the same plan with the same options
 * but the lantern; a state recorded on another mesh is not loaded (the flow then runs from its start). */
typedef struct au_advect_fork au_advect_fork;
au_advect_fork *au_advect_fork_new(void);
void au_advect_fork_free(au_advect_fork **fp);
/* 1 if a state was recorded (the recording flow reached a step where a lantern would act). */
int au_advect_fork_ready(const au_advect_fork *f);

/* The flow's options. Defaults (au_advect_opts_default) are in parentheses; the measurements behind
 * them are in docs/flow.md. Fields are grouped by the part of the flow that reads them. */
typedef struct au_advect_opts {
  /* ---- all methods and domains ---- */
  au_advect_method method; /* (AU_ADVECT_LEAST_SHEAR) */
  int max_steps;        /* most advection steps, 1..AU_ADVECT_MAX_STEPS, undone ones included (60) */
  double tol;           /* stop when the vertex-level mean |ln(area ratio)| is below this (2e-3): the vertex
                           cells are what the paper equalizes, and a lower bound costs many more steps */
  double face_tol;      /* ... and the per-face mean |r - 1| is below this (1e-3) */
  int schedule_steps;   /* K of eq. 19: the remaining excess is spread over K-k+1 steps (4): fewer steps
                           fold, more leave the hard meshes worse at the end */
  double max_log_step;  /* a cell's area changes by at most this factor's log in one step (1.2): bounds the
                           growth a squeezed cell is asked for, which a linear step overshoots */
  double max_move;      /* a vertex moves at most this fraction of the inradius of its triangles per step,
                           which keeps every triangle positively oriented (0 < x < 0.5, 0.3) */
  const double *weight; /* per-vertex target density [0..nv-1] (> 0): domain area proportional to
                           weight x surface area; NULL for equal area (NULL) */
  const double *face_weight; /* per-face target density [0..nf-1] (> 0) instead of the per-vertex one:
                                face f gets domain area proportional to face_weight[f] x its surface
                                area (NULL). At most one of weight and face_weight. */

  /* ---- the least-shear method (the default) ---- */
  double shear;         /* weight of the shear energy against the area residual in the least-shear step
                           while the schedule runs, >= 0 (1) */
  double shear_tail;    /* the weight's floor once the schedule has run, when the last per-face error is
                           taken out, >= 0 (0.01): lower converges faster but turns angles more */
  double face_shear_tail; /* once the vertex cells meet tol, the floor instead of shear_tail; 0: shear_tail
                             throughout (0). The planar --refine-faces uses 3e-4: fewer steps to a lower
                             per-face error where the boundary slides */
  double face_gain;     /* once the vertex cells meet tol, the refinement goes on while it lowers the per-face
                           error by at least this fraction in four steps (in the sphere's chord polish: a
                           quarter of it in one step) (0.1; 0 <= x < 1): the refinement must be worth its
                           steps; 0.02 refines as long as anything happens */

  /* ---- sphere only (least shear) ---- */
  int sphere_areas;     /* 1: the flow drives the areas of the spherical triangles, then polishes those of
                           the chord triangles (the ones param-eval measures); 0: chord areas throughout
                           (1); 2: spherical areas only, no chord polish (for textures, whose straight
                           triangles tend to the spherical ones; au_sphere_map's vertex polish is then
                           of the spherical triangles too). A chord triangle keeps a sizeable
                           area when its corners come onto one great circle, so a chord-area flow
                           cannot see that sliver forming and jams on it */
  double polish_gap;    /* the chord polish runs only if the chord triangles' per-face error exceeds the
                           spherical ones' by more than this fraction (0.1; 0: whenever it is larger):
                           elsewhere it costs steps for nothing */
  int polish_steps;     /* >= 0: the chord polish ends after this many steps if its vertex error is
                           between 1.5 tol and 0.1; 0: no such end (0). For flows whose map later stages
                           polish: its first steps make most of its gain (au_sphere_map sets 2 where its
                           vertex polish follows and no angle steps do; docs/chord-polish.md) */
  double restore;       /* in the spherical part, each step's shear aims this fraction of the way back to
                           triangles similar to the surface's, fading out as the vertex error falls below
                           0.1 (0..1; 0.1; 0: off): fewer long, thin triangles. Not in the polish nor on
                           planar domains, where it kept the areas from converging; with sphere_areas
                           2, off for the rest of a run once a restoring step was undone */
  double restore_gate;  /* shape restoring is off for the whole run when the start's mean shear (ln sigma1 /
                           sigma2 of the map from the surface's triangles, au_advect_report.start_shear)
                           exceeds this many times its vertex error, and the chord polish then keeps the
                           spherical part's shear weight: a start already near equal area and already sheared,
                           such as the coarse-to-fine one (1; 0: never) */
  double lantern;       /* in the spherical part, once the vertex error is below 1: a face's shape restoring
                           is raised to min(1, restore (1 + lantern rho)), rho = l^3 / (16 share), l its
                           longest chord edge and share its target area. l^3 / 16 is the least chord area a
                           spherical triangle with that edge can have (docs/sphere.md): a face near it
                           cannot shrink to its share without a shorter edge (0: off; au_sphere_map's retry
                           uses 2, au_sphere_opts.lantern_retry) */

  /* ---- the Poisson method only (AU_ADVECT_POISSON) ---- */
  double newton_below;  /* switch from the paper's Poisson step to the exact Gauss-Newton step on the vertex
                           areas once the error is below this (0.7; 0: never, inf: always): Poisson steps
                           alone stall well above tol */
  int face_steps;       /* after the vertex cells meet tol, at most this many per-face refinement steps
                           (damped Gauss-Newton on the triangle areas); 0 turns it off (30) */
  double face_damping;  /* Levenberg-Marquardt damping of the face steps, relative (0.1) */

  /* ---- the resolved schedule (least shear, equal area) ---- */
  double resolved_jump; /* a start counts as well resolved when the mean jump of log r (domain share over
                           surface share) across the mesh's interior edges is at most this (0.1; 0: never).
                           The area correction is then smooth at the mesh's scale, and the flow runs the
                           schedule below. Not with a density (weight, face_weight): it undid many steps */
  double resolved_shear;    /* the shear weight of the first step, instead of shear (0.1) */
  double resolved_decay;    /* each accepted step multiplies the shear weight by this, until the first undone
                               step (then by 0.5 as usual) (0 < x <= 1, 0.25) */
  double resolved_log_step; /* a face's area changes by at most this factor's log in one step, instead of
                               max_log_step (2) */
  /* On the sphere the resolved schedule is shorter, until a step has been undone: past its first steps the
   * error is held by the growth cap on the most squeezed faces, not by the schedule (docs/flow-tail.md).
   * Planar domains and the torus keep the fields above. */
  int sphere_resolved_schedule_steps; /* K of eq. 19 for the per-face targets, instead of schedule_steps (>= 1; 3) */
  double sphere_resolved_log_step;    /* instead of resolved_log_step (> 0; 2.5) */
  double sphere_resolved_shear_tail;  /* the shear weight's floor, instead of shear_tail (>= 0; 0.007): the shorter
                                         schedule lands its last step from further out, and a lower floor takes
                                         more of the per-face error out in each tail step */

  /* ---- the angle steps (least shear, au_ang.c) ---- */
  int angle_steps;      /* after the flow, at most this many angle steps: each a Gauss-Newton step towards
                           the map of least Dirichlet energy whose vertex cells have their areas, with the
                           chord triangles' areas held by the weight angle_faces (0: none) */
  double angle_faces;   /* the weight of the per-face areas against the Dirichlet energy (300) */
  double angle_cells;   /* the weight of the vertex cells' areas (1e6: held) */
  double angle_trust;   /* the Levenberg-Marquardt term, relative to each vertex's cotan weights (1) */
  double angle_switch;  /* the flow hands over to them as soon as its vertex error is at most this and its
                           per-face mean |r - 1| at most twice this (0.01; 0: after the flow, its chord
                           polish and per-face refinement included; au_disk_opts_default and
                           --refine-faces set 0). Early hand-over gives better angles on most meshes, but
                           worse areas on those whose long chord edges hold the faces back (cow) */

  /* ---- a flow resumed from another's state (au_advect_fork) ---- */
  au_advect_fork *fork_record;       /* this flow records its state at the start of the round of its first
                                        step where a lantern would act (NULL: none) */
  const au_advect_fork *fork_resume; /* this flow starts from such a recorded state instead of from P,
                                        where one was recorded (au_advect_fork_ready), else as usual */

  /* ---- progress and cancellation ---- */
  /* Progress: called once per step with the step number, max_steps and the current error. May be NULL. */
  void (*progress)(void *user, int step, int max_steps, double err);
  void *user;
  /* Cancellation: when *cancel is nonzero at the start of a step (read atomically, so another thread
     or the progress callback may set it), the run stops, frees what it holds and returns
     AU_E_CANCELLED; P is then left at the last accepted step. NULL (default): never. */
  const int *cancel;
} au_advect_opts;

au_advect_opts au_advect_opts_default(void);
/* The sphere's shorter resolved schedule off: its three fields set to the ones they stand in for
 * (schedule_steps, resolved_log_step, shear_tail), so the flow runs the resolved schedule of the other
 * domains. For flows tuned with that schedule: the coarse-to-fine start's level and fine flows, the
 * refinement's re-flows. */
void au_advect_plain_schedule(au_advect_opts *o);

typedef struct au_advect_report {
  int steps;                            /* steps taken */
  int converged;                        /* 1 if err <= tol at the end */
  double err[AU_ADVECT_MAX_STEPS + 1];  /* vertex-level mean |ln ratio| before each step and at the end */
  double face_err[AU_ADVECT_MAX_STEPS + 1]; /* per-face mean |r - 1| before each step and at the end */
  double frac[AU_ADVECT_MAX_STEPS];     /* mean fraction of the wanted displacement taken per step */
  int face_steps;                       /* of the steps, how many were per-face refinement steps */
  double t_solve;                       /* seconds in the sparse solves (factor + solve) */
  int polish_from;                      /* sphere_areas: the step at which the chord-area polish began
                                           (err and face_err are spherical before it), else 0 */
  int undone;                           /* steps solved, then undone for making the areas worse (not in
                                           steps: the solves are steps + undone) */
  double start_jump;                    /* the start's mean jump of log r across interior edges (see
                                           au_advect_opts.resolved_jump) */
  int resolved;                         /* 1 if the flow ran the resolved schedule */
  double start_shear;                   /* the start's mean ln(sigma1 / sigma2) of the map from each surface
                                           triangle to its domain triangle (see au_advect_opts.restore_gate) */
  int lantern_steps;                    /* the steps solved with shape restoring on and the vertex error
                                           below where the lantern acts: where a flow with the lantern
                                           (au_advect_opts.lantern > 0) differs from one without; 0: the
                                           lantern would change nothing */
  int angle_from;                       /* angle_steps: the step at which they began (err and face_err are
                                           the chord triangles' from there), else 0 */
} au_advect_report;

/* Advect the domain positions P (nv x 3, in/out: on the domain on entry, and on exit) until the
 * barycentric vertex areas of the domain mesh are proportional to those of the surface m (times
 * weight). Every step is fold-free if the entry map is: triangles never change orientation.
 * opts may be NULL for defaults; rep may be NULL.
 * Returns AU_OK, AU_W_NOT_CONVERGED, AU_E_ARG, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_NUMERIC, AU_E_FOLD
 * (the entry map was folded). */
au_status au_advect_run(const au_mesh *m, const au_topo *t, const au_advect_domain *dom,
                        const au_advect_opts *opts, double *P, au_advect_report *rep, au_msg *msg);

/* ---- the same in two parts, so that the part that needs only the mesh can run beside the start ----
 * A plan holds what depends on the mesh alone: a cache-friendly copy of a large mesh and the analysis
 * (fill-reducing order, symbolic factorization) of the least-shear step's system. m and t must outlive the plan. opts (may be NULL) tells the method. */
typedef struct au_advect_plan au_advect_plan;

/* Prepare a plan here. Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_advect_plan_create(const au_mesh *m, const au_topo *t, const au_advect_opts *opts, au_advect_plan **out,
                                au_msg *msg);

/* Prepare a plan in a thread of its own (large meshes; small ones are prepared here and now) and
 * return at once. Until au_advect_plan_wait (or au_advect_run_plan, or au_advect_plan_free) the calling
 * thread holds SIGTERM back (the ordering traps it, see au_solver.c); one that comes meanwhile is
 * delivered then. Call those from the same thread. Returns as au_advect_plan_create. */
au_status au_advect_plan_start(const au_mesh *m, const au_topo *t, const au_advect_opts *opts, au_advect_plan **out,
                               au_msg *msg);

/* Wait for a plan started with au_advect_plan_start; returns its status (AU_OK at once for a plan
 * that is ready). */
au_status au_advect_plan_wait(au_advect_plan *plan, au_msg *msg);

/* au_advect_run on the plan's mesh (waits for it first). A plan can serve several runs. */
au_status au_advect_run_plan(au_advect_plan *plan, const au_advect_domain *dom, const au_advect_opts *opts, double *P,
                             au_advect_report *rep, au_msg *msg);

void au_advect_plan_free(au_advect_plan **plan);

#ifdef __cplusplus
}
#endif
#endif
