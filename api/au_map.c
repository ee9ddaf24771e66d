/* au_map.c - the whole map behind the public header: check the mesh, make the initial map, run the
 * flow, measure, refuse folds, and hand back one result (include/authalic.h: au_map). The data flow
 * is mesh -> validate -> initial map -> advection -> metrics; the writers are the caller's. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "au_api_internal.h"
#include "au_disk.h"
#include "au_metrics.h"
#include "au_par.h"
#include "au_solver.h"
#include "au_report.h"
#include "au_sphere.h"
#include "au_torus.h"

/* A planar map's boundary vertices must lie on the domain's boundary to this distance; the flow
 * projects them there, so more means a numerical failure. */
#define AU_BOUNDARY_TOL 1e-12
/* A sphere map that missed its tolerance warns of the chord floor only when it matters: a single
 * floor-bound face after a short run is no news. */
#define AU_FLOOR_WARN_EXCESS 1e-4

/* A map that misses its tolerance is also said to be squeezed where at least this share of the surface
 * has vertex cells under 1/e of their share: long protrusions a conformal start squeezes by e^-20 and
 * more, which the flow does not open up (tpose; docs/sphere.md). Cells too large are the chord
 * floor's, which has its own warning. */
#define AU_SQUEEZED_WARN_SHARE 0.01
/* refine_mesh's face budget by default, as a multiple of the input's faces: issue 21's bound. */
#define AU_REFINE_DEFAULT_FACES 2

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void warn(au_result *r, const char *fmt, ...) {
  if (r->nwarnings >= AU_MAX_WARNINGS) return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(r->warnings[r->nwarnings++], sizeof r->warnings[0], fmt, ap);
  va_end(ap);
}

void au_result_free(au_result **rp) {
  if (!rp || !*rp) return;
  au_result *r = *rp;
  free(r->P), free(r->P0), free(r->X), free(r->F), free(r->uv), free(r->vt), free(r->Ft);
  free(r->parent), free(r->parent_t);
  free(r->circles), free(r->circle_vertex);
  free(r->conv.err), free(r->conv.face_err), free(r->conv.frac);
  free(r);
  *rp = NULL;
}

/* The progress adapter: the user's callback may cancel, and so may the user's flag; either sets the
 * flag the flow reads. */
typedef struct progress_ctx {
  const au_options *o;
  int cancel;
} progress_ctx;

static int cancelled(progress_ctx *c) {
  if (c->o->cancel && __atomic_load_n(c->o->cancel, __ATOMIC_ACQUIRE)) __atomic_store_n(&c->cancel, 1, __ATOMIC_RELEASE);
  return __atomic_load_n(&c->cancel, __ATOMIC_ACQUIRE);
}

static void on_progress(void *user, int step, int max_steps, double err) {
  progress_ctx *c = user;
  if (c->o->progress && c->o->progress(c->o->user, step, max_steps, err)) __atomic_store_n(&c->cancel, 1, __ATOMIC_RELEASE);
  cancelled(c);
}

/* Check the options that do not depend on the mesh. */
static au_status check_options(const au_options *o, int nv, int nf, au_msg *msg) {
  if (o->max_steps < 0 || o->max_steps > AU_ADVECT_MAX_STEPS)
    return au_msg_set(msg, AU_E_ARG, "max_steps %d: expected 1..%d (0: default)", o->max_steps, AU_ADVECT_MAX_STEPS);
  if (o->tol != o->tol || isinf(o->tol)) return au_msg_set(msg, AU_E_ARG, "tol: expected a finite number");
  if (o->angle_steps < 0 || o->angle_steps > AU_ANGLE_STEPS_MAX)
    return au_msg_set(msg, AU_E_ARG, "angle_steps %d: expected 0..%d", o->angle_steps, AU_ANGLE_STEPS_MAX);
  if (!(o->restore_shapes <= 1) || isinf(o->restore_shapes))
    return au_msg_set(msg, AU_E_ARG, "restore_shapes: expected a number from 0 to 1 (negative: default)");
  if (o->vertex_density && o->face_density)
    return au_msg_set(msg, AU_E_ARG, "give a vertex density or a face density, not both");
  /* The refined mesh's new vertices and faces would have no density (and the flow would read past it). */
  if (o->refine_mesh && (o->vertex_density || o->face_density))
    return au_msg_set(msg, AU_E_ARG, "refine_mesh does not take a density");
  if (o->refine_mesh && o->refine_max_faces != 0 && o->refine_max_faces != AU_REFINE_AUTO &&
      !(o->refine_max_faces > 1 && o->refine_max_faces <= AU_REFINE_MAX_FACES))
    return au_msg_set(msg, AU_E_ARG, "refine_max_faces: expected more than 1 and at most %d (0: the default %d; AU_REFINE_AUTO)",
                      AU_REFINE_MAX_FACES, AU_REFINE_DEFAULT_FACES);
  if (o->expert && (o->expert->vertex_polish < 0 || !(o->expert->polish_cells >= 0) || isinf(o->expert->polish_cells)))
    return au_msg_set(msg, AU_E_ARG, "expert vertex_polish: expected sweeps >= 0 and polish_cells >= 0");
  if (o->expert && o->expert->staged_retry < 0) return au_msg_set(msg, AU_E_ARG, "expert staged_retry: expected stages >= 0");
  if (o->expert && o->expert->global_polish < 0)
    return au_msg_set(msg, AU_E_ARG, "expert global_polish: expected steps >= 0");
  if (o->start != AU_START_CONFORMAL && o->start != AU_START_MULTILEVEL)
    return au_msg_set(msg, AU_E_ARG, "start %d: expected AU_START_CONFORMAL (0) or AU_START_MULTILEVEL (1)", (int)o->start);
  if (o->spherical_areas != 0 && o->spherical_areas != 1)
    return au_msg_set(msg, AU_E_ARG, "spherical_areas %d: expected 0 or 1", o->spherical_areas);
  /* The refinement splits where chord triangles cannot shrink to their shares and judges by chord
   * errors; a map of spherical areas has no such floor (and its refined maps read worse in chord
   * terms: docs/sphere.md). */
  if (o->refine_mesh && (o->spherical_areas || (o->expert && o->expert->sphere_areas == 2)))
    return au_msg_set(msg, AU_E_ARG, "refine_mesh does not take spherical_areas (spherical triangles have no chord floor to refine)");
  if (!(o->inner_radius >= 0 && o->inner_radius < 1))
    return au_msg_set(msg, AU_E_ARG, "inner_radius: expected 0 < r < 1 (0: the conformal modulus's)");
  if (o->boundary != AU_BOUNDARY_SLIDE && o->boundary != AU_BOUNDARY_FIXED)
    return au_msg_set(msg, AU_E_ARG, "boundary: expected AU_BOUNDARY_SLIDE or AU_BOUNDARY_FIXED");
  if (o->lattice != AU_LATTICE_CONFORMAL && o->lattice != AU_LATTICE_SQUARE)
    return au_msg_set(msg, AU_E_ARG, "lattice: expected AU_LATTICE_CONFORMAL or AU_LATTICE_SQUARE");
  if (!(o->aspect >= 0) || isinf(o->aspect))
    return au_msg_set(msg, AU_E_ARG, "aspect: expected a positive finite width / height (0: the unit square)");
  if (o->outer_loop < AU_OUTER_SHORTER)
    return au_msg_set(msg, AU_E_ARG, "outer_loop %d: expected AU_OUTER_LONGER, AU_OUTER_SHORTER or a vertex index",
                      o->outer_loop);
  const double *d = o->vertex_density ? o->vertex_density : o->face_density;
  int n = o->vertex_density ? nv : nf;
  for (int i = 0; d && i < n; i++)
    if (!(d[i] > 0) || isinf(d[i]))
      return au_msg_set(msg, AU_E_DENSITY, "%s density value %d (%g) is not a positive finite number",
                        o->vertex_density ? "vertex" : "face", i, d[i]);
  return AU_OK;
}

