/* test_metrics.c - distortion metrics (analytic maps, invariances, agreement with param-eval) and the JSON report. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "au_metrics.h"
#include "au_report.h"
#include "au_test.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* ------------------------------------------------------------------ fixtures */

typedef struct tmesh {
  int nv, nf;
  double *X, *P; /* surface, domain: nv x 3 */
  int *F;
} tmesh;

static void tmesh_free(tmesh *m) {
  free(m->X), free(m->P), free(m->F);
  memset(m, 0, sizeof *m);
}

static int tmesh_alloc(tmesh *m, int nv, int nf) {
  m->nv = nv, m->nf = nf;
  m->X = calloc(3 * (size_t)nv, sizeof(double)), m->P = calloc(3 * (size_t)nv, sizeof(double));
  m->F = calloc(3 * (size_t)nf, sizeof(int));
  if (m->X && m->P && m->F) return 1;
  tmesh_free(m);
  return 0;
}

/* A fixed pseudo-random generator (xorshift64*), uniform in [-1, 1). */
static double rnd(uint64_t *s) {
  *s ^= *s >> 12, *s ^= *s << 25, *s ^= *s >> 27;
  return (double)((*s * 2685821657736338717ULL) >> 11) / 4503599627370496.0 - 1.0;
}

/* An n x n vertex grid on [0,1]^2 (z = 0), counter-clockwise triangles. With rng, vertices are
 * jittered by up to `jitter` of a cell and each square gets a random diagonal; X and P both hold
 * the grid. */
static int make_grid(tmesh *m, int n, double jitter, uint64_t *rng) {
  if (!tmesh_alloc(m, n * n, 2 * (n - 1) * (n - 1))) return 0;
  double h = 1.0 / (n - 1);
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double *x = m->X + 3 * (j * n + i);
      x[0] = i * h, x[1] = j * h;
      if (rng && i > 0 && j > 0 && i < n - 1 && j < n - 1) x[0] += jitter * h * rnd(rng), x[1] += jitter * h * rnd(rng);
    }
  memcpy(m->P, m->X, 3 * (size_t)m->nv * sizeof(double));
  int *f = m->F;
  for (int j = 0; j + 1 < n; j++)
    for (int i = 0; i + 1 < n; i++) {
      int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      if (rng && rnd(rng) < 0) {
        int t[6] = {a, b, c, b, d, c};
        memcpy(f, t, sizeof t);
      } else {
        int t[6] = {a, b, d, a, d, c};
        memcpy(f, t, sizeof t);
      }
      f += 6;
    }
  return 1;
}

/* A latitude-longitude sphere: poles plus (rings-1) rings of s vertices, outward-oriented
 * triangles; with rng, the angles are jittered. X and P both hold the unit-sphere points. */
static int make_latlong(tmesh *m, int rings, int s, uint64_t *rng) {
  int nr = rings - 1;
  if (!tmesh_alloc(m, 2 + nr * s, 2 * s + 2 * s * (nr - 1))) return 0;
  m->X[2] = 1, m->X[3 * (m->nv - 1) + 2] = -1;
  for (int i = 0; i < nr; i++)
    for (int j = 0; j < s; j++) {
      double th = M_PI * (i + 1) / rings, ph = 2 * M_PI * j / s;
      if (rng) th += 0.25 * M_PI / rings * rnd(rng), ph += 0.25 * 2 * M_PI / s * rnd(rng);
      double *x = m->X + 3 * (1 + i * s + j);
      x[0] = sin(th) * cos(ph), x[1] = sin(th) * sin(ph), x[2] = cos(th);
    }
  memcpy(m->P, m->X, 3 * (size_t)m->nv * sizeof(double));
  int *f = m->F, S = m->nv - 1;
#define RV(i, j) (1 + (i) * s + ((j) % s))
  for (int j = 0; j < s; j++) {
    int t[6] = {0, RV(0, j), RV(0, j + 1), S, RV(nr - 1, j + 1), RV(nr - 1, j)};
    memcpy(f, t, sizeof t);
    f += 6;
  }
  for (int i = 0; i + 1 < nr; i++)
    for (int j = 0; j < s; j++) {
      int a = RV(i, j), b = RV(i, j + 1), c = RV(i + 1, j), d = RV(i + 1, j + 1);
      int t[6] = {a, c, d, a, d, b};
      memcpy(f, t, sizeof t);
      f += 6;
    }
#undef RV
  return 1;
}

