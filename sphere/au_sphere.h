/* au_sphere.h - equal-area (authalic) maps of closed genus-0 meshes onto the unit sphere.
 *
 * Pipeline: a fold-free spherical conformal map (Choi, Lam & Lui 2015: harmonic map of the
 * punctured mesh, inverse stereographic projection, re-solve near the puncture), a Moebius
 * normalization that centres the area-weighted image, then Lie advection in the tangent planes of
 * the sphere with reprojection (Zou et al. 2011, sec. 4.5.2) and local step control that never
 * folds a triangle. */
#ifndef AU_SPHERE_H
#define AU_SPHERE_H

#include "au_advect.h"
#include "au_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Which start the sphere map makes (au_sphere_opts.start). */
typedef enum au_sphere_start {
  AU_SPHERE_START_CONFORMAL = 0, /* the conformal map, balanced (Choi, Lam & Lui 2015) */
  AU_SPHERE_START_MULTILEVEL = 1 /* coarse-to-fine (au_sphere_multilevel) */
} au_sphere_start;

/* The coarse-to-fine start's settings (sphere/au_sphere_ml.c). */
typedef struct au_sphere_ml_opts {
  int coarse_vertices; /* simplify down to about this many vertices (default 300; <= 0: the default) */
  int level_steps;     /* flow steps after each level but the finest (default 3) */
} au_sphere_ml_opts;

au_sphere_ml_opts au_sphere_ml_opts_default(void);

typedef struct au_sphere_opts {
  au_advect_opts flow; /* the advection's options; defaults from au_advect_opts_default() */
  int balance;         /* 1: Moebius-balance the conformal map before the flow (default 1) */
  double lantern_retry; /* > 0: if the flow ends with its vertex error above retry_above x its tolerance,
                           it runs again from the same start with flow.lantern = lantern_retry (shape
                           restoring raised on the faces a long chord edge keeps from shrinking;
                           resumed from the first flow's state where the lantern first acts), and
                           the map with the smaller vertex error of the chord triangles is kept (default
                           2; 0: off). It helps the meshes whose long chord edges keep faces from
                           shrinking; where it does worse, the first map stays (docs/flow.md) */
  double retry_above;   /* see lantern_retry (default 2) */
  double twist_retry;   /* > 0: if the map (after the lantern retry) still misses retry_above x its
                           tolerance and its chord floor's excess (au_metrics.chord_floor_excess) is
                           above this, it is made again from the twisted start (au_sphere_twisted) and
                           the map with the lower vertex error kept (retry_err; default 0.02; 0 off) */
  int vertex_polish;    /* > 0: a map that misses its tolerance gets at most this many sweeps of the vertex
                           polish (au_sphere_vertex_polish), kept if its vertex error falls and its
                           per-face error does not rise (default 200; 0 off); both of the chord
                           triangles, or with flow.sphere_areas 2 (a map of the spherical triangles) of
                           the spherical ones, for the polish's steps as for the comparison. With it
                           (and no flow.angle_steps), flow.polish_steps 0 means 2: the flow's chord
                           polish is cut short, the vertex polish doing the rest (docs/chord-polish.md) */
  double polish_cells;  /* the polish's weight of the vertex cells against the faces (default 1) */
  int global_polish;    /* > 0: a chord map that still misses its tolerance after the vertex polish gets at
                           most this many steps of the global polish (au_sphere_global_polish, with
                           au_sphere_gpolish_settings and a small angle weight; --refine-mesh's on
                           areas alone), kept on the same terms (default 200; 0 off; with vertex_polish
                           0 neither runs) */
  int staged_retry;     /* > 0: a map that misses its tolerance with at least 1% of the surface in vertex
                           cells under 1/e of their share (squeezed protrusions the flow did not open up,
                           au__metrics_squeezed) flows again from itself in stages, each towards a part
                           of the way (au_sphere_map.c), at most this many, then once towards the
                           surface's areas; kept if its vertex error (retry_err) is lower (default 8; 0 off).
                           Not with a density (flow.weight, flow.face_weight) */
  au_sphere_start start; /* the start (default AU_SPHERE_START_CONFORMAL) */
  au_sphere_ml_opts ml;   /* the coarse-to-fine start's settings (au_sphere_ml_opts_default) */
} au_sphere_opts;

au_sphere_opts au_sphere_opts_default(void);