/* The flow's options from the user's. */
static void flow_options(au_target t, const au_options *o, progress_ctx *pc, au_advect_opts *f, au_sphere_opts *sphere) {
  au__flow_defaults(t, o->refine_faces, f, sphere);
  if (o->expert && t == AU_TARGET_SPHERE) {
    const au_expert *e = o->expert;
    sphere->lantern_retry = e->lantern_retry, sphere->retry_above = e->retry_above, sphere->twist_retry = e->twist_retry;
    sphere->vertex_polish = e->vertex_polish, sphere->polish_cells = e->polish_cells;
    sphere->staged_retry = e->staged_retry, sphere->global_polish = e->global_polish;
  }
  if (o->expert) au__flow_from_expert(o->expert, f);
  if (o->spherical_areas && t == AU_TARGET_SPHERE) f->sphere_areas = 2;
  if (o->max_steps > 0) f->max_steps = o->max_steps;
  if (o->tol >= 0) f->tol = o->tol;
  if (o->restore_shapes >= 0) f->restore = o->restore_shapes;
  f->angle_steps = o->angle_steps;
  f->weight = o->vertex_density, f->face_weight = o->face_density;
  f->progress = on_progress, f->user = pc, f->cancel = &pc->cancel;
}

/* The annulus loop the user picked for the unit circle, or -1 (msg set). */
static int pick_outer(const au_options *o, const au_topo *t, au_msg *msg) {
  double l0 = t->loop_len ? t->loop_len[0] : t->loop_start[1] - t->loop_start[0];
  double l1 = t->loop_len ? t->loop_len[1] : t->loop_start[2] - t->loop_start[1];
  if (o->outer_loop == AU_OUTER_LONGER) return l1 > l0 ? 1 : 0;
  if (o->outer_loop == AU_OUTER_SHORTER) return l1 > l0 ? 0 : 1;
  for (int l = 0; l < 2; l++)
    for (int k = t->loop_start[l]; k < t->loop_start[l + 1]; k++)
      if (t->loop_vert[k] == o->outer_loop) return l;
  au_msg_set(msg, AU_E_ARG, "outer_loop: vertex %d is on neither boundary loop", o->outer_loop);
  return -1;
}

/* The square's corners (given, put in loop order; or chosen) and the split mesh it is mapped on. */
static au_status square_mesh(const au_mesh *m, const au_topo *t, const au_options *o, int c[4], au_mesh **ms,
                             au_topo **ts, int *nsplit, au_msg *msg) {
  au_status st;
  if (o->corners[0] >= 0 || o->corners[1] >= 0 || o->corners[2] >= 0 || o->corners[3] >= 0) {
    memcpy(c, o->corners, 4 * sizeof *c);
    st = au_square_order_corners(t, c, msg);
    if (st != AU_OK) {
      char why[sizeof msg->text];
      snprintf(why, sizeof why, "%s", msg ? msg->text : "");
      return au_msg_set(msg, AU_E_ARG, "corners: %s", why);
    }
  } else if ((st = au_square_corners(m, t, c, msg)) != AU_OK) {
    return AU_E_BOUNDARY; /* too few boundary vertices for four corners: a fault of the input */
  }
  st = au_square_split(m, t, c, ms, nsplit, msg);
  if (st == AU_OK) st = au_mesh_topology(*ms, ts, msg);
  return st;
}

/* Everything one map holds while it runs. */
typedef struct map_run {
  au_target target;
  const au_options *o;
  au_mesh *m, *ms; /* the input's copy, and the square's split mesh */
  au_topo *t, *ts;
  const au_mesh *mm; /* the mesh that is mapped: m, or ms for the square */
  const au_topo *tt;
  au_advect_opts flow;
  au_sphere_opts sphere; /* the sphere's retries and polish (its flow field unused: flow above) */
  progress_ctx pc;
  au_result *r;
  int outer; /* annulus, circles: the loop index on the unit circle (circles: -1 for the longest) */
  double t_split;
  double w, h; /* square: the rectangle's sides (au_options.aspect) */
  double refine_budget; /* refine_mesh: the face budget of the map kept (with AU_REFINE_AUTO, the one it chose) */
} map_run;