/* The octahedron: its six vertices are on the unit sphere already. */
static int make_octahedron(tmesh *m) {
  static const double V[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  static const int F[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  if (!tmesh_alloc(m, 6, 8)) return 0;
  memcpy(m->X, V, sizeof V), memcpy(m->P, V, sizeof V), memcpy(m->F, F, sizeof F);
  return 1;
}

/* The irregular planar test map: a jittered 15 x 15 grid lifted to a wavy surface, its domain
 * perturbed, and one interior vertex moved onto its neighbour so two domain triangles collapse
 * (excluded, and counted as folds). */
static int make_plane_case(tmesh *m) {
  uint64_t rng = 0x9E3779B97F4A7C15ULL;
  if (!make_grid(m, 15, 0.3, &rng)) return 0;
  for (int v = 0; v < m->nv; v++) {
    double *x = m->X + 3 * v, *p = m->P + 3 * v;
    x[2] = 0.3 * sin(3 * x[0]) * cos(2 * x[1]) + 0.01 * rnd(&rng);
    x[0] *= 1.7;
    p[0] += 0.02 * rnd(&rng), p[1] += 0.02 * rnd(&rng);
  }
  int v = 7 * 15 + 7;
  memcpy(m->P + 3 * v, m->P + 3 * (v + 1), 3 * sizeof(double));
  return 1;
}

/* The spherical test map: a jittered lat-long sphere; the surface a bumpy ellipsoid over it, the
 * domain the sphere points perturbed and renormalized. */
static int make_sphere_case(tmesh *m) {
  uint64_t rng = 0xD1B54A32D192ED03ULL;
  if (!make_latlong(m, 12, 16, &rng)) return 0;
  for (int v = 0; v < m->nv; v++) {
    double *x = m->X + 3 * v, *p = m->P + 3 * v, b[3] = {x[0], x[1], x[2]};
    double s = 1 + 0.2 * sin(3 * b[0] + 2 * b[2]);
    x[0] = 1.5 * b[0] * s, x[1] = 0.8 * b[1] * s, x[2] = b[2] * s;
    for (int d = 0; d < 3; d++) p[d] = b[d] + 0.04 * rnd(&rng);
    double l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int d = 0; d < 3; d++) p[d] /= l;
  }
  return 1;
}

static au_status compute(const tmesh *m, au_domain dom, au_metrics *out) {
  return au_metrics_compute(m->nv, m->nf, m->X, m->P, m->F, dom, out, NULL, NULL);
}

/* |a - b| within rel of the larger magnitude, plus abs (for figures that are O(1) differences
 * cancelling to nearly zero, such as | |p| - 1 |). NaN matches only NaN. */
static int close_rel(double a, double b, double rel, double abs_tol) {
  if (isnan(a) || isnan(b)) return isnan(a) && isnan(b);
  return fabs(a - b) <= rel * fmax(fabs(a), fabs(b)) + abs_tol;
}

/* The dimensionless double fields of au_metrics (all but the two area totals). */
#define AU_SCALE_FREE(X)                                                                              \
  X(upsilon_mean_abs) X(upsilon_std) X(upsilon_max_abs) X(upsilon_p95_abs) X(upsilon_p99_abs)       \
  X(upsilon_wmean_abs) X(lambda_mean) X(lambda_std) X(lambda_max) X(lambda_p95) X(logr_mean_abs)     \
  X(r_std) X(r_mean_abs_dev) X(r_cv) X(authalic_energy) X(vertex_logr_mean_abs) X(vertex_logr_max_abs) \
  X(angle_diff_mean_deg) X(sph_r_mean_abs_dev) X(sph_r_cv) X(sph_vertex_logr_mean_abs)               \
  X(sphere_radius_max_dev)

/* ------------------------------------------------------------ analytic cases */

static int check_undistorted(const au_metrics *a) {
  AU_CHECK_INT(a->folds, ==, 0);
  AU_CHECK_INT(a->excluded, ==, 0);
  AU_CHECK_NEAR(a->upsilon_max_abs, 0, 1e-12);
  AU_CHECK_NEAR(a->upsilon_std, 0, 1e-12);
  AU_CHECK_NEAR(a->lambda_max, 0, 1e-7); /* ln(gmax/gmin) of a similarity: sqrt of rounding */
  AU_CHECK_NEAR(a->logr_mean_abs, 0, 1e-12);
  AU_CHECK_NEAR(a->r_std, 0, 1e-12);
  AU_CHECK_NEAR(a->r_mean_abs_dev, 0, 1e-12);
  AU_CHECK_NEAR(a->authalic_energy, 0, 1e-12);
  AU_CHECK_NEAR(a->vertex_logr_max_abs, 0, 1e-12);
  AU_CHECK_NEAR(a->angle_diff_mean_deg, 0, 1e-9);
  return 0;
}

static int test_identity_plane(void) {
  tmesh m = {0};
  uint64_t rng = 7;
  AU_CHECK(make_grid(&m, 9, 0.3, &rng));
  au_metrics a;
  double *ups = malloc(m.nf * sizeof *ups), *lam = malloc(m.nf * sizeof *lam);
  AU_CHECK(ups && lam);
  AU_CHECK_STATUS(au_metrics_compute(m.nv, m.nf, m.X, m.P, m.F, AU_DOMAIN_PLANE, &a, ups, lam), AU_OK, NULL);
  int r = check_undistorted(&a);
  AU_CHECK_INT(r, ==, 0);
  AU_CHECK_INT(a.nv, ==, 81);
  AU_CHECK_INT(a.nf, ==, 128);
  AU_CHECK_INT(a.domain, ==, AU_DOMAIN_PLANE);
  AU_CHECK_NEAR(a.surface_area, 1, 1e-12);
  AU_CHECK_NEAR(a.domain_area, 1, 1e-12);
  for (int f = 0; f < m.nf; f++) AU_CHECK(fabs(ups[f]) < 1e-12 && fabs(lam[f]) < 1e-7);
  /* Sphere-only fields stay zero for a planar domain. */
  AU_CHECK_DBL(a.sph_r_cv, ==, 0);
  AU_CHECK_DBL(a.sphere_radius_max_dev, ==, 0);
  free(ups), free(lam), tmesh_free(&m);
  return 0;
}

/* A uniformly scaled domain, and a domain with a z the planar evaluation must ignore. */
static int test_uniform_scale(void) {
  tmesh m = {0};
  uint64_t rng = 11;
  AU_CHECK(make_grid(&m, 9, 0.3, &rng));
  for (int i = 0; i < 3 * m.nv; i++) m.P[i] *= 2.5;
  for (int v = 0; v < m.nv; v++) m.P[3 * v + 2] = 100.0 * v;
  au_metrics a;
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_PLANE, &a), AU_OK, NULL);
  int r = check_undistorted(&a);
  AU_CHECK_INT(r, ==, 0);
  AU_CHECK_NEAR(a.domain_area, 6.25, 1e-12);
  AU_CHECK_NEAR(a.surface_area, 1, 1e-12);
  tmesh_free(&m);
  return 0;
}