typedef struct au_sphere_ml_report {
  int coarse_vertices; /* vertices of the coarse mesh */
  int levels;          /* levels, coarse and fine included */
  int coarse_steps;    /* the coarse map's flow steps */
  int level_steps;     /* flow steps over the levels between the coarse and the fine mesh */
} au_sphere_ml_report;

/* The coarse-to-fine start: the mesh simplified by half-edge collapses (topology kept) to about
 * o->ml.coarse_vertices vertices, mapped by au_sphere_map (conformal start, o's flow and rescues; where that
 * start folds, from a Tutte embedding of a further simplification to a tetrahedron, re-inserted), then
 * the collapses undone in reverse order, each vertex placed strictly inside the kernel of its ring on
 * the sphere where the ring keeps the surface's shape (mean-value coordinates), with o->ml.level_steps
 * flow steps after each level but the finest and two sweeps of the placement after it
 * (sphere/au_sphere_ml.c, docs/coarse-to-fine-placement.md).
 * P: out, nv x 3 unit vectors, fold-free. rep may be NULL. Not with flow.face_weight (AU_E_ARG); a
 * flow.weight is followed from the first level on. Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_CANCELLED,
 * AU_E_FOLD (a ring's kernel was empty to rounding), AU_W_NOT_CONVERGED (the coarse map stayed far from
 * equal area: vertex error above 0.1 on every coarse mesh tried), or the coarse map's error. */
au_status au_sphere_multilevel(const au_mesh *m, const au_topo *t, const au_sphere_opts *o, double *P,
                               au_sphere_ml_report *rep, au_msg *msg);

typedef struct au_sphere_report {
  au_sphere_start start;  /* the start that made the map (a coarse-to-fine start that failed falls back
                             to the conformal one) */
  au_sphere_ml_report ml; /* with the coarse-to-fine start: what it did */
  au_msg ml_fallback;     /* a coarse-to-fine start asked for and not made: why (empty text otherwise) */
  double t_init;          /* seconds spent in the conformal initialization and balancing */
  double t_flow;          /* seconds spent in the advection */
  int init_folds;         /* folded triangles of the conformal map (must be 0) */
  au_advect_report flow;  /* steps, errors, step fractions (of the map kept) */
  int retry;              /* 0: no lantern retry; 1: it ran and its map was discarded; 2: its map was kept */
  double retry_err[2];    /* with a retry: the vertex mean |log ratio| of the first map and of the retry's,
                             of their chord triangles or, for a map of spherical areas only
                             (flow.sphere_areas 2), of their spherical ones: every retry compares maps by
                             the areas the map is made for */
  int twist;              /* 0: no twisted retry; 1: it ran and its map was discarded; 2: its map was kept
                             (P0 stays the conformal start; the twisted start's time is in t_flow);
                             3: every conformal start folded and the map was made from the strong
                             twisted start (au_sphere_twisted_strong; P0 is that start) */
  int twist_faces;        /* with a twisted retry: the faces its start sheared */
  double twist_err;       /* with a twisted retry: its map's vertex error (as retry_err) */
  int staged;             /* 0: no staged retry; 1: it ran and its map was discarded; 2: its map was kept */
  int staged_stages;      /* with a staged retry: the stages it ran (the last run, towards the surface's
                             areas, not counted) */
  double staged_err[2];   /* with a staged retry: the vertex error (as retry_err) before it and of its map */
  int refine_kept_input;  /* au_sphere_refine: 1 if neither refinement beat the input's map */
  int polish;             /* 0: no vertex polish; 1: it ran and was discarded; 2: it was kept */
  int polish_sweeps;      /* with a polish: its sweeps */
  double polish_err[4];   /* with a polish: vertex error before and after, per-face mean |r - 1| before
                             and after (the spherical triangles' with flow.sphere_areas 2, else chord) */
  int global_polish;       /* au_sphere_refine: 0 none; 1 the global polish ran and was discarded; 2 kept */
  int global_polish_steps; /* with a global polish: its steps */
  double global_polish_err[4]; /* with a global polish: vertex error before and after, per-face before and after */
  double global_polish_robust; /* with a global polish: the pseudo-Huber d its area residuals ran with (0: squares;
                                  au_sphere_map.c says where each is used) */
  int lantern_skipped;    /* 1: the lantern retry was due (the map missed retry_above x its tolerance) but not
                             run, since its flow would have repeated the first step for step (the first
                             flow's spherical vertex error never came below 1, where the lantern acts:
                             au_sphere_map.c); retry stays 0 */
} au_sphere_report;