static au_status alloc_result(map_run *x, au_msg *msg) {
  au_result *r = x->r;
  size_t n3 = 3 * (size_t)x->mm->nv;
  r->nv = x->mm->nv, r->nf = x->mm->nf;
  r->P = malloc(n3 * sizeof *r->P), r->P0 = malloc(n3 * sizeof *r->P0), r->X = malloc(n3 * sizeof *r->X);
  r->F = malloc(3 * (size_t)r->nf * sizeof *r->F);
  const int per_vertex_uv = x->target != AU_TARGET_SPHERE && x->target != AU_TARGET_TORUS;
  if (per_vertex_uv) r->uv = malloc(2 * (size_t)r->nv * sizeof *r->uv);
  if (!r->P || !r->P0 || !r->X || !r->F || (per_vertex_uv && !r->uv))
    return au_msg_set(msg, AU_E_NOMEM, "out of memory for the result");
  memcpy(r->X, x->mm->X, n3 * sizeof *r->X);
  memcpy(r->F, x->mm->F, 3 * (size_t)r->nf * sizeof *r->F);
  return AU_OK;
}

/* Keep the flow's log in the result. */
static au_status keep_log(au_result *r, const au_advect_report *f, au_msg *msg) {
  au_convergence *c = &r->conv;
  c->steps = f->steps, c->converged = f->converged, c->undone = f->undone;
  c->polish_from = f->polish_from, c->angle_from = f->angle_from, c->resolved = f->resolved;
  c->start_jump = f->start_jump;
  size_t n = (size_t)f->steps + 1;
  c->err = malloc(n * sizeof *c->err), c->face_err = malloc(n * sizeof *c->face_err);
  c->frac = malloc(n * sizeof *c->frac);
  if (!c->err || !c->face_err || !c->frac) return au_msg_set(msg, AU_E_NOMEM, "out of memory for the log");
  memcpy(c->err, f->err, n * sizeof *c->err);
  memcpy(c->face_err, f->face_err, n * sizeof *c->face_err);
  memcpy(c->frac, f->frac, (n - 1) * sizeof *c->frac);
  return AU_OK;
}

/* The refined mesh replaces the input's in the result (au_options.refine_mesh). P0 of a new vertex is
 * its parents' start midpoint on the sphere, so that the initial metrics cover the same mesh. */
static au_status refine_sphere(map_run *x, const au_sphere_opts *so, au_sphere_report *rep, au_msg *msg) {
  au_result *r = x->r;
  au_mesh *mr = NULL;
  double *Pr = NULL, *prm = NULL;
  int *par = NULL, nnew = 0;
  double t0 = now_s();
  const double max_faces = x->o->refine_max_faces > 0 ? x->o->refine_max_faces : AU_REFINE_DEFAULT_FACES;
  au_refine_trial tr[AU_REFINE_AUTO_TRIALS];
  int ntr = 0, kept = -1;
  au_status st = x->o->refine_max_faces == AU_REFINE_AUTO
                     ? au_sphere_refine_auto(x->m, r->P, so, &mr, &Pr, &par, &prm, &nnew, rep, tr, &ntr, &kept, msg)
                     : au_sphere_refine(x->m, r->P, so, max_faces, &mr, &Pr, &par, &prm, &nnew, rep, msg);
  r->t_flow += now_s() - t0;
  if (st < 0) return st;
  x->refine_budget = kept >= 0 ? tr[kept].budget : max_faces;
  if (ntr > 0) {
    char line[AU_REFINE_AUTO_TRIALS * 96] = "";
    size_t len = 0;
    for (int i = 0; i < ntr && len < sizeof line; i++) {
      int k = snprintf(line + len, sizeof line - len, "%s%gx: %d faces%s, per-face %.4g, vertex %.4g%s", i ? "; " : "",
                       tr[i].budget, tr[i].nf, tr[i].nf == x->m->nf ? " (the input's mesh)" : "", tr[i].face_err,
                       tr[i].vertex_err, i == kept ? " (kept)" : "");
      if (k < 0) break;
      len += (size_t)k;
    }
    warn(r, "refine budget auto (per-face <= %g and vertex <= %g wanted): %s", AU_REFINE_AUTO_FACE, AU_REFINE_AUTO_VERTEX, line);
  }
  double *P0 = realloc(r->P0, sizeof(double) * 3 * (size_t)mr->nv);
  double *X = malloc(sizeof(double) * 3 * (size_t)mr->nv);
  int *F = malloc(sizeof(int) * 3 * (size_t)mr->nf);
  if (P0) r->P0 = P0;
  if (!P0 || !X || !F) {
    au_mesh_free(&mr), free(Pr), free(par), free(prm), free(X), free(F);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory for the refined mesh");
  }
  for (int k = 0; k < nnew; k++) {
    const double *a = P0 + 3 * (size_t)par[2 * k], *b = P0 + 3 * (size_t)par[2 * k + 1];
    double *p = P0 + 3 * (size_t)(x->m->nv + k), n = 0;
    for (int d = 0; d < 3; d++) p[d] = a[d] + b[d], n += p[d] * p[d];
    for (int d = 0; d < 3; d++) p[d] /= sqrt(n);
  }
  memcpy(X, mr->X, sizeof(double) * 3 * (size_t)mr->nv);
  memcpy(F, mr->F, sizeof(int) * 3 * (size_t)mr->nf);
  free(r->P), free(r->X), free(r->F);
  r->P = Pr, r->X = X, r->F = F, r->nv = mr->nv, r->nf = mr->nf;
  r->nrefined = nnew, r->parent = par, r->parent_t = prm;
  au_mesh_free(&mr);
  if (nnew) warn(r, "refined: %d edges split, %d faces (the input has %d); vertices %d..%d are new", nnew, r->nf, x->m->nf,
                 x->m->nv, r->nv - 1);
  else if (rep->refine_kept_input)
    warn(r, "refined: nothing split (no refinement lowered the vertex error without raising the per-face one); the input's mesh and map are written");
  else
    warn(r, "refined: nothing to split (no chord triangle is held by the floor); the input's mesh and map are written");
  return st;
}