/* Domain (2x, y) of the surface (x, y): every J is diag(1/2, 1), so Lambda = ln 2 and, once the
 * surface is scaled to the domain's area, Upsilon = 0. On a regular grid every triangle is right
 * isosceles with axis-parallel legs: its angles 90, 45, 45 become 90, atan(1/2), atan(2). */
static int test_anisotropic(void) {
  tmesh m = {0};
  AU_CHECK(make_grid(&m, 6, 0, NULL));
  for (int v = 0; v < m.nv; v++) m.P[3 * v] *= 2;
  au_metrics a;
  double *lam = malloc(m.nf * sizeof *lam);
  AU_CHECK(lam);
  AU_CHECK_STATUS(au_metrics_compute(m.nv, m.nf, m.X, m.P, m.F, AU_DOMAIN_PLANE, &a, NULL, lam), AU_OK, NULL);
  for (int f = 0; f < m.nf; f++) AU_CHECK_NEAR(lam[f], log(2.0), 1e-14);
  AU_CHECK_NEAR(a.lambda_mean, log(2.0), 1e-14);
  AU_CHECK_NEAR(a.lambda_max, log(2.0), 1e-14);
  AU_CHECK_NEAR(a.lambda_p95, log(2.0), 1e-14);
  AU_CHECK_NEAR(a.lambda_std, 0, 1e-14);
  AU_CHECK_NEAR(a.upsilon_max_abs, 0, 1e-14);
  AU_CHECK_NEAR(a.r_cv, 0, 1e-14);
  AU_CHECK_INT(a.folds, ==, 0);
  double want = 2.0 / 3.0 * (45.0 - atan(0.5) * 180.0 / M_PI);
  AU_CHECK_NEAR(a.angle_diff_mean_deg, want, 1e-11);
  free(lam), tmesh_free(&m);
  return 0;
}

/* Four separate triangles mapped to themselves except some mirrored: the fold count is the
 * minority, whichever orientation is the majority. */
static int test_flipped(void) {
  tmesh m = {0};
  AU_CHECK(tmesh_alloc(&m, 12, 4));
  for (int t = 0; t < 4; t++) {
    double tri[9] = {0, 0, 0, 1, 0, 0, 0.3, 0.8, 0};
    for (int k = 0; k < 3; k++) tri[3 * k] += 2 * t;
    memcpy(m.X + 9 * t, tri, sizeof tri), memcpy(m.P + 9 * t, tri, sizeof tri);
    for (int k = 0; k < 3; k++) m.F[3 * t + k] = 3 * t + k;
  }
  for (int k = 0; k < 3; k++) m.P[9 * 2 + 3 * k + 1] *= -1; /* mirror triangle 2 in y */
  au_metrics a;
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_PLANE, &a), AU_OK, NULL);
  AU_CHECK_INT(a.folds, ==, 1);
  AU_CHECK_NEAR(a.upsilon_max_abs, 0, 1e-14); /* a mirror keeps areas and angles */
  AU_CHECK_NEAR(a.lambda_max, 0, 1e-7);
  for (int t = 0; t < 4; t += 3)
    for (int k = 0; k < 3; k++) m.P[9 * t + 3 * k + 1] *= -1; /* now three of four are mirrored */
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_PLANE, &a), AU_OK, NULL);
  AU_CHECK_INT(a.folds, ==, 1);
  m.P[3 * 2 + 1] = 0; /* triangle 0 collapses onto a line: a second fold, and excluded */
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_PLANE, &a), AU_OK, NULL);
  AU_CHECK_INT(a.folds, ==, 2);
  AU_CHECK_INT(a.excluded, ==, 1);
  tmesh_free(&m);
  return 0;
}