/* Fold-free spherical conformal map of a closed genus-0 mesh.
 * m, t: a mesh that passed au_mesh_validate with loops 0 and genus 0, and its topology.
 * P: out, nv x 3 row-major (caller-allocated, 3*nv doubles), unit vectors.
 * Unreferenced vertices get (0,0,1). Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NOT_SPD,
 * AU_E_NUMERIC, AU_E_FOLD (the map folded: msg says how many triangles). */
au_status au_sphere_conformal(const au_mesh *m, const au_topo *t, double *P, au_msg *msg);

/* The twisted start: as au_sphere_conformal, with the triangles across which the flat log scale jumps
 * by more than 0.3 (the protrusions, and the puncture's neighbourhood) sheared along their girth so that
 * each stands over an end of its edge across the limb, the handedness the same everywhere: a band of
 * triangles turned half a step per ring (an antiprism band) becomes a prism band, which the flow can
 * stretch along the girth without the chord triangles folding to and fro beneath the sphere
 * (au_sphere_init.c, tube_weights). *nsheared: the number of faces sheared; 0: none, P not written.
 * Returns as au_sphere_conformal. */
au_status au_sphere_twisted(const au_mesh *m, const au_topo *t, double *P, int *nsheared, au_msg *msg);

/* The strong twisted start: as au_sphere_twisted down to a jump of 0.1 instead of 0.3, and its
 * compressed attempt compresses both halves of u (also the part the puncture expands). For meshes whose
 * conformal start folds even compressed (nested protrusions: data/tpose.obj); au_sphere_map falls back
 * to it. Returns as au_sphere_twisted. */
au_status au_sphere_twisted_strong(const au_mesh *m, const au_topo *t, double *P, int *nsheared, au_msg *msg);

/* The vertex polish: after the flow, each vertex in turn takes a damped Gauss-Newton step in its
 * tangent plane on its own triangles' chord areas (C / T - 1, T the share of the chord triangles' total;
 * with po->spherical the spherical triangles' areas and 4 pi)
 * and its cells' (cell_weight x log of cell over share, scaled by faces per vertex), halved until that
 * falls with no triangle turned over; sweeps over all vertices until the vertex cells' mean |log ratio|
 * is at most tol or fell by less than 0.2% in the last sweep, at most max_sweeps. The flow moves every
 * vertex along one gradient field and jams where long, thin chord triangles sit on their floor; one
 * vertex alone can slide along a long edge (sphere/au_sphere_polish.c). face_w: per-face target density (NULL: equal area).
 * P: in/out, nv x 3 unit vectors, fold-free; stays fold-free. *sweeps (may be NULL): sweeps run.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_CANCELLED (P partly polished, still fold-free). */
typedef struct au_polish_opts {
  int max_sweeps;     /* at most this many sweeps */
  double cell_weight; /* weight of the vertex cells against the faces (>= 0) */
  double tol;         /* stop once the vertex cells' mean |log ratio| is at most this */
  const int *cancel;  /* when *cancel is nonzero at the start of a sweep (read atomically): AU_E_CANCELLED */
  int spherical;      /* 1: the spherical triangles' areas (a map of spherical areas only), 0: the chord ones' */
} au_polish_opts;
au_status au_sphere_vertex_polish(const au_mesh *m, const au_topo *t, const double *face_w, double *P,
                                  const au_polish_opts *po, int *sweeps, au_msg *msg);

/* The global polish (sphere/au_sphere_gpolish.c): after the vertex polish, a Levenberg-Marquardt
 * iteration over every vertex's tangent displacement at once on the chord triangles' log area ratios,
 * the vertex cells' (times cell_weight), each face's log conformal distortion (times angle_weight) and a log barrier (weight barrier_weight) on each triple product
 * less than 2 x barrier x its face's share of the chord total above its least value (min_orient of the
 * share, or where it started if lower); a step that takes a triple product below its least is halved,
 * or tried with 4x the damping. Steps are taken while they lower that cost, at most
 * max_iter, until five in a row gain less than 0.01% each, the vertex cells' mean |log ratio| is at
 * most tol, or (min_gain) ten steps have gained too little of what a user measures (a map already there is left alone). face_w: per-face target density (NULL:
 * equal area). P: in/out, nv x 3 unit vectors, fold-free; stays so. A vertex with more than 64 faces
 * leaves P unchanged. *iters (may be NULL): steps taken.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_CANCELLED (P as after the last step, fold-free). */