static au_status run_sphere(map_run *x, au_msg *msg) {
  au_result *r = x->r;
  au_status st;
  r->init_method = "conformal";
  if (x->o->init_only) {
    double t0 = now_s();
    st = AU_E_ARG;
    if (x->o->start == AU_START_MULTILEVEL) {
      au_sphere_opts so = x->sphere;
      so.flow = x->flow;
      au_msg m1 = {0};
      st = au_sphere_multilevel(x->m, x->t, &so, r->P, NULL, &m1);
      if (st == AU_OK) r->init_method = "multilevel";
      else if (st == AU_E_CANCELLED || st == AU_E_NOMEM) {
        if (msg) *msg = m1;
        return st;
      } else
        warn(r, "the coarse-to-fine start could not be made (%s); the conformal start was made instead", m1.text);
    }
    if (st != AU_OK) {
      st = au_sphere_conformal(x->m, x->t, r->P, msg);
      if (st == AU_OK && x->o->balance) st = au_sphere_balance(x->m, x->t, r->P, msg);
    }
    r->t_init = now_s() - t0;
    if (st == AU_OK) memcpy(r->P0, r->P, 3 * (size_t)r->nv * sizeof *r->P);
    return st;
  }
  au_sphere_opts so = x->sphere;
  so.flow = x->flow, so.balance = x->o->balance != 0;
  so.start = x->o->start == AU_START_MULTILEVEL ? AU_SPHERE_START_MULTILEVEL : AU_SPHERE_START_CONFORMAL;
  au_sphere_report *rep = calloc(1, sizeof *rep);
  if (!rep) return au_msg_set(msg, AU_E_NOMEM, "out of memory");
  /* With refinement, the vertex polish comes after it (au_sphere_refine): re-flows from a polished map
   * undo its slides and end far worse (cow: vertex error 0.072 against 0.0078). */
  au_sphere_opts sm = so;
  if (x->o->refine_mesh) sm.vertex_polish = 0;
  st = au_sphere_map(x->m, x->t, &sm, r->P, r->P0, rep, msg);
  r->t_init = rep->t_init, r->t_flow = rep->t_flow;
  r->init_method = rep->start == AU_SPHERE_START_MULTILEVEL ? "multilevel" : "conformal";
  if (so.start == AU_SPHERE_START_MULTILEVEL && rep->start != AU_SPHERE_START_MULTILEVEL && st >= 0)
    warn(r, "the coarse-to-fine start could not be made (%s); the map was made from the conformal start", rep->ml_fallback.text);
  if (st >= 0 && x->o->refine_mesh) st = refine_sphere(x, &so, rep, msg);
  if (st >= 0) {
    au_status s2 = keep_log(r, &rep->flow, msg);
    r->conv.lantern_retry = rep->lantern_skipped ? 3 : rep->retry, r->conv.retry_err[0] = rep->retry_err[0], r->conv.retry_err[1] = rep->retry_err[1];
    r->conv.twist_retry = rep->twist, r->conv.twist_faces = rep->twist_faces, r->conv.twist_err = rep->twist_err;
    r->conv.vertex_polish = rep->polish, r->conv.polish_sweeps = rep->polish_sweeps;
    memcpy(r->conv.polish_err, rep->polish_err, sizeof rep->polish_err);
    r->conv.staged_retry = rep->staged, r->conv.staged_stages = rep->staged_stages;
    r->conv.staged_err[0] = rep->staged_err[0], r->conv.staged_err[1] = rep->staged_err[1];
    r->conv.global_polish = rep->global_polish, r->conv.global_polish_steps = rep->global_polish_steps;
    memcpy(r->conv.global_polish_err, rep->global_polish_err, sizeof rep->global_polish_err);
    r->conv.global_polish_robust = rep->global_polish_robust;
    if (s2 != AU_OK) st = s2;
  }
  free(rep);
  return st;
}

/* The circle domain (disk/au_circles.c); with init_only, the start (a flow of no steps). */
static au_status run_circles(map_run *x, au_disk_opts *d, au_disk_report *rep, au_msg *msg) {
  au_result *r = x->r;
  const au_topo *t = x->tt;
  int nl = t->nloops;
  au_circle *c = malloc(sizeof *c * (size_t)nl);
  r->circles = malloc(3 * sizeof(double) * (size_t)nl), r->circle_vertex = malloc(sizeof(int) * (size_t)nl);
  if (!c || !r->circles || !r->circle_vertex) {
    free(c);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory");
  }
  if (x->o->init_only) d->flow.max_steps = 0;
  au_status st = au_circles_map(x->mm, x->tt, d, x->outer, r->P, r->P0, c, rep, msg);
  if (x->o->init_only && st == AU_W_NOT_CONVERGED) st = AU_OK;
  if (st >= 0 && !x->o->init_only) {
    au_status s2 = keep_log(r, &rep->flow, msg);
    if (s2 != AU_OK) st = s2;
  }
  r->ncircles = nl, r->circle_outer = rep->outer_loop;
  for (int l = 0; l < nl; l++) {
    r->circles[3 * l] = c[l].cx, r->circles[3 * l + 1] = c[l].cy, r->circles[3 * l + 2] = c[l].r;
    r->circle_vertex[l] = t->loop_vert[t->loop_start[l]];
  }
  free(c);
  return st;
}

static au_status run_planar(map_run *x, au_msg *msg) {
  au_result *r = x->r;
  const au_options *o = x->o;
  au_disk_opts d = au_disk_opts_default();
  d.flow = x->flow, d.boundary = o->boundary == AU_BOUNDARY_FIXED ? AU_DISK_FIXED : AU_DISK_SLIDE;
  d.inner_radius = o->inner_radius, d.outer_loop = x->outer;
  memcpy(d.corners, r->corners, sizeof d.corners);
  au_disk_report *rep = calloc(1, sizeof *rep);
  if (!rep) return au_msg_set(msg, AU_E_NOMEM, "out of memory");
  au_status st;
  if (x->target == AU_TARGET_CIRCLES) {
    st = run_circles(x, &d, rep, msg);
  } else if (o->init_only) {
    double t0 = now_s();
    if (x->target == AU_TARGET_DISK) st = au_disk_init(x->mm, x->tt, r->P, &rep->init, msg);
    else if (x->target == AU_TARGET_ANNULUS)
      st = au_annulus_init(x->mm, x->tt, x->outer, d.inner_radius, r->P, &rep->inner_radius, &rep->modulus_radius,
                           &rep->init, msg);
    else st = au_square_init(x->mm, x->tt, d.corners, r->P, &rep->init, msg);
    rep->t_init = now_s() - t0;
    if (st == AU_OK) memcpy(r->P0, r->P, 3 * (size_t)r->nv * sizeof *r->P);
  } else {
    if (x->target == AU_TARGET_DISK) st = au_disk_map(x->mm, x->tt, &d, r->P, r->P0, rep, msg);
    else if (x->target == AU_TARGET_ANNULUS) st = au_annulus_map(x->mm, x->tt, &d, r->P, r->P0, rep, msg);
    else st = au_square_map(x->mm, x->tt, &d, r->P, r->P0, rep, msg);
    if (st >= 0) {
      au_status s2 = keep_log(r, &rep->flow, msg);
      if (s2 != AU_OK) st = s2;
    }
  }
  r->t_init = rep->t_init, r->t_flow = rep->t_flow;
  r->init_method = rep->init == AU_INIT_COTAN ? "cotan" : "meanvalue";
  if (x->target == AU_TARGET_ANNULUS) r->inner_radius = rep->inner_radius, r->modulus_radius = rep->modulus_radius;
  free(rep);
  return st;
}