static int test_sphere_identity(void) {
  tmesh m = {0};
  AU_CHECK(make_octahedron(&m));
  au_metrics a;
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_SPHERE, &a), AU_OK, NULL);
  int r = check_undistorted(&a);
  AU_CHECK_INT(r, ==, 0);
  AU_CHECK_INT(a.domain, ==, AU_DOMAIN_SPHERE);
  AU_CHECK_NEAR(a.sph_r_mean_abs_dev, 0, 1e-14);
  AU_CHECK_NEAR(a.sph_r_cv, 0, 1e-14);
  AU_CHECK_NEAR(a.sph_vertex_logr_mean_abs, 0, 1e-14);
  AU_CHECK_DBL(a.sphere_radius_max_dev, ==, 0);
  AU_CHECK_NEAR(a.domain_area, 8 * sqrt(3.0) / 2, 1e-14); /* eight equilateral triangles of side sqrt 2 */
  AU_CHECK_INT(a.chord_floor_faces, ==, 0);
  AU_CHECK_DBL(a.chord_floor_excess, ==, 0);
  tmesh_free(&m);
  /* A finer sphere onto itself: chordal and spherical ratios are 1, no folds. Its surface is
   * mirrored in x, so every surface triangle turns the other way round: orientation is the
   * domain's business and the fold count must not change. */
  AU_CHECK(make_latlong(&m, 8, 12, NULL));
  for (int v = 0; v < m.nv; v++) m.X[3 * v] *= -1;
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_SPHERE, &a), AU_OK, NULL);
  r = check_undistorted(&a);
  AU_CHECK_INT(r, ==, 0);
  AU_CHECK_NEAR(a.sphere_radius_max_dev, 0, 1e-15);
  /* The spherical triangles are larger than the chordal ones near the equator than near the poles,
   * so the spherical ratio statistics are not zero even for the identity. */
  AU_CHECK(a.sph_r_cv > 1e-3);
  /* Points off the sphere are reported. */
  m.P[3 * 5 + 0] *= 1.01, m.P[3 * 5 + 1] *= 1.01, m.P[3 * 5 + 2] *= 1.01;
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_SPHERE, &a), AU_OK, NULL);
  AU_CHECK_NEAR(a.sphere_radius_max_dev, 0.01, 1e-12);
  tmesh_free(&m);
  return 0;
}

/* The chord floor count: a flat tetrahedron (two faces of area ~1/2, two of area h/2) mapped onto the
 * regular tetrahedron in the sphere. Every face there has edges of length sqrt(8/3), whose chords run
 * 1 - 1/sqrt(3) under the sphere at their middles, where the opposite corner sits above: floor
 * sqrt(8/3)/2 * (1 - 1/sqrt(3)) = 0.345. The two small faces' shares (about 1% of the total 2.05 each)
 * are far below it, the large ones' far above. */
static int test_chord_floor(void) {
  tmesh m = {0};
  AU_CHECK(tmesh_alloc(&m, 4, 4));
  const double h = 0.01, X[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, h};
  const int F[12] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3};
  const double s = 1 / sqrt(3.0), P[12] = {s, s, s, s, -s, -s, -s, s, -s, -s, -s, s};
  memcpy(m.X, X, sizeof X), memcpy(m.F, F, sizeof F), memcpy(m.P, P, sizeof P);
  au_metrics a;
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_SPHERE, &a), AU_OK, NULL);
  AU_CHECK_INT(a.folds, ==, 0);
  AU_CHECK_INT(a.chord_floor_faces, ==, 2);
  double fl = sqrt(8.0 / 3) / 2 * (1 - s), face = sqrt(3.0) / 4 * 8.0 / 3, tot = 4 * face;
  double small = h / 2, big = 0.5, big2 = 0.5 * sqrt(2 * h * h + 1), stot = 2 * small + big + big2;
  AU_CHECK_NEAR(a.domain_area, tot, 1e-14);
  AU_CHECK_NEAR(a.chord_floor_excess, 2 * (fl - small / stot * tot) / tot, 1e-12);
  /* The same map of a surface of four equal faces (its own regular tetrahedron): nothing to say. */
  memcpy(m.X, P, sizeof P);
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_SPHERE, &a), AU_OK, NULL);
  AU_CHECK_INT(a.chord_floor_faces, ==, 0);
  tmesh_free(&m);
  return 0;
}

/* Degenerate faces are excluded from the per-face statistics and marked NaN per face. */
static int test_excluded(void) {
  tmesh m = {0};
  AU_CHECK(make_plane_case(&m));
  au_metrics a;
  double *ups = malloc(m.nf * sizeof *ups), *lam = malloc(m.nf * sizeof *lam);
  AU_CHECK(ups && lam);
  AU_CHECK_STATUS(au_metrics_compute(m.nv, m.nf, m.X, m.P, m.F, AU_DOMAIN_PLANE, &a, ups, lam), AU_OK, NULL);
  AU_CHECK_INT(a.excluded, ==, 2);
  AU_CHECK(a.folds >= 2);
  int nnan = 0;
  for (int f = 0; f < m.nf; f++) nnan += isnan(ups[f]) && isnan(lam[f]);
  AU_CHECK_INT(nnan, ==, 2);
  AU_CHECK(isfinite(a.upsilon_max_abs) && isfinite(a.lambda_max) && isfinite(a.r_cv));
  free(ups), free(lam), tmesh_free(&m);
  return 0;
}

