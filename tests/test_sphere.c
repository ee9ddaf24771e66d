/* test_sphere.c - the sphere map: conformal start, balancing, and map quality on data/ meshes. */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

#include "au_dec.h"
#include "au_io.h"
#include "au_metrics.h"
#include "au_solver.h"
#include "au_sphere.h"
#include "au_test.h"

typedef struct loaded {
  au_mesh *m;
  au_topo *t;
  double *P;
} loaded;

static int load(const char *name, double scale, loaded *L) {
  char path[1024];
  snprintf(path, sizeof path, "%s/data/%s", AU_SOURCE_DIR, name);
  au_msg msg = {{0}};
  memset(L, 0, sizeof *L);
  AU_CHECK_STATUS(au_io_read(path, &L->m, &msg), AU_OK, &msg);
  for (int i = 0; i < 3 * L->m->nv; i++) L->m->X[i] *= scale;
  AU_CHECK_STATUS(au_mesh_validate(L->m, NULL, &L->t, &msg), AU_OK, &msg);
  L->P = malloc(sizeof(double) * 3 * L->m->nv);
  AU_CHECK(L->P != NULL);
  return 0;
}

static void unload(loaded *L) {
  au_topo_free(&L->t);
  au_mesh_free(&L->m);
  free(L->P);
}

static double radius_dev(const loaded *L) {
  double worst = 0;
  for (int i = 0; i < L->m->nv; i++) {
    const double *p = L->P + 3 * i;
    worst = fmax(worst, fabs(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 1));
  }
  return worst;
}