/* The torus's metrics of the texture coordinates (nvt, vt, Ft) of the result's mesh (below). */
static au_status torus_metrics_of(const au_result *r, int nvt, const double *vt, const int *Ft, au_metrics *out);

/* The flow on the torus: the start's plane positions advected with every face's corners shifted by its
 * fixed lattice translation (au_advect_domain.shift), then wrapped back into the fundamental domain
 * (au_torus_set_positions). The lattice is kept, so its area 1 is the total the targets share. */
static au_status torus_flow(map_run *x, au_torus_start *s, au_msg *msg) {
  au_result *r = x->r;
  const double(*L)[2] = (const double(*)[2])r->lattice;
  if (x->flow.method != AU_ADVECT_LEAST_SHEAR)
    return au_msg_set(msg, AU_E_ARG, "the torus flow supports the least-shear method only (not the Poisson method)");
  double *shift = malloc(9 * sizeof(double) * (size_t)r->nf);
  au_advect_report *rep = calloc(1, sizeof *rep);
  if (!shift || !rep) {
    free(shift), free(rep);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory");
  }
  au_torus_corner_shifts(s, L, shift);
  au_advect_domain dom = au_torus_domain(shift);
  double t0 = now_s();
  au_status st = au_advect_run(x->m, x->t, &dom, &x->flow, r->P, rep, msg);
  r->t_flow = now_s() - t0;
  if (st >= 0) {
    au_torus_set_positions(s, r->F, L, r->P);
    au_torus_positions(s, L, r->P);
    au_status s2 = keep_log(r, rep, msg);
    if (s2 != AU_OK) st = s2;
  }
  free(shift), free(rep);
  return st;
}

/* The torus: the conformal start in the lattice asked for, the flow (unless init_only), the seamless
 * texture coordinates. */
static au_status run_torus(map_run *x, au_msg *msg) {
  au_result *r = x->r;
  au_torus_start *s = NULL;
  double t0 = now_s();
  au_status st = au_torus_init(x->m, x->t, &s, msg);
  r->t_init = now_s() - t0;
  if (st != AU_OK) return st;
  au_torus_lattice(s, x->o->lattice == AU_LATTICE_SQUARE ? AU_TORUS_SQUARE : AU_TORUS_CONFORMAL, r->lattice);
  memcpy(r->conformal_lattice, s->conformal, sizeof r->conformal_lattice);
  au_torus_positions(s, (const double(*)[2])r->lattice, r->P);
  memcpy(r->P0, r->P, 3 * (size_t)r->nv * sizeof *r->P);
  r->init_method = s->weights == AU_TORUS_COTAN ? "cotan" : s->weights == AU_TORUS_MEANVALUE ? "meanvalue" : "compressed";
  if (s->weights == AU_TORUS_COMPRESSED && isfinite(s->squeeze_before))
    warn(r, "the start squeezed a triangle to e^%.0f of its share: the start compresses the protrusions (e^%.0f)",
         s->squeeze_before, s->squeeze);
  else if (s->weights == AU_TORUS_COMPRESSED)
    warn(r, "the start folded %d triangles in floating point: the start compresses the protrusions (e^%.0f)",
         s->cotan_folds, s->squeeze);
  else if (s->weights != AU_TORUS_COTAN)
    warn(r, "the cotan start folded %d triangles: the start uses positive (mean-value) weights in the cotan lattice",
         s->cotan_folds);
  if (!x->o->init_only) {
    /* The start's metrics, measured as the result's are (the mesh cut at the seams). */
    int nvt0 = 0, *Ft0 = NULL;
    double *vt0 = NULL;
    st = au_torus_texcoords(s, r->F, (const double(*)[2])r->lattice, &nvt0, &vt0, &Ft0, msg);
    if (st == AU_OK && torus_metrics_of(r, nvt0, vt0, Ft0, &r->init_metrics) != AU_OK)
      st = au_msg_set(msg, AU_E_NOMEM, "metrics of the start failed");
    r->init_measured = st == AU_OK;
    free(vt0), free(Ft0);
    if (st == AU_OK) st = torus_flow(x, s, msg);
  }
  if (st >= 0) {
    au_status s2 = au_torus_texcoords(s, r->F, (const double(*)[2])r->lattice, &r->nvt, &r->vt, &r->Ft, msg);
    if (s2 != AU_OK) st = s2;
  }
  au_torus_start_free(&s);
  return st;
}

/* The torus's metrics: of the mesh cut along the seams (au__metrics_vt). */
static au_status torus_metrics_of(const au_result *r, int nvt, const double *vt, const int *Ft, au_metrics *out) {
  return au__metrics_vt(r->nv, r->nf, r->X, r->F, nvt, vt, Ft, out, NULL, NULL);
}

static au_status torus_metrics(au_result *r, au_metrics *out) { return torus_metrics_of(r, r->nvt, r->vt, r->Ft, out); }