static int cmp_dbl(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* numpy's linear percentile of a sorted array, written out plainly. */
static double ref_percentile(const double *s, int n, double q) {
  double pos = (n - 1) * q / 100.0;
  int i = (int)floor(pos);
  return i + 1 < n ? s[i] + (s[i + 1] - s[i]) * (pos - i) : s[i];
}

/* Percentiles and extremes against a full sort of the per-face values, on maps with many equal
 * values (a regular grid under a piecewise-linear stretch) and on irregular ones. */
static int test_percentiles(void) {
  for (int c = 0; c < 3; c++) {
    tmesh m = {0};
    uint64_t rng = 99 + c;
    AU_CHECK(c == 2 ? make_sphere_case(&m) : make_grid(&m, c == 0 ? 30 : 23, c == 0 ? 0 : 0.35, c == 0 ? NULL : &rng));
    if (c == 0)
      for (int v = 0; v < m.nv; v++) m.P[3 * v] = m.P[3 * v] < 0.5 ? m.P[3 * v] : 0.5 + 3 * (m.P[3 * v] - 0.5);
    if (c == 1)
      for (int v = 0; v < m.nv; v++) m.P[3 * v] += 0.01 * rnd(&rng), m.P[3 * v + 1] += 0.01 * rnd(&rng);
    au_metrics a;
    double *ups = malloc(m.nf * sizeof *ups), *lam = malloc(m.nf * sizeof *lam);
    AU_CHECK(ups && lam);
    au_domain dom = c == 2 ? AU_DOMAIN_SPHERE : AU_DOMAIN_PLANE;
    AU_CHECK_STATUS(au_metrics_compute(m.nv, m.nf, m.X, m.P, m.F, dom, &a, ups, lam), AU_OK, NULL);
    for (int f = 0; f < m.nf; f++) ups[f] = fabs(ups[f]);
    qsort(ups, m.nf, sizeof *ups, cmp_dbl), qsort(lam, m.nf, sizeof *lam, cmp_dbl);
    AU_CHECK(ups[m.nf - 1] > 0.1); /* the map is distorted: the percentiles are not all zero */
    AU_CHECK_NEAR(a.upsilon_p95_abs, ref_percentile(ups, m.nf, 95), 1e-15);
    AU_CHECK_NEAR(a.upsilon_p99_abs, ref_percentile(ups, m.nf, 99), 1e-15);
    AU_CHECK_NEAR(a.lambda_p95, ref_percentile(lam, m.nf, 95), 1e-15);
    AU_CHECK_DBL(a.upsilon_max_abs, ==, ups[m.nf - 1]);
    AU_CHECK_DBL(a.lambda_max, ==, lam[m.nf - 1]);
    free(ups), free(lam), tmesh_free(&m);
  }
  return 0;
}

/* Scaling the surface by 1e6 or 1e-6 changes nothing but the surface area. */
static int test_scale_invariance(void) {
  for (int c = 0; c < 2; c++) {
    tmesh m = {0};
    AU_CHECK(c ? make_sphere_case(&m) : make_plane_case(&m));
    au_domain dom = c ? AU_DOMAIN_SPHERE : AU_DOMAIN_PLANE;
    au_metrics a, b;
    AU_CHECK_STATUS(compute(&m, dom, &a), AU_OK, NULL);
    AU_CHECK(a.upsilon_mean_abs > 1e-3 && a.lambda_mean > 1e-3); /* a real distortion to compare */
    for (double s = 1e6; s > 1e-7; s *= 1e-12) {
      double *X0 = m.X, *Xs = malloc(3 * (size_t)m.nv * sizeof *Xs);
      AU_CHECK(Xs);
      for (int i = 0; i < 3 * m.nv; i++) Xs[i] = s * X0[i];
      m.X = Xs;
      au_status st = compute(&m, dom, &b);
      m.X = X0;
      free(Xs);
      AU_CHECK_STATUS(st, AU_OK, NULL);
#define AU_SAME(f) \
  if (!close_rel(a.f, b.f, 1e-12, 0)) { fprintf(stderr, "scale %g: %s %.17g vs %.17g\n", s, #f, a.f, b.f); return 1; }
      AU_SCALE_FREE(AU_SAME)
#undef AU_SAME
      AU_CHECK(close_rel(b.surface_area, s * s * a.surface_area, 1e-12, 0));
      AU_CHECK_DBL(b.domain_area, ==, a.domain_area);
      AU_CHECK_INT(b.folds, ==, a.folds);
      AU_CHECK_INT(b.excluded, ==, a.excluded);
    }
    tmesh_free(&m);
  }
  return 0;
}

static int test_bad_args(void) {
  tmesh m = {0};
  AU_CHECK(make_octahedron(&m));
  au_metrics a;
  AU_CHECK_STATUS(au_metrics_compute(m.nv, m.nf, NULL, m.P, m.F, AU_DOMAIN_SPHERE, &a, NULL, NULL), AU_E_ARG, NULL);
  AU_CHECK_STATUS(au_metrics_compute(m.nv, m.nf, m.X, m.P, m.F, AU_DOMAIN_SPHERE, NULL, NULL, NULL), AU_E_ARG, NULL);
  AU_CHECK_STATUS(au_metrics_compute(m.nv, 0, m.X, m.P, m.F, AU_DOMAIN_SPHERE, &a, NULL, NULL), AU_E_ARG, NULL);
  AU_CHECK_STATUS(au_metrics_compute(m.nv, m.nf, m.X, m.P, m.F, (au_domain)7, &a, NULL, NULL), AU_E_ARG, NULL);
  m.F[5] = 6;
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_SPHERE, &a), AU_E_ARG, NULL);
  m.F[5] = 4;
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_SPHERE, &a), AU_OK, NULL);
  m.P[0] = 0; /* vertex 0 at the origin: no sphere map */
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_SPHERE, &a), AU_E_ARG, NULL);
  memset(m.P, 0, 18 * sizeof(double)); /* zero domain area */
  AU_CHECK_STATUS(compute(&m, AU_DOMAIN_PLANE, &a), AU_E_ARG, NULL);
  tmesh_free(&m);
  return 0;
}