typedef struct au_gpolish_opts {
  int max_iter;          /* at most this many steps */
  double cell_weight;    /* weight of a vertex cell's log ratio against a face's (>= 0) */
  double barrier;        /* the barrier acts below 2 x this x a face's share (triple product, >= 0) */
  double barrier_weight; /* its weight (>= 0; 0: no barrier) */
  double min_orient;     /* least triple product, as a fraction of the share (>= 0) */
  double angle_weight;   /* weight of each face's squared log conformal distortion (>= 0; 0: areas only) */
  double robust;         /* > 0: area residuals r enter as the pseudo-Huber loss 2 d^2 (sqrt(1 + (r/d)^2) - 1)
                          * with d this (>= 0; 0: squares) */
  double tol;            /* stop once the vertex cells' mean |log ratio| is at most this */
  const int *cancel;     /* when *cancel is nonzero at the start of a step (read atomically): AU_E_CANCELLED */
  double min_gain;       /* > 0: also stop once the last 20 steps together have lowered neither the vertex cells' mean
                          * |log ratio| nor the faces' mean |r - 1| (against the surface's shares) by this
                          * part of its value (0..1; 0: off, as au_sphere_gpolish_settings leaves it) */
  int face_window;       /* > 0: at the tolerance, go on while the faces' mean |r - 1| is above face_target and
                          * has fallen by more than face_gain of its value over the last face_window steps
                          * (1..20; 0: stop at the tolerance, as au_sphere_gpolish_settings leaves it); a map
                          * already at the tolerance when the polish starts is left as it is */
  double face_gain;      /* see face_window (0..1) */
  double face_target;    /* see face_window (>= 0) */
} au_gpolish_opts;
au_status au_sphere_global_polish(const au_mesh *m, const au_topo *t, const double *face_w, double *P,
                                  const au_gpolish_opts *o, int *iters, au_msg *msg);
/* The sphere map and the refinement run it on meshes of at most this many vertices: its factor, on the
 * two-ring pattern, takes about 9 KB per vertex (armadillo, 43k vertices: peak 167 -> 537 MB). */
#define AU_GPOLISH_MAX_VERTICES 100000
/* The settings the sphere map and the refinement use, with max_iter, angle_weight, tol and cancel as given
 * (robust 0: the refinement sets its own). */
au_gpolish_opts au_sphere_gpolish_settings(int max_iter, double angle_weight, double tol, const int *cancel);

/* au_sphere_vertex_polish with o->vertex_polish sweeps and o->polish_cells, on a copy of P, which
 * replaces P when its vertex error is lower and its per-face error not higher, both in the map's measure
 * (the spherical triangles' for flow.sphere_areas 2, else the chord ones'; au_sphere_map runs it on a
 * map that misses its tolerance). rep->polish, polish_sweeps and polish_err tell what happened. Then,
 * for a chord map still short of it, the global polish (o->global_polish steps at most), on the same
 * terms: rep->global_polish, global_polish_steps, global_polish_err, global_polish_robust.
 * o->flow.cancel is honoured between sweeps and steps. Returns AU_OK, AU_E_ARG, AU_E_NOMEM,
 * AU_E_CANCELLED (P unchanged, or with the vertex polish only). */
au_status au_sphere_polish_map(const au_mesh *m, const au_topo *t, const au_sphere_opts *o, double *P,
                               au_sphere_report *rep, au_msg *msg);

/* Moebius-normalize a sphere map in place so the surface-area-weighted centroid of the image
 * is the origin (the conformal map stays conformal). P: nv x 3 unit vectors, in/out.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_sphere_balance(const au_mesh *m, const au_topo *t, double *P, au_msg *msg);

/* The unit sphere as the advection's domain: displacements kept in the tangent plane (eq. 22),
 * positions pulled back onto the sphere. */
au_advect_domain au_sphere_domain(void);

/* The whole map: conformal start, balancing, advection.
 * opts may be NULL for defaults; rep may be NULL. P: out, nv x 3 (caller-allocated), |p| = 1.
 * P0: out, the starting map (conformal and balanced), nv x 3; may be NULL.
 * Returns AU_OK, AU_W_NOT_CONVERGED (the map is valid and fold-free but the tolerance was not met
 * in max_steps), or an error as au_sphere_conformal / au_advect_run. */