/* The planar result's texture coordinates, and how far its boundary is from the domain's. */
static au_status planar_finish(map_run *x, au_msg *msg) {
  au_result *r = x->r;
  const au_topo *t = x->tt;
  double bdev = 0;
  for (int i = 0; i < r->nv; i++) {
    const double *p = r->P + 3 * (size_t)i;
    if (x->target == AU_TARGET_SQUARE) {
      r->uv[2 * i] = p[0], r->uv[2 * i + 1] = p[1];
      if (t->vb[i]) bdev = fmax(bdev, fmin(fmin(fabs(p[0]), fabs(p[0] - x->w)), fmin(fabs(p[1]), fabs(p[1] - x->h))));
    } else {
      r->uv[2 * i] = 0.5 * (p[0] + 1), r->uv[2 * i + 1] = 0.5 * (p[1] + 1);
    }
  }
  if (x->target == AU_TARGET_CIRCLES)
    for (int l = 0; l < r->ncircles; l++)
      for (int k = t->loop_start[l]; k < t->loop_start[l + 1]; k++) {
        const double *p = r->P + 3 * (size_t)t->loop_vert[k], *c = r->circles + 3 * l;
        bdev = fmax(bdev, fabs(hypot(p[0] - c[0], p[1] - c[1]) - c[2]));
      }
  else if (x->target != AU_TARGET_SQUARE)
    for (int l = 0; l < t->nloops; l++) {
      double want = x->target == AU_TARGET_DISK || l == x->outer ? 1.0 : r->inner_radius;
      for (int k = t->loop_start[l]; k < t->loop_start[l + 1]; k++) {
        const double *p = r->P + 3 * (size_t)t->loop_vert[k];
        bdev = fmax(bdev, fabs(hypot(p[0], p[1]) - want));
      }
    }
  r->boundary_dev = bdev;
  if (!(bdev <= AU_BOUNDARY_TOL))
    return au_msg_set(msg, AU_E_NUMERIC, "a boundary vertex is %.3g off the domain's boundary", bdev);
  return AU_OK;
}

/* Metrics of the result (and of its start), the fold check, the warnings about the flow. */
/* One au_metrics_compute of the result's mesh with domain positions P, for au__run_pair. */
typedef struct metrics_job {
  const au_result *r;
  const double *P;
  au_domain dom;
  au_metrics *out;
  au_status st;
} metrics_job;

static void *metrics_run(void *arg) {
  metrics_job *j = arg;
  j->st = au_metrics_compute(j->r->nv, j->r->nf, j->r->X, j->P, j->r->F, j->dom, j->out, NULL, NULL);
  return NULL;
}

static au_status measure(map_run *x, au_status st, au_msg *msg) {
  au_result *r = x->r;
  au_domain dom = x->target == AU_TARGET_SPHERE ? AU_DOMAIN_SPHERE : AU_DOMAIN_PLANE;
  double t0 = now_s();
  au_status ms = AU_OK;
  if (x->target == AU_TARGET_TORUS) {
    ms = torus_metrics(r, &r->metrics);
    r->t_metrics = now_s() - t0;
    if (ms != AU_OK) return au_msg_set(msg, ms, "metrics of the map failed");
    if (st == AU_W_NOT_CONVERGED && !x->o->init_only)
      warn(r, "tolerance %g not reached in %d steps (error %.3e)", x->flow.tol, r->conv.steps, r->conv.err[r->conv.steps]);
    if (r->metrics.folds > 0)
      return au_msg_set(msg, AU_E_FOLD, "the map has %d folded triangle%s", r->metrics.folds,
                        r->metrics.folds == 1 ? "" : "s");
    return AU_OK;
  }
  if (!x->o->init_only && x->o->measure_start) {
    /* The start's metrics and the map's are independent: one on each core. */
    metrics_job job[2] = {{r, r->P0, dom, &r->init_metrics, AU_OK}, {r, r->P, dom, &r->metrics, AU_OK}};
    au__run_pair(metrics_run, &job[0], &job[1]);
    r->init_measured = job[0].st == AU_OK;
    ms = job[0].st != AU_OK ? job[0].st : job[1].st;
  } else {
    ms = au_metrics_compute(r->nv, r->nf, r->X, r->P, r->F, dom, &r->metrics, NULL, NULL);
  }
  r->t_metrics = now_s() - t0;
  if (ms != AU_OK) return au_msg_set(msg, ms, "metrics of the map failed");
  const int not_converged = st == AU_W_NOT_CONVERGED;
  if (not_converged)
    warn(r, "tolerance %g not reached in %d steps (error %.3e%s)", x->flow.tol, r->conv.steps,
         r->conv.global_polish == 2 ? r->conv.global_polish_err[1]
         : r->conv.vertex_polish == 2 ? r->conv.polish_err[1]
                                      : r->conv.err[r->conv.steps],
         r->conv.global_polish == 2 ? " after the global polish"
         : r->conv.vertex_polish == 2 ? " after the vertex polish"
                                      : "");
  /* A folded map is never handed back: zero folds is the promise, not a hope. Folded here means a
   * sign a reader of the output would see: triangles the start squeezed below a double's resolution
   * that the flow had no steps left to grow. */
  if (r->metrics.folds > 0)
    return au_msg_set(msg, AU_E_FOLD, "the map has %d folded triangle%s%s", r->metrics.folds,
                      r->metrics.folds == 1 ? "" : "s",
                      x->o->init_only ? " (the start squeezes them below a double's resolution; the flow grows them back)"
                      : not_converged ? " (the flow had not converged: more steps may grow them back)"
                                      : "");
  /* The floor holds chord triangles only: a map of the spherical triangles' areas is not held by it, and
   * its tolerance was missed for another reason. The remedies are named as the program spells them;
   * Python's keywords are the same words (refine_mesh, refine_budget, spherical_areas), C's fields too
   * but for refine_max_faces. */
  if (dom == AU_DOMAIN_SPHERE && not_converged && x->flow.sphere_areas != 2 && r->metrics.chord_floor_faces > 0 &&
      r->metrics.chord_floor_excess >= AU_FLOOR_WARN_EXCESS) {
    char budget_hint[96];
    snprintf(budget_hint, sizeof budget_hint, "a face budget over the %gx auto kept lowers that error (--refine-budget K)",
             x->refine_budget);
    warn(r,
         "%d long, thin triangles of the map cannot bring their chord area down to their share without shorter "
         "long edges (a long edge's chord runs under the sphere; excess %.2g%% of the area): %s; the spherical "
         "triangles' areas are not held by it (--spherical-areas)",
         r->metrics.chord_floor_faces, 100 * r->metrics.chord_floor_excess,
         !x->o->refine_mesh ? "a finer mesh there lowers that error (--refine-mesh)"
         : x->o->refine_max_faces == AU_REFINE_AUTO ? budget_hint
                                                     : "a larger face budget lowers that error (--refine-budget K, or auto)");
  }
  int nfar = 0;
  /* Against the surface's own areas: with a density, cells are meant to be small (not measured). */
  const int density = x->flow.weight || x->flow.face_weight;
  double far = not_converged && !density ? au__metrics_squeezed(r->nv, r->nf, r->X, r->P, r->F, &nfar) : 0;
  if (far >= AU_SQUEEZED_WARN_SHARE)
    warn(r,
         "%.2g%% of the surface (%d vertices) is mapped to less than 1/e of its area share: long protrusions "
         "that the start squeezed and the flow could not open up",
         100 * far, nfar);
  return dom == AU_DOMAIN_PLANE ? planar_finish(x, msg) : AU_OK;
}