/* ------------------------------------------------------- agreement with param-eval */

static int write_obj(const char *path, int nv, int nf, const double *V, const int *F, int planar) {
  FILE *fp = fopen(path, "w");
  if (!fp) return 0;
  for (int v = 0; v < nv; v++)
    fprintf(fp, "v %.17g %.17g %.17g\n", V[3 * v], V[3 * v + 1], planar ? 0.0 : V[3 * v + 2]);
  for (int f = 0; f < nf; f++) fprintf(fp, "f %d %d %d\n", F[3 * f] + 1, F[3 * f + 1] + 1, F[3 * f + 2] + 1);
  return fclose(fp) == 0;
}

/* Our metrics object, as the report renders it. */
static cJSON *our_metrics(const au_metrics *a, cJSON **root) {
  au_report_info info = {0};
  info.final = a;
  char *json = NULL;
  if (au_report_json(&info, &json, NULL) != AU_OK) return NULL;
  *root = cJSON_Parse(json);
  free(json);
  return cJSON_GetObjectItemCaseSensitive(*root, "metrics");
}

static int agree_with_param_eval(int sphere) {
  char tool[1024];
  struct stat st;
  snprintf(tool, sizeof tool, "%s/tools/param-eval", AU_SHARED_DIR);
  if (stat(tool, &st) != 0 || stat("/usr/bin/python3", &st) != 0) return AU_SKIP;
  if (system("/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1") != 0) return AU_SKIP;

  tmesh m = {0};
  AU_CHECK(sphere ? make_sphere_case(&m) : make_plane_case(&m));
  au_metrics a;
  AU_CHECK_STATUS(compute(&m, sphere ? AU_DOMAIN_SPHERE : AU_DOMAIN_PLANE, &a), AU_OK, NULL);
  if (!sphere) AU_CHECK_INT(a.excluded, ==, 2); /* the exclusion rule is part of the comparison */

  char dir[] = "/tmp/au_metrics_XXXXXX", orig[64], map[64], cmd[2400];
  AU_CHECK(mkdtemp(dir));
  snprintf(orig, sizeof orig, "%s/orig.obj", dir), snprintf(map, sizeof map, "%s/map.obj", dir);
  int wrote = write_obj(orig, m.nv, m.nf, m.X, m.F, 0) && write_obj(map, m.nv, m.nf, m.P, m.F, !sphere);
  snprintf(cmd, sizeof cmd, "/usr/bin/python3 '%s' '%s' '%s' --domain %s --json", tool, orig, map,
           sphere ? "sphere" : "plane");
  char *out = NULL;
  size_t len = 0, cap = 0;
  FILE *pp = wrote ? popen(cmd, "r") : NULL;
  int rc = -1;
  if (pp) {
    for (;;) {
      if (len + 4096 + 1 > cap) {
        char *t = realloc(out, cap = 2 * cap + 8192);
        if (!t) break;
        out = t;
      }
      size_t k = fread(out + len, 1, 4096, pp);
      if (k == 0) break;
      len += k;
    }
    rc = pclose(pp);
  }
  if (out) out[len] = '\0';
  remove(orig), remove(map), rmdir(dir);
  AU_CHECK(wrote);
  AU_CHECK_INT(rc, ==, 0);
  AU_CHECK(out);
  cJSON *pe = cJSON_Parse(out), *root = NULL;
  free(out);
  AU_CHECK(pe);
  cJSON *ours = our_metrics(&a, &root);
  AU_CHECK(ours);
  AU_CHECK(cJSON_IsString(cJSON_GetObjectItemCaseSensitive(pe, "domain")));
  AU_CHECK(strcmp(cJSON_GetObjectItemCaseSensitive(pe, "domain")->valuestring, sphere ? "sphere" : "plane") == 0);

  /* Every numeric key of our metrics that param-eval also reports must agree to 1e-9 relative;
   * the absolute floor only matters for figures that are rounding noise around zero. */
  int shared = 0, bad = 0;
  cJSON *it;
  cJSON_ArrayForEach(it, ours) {
    cJSON *p = cJSON_GetObjectItemCaseSensitive(pe, it->string);
    if (!p || cJSON_IsString(it)) continue;
    shared++;
    double x = cJSON_IsNumber(it) ? it->valuedouble : NAN, y = cJSON_IsNumber(p) ? p->valuedouble : NAN;
    if (!close_rel(x, y, 1e-9, 1e-13)) {
      fprintf(stderr, "%s: ours %.17g, param-eval %.17g\n", it->string, x, y);
      bad++;
    }
  }
  int nv_pe = cJSON_GetObjectItemCaseSensitive(pe, "V") ? cJSON_GetObjectItemCaseSensitive(pe, "V")->valueint : -1;
  cJSON_Delete(pe), cJSON_Delete(root);
  int nf = m.nf, nv = m.nv;
  tmesh_free(&m);
  AU_CHECK_INT(bad, ==, 0);
  AU_CHECK_INT(shared, ==, sphere ? 25 : 21); /* all but angle_diff_mean_deg are param-eval's */
  AU_CHECK_INT(nv_pe, ==, nv);
  AU_CHECK(nf > 300);
  return 0;
}

static int test_agree_plane(void) { return agree_with_param_eval(0); }
static int test_agree_sphere(void) { return agree_with_param_eval(1); }