/* The conformal start is fold-free, on the sphere, and nearly conformal on a smooth mesh. */
static int conformal_ellipsoid(void) {
  loaded L;
  if (load("ellipsoid.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_sphere_conformal(L.m, L.t, L.P, &msg), AU_OK, &msg);
  au_metrics q;
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  AU_CHECK_INT(q.folds, ==, 0);
  AU_CHECK_DBL(radius_dev(&L), <=, 1e-12);
  /* Measured 0.178 on this 2k-face mesh; mostly the puncture's neighbourhood. */
  AU_CHECK_DBL(q.lambda_mean, <=, 0.2);
  unload(&L);
  return 0;
}

/* Balancing moves the area-weighted centroid of the image to the origin and keeps the map fold-free. */
static int balance_centroid(void) {
  loaded L;
  if (load("bumpy_star.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_sphere_conformal(L.m, L.t, L.P, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_sphere_balance(L.m, L.t, L.P, &msg), AU_OK, &msg);
  double *A = malloc(sizeof(double) * L.m->nv), c[3] = {0, 0, 0}, tot = 0;
  au_dec_vertex_areas(L.m->nv, L.m->nf, L.m->F, L.m->X, NULL, A);
  for (int i = 0; i < L.m->nv; i++) {
    tot += A[i];
    for (int d = 0; d < 3; d++) c[d] += A[i] * L.P[3 * i + d];
  }
  AU_CHECK_DBL(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / tot, <=, 1e-6);
  au_metrics q;
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  AU_CHECK_INT(q.folds, ==, 0);
  free(A);
  unload(&L);
  return 0;
}

/* The whole map on a data/ mesh: zero folds, |p| = 1, area error bounds (measured values in comments). */
static int map_quality(const char *name, double max_vertex, double max_rmad) {
  loaded L;
  if (load(name, 1, &L)) return 1;
  au_msg msg = {{0}};
  au_sphere_report rep;
  au_status st = au_sphere_map(L.m, L.t, NULL, L.P, NULL, &rep, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  au_metrics q;
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  AU_CHECK_INT(q.folds, ==, 0);
  AU_CHECK_DBL(radius_dev(&L), <=, 1e-12);
  AU_CHECK_DBL(q.vertex_logr_mean_abs, <=, max_vertex);
  AU_CHECK_DBL(q.r_mean_abs_dev, <=, max_rmad);
  /* The flow improved on its start by a wide margin. */
  AU_CHECK_DBL(rep.flow.err[rep.flow.steps], <=, 0.05 * rep.flow.err[0]);
  unload(&L);
  return 0;
}

/* ellipsoid: measured vertex 0.00075, per-face 0.0100 (with shape restoring; without it
 * 0.0022 / 0.0240: the per-face residual was a mode the least-shear step removed only slowly). */
static int map_ellipsoid(void) { return map_quality("ellipsoid.obj", 0.003, 0.03); }
/* spiky_ico: measured vertex 0.037, per-face 0.077 (chord-only flow: 0.056 / 0.106): its spikes'
 * long triangles cannot have their spherical and chord areas right at once (the paper's Poisson
 * step reached vertex 0.00075 but left per-face 0.238). */
static int map_spiky(void) { return map_quality("spiky_ico.obj", 0.07, 0.15); }
/* The Dirichlet energy of a map P of the mesh: sum over edges of the surface's cotan weight times the
 * squared length of the edge's image. */
static double dirichlet(const loaded *L) {
  double *w = malloc(sizeof(double) * (size_t)L->t->ne), e = 0;
  if (!w) return NAN;
  au_dec_cotan(L->t, L->m->F, L->m->X, w);
  for (int k = 0; k < L->t->ne; k++) {
    const double *p = L->P + 3 * L->t->E[2 * k], *q = L->P + 3 * L->t->E[2 * k + 1];
    e += w[k] * ((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
  }
  free(w);
  return e;
}

/* The angle steps (au_advect_opts.angle_steps, --angles): from a vertex error of 0.01 on
 * (angle_switch), towards the map of least Dirichlet energy with the vertex cells held at their areas.
 * On bumpy_star (measured, 5 steps): vertex error 0.00193 -> 0.000046, mean angle difference
 * 41.759 -> 41.572 degrees, per-face 0.0138 -> 0.0195, 16 steps instead of 19. Taken after the flow,
 * from its map, the energy falls; the cells come within 3e-4, the faces stay within 0.025, and no
 * triangle folds. (On ellipsoid the angle
 * rose, 27.64 -> 28.19 degrees, with the energy lower: the energy is not the angle measure.) */
static int angle_steps(void) {
  loaded L;
  if (load("bumpy_star.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  au_metrics q[3];
  au_sphere_report rep[3];
  double energy[3];
  /* 0: no angle steps; 1: five after the flow (angle_switch 0), so from the map of run 0; 2: five
   * from the default hand-over. */
  for (int r = 0; r < 3; r++) {
    au_sphere_opts o = au_sphere_opts_default();
    o.flow.angle_steps = r ? 5 : 0;
    if (r == 1) o.flow.angle_switch = 0;
    au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rep[r], &msg);
    AU_CHECK_STATUS(st, AU_OK, &msg);
    AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q[r], NULL, NULL), AU_OK,
                    (au_msg *)NULL);
    AU_CHECK_INT(q[r].folds, ==, 0);
    AU_CHECK_DBL(radius_dev(&L), <=, 1e-12);
    energy[r] = dirichlet(&L);
    fprintf(stderr, "bumpy_star, run %d (from step %d): energy %.6f, vertex %.6f, per-face %.4f, angle %.3f\n", r,
            rep[r].flow.angle_from, energy[r], q[r].vertex_logr_mean_abs, q[r].r_mean_abs_dev, q[r].angle_diff_mean_deg);
  }
  AU_CHECK_INT(rep[0].flow.angle_from, ==, 0);
  /* After the flow: from its map, the energy falls. */
  AU_CHECK_INT(rep[1].flow.angle_from, ==, rep[0].flow.steps);
  AU_CHECK_INT(rep[1].flow.steps, ==, rep[1].flow.angle_from + 5);
  AU_CHECK_DBL(energy[1], <, energy[0]);
  /* Handed over earlier: fewer steps in all, and the angles better than the flow's own. */
  AU_CHECK(rep[2].flow.angle_from > 0 && rep[2].flow.angle_from < rep[0].flow.steps);
  AU_CHECK_INT(rep[2].flow.steps, ==, rep[2].flow.angle_from + 5);
  AU_CHECK_DBL(q[2].angle_diff_mean_deg, <, q[0].angle_diff_mean_deg);
  for (int r = 1; r < 3; r++) {
    AU_CHECK_DBL(q[r].vertex_logr_mean_abs, <=, 3e-4);
    AU_CHECK_DBL(q[r].r_mean_abs_dev, <=, 0.025);
  }
  unload(&L);
  return 0;
}

/* The lantern retry (au_sphere_opts.lantern_retry): a map that misses its tolerance by more than
 * retry_above runs again with the lantern-aware shape restoring, and the map with the smaller vertex
 * error is the one returned, whichever it is. On spiky_ico's needles (43 faces at their chord floor)
 * the retry is a different map; measured (default 2): vertex 0.0289 first, 0.0356 retry,
 * the first kept. */
static int lantern_retry(void) {
  loaded L;
  if (load("spiky_ico.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  const double coef[] = {0, 2, 8};
  int kept = 0, discarded = 0;
  for (int r = 0; r < 3; r++) {
    au_sphere_opts o = au_sphere_opts_default();
    o.lantern_retry = coef[r];
    o.vertex_polish = 0; /* the retry's own map is what is checked (test vertex_polish for the polish) */
    au_sphere_report rep;
    au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rep, &msg);
    AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
    au_metrics q;
    AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                    (au_msg *)NULL);
    AU_CHECK_INT(q.folds, ==, 0);
    fprintf(stderr, "spiky_ico, lantern_retry %g: retry %d, vertex %.5f first, %.5f retry; returned %.5f\n", coef[r],
            rep.retry, rep.retry_err[0], rep.retry_err[1], q.vertex_logr_mean_abs);
    if (r == 0) {
      AU_CHECK_INT(rep.retry, ==, 0);
      continue;
    }
    AU_CHECK(rep.retry == 1 || rep.retry == 2);
    /* The retry is another map (the lantern factor acts), and the better of the two is returned, by
     * the same measure as au_metrics (param-eval's). */
    AU_CHECK_DBL(fabs(rep.retry_err[0] - rep.retry_err[1]), >, 1e-4);
    AU_CHECK_NEAR(q.vertex_logr_mean_abs, fmin(rep.retry_err[0], rep.retry_err[1]), 1e-9);
    AU_CHECK_INT(rep.retry, ==, rep.retry_err[1] < rep.retry_err[0] ? 2 : 1);
    kept += rep.retry == 2, discarded += rep.retry == 1;
  }
  /* Both outcomes occur here (measured: discarded with 2, kept with 8), so both paths are exercised. */
  AU_CHECK_INT(kept, >=, 1);
  AU_CHECK_INT(discarded, >=, 1);
  unload(&L);
  return 0;
}

/* The lantern retry is not run where its flow would repeat the first one step for step: the lantern acts
 * only at spherical steps whose vertex error is below 1 (AU_LANTERN_BELOW in common/au_advect.c; the flow's
 * report counts them: lantern_steps). spiky_ico
 * with a budget of 3 steps takes 2 spherical steps, both above it (measured: 1.343, 1.115), then one of
 * the chord polish; a lantern flow then gives the same map to the last bit (the premise of the skip: if
 * the flow let the lantern act above 1 this fails), the map misses 2 tol, and the report says the retry
 * was due and skipped. With 10 steps the error comes below 1 at step 2 and the retry runs. */
static int lantern_skipped(void) {
  loaded L;
  if (load("spiky_ico.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  double *Q = malloc(sizeof(double) * 3 * (size_t)L.m->nv);
  AU_CHECK(Q != NULL);
  const int budget[] = {3, 10};
  for (int b = 0; b < 2; b++) {
    au_sphere_opts o = au_sphere_opts_default();
    o.flow.max_steps = budget[b];
    o.vertex_polish = 0, o.staged_retry = 0, o.twist_retry = 0;
    au_sphere_report rep;
    au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rep, &msg);
    AU_CHECK_INT(st, ==, AU_W_NOT_CONVERGED);
    fprintf(stderr, "spiky_ico, %d steps: polish from %d, vertex error", budget[b], rep.flow.polish_from);
    for (int k = 0; k <= rep.flow.steps; k++) fprintf(stderr, " %.3f", rep.flow.err[k]);
    fprintf(stderr, "; lantern retry %d, skipped %d\n", rep.retry, rep.lantern_skipped);
    if (b == 0) {
      AU_CHECK_INT(rep.flow.polish_from, >, 0);
      for (int k = 0; k < rep.flow.polish_from; k++) AU_CHECK_DBL(rep.flow.err[k], >=, 1);
      AU_CHECK_INT(rep.lantern_skipped, ==, 1);
      AU_CHECK_INT(rep.flow.lantern_steps, ==, 0);
      AU_CHECK_INT(rep.retry, ==, 0);
      /* The lantern flow itself, from the same start: the same map. */
      au_sphere_opts o2 = o;
      o2.lantern_retry = 0, o2.flow.lantern = 2;
      AU_CHECK_STATUS(au_sphere_map(L.m, L.t, &o2, Q, NULL, NULL, &msg), AU_W_NOT_CONVERGED, &msg);
      AU_CHECK_INT(memcmp(Q, L.P, sizeof(double) * 3 * (size_t)L.m->nv), ==, 0);
    } else {
      AU_CHECK_INT(rep.lantern_skipped, ==, 0);
      AU_CHECK_INT(rep.flow.lantern_steps, >, 0);
      AU_CHECK(rep.retry == 1 || rep.retry == 2);
    }
  }
  free(Q);
  unload(&L);
  return 0;
}

/* The lantern retry resumes from the first flow's state at the round where the lantern first acts
 * (au_advect_fork): its map is the lantern flow's from the start, bit for bit, for fewer factorizations.
 * On spiky_ico, without the polishes and the other retries: the first flow alone, the lantern flow alone
 * from the same start, and the map with the retry, whose lantern map is kept (measured: 44 factorizations
 * each, 2 of them the start's, and 84 with the retry where repeating the shared steps took 86). Fails
 * if the retry repeats them (the count) or parts from the lantern flow (the bits). */
static int lantern_resumed(void) {
  loaded L;
  if (load("spiky_ico.obj", 1, &L)) return 1;
  const size_t bytes = sizeof(double) * 3 * (size_t)L.m->nv;
  double *Q = malloc(bytes);
  AU_CHECK(Q != NULL);
  au_msg msg = {{0}};
  au_sphere_opts o = au_sphere_opts_default();
  /* The flows' chord polish cut as where the vertex polish follows (chord_polish_cut): so the lantern's
   * map is the better one, and kept. */
  o.vertex_polish = 0, o.flow.polish_steps = 2, o.staged_retry = 0, o.twist_retry = 0;
  au_sphere_opts o1 = o, o2 = o;
  o1.lantern_retry = 0;
  o2.lantern_retry = 0, o2.flow.lantern = o.lantern_retry;
  long f = au__solver_factorizations();
  AU_CHECK_STATUS(au_sphere_map(L.m, L.t, &o1, Q, NULL, NULL, &msg), AU_W_NOT_CONVERGED, &msg);
  const long first = au__solver_factorizations() - f;
  f = au__solver_factorizations();
  AU_CHECK_STATUS(au_sphere_map(L.m, L.t, &o2, Q, NULL, NULL, &msg), AU_W_NOT_CONVERGED, &msg);
  const long lantern = au__solver_factorizations() - f;
  /* Each of the three commands makes the start once. */
  f = au__solver_factorizations();
  AU_CHECK_STATUS(au_sphere_conformal(L.m, L.t, L.P, &msg), AU_OK, &msg);
  const long start = au__solver_factorizations() - f;
  au_sphere_report rep;
  f = au__solver_factorizations();
  const au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rep, &msg);
  const long both = au__solver_factorizations() - f;
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  fprintf(stderr, "spiky_ico: start %ld factorizations, first map %ld, lantern map %ld, the map with the retry %ld (retry %d, "
          "lantern steps %d)\n", start, first, lantern, both, rep.retry, rep.flow.lantern_steps);
  AU_CHECK_INT(rep.retry, ==, 2);
  AU_CHECK_INT(memcmp(Q, L.P, bytes), ==, 0);
  AU_CHECK(both < first + lantern - start);
  free(Q);
  unload(&L);
  return 0;
}

/* The same on hand_closed (../shared only; the plain build): 7993 vertices, so the flows run on the plan's
 * reordered copy; the lantern acts on 23 of the lantern flow's 33 steps (measured). The map with the
 * retry (its lantern map kept) and its flow's report are the lantern flow's from the start: every
 * recorded error and step fraction, the step counts and the flags. */
static int lantern_resumed_hand_closed(void) {
  char path[1024];
  if (!au_test_shared_mesh("hand_closed.obj", path, sizeof path)) {
    fprintf(stderr, "skipped: %s is absent\n", path);
    return AU_SKIP;
  }
  au_msg msg = {{0}};
  loaded L;
  memset(&L, 0, sizeof L);
  AU_CHECK_STATUS(au_io_read(path, &L.m, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_mesh_validate(L.m, NULL, &L.t, &msg), AU_OK, &msg);
  const size_t bytes = sizeof(double) * 3 * (size_t)L.m->nv;
  L.P = malloc(bytes);
  double *Q = malloc(bytes);
  AU_CHECK(L.P != NULL && Q != NULL);
  au_sphere_opts o = au_sphere_opts_default();
  o.vertex_polish = 0, o.flow.polish_steps = 2, o.staged_retry = 0, o.twist_retry = 0;
  au_sphere_opts o2 = o;
  o2.lantern_retry = 0, o2.flow.lantern = o.lantern_retry;
  au_sphere_report a, b;
  AU_CHECK_STATUS(au_sphere_map(L.m, L.t, &o2, Q, NULL, &a, &msg), AU_W_NOT_CONVERGED, &msg);
  const au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &b, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  const au_advect_report *r = &a.flow, *s = &b.flow;
  fprintf(stderr, "hand_closed: lantern flow %d steps (%d undone, lantern from its step %d of them); the retry %d\n", r->steps,
          r->undone, r->steps - r->lantern_steps, b.retry);
  AU_CHECK_INT(L.m->nv, >=, 4096);
  AU_CHECK_INT(b.retry, ==, 2);
  AU_CHECK_INT(memcmp(Q, L.P, bytes), ==, 0);
  AU_CHECK_INT(s->steps, ==, r->steps);
  AU_CHECK_INT(s->undone, ==, r->undone);
  AU_CHECK_INT(s->converged, ==, r->converged);
  AU_CHECK_INT(s->polish_from, ==, r->polish_from);
  AU_CHECK_INT(s->lantern_steps, ==, r->lantern_steps);
  AU_CHECK_INT(s->resolved, ==, r->resolved);
  AU_CHECK_INT(s->face_steps, ==, r->face_steps);
  AU_CHECK_INT(s->angle_from, ==, r->angle_from);
  AU_CHECK(s->start_jump == r->start_jump && s->start_shear == r->start_shear);
  AU_CHECK_INT(memcmp(s->err, r->err, sizeof(double) * (size_t)(r->steps + 1)), ==, 0);
  AU_CHECK_INT(memcmp(s->face_err, r->face_err, sizeof(double) * (size_t)(r->steps + 1)), ==, 0);
  AU_CHECK_INT(memcmp(s->frac, r->frac, sizeof(double) * (size_t)r->steps), ==, 0);
  free(Q);
  unload(&L);
  return 0;
}

/* The staged retry comes before the lantern retry where the first map is squeezed enough for it (at
 * least 1% of the surface in cells under 1/e of their share), and the lantern runs only if the staged map
 * is not kept: the staged flows start from the start, so a lantern map they replace was made for
 * nothing. octopus (strong twisted start; the lantern would act: its spherical error comes below 1 at
 * step 32): measured, the staged map kept (vertex error 0.677 -> 0.298 in 7 stages), no lantern flow; the
 * same map as with the lantern first (docs/sphere-retries.md). Without the polishes, which come after. */
static int staged_before_lantern(void) {
  loaded L;
  if (load("octopus.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  au_sphere_opts o = au_sphere_opts_default();
  o.vertex_polish = 0;
  au_sphere_report rep;
  au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rep, &msg);
  AU_CHECK_INT(st, ==, AU_W_NOT_CONVERGED);
  au_metrics q;
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  fprintf(stderr, "octopus: staged %d (%d stages, %.4f -> %.4f), lantern retry %d, skipped %d; vertex %.4f, folds %d\n",
          rep.staged, rep.staged_stages, rep.staged_err[0], rep.staged_err[1], rep.retry, rep.lantern_skipped,
          q.vertex_logr_mean_abs, q.folds);
  AU_CHECK_INT(rep.twist, ==, 3);
  AU_CHECK_INT(rep.lantern_skipped, ==, 0); /* the lantern would act: not the skip of lantern_skipped */
  AU_CHECK_INT(rep.staged, ==, 2);
  AU_CHECK_INT(rep.retry, ==, 0);
  AU_CHECK_DBL(rep.staged_err[1], <, rep.staged_err[0]);
  AU_CHECK_NEAR(q.vertex_logr_mean_abs, rep.staged_err[1], 1e-9);
  AU_CHECK_INT(q.folds, ==, 0);
  unload(&L);
  return 0;
}

/* au_advect_opts.restore (0.1, the default, against 0): aiming the shear back at the surface's
 * triangle shapes lowers the angle distortion and, on spiky_ico's needles, the area error too.
 * Measured: mean angle difference 49.1 -> 47.9 degrees, per-face 0.086 -> 0.077. */
static int restore_shapes(void) {
  loaded L;
  if (load("spiky_ico.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  au_metrics q[2];
  for (int r = 0; r < 2; r++) {
    au_sphere_opts o = au_sphere_opts_default();
    o.flow.restore = r ? 0.1 : 0;
    o.global_polish = 0; /* the flow's angles (the global polish weighs areas only) */
    au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, NULL, &msg);
    AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
    AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q[r], NULL, NULL),
                    AU_OK, (au_msg *)NULL);
    AU_CHECK_INT(q[r].folds, ==, 0);
  }
  fprintf(stderr, "restore 0 / 0.1: angle %.2f / %.2f deg, per-face %.4f / %.4f\n", q[0].angle_diff_mean_deg,
          q[1].angle_diff_mean_deg, q[0].r_mean_abs_dev, q[1].r_mean_abs_dev);
  AU_CHECK_DBL(q[1].angle_diff_mean_deg, <, q[0].angle_diff_mean_deg - 0.5);
  AU_CHECK_DBL(q[1].r_mean_abs_dev, <, q[0].r_mean_abs_dev);
  au_sphere_opts o = au_sphere_opts_default();
  o.flow.restore = 1.5;
  AU_CHECK_STATUS(au_sphere_map(L.m, L.t, &o, L.P, NULL, NULL, &msg), AU_E_ARG, &msg);
  unload(&L);
  return 0;
}

/* The start's resolution decides the schedule (au_advect_opts.resolved_jump, default 0.1). ellipsoid's
 * 2k faces resolve its start only coarsely (jump of log r across edges 0.177): the ordinary schedule.
 * Declared resolved, it runs the resolved one and still meets the quality bounds of map_ellipsoid. */
static int resolved_schedule(void) {
  loaded L;
  if (load("ellipsoid.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  au_sphere_report rep[2];
  for (int r = 0; r < 2; r++) {
    au_sphere_opts o = au_sphere_opts_default();
    if (r) o.flow.resolved_jump = 0.5;
    au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rep[r], &msg);
    AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
    AU_CHECK_INT(rep[r].flow.resolved, ==, r);
    AU_CHECK_NEAR(rep[r].flow.start_jump, 0.177, 0.01);
    au_metrics q;
    AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                    (au_msg *)NULL);
    AU_CHECK_INT(q.folds, ==, 0);
    AU_CHECK_DBL(q.vertex_logr_mean_abs, <=, 0.003);
    AU_CHECK_DBL(q.r_mean_abs_dev, <=, 0.03);
    fprintf(stderr, "ellipsoid, %s schedule: %d steps, vertex %.5f, per-face %.4f\n", r ? "resolved" : "ordinary",
            rep[r].flow.steps, q.vertex_logr_mean_abs, q.r_mean_abs_dev);
  }
  /* The sphere's shorter resolved schedule (au_advect_opts.sphere_resolved_*): 13 steps, where the
   * resolved schedule with the fields it replaces (schedule_steps, resolved_log_step, shear_tail) takes 14
   * (measured; docs/flow-tail.md). */
  AU_CHECK_INT(rep[1].flow.steps, <=, 13);
  {
    au_sphere_opts o = au_sphere_opts_default();
    o.flow.resolved_jump = 0.5;
    o.flow.sphere_resolved_schedule_steps = o.flow.schedule_steps;
    o.flow.sphere_resolved_log_step = o.flow.resolved_log_step;
    o.flow.sphere_resolved_shear_tail = o.flow.shear_tail;
    au_sphere_report rg;
    au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rg, &msg);
    AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
    fprintf(stderr, "ellipsoid, resolved schedule without the sphere's fields: %d steps\n", rg.flow.steps);
    AU_CHECK_INT(rg.flow.resolved, ==, 1);
    AU_CHECK_INT(rep[1].flow.steps, <, rg.flow.steps);
  }
  /* With a prescribed density the ordinary schedule runs, however resolved the start. */
  double *w = malloc(sizeof(double) * L.m->nv);
  AU_CHECK(w != NULL);
  for (int i = 0; i < L.m->nv; i++) w[i] = L.m->X[3 * i + 2] > 0 ? 2 : 1;
  au_sphere_opts o = au_sphere_opts_default();
  o.flow.resolved_jump = 0.5, o.flow.weight = w;
  au_sphere_report rd;
  au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rd, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  AU_CHECK_INT(rd.flow.resolved, ==, 0);
  free(w);
  unload(&L);
  return 0;
}

/* bumpy_star: measured vertex 0.0019, per-face 0.0138 with the default tolerance 2e-3
 * (0.0011 / 0.0055 with 1e-3). */
static int map_bumpy(void) { return map_quality("bumpy_star.obj", 0.004, 0.025); }
/* dumbbell: measured vertex 0.0018, per-face 0.0175. A step undone for making the areas worse is
 * retried without the shape restoring; retried with it, ever stiffer, the flow stuck at 0.21. */
static int map_dumbbell(void) { return map_quality("dumbbell.obj", 0.004, 0.035); }

/* Large meshes are advected in a cache-friendly order of their own (au_advect_run): the map must not
 * depend on the input's numbering. bumpy_star split 1-to-4 (10242 vertices, above the threshold) is
 * advected from the same start once as it is and once with its vertices and faces renumbered. */
/* The mesh with every triangle split in four at its edges' midpoints (vertices: m's, then one per edge). */
static au_status subdivide(const au_mesh *m, const au_topo *t, au_mesh **out) {
  const int nv = m->nv + t->ne, nf = 4 * m->nf;
  au_mesh *a = NULL;
  au_status st = au_mesh_alloc(nv, nf, &a);
  if (st != AU_OK) return st;
  memcpy(a->X, m->X, sizeof(double) * 3 * m->nv);
  for (int e = 0; e < t->ne; e++)
    for (int d = 0; d < 3; d++) a->X[3 * (m->nv + e) + d] = 0.5 * (m->X[3 * t->E[2 * e] + d] + m->X[3 * t->E[2 * e + 1] + d]);
  for (int f = 0; f < m->nf; f++) {
    const int *v = m->F + 3 * f;
    int mid[3]; /* the midpoint opposite corner k */
    for (int k = 0; k < 3; k++) mid[k] = m->nv + t->FE[3 * f + k];
    int q[4][3] = {{v[0], mid[2], mid[1]}, {v[1], mid[0], mid[2]}, {v[2], mid[1], mid[0]}, {mid[0], mid[1], mid[2]}};
    memcpy(a->F + 12 * f, q, sizeof q);
  }
  *out = a;
  return AU_OK;
}

static volatile sig_atomic_t terms;
static void count_term(int sig) {
  (void)sig;
  terms++;
}

/* A plan prepared in a thread beside other work gives the map au_advect_run gives, bit for bit, and
 * the calling thread's SIGTERM waits for the plan: one that comes meanwhile reaches the program's own
 * handler afterwards (the ordering in the thread traps SIGTERM; delivered here, its handler would jump
 * into the other thread). */
static int plan_in_thread(void) {
  loaded L;
  if (load("bumpy_star.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  au_mesh *a = NULL;
  au_topo *ta = NULL;
  AU_CHECK_STATUS(subdivide(L.m, L.t, &a), AU_OK, &msg);
  AU_CHECK_STATUS(au_mesh_validate(a, NULL, &ta, &msg), AU_OK, &msg);
  const int nv = a->nv;
  AU_CHECK_INT(nv, >=, 4096); /* large enough for the thread and the reordered copy */
  double *P1 = malloc(sizeof(double) * 3 * nv), *P2 = malloc(sizeof(double) * 3 * nv);
  AU_CHECK(P1 && P2);
  struct sigaction sa, old;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = count_term;
  sigemptyset(&sa.sa_mask);
  AU_CHECK(sigaction(SIGTERM, &sa, &old) == 0);
  terms = 0;
  au_advect_opts o = au_advect_opts_default();
  o.max_steps = 8;
  au_advect_plan *plan = NULL;
  AU_CHECK_STATUS(au_advect_plan_start(a, ta, &o, &plan, &msg), AU_OK, &msg);
  raise(SIGTERM); /* held back while the plan is prepared */
  AU_CHECK_INT((int)terms, ==, 0);
  AU_CHECK_STATUS(au_sphere_conformal(a, ta, P1, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_sphere_balance(a, ta, P1, &msg), AU_OK, &msg);
  memcpy(P2, P1, sizeof(double) * 3 * nv);
  AU_CHECK_STATUS(au_advect_plan_wait(plan, &msg), AU_OK, &msg);
  AU_CHECK_INT((int)terms, ==, 1); /* delivered when the plan was done */
  raise(SIGTERM);
  AU_CHECK_INT((int)terms, ==, 2); /* and the handler is still the program's */
  au_advect_domain dom = au_sphere_domain();
  au_advect_report r1, r2;
  au_status s1 = au_advect_run_plan(plan, &dom, &o, P1, &r1, &msg);
  au_status s2 = au_advect_run(a, ta, &dom, &o, P2, &r2, &msg);
  AU_CHECK(s1 == AU_OK || s1 == AU_W_NOT_CONVERGED);
  AU_CHECK_INT(s2, ==, s1);
  AU_CHECK_INT(r1.steps, >, 0);
  AU_CHECK_INT(r2.steps, ==, r1.steps);
  AU_CHECK(memcmp(P1, P2, sizeof(double) * 3 * nv) == 0);
  AU_CHECK(sigaction(SIGTERM, &old, NULL) == 0);
  au_advect_plan_free(&plan);
  free(P1), free(P2);
  au_topo_free(&ta);
  au_mesh_free(&a);
  unload(&L);
  return 0;
}

static int order_independent(void) {
  loaded L;
  if (load("bumpy_star.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  const au_mesh *m = L.m;
  const au_topo *t = L.t;
  au_mesh *a = NULL, *b = NULL;
  const int nv = m->nv + t->ne, nf = 4 * m->nf;
  AU_CHECK_STATUS(subdivide(m, t, &a), AU_OK, &msg);
  AU_CHECK_STATUS(au_mesh_alloc(nv, nf, &b), AU_OK, &msg);
  /* b: vertex i of a is vertex (7919 i) mod nv of b, and the faces come in reverse order. */
  int *to = malloc(sizeof(int) * nv);
  for (int i = 0; i < nv; i++) to[i] = (int)((7919LL * i) % nv);
  for (int i = 0; i < nv; i++) memcpy(b->X + 3 * to[i], a->X + 3 * i, 3 * sizeof(double));
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) b->F[3 * (nf - 1 - f) + k] = to[a->F[3 * f + k]];
  au_topo *ta = NULL, *tb = NULL;
  AU_CHECK_STATUS(au_mesh_validate(a, NULL, &ta, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_mesh_validate(b, NULL, &tb, &msg), AU_OK, &msg);
  double *Pa = malloc(sizeof(double) * 3 * nv), *Pb = malloc(sizeof(double) * 3 * nv);
  AU_CHECK_STATUS(au_sphere_conformal(a, ta, Pa, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_sphere_balance(a, ta, Pa, &msg), AU_OK, &msg);
  for (int i = 0; i < nv; i++) memcpy(Pb + 3 * to[i], Pa + 3 * i, 3 * sizeof(double));
  au_advect_domain dom = au_sphere_domain();
  au_advect_report ra, rb;
  au_status sa = au_advect_run(a, ta, &dom, NULL, Pa, &ra, &msg), sb = au_advect_run(b, tb, &dom, NULL, Pb, &rb, &msg);
  AU_CHECK(sa == AU_OK || sa == AU_W_NOT_CONVERGED);
  AU_CHECK_INT(sb, ==, sa);
  AU_CHECK_INT(rb.steps, ==, ra.steps);
  double worst = 0;
  for (int i = 0; i < nv; i++)
    for (int d = 0; d < 3; d++) worst = fmax(worst, fabs(Pa[3 * i + d] - Pb[3 * to[i] + d]));
  fprintf(stderr, "%d vertices, %d steps, largest difference %.3g\n", nv, ra.steps, worst);
  AU_CHECK_DBL(worst, <=, 1e-7); /* measured 5e-10: only the order of sums differs */
  au_metrics q;
  AU_CHECK_STATUS(au_metrics_compute(nv, nf, a->X, Pa, a->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK, (au_msg *)NULL);
  AU_CHECK_INT(q.folds, ==, 0);
  free(to), free(Pa), free(Pb);
  au_topo_free(&ta), au_topo_free(&tb);
  au_mesh_free(&a), au_mesh_free(&b);
  unload(&L);
  return 0;
}

/* A step undone for making the areas worse leaves no trace in the report: the flow goes back to the
 * step it came from and solves it again, stiffer; rep.flow.undone counts these. Counted as steps,
 * each left a copy of the last errors behind, which the stall test read as no progress. spiky_ico:
 * measured 15 undone, none copied. */
static int undone_steps_leave_no_trace(void) {
  loaded L;
  if (load("spiky_ico.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  au_sphere_report rep;
  au_status st = au_sphere_map(L.m, L.t, NULL, L.P, NULL, &rep, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  fprintf(stderr, "%d steps, %d undone\n", rep.flow.steps, rep.flow.undone);
  AU_CHECK_INT(rep.flow.undone, >, 0);
  for (int k = 1; k <= rep.flow.steps; k++) AU_CHECK(rep.flow.err[k] != rep.flow.err[k - 1]);
  unload(&L);
  return 0;
}

/* The chord-area polish runs only where the chord triangles' areas fall behind the spherical ones':
 * not on the smooth ellipsoid (measured: no polish, 17 steps), but on spiky_ico's needles. */
static int polish_when_needed(void) {
  const char *names[2] = {"ellipsoid.obj", "spiky_ico.obj"};
  for (int i = 0; i < 2; i++) {
    loaded L;
    if (load(names[i], 1, &L)) return 1;
    au_msg msg = {{0}};
    au_sphere_report rep;
    au_status st = au_sphere_map(L.m, L.t, NULL, L.P, NULL, &rep, &msg);
    AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
    fprintf(stderr, "%s: %d steps, polish from %d\n", names[i], rep.flow.steps, rep.flow.polish_from);
    if (i == 0) AU_CHECK_INT(rep.flow.polish_from, ==, 0);
    else AU_CHECK_INT(rep.flow.polish_from, >, 0);
    unload(&L);
  }
  return 0;
}

/* Where the vertex polish follows (au_sphere_map with vertex_polish > 0), the flow's chord polish ends
 * after AU_SPHERE_POLISH_STEPS (2) steps while its vertex error is between 1.5 tol and 0.1
 * (au_advect_opts.polish_steps). On spiky_ico, without the retries and the global polish: uncut
 * (polish_steps beyond the budget) the chord polish runs 9 steps, 0.0592 -> 0.0289, and the vertex
 * polish takes that map to vertex 0.0124, per-face 0.0473; cut, 2 steps to 0.0356, and the vertex
 * polish to 0.0115, 0.0469, with 44 factorizations instead of 62 (measured). Fails with the cut removed. */
static int chord_polish_cut(void) {
  int len[2] = {0, 0};
  long fact[2] = {0, 0};
  au_metrics q[2];
  for (int i = 0; i < 2; i++) {
    loaded L;
    if (load("spiky_ico.obj", 1, &L)) return 1;
    au_msg msg = {{0}};
    au_sphere_opts o = au_sphere_opts_default();
    o.lantern_retry = 0, o.twist_retry = 0, o.staged_retry = 0, o.global_polish = 0;
    if (i == 0) o.flow.polish_steps = AU_ADVECT_MAX_STEPS;
    au_sphere_report rep;
    const long f0 = au__solver_factorizations();
    const au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rep, &msg);
    fact[i] = au__solver_factorizations() - f0;
    AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
    const au_advect_report *r = &rep.flow;
    AU_CHECK_INT(r->polish_from, >, 0);
    len[i] = r->steps - r->polish_from;
    AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q[i], NULL, NULL), AU_OK,
                    (au_msg *)NULL);
    fprintf(stderr, "%s: chord polish from step %d, %d steps, %.5f -> %.5f; polished map vertex %.5f, per-face %.5f; "
            "%ld factorizations\n", i ? "cut" : "uncut", r->polish_from, len[i], r->err[r->polish_from], r->err[r->steps],
            q[i].vertex_logr_mean_abs, q[i].r_mean_abs_dev, fact[i]);
    AU_CHECK_INT(rep.polish, ==, 2);
    AU_CHECK_INT(q[i].folds, ==, 0);
    /* Cut where the error after two steps is within the window, not below 1.5 tol. */
    AU_CHECK_DBL(r->err[r->polish_from + 2], >, 1.5 * o.flow.tol);
    AU_CHECK_DBL(r->err[r->polish_from + 2], <, 0.1);
    unload(&L);
  }
  AU_CHECK_INT(len[0], >, 2);
  AU_CHECK_INT(len[1], ==, 2);
  AU_CHECK_INT(fact[1], <, fact[0]);
  /* The polished map of the cut flow is as good as the uncut one's (here better; 2% for the paths that
   * rounding moves). */
  AU_CHECK_DBL(q[1].vertex_logr_mean_abs, <=, 1.02 * q[0].vertex_logr_mean_abs);
  AU_CHECK_DBL(q[1].r_mean_abs_dev, <=, 1.02 * q[0].r_mean_abs_dev);
  return 0;
}

/* The flow's phases hand over by their rules (the table flow_phases in au_advect.c), seen in the report:
 * - the Poisson method's cells phase ends where the vertex cells meet tol, and the per-face refinement
 *   takes over at that very step;
 * - with the budget spent, the angle steps come on top of it: angle_from = max_steps - undone, and the
 *   steps after it are the angle steps;
 * - on spiky_ico the spherical part hands over to the chord polish, and the angle steps (handed over
 *   at the end) come after the polish.
 * Measured on the ellipsoid: Poisson 6 cell steps then 30 face steps; the budget of 8 runs out in the
 * polish (from step 5), then 2 angle steps. */
static int phase_transitions(void) {
  loaded L;
  if (load("ellipsoid.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  au_sphere_opts o = au_sphere_opts_default();
  o.lantern_retry = 0;
  o.flow.method = AU_ADVECT_POISSON;
  au_sphere_report rep;
  au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rep, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  const au_advect_report *r = &rep.flow;
  fprintf(stderr, "poisson: %d steps, %d face steps\n", r->steps, r->face_steps);
  AU_CHECK_INT(r->face_steps, >, 0);
  AU_CHECK_INT(r->face_steps, <=, o.flow.face_steps);
  AU_CHECK_INT(r->polish_from + r->angle_from + r->undone, ==, 0);
  int first_face = r->steps - r->face_steps;
  AU_CHECK_DBL(r->err[first_face], <=, o.flow.tol);
  AU_CHECK_DBL(r->err[first_face - 1], >, o.flow.tol);

  o = au_sphere_opts_default();
  o.lantern_retry = 0;
  o.vertex_polish = 0; /* the chord polish uncut (chord_polish_cut), so that the budget runs out in it */
  o.flow.max_steps = 8, o.flow.angle_steps = 2;
  st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rep, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  fprintf(stderr, "budget: %d steps, polish from %d, angles from %d, %d undone\n", r->steps, r->polish_from,
          r->angle_from, r->undone);
  AU_CHECK_INT(r->polish_from, >, 0);
  AU_CHECK_INT(r->angle_from, >, r->polish_from);
  AU_CHECK_INT(r->angle_from + r->undone, ==, o.flow.max_steps);
  AU_CHECK_INT(r->steps, <=, r->angle_from + o.flow.angle_steps);
  unload(&L);

  if (load("spiky_ico.obj", 1, &L)) return 1;
  o = au_sphere_opts_default();
  o.lantern_retry = 0;
  o.flow.angle_steps = 3, o.flow.angle_switch = 0;
  st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rep, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  fprintf(stderr, "spiky: %d steps, polish from %d, angles from %d, %d undone\n", r->steps, r->polish_from,
          r->angle_from, r->undone);
  AU_CHECK_INT(r->polish_from, >, 0);
  AU_CHECK_INT(r->angle_from, >, r->polish_from);
  AU_CHECK_INT(r->steps, <=, r->angle_from + 3);
  AU_CHECK_INT(r->undone, >, 0);
  unload(&L);
  return 0;
}

/* Prescribed density (issue 6): weight 4 on the faces of one half of the ellipsoid (centroid x > 0)
 * gives that half 4x the domain area per unit surface area. Per vertex: weight 4 on the vertices with
 * x > 0, measured on the faces whose corners all lie in one half. Measured: per face 3.99868, per vertex 3.99934, i.e. within 3.3e-4 and 1.6e-4 relative;
 * the checks ask 1e-3 relative (the bound). */
static double half_ratio(const loaded *L, const double *P, int by_vertex) {
  const au_mesh *m = L->m;
  double dom[2] = {0, 0}, sur[2] = {0, 0};
  for (int f = 0; f < m->nf; f++) {
    const int *v = m->F + 3 * f;
    int side = -1;
    if (by_vertex) {
      int pos = 0;
      for (int k = 0; k < 3; k++) pos += m->X[3 * v[k]] > 0;
      if (pos == 3) side = 1;
      else if (pos == 0) side = 0;
    } else {
      side = m->X[3 * v[0]] + m->X[3 * v[1]] + m->X[3 * v[2]] > 0;
    }
    if (side < 0) continue;
    double as, ad;
    au_dec_face_areas(1, v, m->X, &as);
    au_dec_face_areas(1, v, P, &ad);
    dom[side] += ad, sur[side] += as;
  }
  return (dom[1] / sur[1]) / (dom[0] / sur[0]);
}

static int density_half(void) {
  loaded L;
  if (load("ellipsoid.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  const au_mesh *m = L.m;
  double *fw = malloc(sizeof(double) * m->nf), *vw = malloc(sizeof(double) * m->nv);
  for (int f = 0; f < m->nf; f++) {
    const int *v = m->F + 3 * f;
    fw[f] = m->X[3 * v[0]] + m->X[3 * v[1]] + m->X[3 * v[2]] > 0 ? 4 : 1;
  }
  for (int i = 0; i < m->nv; i++) vw[i] = m->X[3 * i] > 0 ? 4 : 1;
  au_sphere_opts o = au_sphere_opts_default();
  o.flow.face_weight = fw;
  au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, NULL, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  au_metrics q;
  AU_CHECK_STATUS(au_metrics_compute(m->nv, m->nf, m->X, L.P, m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  AU_CHECK_INT(q.folds, ==, 0);
  fprintf(stderr, "per-face density 4: ratio %.5f\n", half_ratio(&L, L.P, 0));
  AU_CHECK_NEAR(half_ratio(&L, L.P, 0), 4.0, 4e-3);
  o.flow.face_weight = NULL;
  o.flow.weight = vw;
  st = au_sphere_map(L.m, L.t, &o, L.P, NULL, NULL, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  fprintf(stderr, "per-vertex density 4: ratio %.5f\n", half_ratio(&L, L.P, 1));
  AU_CHECK_NEAR(half_ratio(&L, L.P, 1), 4.0, 4e-3);
  /* Both densities at once are refused. */
  o.flow.face_weight = fw;
  AU_CHECK_STATUS(au_sphere_map(L.m, L.t, &o, L.P, NULL, NULL, &msg), AU_E_ARG, &msg);
  free(fw), free(vw);
  unload(&L);
  return 0;
}

/* The map does not depend on the unit of the input: scaling X by 1e3 or 1e-3 gives the same map. */
static int scale_invariance(void) {
  loaded a, b, c;
  if (load("ellipsoid.obj", 1, &a) || load("ellipsoid.obj", 1e3, &b) || load("ellipsoid.obj", 1e-3, &c)) return 1;
  au_msg msg = {{0}};
  au_sphere_opts o = au_sphere_opts_default();
  o.flow.max_steps = 10;
  au_status s1 = au_sphere_map(a.m, a.t, &o, a.P, NULL, NULL, &msg);
  au_status s2 = au_sphere_map(b.m, b.t, &o, b.P, NULL, NULL, &msg);
  au_status s3 = au_sphere_map(c.m, c.t, &o, c.P, NULL, NULL, &msg);
  AU_CHECK(s1 >= 0 && s2 >= 0 && s3 >= 0);
  double worst = 0;
  for (int i = 0; i < 3 * a.m->nv; i++) worst = fmax(worst, fmax(fabs(a.P[i] - b.P[i]), fabs(a.P[i] - c.P[i])));
  AU_CHECK_DBL(worst, <=, 1e-6);
  unload(&a), unload(&b), unload(&c);
  return 0;
}

static void t_constrain(void *ctx, int i, const double *p, double *d) {
  (void)ctx, (void)i;
  double s = d[0] * p[0] + d[1] * p[1] + d[2] * p[2];
  d[0] -= s * p[0], d[1] -= s * p[1], d[2] -= s * p[2];
}
static void t_retract(void *ctx, int i, double *p) {
  (void)ctx, (void)i;
  double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  p[0] /= r, p[1] /= r, p[2] /= r;
}

/* A folded start is refused by the flow with AU_E_FOLD, not silently advected. */
static int folded_start_refused(void) {
  loaded L;
  if (load("ellipsoid.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_sphere_conformal(L.m, L.t, L.P, &msg), AU_OK, &msg);
  /* Swap the positions of two corners of one face: it turns over. */
  int a = L.m->F[0], b = L.m->F[1];
  for (int d = 0; d < 3; d++) {
    double tmp = L.P[3 * a + d];
    L.P[3 * a + d] = L.P[3 * b + d];
    L.P[3 * b + d] = tmp;
  }
  au_advect_domain dom = {t_constrain, t_retract, 1, NULL, 0, NULL, NULL};
  AU_CHECK_STATUS(au_advect_run(L.m, L.t, &dom, NULL, L.P, NULL, &msg), AU_E_FOLD, &msg);
  AU_CHECK(strstr(msg.text, "folded") != NULL);
  unload(&L);
  return 0;
}


/* limbs8 (data/mklimbs.c): eight legs up to 20 diameters long, squeezed by the conformal start past any
 * coordinate's resolution, so cotan and clamped weights fold; the start compressed along the legs
 * (au_sphere_init.c, attempt 2) is fold-free and the flow keeps it so. Measured: vertex 0.566,
 * per-face 0.806; with the twisted retry (kept) 0.224 / 0.321 (docs/sphere.md; the equal-area
 * bounds of issue 21 are not reached). */
static int compressed_start_limbs8(void) {
  loaded L;
  if (load("limbs8.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_sphere_conformal(L.m, L.t, L.P, &msg), AU_OK, &msg);
  au_sphere_report rep;
  au_status st = au_sphere_map(L.m, L.t, NULL, L.P, NULL, &rep, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  au_metrics q;
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  AU_CHECK_INT(q.folds, ==, 0);
  AU_CHECK_DBL(radius_dev(&L), <=, 1e-12);
  AU_CHECK_DBL(q.vertex_logr_mean_abs, <=, 0.7);
  AU_CHECK_DBL(rep.flow.err[rep.flow.steps], <=, 0.5 * rep.flow.err[0]);
  unload(&L);
  return 0;
}

/* Refinement where the chord floor binds (au_sphere_refine) on limbs4: the input's vertices stay first
 * and unmoved on the surface, every new vertex is exactly at its parents' stated parameter (so on the
 * surface), at most twice the faces, the refined map fold-free on the unit sphere and nearer equal area
 * than the unrefined one (issue 21's refined bounds are not reached on limbs4; cli.refine_mesh.* checks
 * them on cow and cheburashka). */
static int refine_mesh_limbs4(void) {
  loaded L;
  if (load("limbs4.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  au_status st = au_sphere_map(L.m, L.t, NULL, L.P, NULL, NULL, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  au_mesh *mr = NULL;
  double *Pr = NULL, *prm = NULL;
  int *par = NULL, nnew = 0;
  st = au_sphere_refine(L.m, L.P, NULL, 2, &mr, &Pr, &par, &prm, &nnew, NULL, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  AU_CHECK_INT(nnew, >, 0);
  AU_CHECK_INT(mr->nv, ==, L.m->nv + nnew);
  AU_CHECK_INT(mr->nf, <=, 2 * L.m->nf);
  AU_CHECK(memcmp(mr->X, L.m->X, sizeof(double) * 3 * (size_t)L.m->nv) == 0);
  for (int k = 0; k < nnew; k++) {
    int a = par[2 * k], b = par[2 * k + 1], v = L.m->nv + k;
    AU_CHECK(a >= 0 && b >= 0 && a < v && b < v && a != b);
    AU_CHECK_DBL(prm[k], ==, 0.5);
    for (int d = 0; d < 3; d++)
      AU_CHECK_DBL(mr->X[3 * v + d], ==, (1 - prm[k]) * mr->X[3 * a + d] + prm[k] * mr->X[3 * b + d]);
  }
  au_metrics q;
  AU_CHECK_STATUS(au_metrics_compute(mr->nv, mr->nf, mr->X, Pr, mr->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  AU_CHECK_INT(q.folds, ==, 0);
  for (int i = 0; i < mr->nv; i++) AU_CHECK_DBL(fabs(sqrt(Pr[3 * i] * Pr[3 * i] + Pr[3 * i + 1] * Pr[3 * i + 1] + Pr[3 * i + 2] * Pr[3 * i + 2]) - 1), <=, 1e-12);
  /* The legs' base bands are split whole (the longest-edges candidate): the refined map has well under
   * the unrefined one's errors (0.084 / 0.044; the floor-face rounds alone gave 0.064 / 0.026, now
   * 0.028 / 0.013 here, from the polished map). */
  au_metrics q0;
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q0, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  fprintf(stderr, "limbs4: per-face %.4f -> %.4f, vertex %.4f -> %.4f, %d -> %d faces\n", q0.r_mean_abs_dev,
          q.r_mean_abs_dev, q0.vertex_logr_mean_abs, q.vertex_logr_mean_abs, L.m->nf, mr->nf);
  AU_CHECK_DBL(q.r_mean_abs_dev, <=, 0.5 * q0.r_mean_abs_dev);
  AU_CHECK_DBL(q.vertex_logr_mean_abs, <=, 0.5 * q0.vertex_logr_mean_abs);
  au_mesh_free(&mr);
  free(Pr), free(par), free(prm);
  unload(&L);
  return 0;
}

/* The spherical split candidate of au_sphere_refine on limbs8, whose eight legs' refined
 * map the other candidates left at 0.1219 / 0.0560 (a third of the unrefined errors, 0.272 / 0.164): it
 * is kept, and the refined map has at most a quarter of the unrefined per-face and a fifth of its vertex
 * error (0.0568 / 0.0247), 0 folds, at most twice the faces, every new vertex at its parents' midpoint
 * (parents may be vertices the same refinement made, never later ones). */
static int refine_spherical_split_limbs8(void) {
  loaded L;
  if (load("limbs8.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  au_sphere_opts o = au_sphere_opts_default();
  au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, NULL, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  au_metrics q0, q;
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q0, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  au_mesh *mr = NULL;
  double *Pr = NULL, *prm = NULL;
  int *par = NULL, nnew = 0;
  st = au_sphere_refine(L.m, L.P, &o, 2, &mr, &Pr, &par, &prm, &nnew, NULL, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  AU_CHECK_INT(nnew, >, 0);
  AU_CHECK_INT(mr->nf, <=, 2 * L.m->nf);
  AU_CHECK(memcmp(mr->X, L.m->X, sizeof(double) * 3 * (size_t)L.m->nv) == 0);
  /* Still a closed, consistently oriented genus-0 mesh: every edge has two faces, V - E + F = 2. */
  au_topo *tr = NULL;
  au_mesh_expect ex = au_mesh_expect_default();
  AU_CHECK_STATUS(au_mesh_validate(mr, &ex, &tr, &msg), AU_OK, &msg);
  AU_CHECK_INT(mr->nv - tr->ne + mr->nf, ==, 2);
  au_topo_free(&tr);
  int deep = 0;
  for (int k = 0; k < nnew; k++) {
    int a = par[2 * k], b = par[2 * k + 1], v = L.m->nv + k;
    AU_CHECK(a >= 0 && b >= 0 && a < v && b < v && a != b);
    deep += a >= L.m->nv || b >= L.m->nv;
    for (int d = 0; d < 3; d++)
      AU_CHECK_DBL(mr->X[3 * v + d], ==, (1 - prm[k]) * mr->X[3 * a + d] + prm[k] * mr->X[3 * b + d]);
  }
  AU_CHECK_STATUS(au_metrics_compute(mr->nv, mr->nf, mr->X, Pr, mr->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  fprintf(stderr, "limbs8: per-face %.4f -> %.4f, vertex %.4f -> %.4f, %d -> %d faces, %d of %d new vertices split a new edge\n",
          q0.r_mean_abs_dev, q.r_mean_abs_dev, q0.vertex_logr_mean_abs, q.vertex_logr_mean_abs, L.m->nf, mr->nf, deep, nnew);
  AU_CHECK_INT(q.folds, ==, 0);
  AU_CHECK_INT(deep, >, 0); /* the long edges are split more than once where they need it */
  AU_CHECK_DBL(q.r_mean_abs_dev, <=, 0.25 * q0.r_mean_abs_dev);
  AU_CHECK_DBL(q.vertex_logr_mean_abs, <=, 0.2 * q0.vertex_logr_mean_abs);
  au_mesh_free(&mr);
  free(Pr), free(par), free(prm);
  unload(&L);
  return 0;
}

/* The global polish (au_sphere_global_polish) on limbs4's default map, on areas alone: fold-free with
 * every triple product at or above the least it allows, the vertex error down by a third or more (0.0436
 * -> 0.0221) and the per-face error not up; with robust residuals both mean errors lower still (0.0754 /
 * 0.0230 -> 0.0745 / 0.0157); a cancel leaves the map alone; bad options are refused; min_gain stops it
 * where the errors stop falling by that part in 20 steps. */
static int global_polish_limbs4(void) {
  loaded L;
  if (load("limbs4.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  au_sphere_opts o = au_sphere_opts_default();
  o.global_polish = 0; /* the map the vertex polish leaves */
  au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, NULL, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  const int nv = L.m->nv, nf = L.m->nf, *F = L.m->F;
  double *P0 = malloc(sizeof(double) * 3 * (size_t)nv), *A = malloc(sizeof(double) * (size_t)nf);
  double *C = malloc(sizeof(double) * (size_t)nf);
  AU_CHECK(P0 && A && C);
  memcpy(P0, L.P, sizeof(double) * 3 * (size_t)nv);
  au_metrics q0, q;
  AU_CHECK_STATUS(au_metrics_compute(nv, nf, L.m->X, L.P, F, AU_DOMAIN_SPHERE, &q0, NULL, NULL), AU_OK, (au_msg *)NULL);
  au_gpolish_opts go = au_sphere_gpolish_settings(200, 0, 0.002, NULL); /* on areas alone, as au_sphere_refine */
  int one = 1, steps = -1;
  go.cancel = &one;
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &go, &steps, &msg), AU_E_CANCELLED, &msg);
  AU_CHECK(steps == 0 && memcmp(L.P, P0, sizeof(double) * 3 * (size_t)nv) == 0);
  go.cancel = NULL;
  au_gpolish_opts bad = go;
  bad.min_orient = -1;
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &bad, &steps, &msg), AU_E_ARG, &msg);
  bad = go, bad.angle_weight = -1;
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &bad, &steps, &msg), AU_E_ARG, &msg);
  bad = go, bad.max_iter = -1;
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &bad, &steps, &msg), AU_E_ARG, &msg);
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &go, &steps, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_metrics_compute(nv, nf, L.m->X, L.P, F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK, (au_msg *)NULL);
  fprintf(stderr, "limbs4: %d steps; per-face %.4f -> %.4f, vertex %.4f -> %.4f\n", steps, q0.r_mean_abs_dev,
          q.r_mean_abs_dev, q0.vertex_logr_mean_abs, q.vertex_logr_mean_abs);
  AU_CHECK_INT(steps, >, 0);
  AU_CHECK_INT(q.folds, ==, 0);
  AU_CHECK_DBL(q.vertex_logr_mean_abs, <=, (2.0 / 3.0) * q0.vertex_logr_mean_abs);
  AU_CHECK_DBL(q.r_mean_abs_dev, <=, q0.r_mean_abs_dev);
  /* The least triple product: a tenth of the face's share of the chord total, or the start's if lower. */
  double sA = 0, sC = 0;
  au_dec_face_areas(nf, F, L.m->X, A);
  au_dec_face_areas(nf, F, P0, C);
  for (int f = 0; f < nf; f++) sA += A[f], sC += C[f];
  int low = 0;
  for (int f = 0; f < nf; f++) {
    const int *v = F + 3 * f;
    double o0 = au_dec_sphere_orient(P0 + 3 * v[0], P0 + 3 * v[1], P0 + 3 * v[2]);
    double o1 = au_dec_sphere_orient(L.P + 3 * v[0], L.P + 3 * v[1], L.P + 3 * v[2]);
    double least = fmin(o0, 0.1 * A[f] / sA * sC);
    low += !(o1 >= least * (1 - 1e-6));
  }
  AU_CHECK_INT(low, ==, 0);
  /* With robust residuals (pseudo-Huber, as au_sphere_refine polishes), from the same start: fold-free,
   * and the mean absolute errors it stands for lower than with squares'. */
  memcpy(L.P, P0, sizeof(double) * 3 * (size_t)nv);
  go.robust = 0.01;
  bad = go, bad.robust = -1;
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &bad, &steps, &msg), AU_E_ARG, &msg);
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &go, &steps, &msg), AU_OK, &msg);
  au_metrics qr;
  AU_CHECK_STATUS(au_metrics_compute(nv, nf, L.m->X, L.P, F, AU_DOMAIN_SPHERE, &qr, NULL, NULL), AU_OK, (au_msg *)NULL);
  fprintf(stderr, "limbs4, robust: %d steps; per-face %.4f, vertex %.4f\n", steps, qr.r_mean_abs_dev, qr.vertex_logr_mean_abs);
  AU_CHECK_INT(qr.folds, ==, 0);
  AU_CHECK_DBL(qr.r_mean_abs_dev, <, q.r_mean_abs_dev);
  AU_CHECK_DBL(qr.vertex_logr_mean_abs, <, q.vertex_logr_mean_abs);
  /* min_gain (the sphere map's stop once the errors stop paying): asked for half of both errors every 20
   * steps, which no 20 steps of this polish give (200 take the vertex error only from 0.0436 to 0.0221),
   * it stops at the 20th step, fold-free and no worse; 1 or more is refused. */
  memcpy(L.P, P0, sizeof(double) * 3 * (size_t)nv);
  go.robust = 0, go.min_gain = 0.5;
  bad = go, bad.min_gain = 1;
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &bad, &steps, &msg), AU_E_ARG, &msg);
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &go, &steps, &msg), AU_OK, &msg);
  au_metrics qg;
  AU_CHECK_STATUS(au_metrics_compute(nv, nf, L.m->X, L.P, F, AU_DOMAIN_SPHERE, &qg, NULL, NULL), AU_OK, (au_msg *)NULL);
  fprintf(stderr, "limbs4, min_gain 0.5: %d steps; per-face %.4f, vertex %.4f\n", steps, qg.r_mean_abs_dev,
          qg.vertex_logr_mean_abs);
  AU_CHECK_INT(steps, ==, 20);
  AU_CHECK_INT(qg.folds, ==, 0);
  AU_CHECK_DBL(qg.vertex_logr_mean_abs, <, q0.vertex_logr_mean_abs);
  AU_CHECK_DBL(qg.r_mean_abs_dev, <=, q0.r_mean_abs_dev);
  /* face_window (the sphere map's rule at the tolerance), with the sphere map's wide barrier, asked for a
   * vertex error this polish reaches within its 120 steps (0.03, from 0.0436; measured: at step 37 with one
   * OpenBLAS thread, as ctest runs it, 40 with four): without a window, and with a face_target above every
   * per-face error, it stops there; with a window (gain 0: any fall of the per-face error over 5 steps) it
   * goes on (to step 57; 42 with four threads). The threads change the path, so only these are asserted.
   * Bad windows, gains and targets are refused. */
  go.min_gain = 0, go.tol = 0.03, go.barrier = 1, go.barrier_weight = 0.1, go.max_iter = 120;
  bad = go, bad.face_window = 21;
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &bad, &steps, &msg), AU_E_ARG, &msg);
  bad = go, bad.face_window = -1;
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &bad, &steps, &msg), AU_E_ARG, &msg);
  bad = go, bad.face_gain = 1;
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &bad, &steps, &msg), AU_E_ARG, &msg);
  bad = go, bad.face_target = -1;
  AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &bad, &steps, &msg), AU_E_ARG, &msg);
  au_metrics qw[3];
  int wsteps[3];
  for (int k = 0; k < 3; k++) {
    memcpy(L.P, P0, sizeof(double) * 3 * (size_t)nv);
    go.face_window = k ? 5 : 0, go.face_gain = 0, go.face_target = k == 2 ? 1 : 0;
    AU_CHECK_STATUS(au_sphere_global_polish(L.m, L.t, NULL, L.P, &go, &wsteps[k], &msg), AU_OK, &msg);
    AU_CHECK_STATUS(au_metrics_compute(nv, nf, L.m->X, L.P, F, AU_DOMAIN_SPHERE, &qw[k], NULL, NULL), AU_OK,
                    (au_msg *)NULL);
    AU_CHECK_INT(qw[k].folds, ==, 0);
  }
  fprintf(stderr, "limbs4, tol 0.03: %d steps (per-face %.4f); window: %d (%.4f); window, target 1: %d\n", wsteps[0],
          qw[0].r_mean_abs_dev, wsteps[1], qw[1].r_mean_abs_dev, wsteps[2]);
  AU_CHECK_DBL(qw[0].vertex_logr_mean_abs, <=, 0.03);
  AU_CHECK_INT(wsteps[0], <, 120);
  AU_CHECK_INT(wsteps[1], >, wsteps[0]);
  AU_CHECK_DBL(qw[2].vertex_logr_mean_abs, <=, 0.03);
  AU_CHECK_INT(wsteps[2], ==, wsteps[0]); /* face_target 1: every per-face error is below it, so the window stops at once */
  free(P0), free(A), free(C);
  unload(&L);
  return 0;
}

/* The twisted start (au_sphere_twisted) on limbs4, whose legs are antiprism tubes (each ring turned
 * half a step): a fold-free map on the unit sphere, not the conformal one. */
static int twisted_start(void) {
  loaded L;
  if (load("limbs4.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  double *Pc = malloc(sizeof(double) * 3 * (size_t)L.m->nv), diff = 0;
  AU_CHECK(Pc != NULL);
  AU_CHECK_STATUS(au_sphere_conformal(L.m, L.t, Pc, &msg), AU_OK, &msg);
  int nsheared = 0;
  AU_CHECK_STATUS(au_sphere_twisted(L.m, L.t, L.P, &nsheared, &msg), AU_OK, &msg);
  for (int i = 0; i < 3 * L.m->nv; i++) diff = fmax(diff, fabs(L.P[i] - Pc[i]));
  free(Pc);
  fprintf(stderr, "limbs4: %d faces sheared; largest coordinate difference to the conformal start %.3g\n", nsheared, diff);
  AU_CHECK_INT(nsheared, >, L.m->nf / 4);
  AU_CHECK_DBL(diff, >, 0.01);
  au_metrics q;
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  AU_CHECK_INT(q.folds, ==, 0);
  AU_CHECK_DBL(radius_dev(&L), <=, 1e-12);
  unload(&L);
  return 0;
}

/* The longest edge of the map P relative to the surface's, each measured against its whole's scale
 * (4 pi on the sphere, the surface's area): 1 where the map keeps every edge's length. */
static double longest_edge_ratio(const loaded *L) {
  const au_mesh *m = L->m;
  double area = 0, worst = 0;
  for (int f = 0; f < m->nf; f++) {
    const double *a = m->X + 3 * m->F[3 * f], *b = m->X + 3 * m->F[3 * f + 1], *c = m->X + 3 * m->F[3 * f + 2];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  }
  for (int f = 0; f < m->nf; f++)
    for (int k = 0; k < 3; k++) {
      const int i = m->F[3 * f + k], j = m->F[3 * f + (k + 1) % 3];
      double ds = 0, dp = 0;
      for (int d = 0; d < 3; d++) {
        const double x = m->X[3 * i + d] - m->X[3 * j + d], p = L->P[3 * i + d] - L->P[3 * j + d];
        ds += x * x, dp += p * p;
      }
      if (ds > 0) worst = fmax(worst, sqrt(dp / (4 * 3.14159265358979323846)) / sqrt(ds / area));
    }
  return worst;
}

/* The coarse-to-fine start (au_sphere_multilevel) on spiky_ico, whose twelve spikes the conformal start
 * squeezes (worst vertex e^-5): fold-free on the unit sphere, nearer equal area than the conformal start
 * (measured: vertex error 0.90 against 1.34), and with the re-inserted vertices placed by their rings'
 * surface shapes, no long edges (measured: the longest 2.4 times the surface's, the conformal start's 4.6,
 * a placement by local areas' 8.1); the map made from it (au_sphere_opts.start) is fold-free, says which
 * start made it and meets issue 39's bounds. */
static int multilevel_start_spiky(void) {
  loaded L;
  if (load("spiky_ico.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  au_sphere_opts o = au_sphere_opts_default();
  au_sphere_ml_report mr;
  AU_CHECK_STATUS(au_sphere_multilevel(L.m, L.t, &o, L.P, &mr, &msg), AU_OK, &msg);
  au_metrics q, qc;
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  AU_CHECK_INT(q.folds, ==, 0);
  AU_CHECK_DBL(radius_dev(&L), <=, 1e-12);
  AU_CHECK_INT(mr.levels, >=, 2);
  AU_CHECK_INT(mr.coarse_vertices, <=, 2 * o.ml.coarse_vertices);
  const double edge = longest_edge_ratio(&L);
  AU_CHECK_STATUS(au_sphere_conformal(L.m, L.t, L.P, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_sphere_balance(L.m, L.t, L.P, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &qc, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  const double edge_c = longest_edge_ratio(&L);
  fprintf(stderr, "spiky_ico start: coarse %d vertices, %d levels; vertex error %.3f (conformal %.3f), folds %d (conformal %d), "
          "longest edge %.2f (conformal %.2f)\n", mr.coarse_vertices, mr.levels, q.vertex_logr_mean_abs, qc.vertex_logr_mean_abs,
          q.folds, qc.folds, edge, edge_c);
  AU_CHECK_DBL(q.vertex_logr_mean_abs, <=, 0.75 * qc.vertex_logr_mean_abs);
  AU_CHECK_DBL(edge, <=, 4);
  AU_CHECK_DBL(edge, <, edge_c);
  o.start = AU_SPHERE_START_MULTILEVEL;
  au_sphere_report rep;
  const au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rep, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  AU_CHECK_INT(rep.start, ==, AU_SPHERE_START_MULTILEVEL);
  /* The flow from this start misses its tolerance here (vertex 0.058 before the polish), yet the lantern
   * retry does not run: from a start that squeezes nothing no final map came from it (bench/coarse-to-fine.md). */
  AU_CHECK_INT(rep.retry, ==, 0);
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  fprintf(stderr, "spiky_ico map: %d steps, per-face %.4f, vertex %.4f\n", rep.flow.steps, q.r_mean_abs_dev, q.vertex_logr_mean_abs);
  AU_CHECK_INT(q.folds, ==, 0);
  /* Issue 39's bounds (measured 0.0192 / 0.0026). */
  AU_CHECK_DBL(q.r_mean_abs_dev, <=, 0.03);
  AU_CHECK_DBL(q.vertex_logr_mean_abs, <=, 0.01);
  AU_CHECK_DBL(radius_dev(&L), <=, 1e-12);
  unload(&L);
  return 0;
}

/* The flow from a start already near equal area and already sheared: bunny's coarse-to-fine start
 * (vertex error 0.47, its triangles' mean ln(sigma1/sigma2) 0.63 against the conformal start's 0.04 at
 * 1.75). Shape restoring aimed every face back at the surface's shape by a fixed fraction of a linear
 * motion of several triangle sizes there: the step control cut the first step to 1.4% and every other
 * restoring step was undone, so the spherical part took 21 steps with 18 undone (measured). Without it
 * (the start's shear above its vertex error), 12 steps (measured). ../shared only. */
static int near_start_bunny(void) {
  char path[1024];
  if (!au_test_shared_mesh("bunny.obj", path, sizeof path)) {
    fprintf(stderr, "skipped: %s is absent\n", path);
    return AU_SKIP;
  }
  au_msg msg = {{0}};
  loaded L;
  memset(&L, 0, sizeof L);
  AU_CHECK_STATUS(au_io_read(path, &L.m, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_mesh_validate(L.m, NULL, &L.t, &msg), AU_OK, &msg);
  L.P = calloc(3 * (size_t)L.m->nv, sizeof(double));
  AU_CHECK(L.P != NULL);
  au_sphere_opts o = au_sphere_opts_default();
  au_sphere_ml_report mr;
  AU_CHECK_STATUS(au_sphere_multilevel(L.m, L.t, &o, L.P, &mr, &msg), AU_OK, &msg);
  au_advect_domain dom = au_sphere_domain();
  au_advect_report *rep = malloc(sizeof *rep);
  AU_CHECK(rep != NULL);
  const au_status st = au_advect_run(L.m, L.t, &dom, &o.flow, L.P, rep, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  const int spherical = rep->polish_from > 0 ? rep->polish_from : rep->steps;
  fprintf(stderr, "bunny from the coarse-to-fine start: error %.3f, shear %.3f; spherical part %d steps (error %.4f), "
          "%d undone, %d steps in all\n", rep->err[0], rep->start_shear, spherical, rep->err[spherical], rep->undone, rep->steps);
  AU_CHECK_DBL(rep->start_shear, >, rep->err[0]);
  AU_CHECK_INT(spherical, <=, 14);
  au_metrics q;
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  AU_CHECK_INT(q.folds, ==, 0);
  free(rep);
  unload(&L);
  return 0;
}

/* The sphere map with default options of the mesh at path (L loaded, P the map), its report and metrics.
 * Returns 0, or 1 after a failed check. */
static int map_default(const char *path, loaded *L, au_sphere_report *rep, au_metrics *q) {
  au_msg msg = {{0}};
  memset(L, 0, sizeof *L);
  AU_CHECK_STATUS(au_io_read(path, &L->m, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_mesh_validate(L->m, NULL, &L->t, &msg), AU_OK, &msg);
  L->P = calloc(3 * (size_t)L->m->nv, sizeof(double));
  AU_CHECK(L->P != NULL);
  au_sphere_opts o = au_sphere_opts_default();
  const au_status st = au_sphere_map(L->m, L->t, &o, L->P, NULL, rep, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  AU_CHECK_STATUS(au_metrics_compute(L->m->nv, L->m->nf, L->m->X, L->P, L->m->F, AU_DOMAIN_SPHERE, q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  return 0;
}

/* bunny's map on the sphere's shorter resolved schedule (docs/flow-tail.md): 9 steps and 10 factorizations,
 * per-face 0.0061 and vertex 0.0016 by param-eval (measured), where the resolved schedule with the fields
 * it replaces took 10 steps and 11 factorizations to per-face 0.0065, vertex 0.0016. ../shared only. */
static int resolved_bunny(void) {
  char path[1024];
  if (!au_test_shared_mesh("bunny.obj", path, sizeof path)) {
    fprintf(stderr, "skipped: %s is absent\n", path);
    return AU_SKIP;
  }
  loaded L;
  au_sphere_report rep;
  au_metrics q;
  if (map_default(path, &L, &rep, &q)) return 1;
  fprintf(stderr, "bunny: resolved %d, %d steps (%d undone), vertex %.5f, per-face %.5f, folds %d\n", rep.flow.resolved,
          rep.flow.steps, rep.flow.undone, q.vertex_logr_mean_abs, q.r_mean_abs_dev, q.folds);
  AU_CHECK_INT(rep.flow.resolved, ==, 1);
  AU_CHECK_INT(rep.flow.steps, <=, 9);
  AU_CHECK_INT(q.folds, ==, 0);
  AU_CHECK_DBL(q.r_mean_abs_dev, <=, 0.0068);
  AU_CHECK_DBL(q.vertex_logr_mean_abs, <=, 0.0017);
  unload(&L);
  return 0;
}

/* The default sphere map of the mesh at path: its global polish ran and was kept with the loss d (0:
 * squares), 0 folds, per-face mean |r - 1| at most max_face and vertex error at most max_vertex. */
static int polish_with_loss(const char *path, double d, double max_face, double max_vertex) {
  loaded L;
  au_sphere_report rep;
  au_metrics q;
  if (map_default(path, &L, &rep, &q)) return 1;
  fprintf(stderr, "%s: global polish %d, d %g, %d steps, vertex %.5f, per-face %.5f, folds %d\n", path, rep.global_polish,
          rep.global_polish_robust, rep.global_polish_steps, q.vertex_logr_mean_abs, q.r_mean_abs_dev, q.folds);
  AU_CHECK_INT(rep.global_polish, ==, 2);
  AU_CHECK_DBL(rep.global_polish_robust, ==, d);
  AU_CHECK_INT(q.folds, ==, 0);
  AU_CHECK_DBL(q.r_mean_abs_dev, <=, max_face);
  AU_CHECK_DBL(q.vertex_logr_mean_abs, <=, max_vertex);
  unload(&L);
  return 0;
}

/* The global polish's robust loss where the chord floor is a few outliers (au_sphere_map.c,
 * AU_GPOLISH_ROBUST): cow's map before the polish has a floor excess of 0.0015, so the polish runs with
 * d 0.03 and reaches the tolerance: per-face 0.0141-0.0152, vertex 0.0020 in 44-72 steps (one or two
 * BLAS threads, three rotations of the input); with squares it stalled at 0.0157-0.0167 / 0.0027-0.0029
 * after 74-131 steps. With the flow's chord polish cut short (chord_polish_cut): 0.0144-0.0151 /
 * 0.0020-0.0021 over the three rotations and the input, squares 0.0157-0.0161 / 0.0027 (one or two
 * BLAS threads). The vertex bound fails on every map of the squares. */
static int robust_polish_cow(void) {
  char path[1024];
  if (!au_test_shared_mesh("cow.off", path, sizeof path)) {
    fprintf(stderr, "skipped: %s is absent\n", path);
    return AU_SKIP;
  }
  return polish_with_loss(path, 0.03, 0.0156, 0.0022);
}

/* ... and squares where the floor is the bulk of the error: limbs4's map before the polish has a floor
 * excess over the gate 0.01; with d 0.03 its polish ended at per-face 0.0755 (vertex 0.0205),
 * with squares 0.0729 (0.0238; the map is this one; one BLAS thread): the per-face bound fails with the
 * loss. */
static int robust_polish_gate_limbs4(void) {
  char path[1024];
  snprintf(path, sizeof path, "%s/data/limbs4.obj", AU_SOURCE_DIR);
  return polish_with_loss(path, 0, 0.0740, 0.0245);
}

/* The coarse-to-fine start on limbs4, whose coarse mesh's conformal start folds (its limbs squeezed below
 * a double whatever the resolution): the coarse map is made from a Tutte embedding of a few vertices
 * instead (coarse_progressive), so the start is the coarse-to-fine one, not the conformal fallback, and
 * fold-free; the map made from it (without the polishes) has 0 folds and the per-face error measured
 * here (0.0886) with margin. */
static int multilevel_start_limbs4(void) {
  loaded L;
  if (load("limbs4.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  au_sphere_opts o = au_sphere_opts_default();
  au_sphere_ml_report mr;
  AU_CHECK_STATUS(au_sphere_multilevel(L.m, L.t, &o, L.P, &mr, &msg), AU_OK, &msg);
  au_metrics q;
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  fprintf(stderr, "limbs4 start: coarse %d vertices, %d levels, %d coarse steps; vertex error %.3f, folds %d\n",
          mr.coarse_vertices, mr.levels, mr.coarse_steps, q.vertex_logr_mean_abs, q.folds);
  AU_CHECK_INT(q.folds, ==, 0);
  AU_CHECK_DBL(radius_dev(&L), <=, 1e-12);
  AU_CHECK_INT(mr.levels, >=, 2);
  /* The conformal start squeezes limbs4 to 4.55 (77 folded triangles); this start is far nearer. */
  AU_CHECK_DBL(q.vertex_logr_mean_abs, <=, 1.5);
  /* Without the polishes, which do not depend on the start and cost most of the time here. */
  o.start = AU_SPHERE_START_MULTILEVEL, o.vertex_polish = 0;
  au_sphere_report rep;
  const au_status st = au_sphere_map(L.m, L.t, &o, L.P, NULL, &rep, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  AU_CHECK_INT(rep.start, ==, AU_SPHERE_START_MULTILEVEL);
  AU_CHECK(rep.ml_fallback.text[0] == 0);
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  fprintf(stderr, "limbs4 map: %d steps, per-face %.4f, vertex %.4f\n", rep.flow.steps, q.r_mean_abs_dev, q.vertex_logr_mean_abs);
  AU_CHECK_INT(q.folds, ==, 0);
  AU_CHECK_DBL(q.r_mean_abs_dev, <=, 0.1);
  AU_CHECK_DBL(radius_dev(&L), <=, 1e-12);
  unload(&L);
  return 0;
}

/* Map L with o into L->P (rep may be NULL) and measure it into *q: a valid status, 0 folds, every point
 * on the unit sphere. Returns 0, or 1 after a failed check. */
static int map_measured(loaded *L, const au_sphere_opts *o, au_sphere_report *rep, au_metrics *q) {
  au_msg msg = {{0}};
  au_status st = au_sphere_map(L->m, L->t, o, L->P, NULL, rep, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  AU_CHECK_STATUS(au_metrics_compute(L->m->nv, L->m->nf, L->m->X, L->P, L->m->F, AU_DOMAIN_SPHERE, q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  AU_CHECK_INT(q->folds, ==, 0);
  AU_CHECK_DBL(radius_dev(L), <=, 1e-12);
  return 0;
}

/* The twisted retry (au_sphere_opts.twist_retry): limbs4's map misses its tolerance with 11% of the
 * chord area on the floor, so it is made again from the twisted start and that map kept; its vertex
 * and per-face errors are well below the map without the retry (measured: vertex 0.178 ->
 * 0.065, per-face 0.240 -> 0.089; docs/sphere.md). */
static int twist_retry_limbs4(void) {
  loaded L;
  if (load("limbs4.obj", 1, &L)) return 1;
  au_metrics q[2];
  au_sphere_report rep[2];
  for (int r = 0; r < 2; r++) {
    au_sphere_opts o = au_sphere_opts_default();
    if (r == 0) o.twist_retry = 0;
    o.vertex_polish = 0; /* the retry's own map is what is checked (test vertex_polish for the polish) */
    if (map_measured(&L, &o, &rep[r], &q[r])) return 1;
  }
  fprintf(stderr, "limbs4: vertex %.4f -> %.4f, per-face %.4f -> %.4f, chord floor excess %.4f -> %.4f (twisted: %d faces "
          "sheared, kept %d)\n", q[0].vertex_logr_mean_abs, q[1].vertex_logr_mean_abs, q[0].r_mean_abs_dev,
          q[1].r_mean_abs_dev, q[0].chord_floor_excess, q[1].chord_floor_excess, rep[1].twist_faces, rep[1].twist);
  AU_CHECK_INT(rep[0].twist, ==, 0);
  AU_CHECK_INT(rep[1].twist, ==, 2);
  /* The twisted retry comes first where the floor excess passes its gate, and once its map is kept the
   * lantern retry does not run; without the twisted retry the lantern does. */
  AU_CHECK_INT(rep[1].retry, ==, 0);
  AU_CHECK_INT(rep[0].retry, >, 0);
  AU_CHECK_DBL(fabs(rep[1].twist_err - q[1].vertex_logr_mean_abs), <=, 1e-9);
  AU_CHECK_DBL(q[1].vertex_logr_mean_abs, <=, 0.5 * q[0].vertex_logr_mean_abs);
  AU_CHECK_DBL(q[1].r_mean_abs_dev, <=, 0.5 * q[0].r_mean_abs_dev);
  AU_CHECK_DBL(q[1].chord_floor_excess, <=, 0.5 * q[0].chord_floor_excess);
  unload(&L);
  return 0;
}

/* The vertex polish (au_sphere_opts.vertex_polish): a map that misses its tolerance is polished one
 * vertex at a time on its chord triangles, and the polished map is returned only if its vertex error is
 * lower and its per-face error not higher; it stays fold-free and on the sphere. On spiky_ico's needles
 * and limbs4's legs (long, thin triangles on their chord floor) it lowers the vertex error by at least a
 * tenth and the per-face one by 3% (measured, the flow's chord polish cut as it is where the polish
 * follows: spiky_ico vertex 0.0331 -> 0.0129, per-face 0.0970 -> 0.0581; limbs4 0.0645 -> 0.0447, 0.0886
 * -> 0.0853). Each error is measured here with au_metrics, as param-eval does. */
static int vertex_polish(void) {
  const char *names[] = {"spiky_ico.obj", "limbs4.obj"};
  for (int k = 0; k < 2; k++) {
    loaded L;
    if (load(names[k], 1, &L)) return 1;
    au_msg msg = {{0}};
    au_metrics q[2];
    au_sphere_report rep[2];
    for (int r = 0; r < 2; r++) {
      au_sphere_opts o = au_sphere_opts_default();
      o.global_polish = 0; /* the vertex polish alone (the global one follows it: global_polish_limbs4) */
      /* Without the polish, the flow's chord polish cut as it is where the polish follows, so that both
       * runs polish the same flow's map (chord_polish_cut). */
      if (r == 0) o.vertex_polish = 0, o.flow.polish_steps = 2;
      if (map_measured(&L, &o, &rep[r], &q[r])) return 1;
    }
    fprintf(stderr, "%s: vertex %.4f -> %.4f, per-face %.4f -> %.4f (%d sweeps, kept %d)\n", names[k],
            q[0].vertex_logr_mean_abs, q[1].vertex_logr_mean_abs, q[0].r_mean_abs_dev, q[1].r_mean_abs_dev,
            rep[1].polish_sweeps, rep[1].polish);
    AU_CHECK_INT(rep[0].polish, ==, 0);
    AU_CHECK_INT(rep[1].polish, ==, 2);
    AU_CHECK_INT(rep[1].polish_sweeps, >=, 1);
    /* The report's before and after are the unpolished and the returned maps, by au_metrics' measure. */
    AU_CHECK_NEAR(rep[1].polish_err[0], q[0].vertex_logr_mean_abs, 1e-9);
    AU_CHECK_NEAR(rep[1].polish_err[1], q[1].vertex_logr_mean_abs, 1e-9);
    AU_CHECK_DBL(q[1].vertex_logr_mean_abs, <=, 0.9 * q[0].vertex_logr_mean_abs);
    AU_CHECK_DBL(q[1].r_mean_abs_dev, <=, 0.97 * q[0].r_mean_abs_dev);
    /* A cancellation is honoured at the first sweep: nothing moves. */
    const int stop = 1;
    au_polish_opts po = {50, 1, 0, &stop, 0};
    double *Pc = malloc(sizeof(double) * 3 * (size_t)L.m->nv);
    AU_CHECK(Pc != NULL);
    memcpy(Pc, L.P, sizeof(double) * 3 * (size_t)L.m->nv);
    int sw = -1;
    AU_CHECK_STATUS(au_sphere_vertex_polish(L.m, L.t, NULL, Pc, &po, &sw, &msg), AU_E_CANCELLED, &msg);
    AU_CHECK_INT(sw, ==, 0);
    AU_CHECK(memcmp(Pc, L.P, sizeof(double) * 3 * (size_t)L.m->nv) == 0);
    free(Pc);
    unload(&L);
  }
  return 0;
}

/* The vertex polish of a map of spherical areas only (flow.sphere_areas 2, `--spherical-areas`, the
 * texture command's map): it moves the vertices on their spherical triangles' areas, the measure that
 * map is made for, and is kept only if the spherical vertex error falls and the spherical per-face one
 * does not rise. On limbs8 it lowers both (measured: vertex 0.0066 -> 0.0036, per-face
 * 0.0168 -> 0.0120; before, the polish ran on chord maps only); the report's before and after are
 * au_metrics' spherical figures, as param-eval's sph_ ones. */
static int vertex_polish_spherical(void) {
  loaded L;
  if (load("limbs8.obj", 1, &L)) return 1;
  au_metrics q[2];
  au_sphere_report rep[2];
  for (int r = 0; r < 2; r++) {
    au_sphere_opts o = au_sphere_opts_default();
    o.flow.sphere_areas = 2;
    if (r == 0) o.vertex_polish = 0;
    if (map_measured(&L, &o, &rep[r], &q[r])) return 1;
  }
  fprintf(stderr, "limbs8 spherical areas: vertex %.4f -> %.4f, per-face %.4f -> %.4f (%d sweeps, kept %d)\n",
          q[0].sph_vertex_logr_mean_abs, q[1].sph_vertex_logr_mean_abs, q[0].sph_r_mean_abs_dev, q[1].sph_r_mean_abs_dev,
          rep[1].polish_sweeps, rep[1].polish);
  AU_CHECK_INT(rep[0].polish, ==, 0);
  AU_CHECK_INT(rep[1].polish, ==, 2);
  AU_CHECK_INT(rep[1].polish_sweeps, >=, 1);
  AU_CHECK_NEAR(rep[1].polish_err[0], q[0].sph_vertex_logr_mean_abs, 1e-9);
  AU_CHECK_NEAR(rep[1].polish_err[1], q[1].sph_vertex_logr_mean_abs, 1e-9);
  AU_CHECK_NEAR(rep[1].polish_err[2], q[0].sph_r_mean_abs_dev, 1e-9);
  AU_CHECK_NEAR(rep[1].polish_err[3], q[1].sph_r_mean_abs_dev, 1e-9);
  AU_CHECK_DBL(q[1].sph_vertex_logr_mean_abs, <=, 0.8 * q[0].sph_vertex_logr_mean_abs);
  AU_CHECK_DBL(q[1].sph_r_mean_abs_dev, <=, 0.9 * q[0].sph_r_mean_abs_dev);
  unload(&L);
  return 0;
}

/* tpose (data/mklimbs.c): fingers on flat hands on arms, every conformal start folds, even compressed
 * (au_sphere_conformal refuses it). au_sphere_map then starts from the strong twisted start
 * (au_sphere_twisted_strong) and returns a fold-free map on the unit sphere that the flow moved
 * towards equal area; without the twisted retries it refuses the mesh as before. Measured:
 * start vertex error 11.1, map 7.09, per-face 1.68 (far from equal area; docs/sphere.md). */
static int strong_start_tpose(void) {
  loaded L;
  if (load("tpose.obj", 1, &L)) return 1;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_sphere_conformal(L.m, L.t, L.P, &msg), AU_E_FOLD, &msg);
  au_sphere_opts o = au_sphere_opts_default();
  o.twist_retry = 0;
  AU_CHECK_STATUS(au_sphere_map(L.m, L.t, &o, L.P, NULL, NULL, &msg), AU_E_FOLD, &msg);
  double *P0 = malloc(sizeof(double) * 3 * (size_t)L.m->nv);
  AU_CHECK(P0 != NULL);
  au_sphere_report rep;
  au_status st = au_sphere_map(L.m, L.t, NULL, L.P, P0, &rep, &msg);
  AU_CHECK(st == AU_OK || st == AU_W_NOT_CONVERGED);
  AU_CHECK_INT(rep.twist, ==, 3);
  AU_CHECK_INT(rep.twist_faces, >, 0);
  /* Its flow's spherical error stays above 8 (the lantern acts below 1): the lantern retry, due, is not
   * run (test lantern_skipped). */
  AU_CHECK_INT(rep.lantern_skipped, ==, 1);
  AU_CHECK_INT(rep.retry, ==, 0);
  au_metrics q, q0;
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, L.P, L.m->F, AU_DOMAIN_SPHERE, &q, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  AU_CHECK_STATUS(au_metrics_compute(L.m->nv, L.m->nf, L.m->X, P0, L.m->F, AU_DOMAIN_SPHERE, &q0, NULL, NULL), AU_OK,
                  (au_msg *)NULL);
  fprintf(stderr, "tpose: strong twisted start, %d faces sheared; vertex %.3f (start %.3f), per-face %.3f, %d steps\n",
          rep.twist_faces, q.vertex_logr_mean_abs, q0.vertex_logr_mean_abs, q.r_mean_abs_dev, rep.flow.steps);
  AU_CHECK_INT(q.folds, ==, 0);
  AU_CHECK_INT(q0.folds, ==, 0);
  AU_CHECK_DBL(radius_dev(&L), <=, 1e-12);
  AU_CHECK_DBL(q.vertex_logr_mean_abs, <, 0.8 * q0.vertex_logr_mean_abs);
  free(P0);
  unload(&L);
  return 0;
}

int main(int argc, char **argv) {
  static const au_test_case cases[] = {
      {"conformal_ellipsoid", conformal_ellipsoid}, {"balance_centroid", balance_centroid},
      {"map_ellipsoid", map_ellipsoid},             {"resolved_schedule", resolved_schedule},
      {"map_spiky", map_spiky},
      {"map_bumpy", map_bumpy}, {"map_dumbbell", map_dumbbell}, {"polish_when_needed", polish_when_needed}, {"order_independent", order_independent}, {"plan_in_thread", plan_in_thread}, {"undone_steps_leave_no_trace", undone_steps_leave_no_trace}, {"phase_transitions", phase_transitions},                     {"restore_shapes", restore_shapes}, {"lantern_retry", lantern_retry}, {"lantern_skipped", lantern_skipped}, {"staged_before_lantern", staged_before_lantern}, {"vertex_polish", vertex_polish}, {"vertex_polish_spherical", vertex_polish_spherical}, {"angle_steps", angle_steps},                     {"density_half", density_half},                     {"scale_invariance", scale_invariance},
      {"folded_start_refused", folded_start_refused}, {"compressed_start_limbs8", compressed_start_limbs8},
      {"refine_mesh_limbs4", refine_mesh_limbs4}, {"refine_spherical_split_limbs8", refine_spherical_split_limbs8},
      {"global_polish_limbs4", global_polish_limbs4}, {"twisted_start", twisted_start},
      {"twist_retry_limbs4", twist_retry_limbs4}, {"strong_start_tpose", strong_start_tpose},
      {"multilevel_start_spiky", multilevel_start_spiky},
      {"multilevel_start_limbs4", multilevel_start_limbs4},
      {"near_start_bunny", near_start_bunny}, {"resolved_bunny", resolved_bunny},
      {"robust_polish_cow", robust_polish_cow}, {"chord_polish_cut", chord_polish_cut}, {"lantern_resumed", lantern_resumed}, {"lantern_resumed_hand_closed", lantern_resumed_hand_closed}, {"robust_polish_gate_limbs4", robust_polish_gate_limbs4},
  };
  return au_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0]));
}