/* The circle domain: at least one loop; the outer loop the user named by a vertex, or -1 (the longest). */
static au_status circles_outer(map_run *x, au_msg *msg) {
  const au_topo *t = x->t;
  if (t->nloops == 0)
    return au_msg_set(msg, AU_E_BOUNDARY, "mesh is closed (no boundary loop): the circles map needs at least one; "
                                          "map a closed genus-0 mesh onto the sphere");
  x->outer = -1;
  if (x->o->outer_loop < 0) return AU_OK;
  for (int l = 0; l < t->nloops; l++)
    for (int k = t->loop_start[l]; k < t->loop_start[l + 1]; k++)
      if (t->loop_vert[k] == x->o->outer_loop) x->outer = l;
  if (x->outer < 0) return au_msg_set(msg, AU_E_ARG, "outer: vertex %d is on no boundary loop (outer_loop)", x->o->outer_loop);
  return AU_OK;
}

/* The square's map stretched to the rectangle [0, w] x [0, h] (au_options.aspect): every area is scaled
 * by w h alike, so the map stays equal area, and orientations are kept. */
static void stretch_rectangle(map_run *x) {
  au_result *r = x->r;
  for (int i = 0; i < r->nv; i++) {
    r->P[3 * (size_t)i] *= x->w, r->P[3 * (size_t)i + 1] *= x->h;
    r->P0[3 * (size_t)i] *= x->w, r->P0[3 * (size_t)i + 1] *= x->h;
  }
}

/* Check the mesh and prepare the mesh that is mapped. */
static au_status prepare(map_run *x, const double *V, int nv, const int *F, int nf, au_status *check, au_msg *msg) {
  au_status st = au_mesh_alloc(nv, nf, &x->m);
  if (st != AU_OK) return au_msg_set(msg, st, "out of memory for the mesh");
  memcpy(x->m->X, V, 3 * (size_t)nv * sizeof *V);
  memcpy(x->m->F, F, 3 * (size_t)nf * sizeof *F);
  au_mesh_expect ex = au__target_expect(x->target);
  double t0 = now_s();
  /* A mesh that validates has faces that already agree: the orientation walk would change nothing
   * and say nothing, and it costs a second sort of every half-edge. Otherwise the faces are made to
   * agree first and the mesh is validated again; validation still names any problem that comes
   * before the orientation (an index, a non-manifold edge), and the walk names a non-orientable
   * surface. */
  au_msg om = {{0}};
  au_status so = AU_OK;
  *check = au_mesh_validate(x->m, &ex, &x->t, msg);
  if (*check < 0) {
    so = au_mesh_orient(x->m, NULL, &om);
    *check = au_mesh_validate(x->m, &ex, &x->t, msg);
  }
  x->r->t_check = now_s() - t0;
  if (*check == AU_E_ORIENTATION && so < 0) {
    if (msg) *msg = om;
    return *check = so;
  }
  if (*check < 0) return *check;
  if (so > 0) warn(x->r, "%s", om.text);
  if (*check > 0) warn(x->r, "%s", msg && msg->text[0] ? msg->text : au_status_str(*check));
  if (so > 0 && *check == AU_OK) *check = so;
  x->mm = x->m, x->tt = x->t;
  x->r->nv_in = nv, x->r->nf_in = nf;
  if (x->target == AU_TARGET_CIRCLES) {
    if ((st = circles_outer(x, msg)) != AU_OK) return st;
  } else if (x->target == AU_TARGET_ANNULUS) {
    if ((x->outer = pick_outer(x->o, x->t, msg)) < 0) return AU_E_ARG;
    const au_topo *t = x->t;
    x->r->outer_loop_vertex = t->loop_vert[t->loop_start[x->outer]];
  } else if (x->target == AU_TARGET_SQUARE) {
    t0 = now_s();
    st = square_mesh(x->m, x->t, x->o, x->r->corners, &x->ms, &x->ts, &x->r->nsplit, msg);
    if (st != AU_OK) return st;
    x->mm = x->ms, x->tt = x->ts;
    if (x->r->nsplit)
      warn(x->r, "split %d edge%s joining vertices of one side; vertices %d..%d are their midpoints", x->r->nsplit,
           x->r->nsplit == 1 ? "" : "s", nv, x->ms->nv - 1);
    x->t_split = now_s() - t0;
  }
  return AU_OK;
}