/* ------------------------------------------------------------------- report */

static const char *warnings[] = {"first warning", "second \"quoted\" warning"};
static const au_report_stage stages[] = {{"read", 0.1}, {"flow", 0.2}, {"write", 0.125}};
static const double step_err[] = {0.5, 0.1, INFINITY};
static const double step_frac[] = {1.0, 0.5};

static int fill_info(au_report_info *info, au_metrics *fin, au_metrics *init) {
  tmesh m = {0};
  uint64_t rng = 5;
  if (!make_grid(&m, 6, 0.2, &rng) || compute(&m, AU_DOMAIN_PLANE, fin) != AU_OK) return 0;
  tmesh_free(&m);
  if (!make_octahedron(&m) || compute(&m, AU_DOMAIN_SPHERE, init) != AU_OK) return 0;
  tmesh_free(&m);
  fin->r_cv = NAN, fin->folds = 3;
  memset(info, 0, sizeof *info);
  info->tool_version = "0.1.0", info->command = "disk", info->input = "in.obj", info->output = NULL;
  info->nv = 36, info->nf = 50, info->steps = 2, info->converged = 1;
  info->final = fin, info->init = init;
  info->stages = stages, info->nstages = 3;
  info->step_err = step_err, info->step_frac = step_frac;
  info->warnings = warnings, info->nwarnings = 2;
  return 1;
}

static double num_at(const cJSON *o, const char *k) {
  const cJSON *it = cJSON_GetObjectItemCaseSensitive(o, k);
  return cJSON_IsNumber(it) ? it->valuedouble : NAN;
}

static int check_report(const char *json, const au_metrics *fin) {
  cJSON *r = cJSON_Parse(json);
  AU_CHECK(r);
  const cJSON *tool = cJSON_GetObjectItemCaseSensitive(r, "tool"), *ver = cJSON_GetObjectItemCaseSensitive(r, "version");
  AU_CHECK(cJSON_IsString(tool) && strcmp(tool->valuestring, "authalic") == 0);
  AU_CHECK(cJSON_IsString(ver) && strcmp(ver->valuestring, "0.1.0") == 0);
  AU_CHECK(strcmp(cJSON_GetObjectItemCaseSensitive(r, "command")->valuestring, "disk") == 0);
  AU_CHECK(strcmp(cJSON_GetObjectItemCaseSensitive(r, "input")->valuestring, "in.obj") == 0);
  AU_CHECK(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(r, "output")));
  AU_CHECK_DBL(num_at(r, "V"), ==, 36);
  AU_CHECK_DBL(num_at(r, "F"), ==, 50);
  AU_CHECK_DBL(num_at(r, "steps"), ==, 2);
  AU_CHECK_DBL(num_at(r, "folds"), ==, 3);
  AU_CHECK(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(r, "converged")));
  const cJSON *t = cJSON_GetObjectItemCaseSensitive(r, "time");
  AU_CHECK_DBL(num_at(t, "read"), ==, 0.1);
  AU_CHECK_DBL(num_at(t, "flow"), ==, 0.2);
  /* 0.1 + 0.2 + 0.125 is 0.42500000000000004: the last bit must survive the trip through text. */
  AU_CHECK_DBL(num_at(t, "total"), ==, 0.1 + 0.2 + 0.125);
  AU_CHECK_DBL(num_at(t, "total"), !=, 0.425);
  AU_CHECK_INT(cJSON_GetArraySize(t), ==, 4);

  const cJSON *mt = cJSON_GetObjectItemCaseSensitive(r, "metrics");
  AU_CHECK(cJSON_IsObject(mt));
  AU_CHECK(strcmp(cJSON_GetObjectItemCaseSensitive(mt, "domain")->valuestring, "plane") == 0);
  /* Every value goes out with enough digits to come back exactly. */
  AU_CHECK_DBL(num_at(mt, "upsilon_mean_abs"), ==, fin->upsilon_mean_abs);
  AU_CHECK_DBL(num_at(mt, "lambda_p95"), ==, fin->lambda_p95);
  AU_CHECK_DBL(num_at(mt, "angle_diff_mean_deg"), ==, fin->angle_diff_mean_deg);
  AU_CHECK_DBL(num_at(mt, "domain_area_sum"), ==, fin->domain_area);
  AU_CHECK_DBL(num_at(mt, "folds"), ==, 3);
  AU_CHECK_DBL(num_at(mt, "excluded_faces"), ==, fin->excluded);
  AU_CHECK(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(mt, "r_cv"))); /* NaN became null */
  AU_CHECK(!cJSON_GetObjectItemCaseSensitive(mt, "sph_r_cv"));        /* planar: no sphere keys */
  AU_CHECK(!cJSON_GetObjectItemCaseSensitive(mt, "sphere_radius_max_dev"));
  AU_CHECK(!cJSON_GetObjectItemCaseSensitive(mt, "chord_floor_faces"));
  AU_CHECK_INT(cJSON_GetArraySize(mt), ==, 23);

  const cJSON *im = cJSON_GetObjectItemCaseSensitive(r, "initial_metrics");
  AU_CHECK(cJSON_IsObject(im));
  AU_CHECK(strcmp(cJSON_GetObjectItemCaseSensitive(im, "domain")->valuestring, "sphere") == 0);
  AU_CHECK_DBL(num_at(im, "sphere_radius_max_dev"), ==, 0);
  AU_CHECK(cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(im, "sph_r_cv")));
  AU_CHECK(cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(im, "chord_floor_faces")));
  AU_CHECK(cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(im, "chord_floor_excess")));
  AU_CHECK_INT(cJSON_GetArraySize(im), ==, 29);

  const cJSON *cv = cJSON_GetObjectItemCaseSensitive(r, "convergence");
  const cJSON *err = cJSON_GetObjectItemCaseSensitive(cv, "err"), *frac = cJSON_GetObjectItemCaseSensitive(cv, "frac");
  AU_CHECK_INT(cJSON_GetArraySize(err), ==, 3);
  AU_CHECK_INT(cJSON_GetArraySize(frac), ==, 2);
  AU_CHECK_DBL(cJSON_GetArrayItem(err, 1)->valuedouble, ==, 0.1);
  AU_CHECK(cJSON_IsNull(cJSON_GetArrayItem(err, 2))); /* infinity became null */
  AU_CHECK_DBL(cJSON_GetArrayItem(frac, 1)->valuedouble, ==, 0.5);
  const cJSON *w = cJSON_GetObjectItemCaseSensitive(r, "warnings");
  AU_CHECK_INT(cJSON_GetArraySize(w), ==, 2);
  AU_CHECK(strcmp(cJSON_GetArrayItem(w, 1)->valuestring, warnings[1]) == 0);
  cJSON_Delete(r);
  return 0;
}