au_status au_sphere_map(const au_mesh *m, const au_topo *t, const au_sphere_opts *opts, double *P, double *P0,
                        au_sphere_report *rep, au_msg *msg);

/* Refine a sphere map where the chord floor binds (sphere/au_sphere_refine.c), where some face's least
 * chord area (au_dec_sphere_chord_floor) exceeds half its share: three refinements are made and the one
 * with the lowest vertex error is kept. The first splits the longest edge of each face whose floor
 * exceeds a tenth of its share at its midpoint (on the surface: the average of its ends; on the sphere:
 * the great arc's midpoint) and flows again on the refined mesh from there, at the shear weight's floor;
 * up to eight rounds, each spending at most half the face budget left (max_faces x m->nf). The second
 * splits the map's longest edges in one round (at most 3x the faces); the third splits, from the map of
 * spherical areas, the faces whose chord triangles lack the most of their spherical ones' area, by their
 * longest edges, then flows the spherical areas and polishes the chord ones. Where no face is held only
 * the first is made.
 * m: the input mesh (validated, closed, genus 0); P: its map (nv x 3, fold-free, e.g. au_sphere_map's).
 * opts: the flow's options (may be NULL); max_faces >= 1 (2: at most twice the faces).
 * out, Pout: the refined mesh and its map, library-allocated (au_mesh_free, free): the input's vertices
 * first, in order, then the new ones; face f of the input keeps index f for its first piece, the other
 * pieces come after the input's faces. parent [0..2*nnew-1], param [0..nnew-1] (free): new vertex
 * m->nv + k lies at (1 - param[k]) X[parent[2k]] + param[k] X[parent[2k+1]] (a parent may itself be
 * new, with a smaller number), on the surface. With nothing to split, or when neither refinement
 * lowers the input map's vertex error, or the better one raises its per-face error, out is a copy of m,
 * Pout P (with the vertex polish, au_sphere_polish_map, when P misses the tolerance) and nnew is 0
 * (rep->refine_kept_input 1 when something was split). rep (may be NULL): the input map's report in, the kept refinement's last
 * flow's report in rep->flow out (unchanged when the input's map is kept).
 * Returns AU_OK, AU_W_NOT_CONVERGED (the last flow missed its tolerance; the map is fold-free),
 * AU_E_ARG, AU_E_NOMEM, or an error of au_advect_run. */
au_status au_sphere_refine(const au_mesh *m, const double *P, const au_sphere_opts *opts, double max_faces,
                           au_mesh **out, double **Pout, int **parent, double **param, int *nnew,
                           au_sphere_report *rep, au_msg *msg);

/* One face budget au_sphere_refine_auto tried: the budget (x the input's faces), the refined mesh's
 * faces, and its map's per-face mean |r - 1| and vertex mean |log r| (the chord triangles', as param-eval). */
typedef struct au_refine_trial {
  double budget;
  int nf;
  double face_err, vertex_err;
} au_refine_trial;

#define AU_REFINE_AUTO_TRIALS 3
#define AU_REFINE_AUTO_FACE 0.02   /* what au_sphere_refine_auto asks of a refined map: per-face mean |r - 1| */
#define AU_REFINE_AUTO_VERTEX 0.005 /* and vertex mean |log r| */

/* au_sphere_refine at twice the faces, then at 3x and 4x while the refined map misses a per-face mean
 * |r - 1| of 0.02 or a vertex mean |log r| of 0.005 (issue 21's bounds for a refined map): the first
 * budget that meets both is kept, else the one with the lowest per-face error. Each budget runs from P
 * afresh (the refinement is not incremental). It stops early where a budget split nothing because no
 * face is held by the floor (with rep NULL, where a budget split nothing at all). An error at 3x or 4x
 * other than AU_E_CANCELLED leaves the best map so far. trials[AU_REFINE_AUTO_TRIALS] (may be NULL) and
 * *ntrials tell what was tried, *kept which of them stands. Arguments and returns as au_sphere_refine's. */
au_status au_sphere_refine_auto(const au_mesh *m, const double *P, const au_sphere_opts *opts, au_mesh **out,
                                double **Pout, int **parent, double **param, int *nnew, au_sphere_report *rep,
                                au_refine_trial *trials, int *ntrials, int *kept, au_msg *msg);

#ifdef __cplusplus
}
#endif
#endif