au_status au_map(const double *V, int nv, const int *F, int nf, au_target t, const au_options *opts, au_result **out,
                 au_msg *msg) {
  if (msg) msg->text[0] = '\0';
  if (!out) return au_msg_set(msg, AU_E_ARG, "au_map: out is NULL");
  *out = NULL;
  if (!au_target_name(t)) return au_msg_set(msg, AU_E_ARG, "au_map: unknown target %d", (int)t);
  if (nv < 0 || nf < 0 || (nv > 0 && !V) || (nf > 0 && !F)) return au_msg_set(msg, AU_E_ARG, "au_map: bad mesh arrays");
  au_options dflt = au_options_default();
  const au_options *o = opts ? opts : &dflt;
  au_status st = check_options(o, nv, nf, msg);
  if (st != AU_OK) return st;

  map_run x;
  memset(&x, 0, sizeof x);
  x.target = t, x.o = o, x.pc.o = o;
  if (!(x.r = calloc(1, sizeof *x.r))) return au_msg_set(msg, AU_E_NOMEM, "out of memory");
  x.r->target = t, x.r->init_only = o->init_only != 0;
  memcpy(x.r->corners, (int[4]){-1, -1, -1, -1}, sizeof x.r->corners);
  flow_options(t, o, &x.pc, &x.flow, &x.sphere);

  au_status check = AU_OK;
  const long factorizations = au__solver_factorizations();
  st = prepare(&x, V, nv, F, nf, &check, msg);
  if (st == AU_OK) st = alloc_result(&x, msg);
  if (st == AU_OK && cancelled(&x.pc)) st = au_msg_set(msg, AU_E_CANCELLED, "cancelled");
  if (st == AU_OK)
    st = t == AU_TARGET_SPHERE ? run_sphere(&x, msg) : t == AU_TARGET_TORUS ? run_torus(&x, msg) : run_planar(&x, msg);
  x.w = o->aspect > 1 || o->aspect == 0 ? 1 : o->aspect, x.h = o->aspect > 1 ? 1 / o->aspect : 1;
  if (st >= 0 && t == AU_TARGET_SQUARE && o->aspect > 0) stretch_rectangle(&x);
  if (st >= 0) {
    x.r->t_init += x.t_split;
    x.r->factorizations = au__solver_factorizations() - factorizations;
    st = measure(&x, st, msg) == AU_OK ? st : AU_E_FOLD;
  }
  if (st >= 0 && st == AU_OK && check > 0) st = check;
  if (st >= 0) x.r->status = st, *out = x.r;
  else au_result_free(&x.r);
  au_topo_free(&x.ts);
  au_mesh_free(&x.ms);
  au_topo_free(&x.t);
  au_mesh_free(&x.m);
  return st;
}

au_status au_result_json(const au_result *r, const au_report_extra *extra, char **json, au_msg *msg) {
  if (!r || !json) return au_msg_set(msg, AU_E_ARG, "au_result_json: bad arguments");
  au_report_extra e;
  memset(&e, 0, sizeof e);
  e.t_read = e.t_validate = e.t_write = -1;
  if (extra) e = *extra;
  au_report_stage stages[8];
  int ns = 0;
  if (e.t_read >= 0) stages[ns++] = (au_report_stage){"read", e.t_read};
  stages[ns++] = (au_report_stage){"validate", e.t_validate >= 0 ? e.t_validate : r->t_check};
  stages[ns++] = (au_report_stage){"init", r->t_init};
  stages[ns++] = (au_report_stage){"flow", r->t_flow};
  stages[ns++] = (au_report_stage){"metrics", r->t_metrics};
  if (e.t_write >= 0) stages[ns++] = (au_report_stage){"write", e.t_write};
  const char *warnings[2 * AU_MAX_WARNINGS];
  int nw = 0;
  for (int i = 0; i < r->nwarnings; i++) warnings[nw++] = r->warnings[i];
  for (int i = 0; i < e.nwarnings && nw < 2 * AU_MAX_WARNINGS; i++) warnings[nw++] = e.warnings[i];
  const int flow = !r->init_only;
  au_report_info info;
  memset(&info, 0, sizeof info);
  info.tool_version = au_version(), info.command = au_target_name(r->target);
  info.input = e.input, info.output = e.output;
  info.nv = r->nv, info.nf = r->nf;
  info.steps = r->conv.steps, info.converged = flow && r->conv.converged;
  /* The start's metrics when the map skipped them (au_options.measure_start 0): measured here. */
  au_metrics start;
  const au_metrics *init = r->init_measured ? &r->init_metrics : NULL;
  if (flow && !init && r->target != AU_TARGET_TORUS && r->P0 &&
      au_metrics_compute(r->nv, r->nf, r->X, r->P0, r->F, r->target == AU_TARGET_SPHERE ? AU_DOMAIN_SPHERE : AU_DOMAIN_PLANE,
                         &start, NULL, NULL) == AU_OK)
    init = &start;
  info.init = flow ? init : NULL, info.final = &r->metrics;
  info.stages = stages, info.nstages = ns;
  info.step_err = flow ? r->conv.err : NULL, info.step_frac = flow ? r->conv.frac : NULL;
  info.step_face_err = flow ? r->conv.face_err : NULL;
  info.warnings = warnings, info.nwarnings = nw;
  info.polish_from = flow ? r->conv.polish_from : 0, info.undone = flow ? r->conv.undone : 0;
  info.has_schedule = flow, info.start_jump = r->conv.start_jump, info.resolved = r->conv.resolved;
  info.retry = r->conv.lantern_retry, info.retry_err[0] = r->conv.retry_err[0], info.retry_err[1] = r->conv.retry_err[1];
  info.twist = r->conv.twist_retry, info.twist_faces = r->conv.twist_faces, info.twist_err = r->conv.twist_err;
  info.polish = r->conv.vertex_polish, info.polish_sweeps = r->conv.polish_sweeps, info.polish_err = r->conv.polish_err;
  info.staged = r->conv.staged_retry, info.staged_stages = r->conv.staged_stages, info.staged_err = r->conv.staged_err;
  info.global_polish = r->conv.global_polish, info.global_polish_steps = r->conv.global_polish_steps;
  info.global_polish_err = r->conv.global_polish_err, info.global_polish_robust = r->conv.global_polish_robust;
  info.angle_from = flow ? r->conv.angle_from : 0;
  if (r->target == AU_TARGET_TORUS)
    info.lattice = (const double(*)[2])r->lattice, info.conformal_lattice = (const double(*)[2])r->conformal_lattice;
  info.factorizations = r->factorizations;
  info.start = r->target == AU_TARGET_TORUS || r->target == AU_TARGET_SPHERE ? r->init_method : NULL;
  info.ncircles = r->ncircles, info.circles = r->circles, info.circle_vertex = r->circle_vertex;
  info.circle_outer = r->circle_outer;
  return au_report_json(&info, json, msg);
}