static int test_report_json(void) {
  au_report_info info;
  au_metrics fin, init;
  AU_CHECK(fill_info(&info, &fin, &init));
  char *json = NULL;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_report_json(&info, &json, &msg), AU_OK, &msg);
  AU_CHECK(json);
  AU_CHECK(!strstr(json, "nan") && !strstr(json, "inf"));
  int r = check_report(json, &fin);
  free(json);
  AU_CHECK_INT(r, ==, 0);

  /* Without the optional parts: no initial_metrics, empty convergence arrays. */
  info.init = NULL, info.step_err = NULL, info.step_frac = NULL, info.nwarnings = 0, info.nstages = 0;
  AU_CHECK_STATUS(au_report_json(&info, &json, &msg), AU_OK, &msg);
  cJSON *p = cJSON_Parse(json);
  free(json);
  AU_CHECK(p);
  int ok = !cJSON_GetObjectItemCaseSensitive(p, "initial_metrics") &&
           cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(p, "convergence"), "err")) == 0 &&
           num_at(cJSON_GetObjectItemCaseSensitive(p, "time"), "total") == 0;
  cJSON_Delete(p);
  AU_CHECK(ok);

  info.final = NULL;
  AU_CHECK_STATUS(au_report_json(&info, &json, &msg), AU_E_ARG, &msg);
  AU_CHECK(json == NULL);
  AU_CHECK_STATUS(au_report_json(NULL, &json, &msg), AU_E_ARG, &msg);
  info.final = &fin, info.nwarnings = 1, info.warnings = NULL;
  AU_CHECK_STATUS(au_report_json(&info, &json, &msg), AU_E_ARG, &msg);
  return 0;
}

static int test_report_write(void) {
  au_report_info info;
  au_metrics fin, init;
  AU_CHECK(fill_info(&info, &fin, &init));
  char dir[] = "/tmp/au_report_XXXXXX", path[64], bad[96];
  AU_CHECK(mkdtemp(dir));
  snprintf(path, sizeof path, "%s/report.json", dir);
  snprintf(bad, sizeof bad, "%s/missing/report.json", dir);
  au_msg msg = {{0}};
  au_status st = au_report_write(path, &info, &msg), st_bad = au_report_write(bad, &info, NULL);
  char *buf = NULL;
  FILE *fp = fopen(path, "rb");
  long n = -1;
  if (fp && fseek(fp, 0, SEEK_END) == 0 && (n = ftell(fp)) > 0 && fseek(fp, 0, SEEK_SET) == 0 && (buf = malloc(n + 1)))
    buf[fread(buf, 1, n, fp)] = '\0';
  if (fp) fclose(fp);
  remove(path), rmdir(dir);
  AU_CHECK_STATUS(st, AU_OK, &msg);
  AU_CHECK_STATUS(st_bad, AU_E_IO, NULL);
  AU_CHECK(buf);
  AU_CHECK(buf[n - 1] == '\n');
  int r = check_report(buf, &fin);
  free(buf);
  AU_CHECK_INT(r, ==, 0);
  AU_CHECK_STATUS(au_report_write(NULL, &info, NULL), AU_E_ARG, NULL);
  return 0;
}

int main(int argc, char **argv) {
  static const au_test_case cases[] = {
      {"identity_plane", test_identity_plane},   {"uniform_scale", test_uniform_scale},
      {"anisotropic", test_anisotropic},         {"flipped", test_flipped},
      {"sphere_identity", test_sphere_identity}, {"chord_floor", test_chord_floor}, {"excluded", test_excluded},
      {"percentiles", test_percentiles},         {"scale_invariance", test_scale_invariance},
      {"bad_args", test_bad_args},               {"agree_plane", test_agree_plane},
      {"agree_sphere", test_agree_sphere},       {"report_json", test_report_json},
      {"report_write", test_report_write},
  };
  return au_test_main(argc, argv, cases, (int)(sizeof cases / sizeof *cases));
}
