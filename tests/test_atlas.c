/* test_atlas.c - the flat cone metric that starts the atlas (atlas/au_atlas.h): cone placement keeps
 * Gauss-Bonnet exactly, the conformal solve makes every interior vertex flat but the cones, on meshes of
 * genus 0, 1 and 2 (a plate with holes, made here), closed and open; bad cones are refused. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "au_atlas.h"
#include "au_mesh.h"
#include "au_test.h"
#include "authalic.h"

#define PI 3.14159265358979323846

/* The surface of a plate of nx x 3 unit cubes with holes at cubes (1, 1), (3, 1), ... (genus = their
 * number), each cube face cut into s x s quads of two triangles, outward-oriented. */
static au_mesh *holed_plate(int holes, int s) {
  int nx = 2 * holes + 1, ny = 3, nz = 1;
  int gx = nx * s + 1, gy = ny * s + 1, gz = nz * s + 1;
  int *id = malloc((size_t)gx * gy * gz * sizeof *id);
  double *X = malloc((size_t)3 * gx * gy * gz * sizeof *X);
  int *F = malloc((size_t)6 * 6 * nx * ny * nz * s * s * sizeof *F);
  if (!id || !X || !F) return NULL;
  for (int i = 0; i < gx * gy * gz; i++) id[i] = -1;
  int nv = 0, nf = 0;
#define SOLID(x, y, z)                                                                                  \
  ((x) >= 0 && (x) < nx && (y) >= 0 && (y) < ny && (z) >= 0 && (z) < nz && !((y) == 1 && (x) % 2 == 1))
  for (int x = 0; x < nx; x++)
    for (int y = 0; y < ny; y++)
      for (int z = 0; z < nz; z++) {
        if (!SOLID(x, y, z)) continue;
        int cell[3] = {x, y, z};
        for (int a = 0; a < 3; a++)
          for (int sg = -1; sg <= 1; sg += 2) {
            int nb[3] = {x, y, z};
            nb[a] += sg;
            if (SOLID(nb[0], nb[1], nb[2])) continue;
            int b = (a + 1) % 3, c = (a + 2) % 3;
            for (int i = 0; i < s; i++)
              for (int j = 0; j < s; j++) {
                int q[4];
                static const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
                for (int k = 0; k < 4; k++) {
                  int p[3];
                  p[a] = (cell[a] + (sg > 0)) * s;
                  p[b] = cell[b] * s + i + du[k];
                  p[c] = cell[c] * s + j + dv[k];
                  int key = (p[0] * gy + p[1]) * gz + p[2];
                  if (id[key] < 0) {
                    id[key] = nv;
                    for (int r = 0; r < 3; r++) X[3 * nv + r] = (double)p[r] / s;
                    nv++;
                  }
                  q[k] = id[key];
                }
                int t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
                if (sg < 0) t[1] = q[2], t[2] = q[1], t[4] = q[3], t[5] = q[2];
                memcpy(F + 3 * nf, t, sizeof t);
                nf += 2;
              }
          }
      }
#undef SOLID
  au_mesh *m = NULL;
  if (au_mesh_alloc(nv, nf, &m) == AU_OK) {
    memcpy(m->X, X, (size_t)3 * nv * sizeof *X);
    memcpy(m->F, F, (size_t)3 * nf * sizeof *F);
  }
  free(id), free(X), free(F);
  return m;
}

/* Place cones (or take none), solve the metric, and check: Gauss-Bonnet of the cones on a closed surface,
 * Newton's convergence, no degenerate triangle, every interior vertex's angle sum 2 pi but the cones',
 * which are their angles; and with quarter, every curvature a multiple of pi/2. */
static int check_metric(au_mesh *m, int genus, int loops, int quarter, int place, int *ncones) {
  AU_CHECK(m);
  au_topo *t = NULL;
  au_msg msg;
  au_mesh_expect x = au_mesh_expect_default();
  x.genus = genus, x.loops = loops;
  AU_CHECK_STATUS(au_mesh_validate(m, &x, &t, &msg), AU_OK, &msg);
  au_atlas_opts o = au_atlas_opts_default();
  o.quarter = quarter;
  au_atlas_cones c;
  memset(&c, 0, sizeof c);
  if (place) AU_CHECK_STATUS(au_atlas_place_cones(m, t, &o, &c, &msg), AU_OK, &msg);
  double ksum = 0;
  for (int i = 0; i < c.n; i++) {
    double k = 2 * PI - c.angle[i];
    AU_CHECK(c.angle[i] > 0);
    AU_CHECK(!t->vb[c.v[i]]);
    if (quarter) AU_CHECK_NEAR(k / (PI / 2), round(k / (PI / 2)), 1e-12);
    AU_CHECK(fabs(k) > 1e-3);
    ksum += k;
  }
  if (loops == 0) AU_CHECK_NEAR(ksum, 2 * PI * (2 - 2 * genus), 1e-9);
  AU_CHECK_INT(c.n, <=, o.max_cones);
  double *u = malloc((size_t)m->nv * sizeof *u), *ang = malloc((size_t)3 * m->nf * sizeof *ang);
  double *sum = calloc((size_t)m->nv, sizeof *sum), *want = malloc((size_t)m->nv * sizeof *want);
  AU_CHECK(u && ang && sum && want);
  au_atlas_cetm_info info;
  AU_CHECK_STATUS(au_atlas_cetm(m, t, &c, &o, u, &info, &msg), AU_OK, &msg);
  AU_CHECK_DBL(info.err, <=, 1e-10);
  AU_CHECK_INT(info.degenerate, ==, 0);
  AU_CHECK_INT(info.steps, <=, 20);
  AU_CHECK_INT(au_atlas_corner_angles(m, u, ang), ==, 0);
  for (int i = 0; i < 3 * m->nf; i++) sum[m->F[i]] += ang[i];
  for (int v = 0; v < m->nv; v++) want[v] = 2 * PI;
  for (int i = 0; i < c.n; i++) want[c.v[i]] = c.angle[i];
  for (int v = 0; v < m->nv; v++) {
    if (t->vb[v]) {
      AU_CHECK_DBL(u[v], ==, 0);
      continue;
    }
    AU_CHECK_NEAR(sum[v], want[v], 1e-9);
  }
  if (ncones) *ncones = c.n;
  free(u), free(ang), free(sum), free(want);
  au_atlas_cones_clear(&c);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}

static int metric_sphere(void) {
  int n = 0;
  if (check_metric(au_test_data_mesh("ellipsoid"), 0, 0, 0, 1, &n)) return 1;
  AU_CHECK_INT(n, >=, 2); /* 4 pi of curvature needs more than one cone of a positive angle */
  return check_metric(au_test_data_mesh("bumpy_star"), 0, 0, 0, 1, NULL);
}

static int metric_quarter(void) {
  if (check_metric(au_test_data_mesh("ellipsoid"), 0, 0, 1, 1, NULL)) return 1;
  return check_metric(holed_plate(2, 3), 2, 0, 1, 1, NULL);
}

static int metric_torus(void) { return check_metric(au_test_data_mesh("torus_r3"), 1, 0, 0, 1, NULL); }

static int metric_genus(void) {
  /* The plate's cube corners carry curvature +-pi/2; cones collect it. Genus 2 and 3. */
  if (check_metric(holed_plate(2, 3), 2, 0, 0, 1, NULL)) return 1;
  return check_metric(holed_plate(3, 2), 3, 0, 0, 1, NULL);
}

static int metric_open(void) {
  /* A disk flattens with its boundary taking the curvature, cones or not; so does an annulus. */
  if (check_metric(au_test_data_mesh("disk_bump"), 0, 1, 0, 0, NULL)) return 1;
  if (check_metric(au_test_data_mesh("disk_bump"), 0, 1, 0, 1, NULL)) return 1;
  return check_metric(au_test_data_mesh("annulus_bump"), 0, 2, 0, 1, NULL);
}

static int metric_bad_cones(void) {
  au_mesh *m = au_test_data_mesh("ellipsoid");
  AU_CHECK(m);
  au_topo *t = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_mesh_validate(m, NULL, &t, &msg), AU_OK, &msg);
  double *u = malloc((size_t)m->nv * sizeof *u);
  AU_CHECK(u);
  /* Four cones of angle pi/2 hold 6 pi, not 4 pi. */
  int v[4] = {0, 1, 2, 3};
  double a[4] = {PI / 2, PI / 2, PI / 2, PI / 2};
  au_atlas_cones c = {4, v, a};
  AU_CHECK_STATUS(au_atlas_cetm(m, t, &c, NULL, u, NULL, &msg), AU_E_ARG, &msg);
  AU_CHECK(strstr(msg.text, "Gauss-Bonnet"));
  /* No cone at all on a sphere: refused the same way. */
  AU_CHECK_STATUS(au_atlas_cetm(m, t, NULL, NULL, u, NULL, &msg), AU_E_ARG, &msg);
  a[0] = -1;
  AU_CHECK_STATUS(au_atlas_cetm(m, t, &c, NULL, u, NULL, &msg), AU_E_ARG, &msg);
  AU_CHECK(strstr(msg.text, "positive angle"));
  au_topo_free(&t);
  au_mesh_free(&m);
  /* A cone on a boundary vertex. */
  m = au_test_data_mesh("disk_bump");
  AU_CHECK(m);
  au_mesh_expect x = au_mesh_expect_default();
  x.loops = 1;
  AU_CHECK_STATUS(au_mesh_validate(m, &x, &t, &msg), AU_OK, &msg);
  v[0] = t->loop_vert[0], a[0] = PI;
  c.n = 1;
  free(u);
  u = malloc((size_t)m->nv * sizeof *u);
  AU_CHECK(u);
  AU_CHECK_STATUS(au_atlas_cetm(m, t, &c, NULL, u, NULL, &msg), AU_E_ARG, &msg);
  AU_CHECK(strstr(msg.text, "interior vertex"));
  free(u);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}


/* The start of the atlas on m: cones, metric, cut, charts. Checked: vt in [0, 1]^2, no fold, no texel
 * covered twice at 1024 x 1024, both sides of every seam edge of one length (1e-9) and one rotation per
 * seam (1e-9), and with quarter (the holonomy around the handles fixed) every seam's rotation a multiple of
 * pi/2; at least min_cover of the square. */
static int check_layout(au_mesh *m, int genus, int loops, int quarter, double min_cover, au_atlas_layout *out) {
  AU_CHECK(m);
  au_topo *t = NULL;
  au_msg msg;
  au_mesh_expect x = au_mesh_expect_default();
  x.genus = genus, x.loops = loops;
  AU_CHECK_STATUS(au_mesh_validate(m, &x, &t, &msg), AU_OK, &msg);
  au_atlas_opts o = au_atlas_opts_default();
  o.quarter = quarter;
  au_atlas_cones c;
  AU_CHECK_STATUS(au_atlas_place_cones(m, t, &o, &c, &msg), AU_OK, &msg);
  double *u = malloc((size_t)m->nv * sizeof *u);
  AU_CHECK(u);
  AU_CHECK_STATUS(au_atlas_cetm(m, t, &c, &o, u, NULL, &msg), AU_OK, &msg);
  double *len = malloc((size_t)t->ne * sizeof *len);
  AU_CHECK(len);
  au_atlas_edge_lengths(m, t, u, len);
  if (quarter) {
    /* The holonomy around the handles made a multiple of pi/2 too: every seam then turns by quarter turns. */
    au_atlas_holonomy_info hi;
    au_status sh = au_atlas_holonomy_fix(m, t, &c, len, &hi, &msg);
    if (sh == AU_W_NOT_CONVERGED) {
      /* Too far for the lengths alone: a few cones turned by quarter turns first, as au_atlas does. */
      int changed = 0;
      AU_CHECK_STATUS(au_atlas_holonomy_balance(m, t, &c, len, 1, &changed, &msg), AU_OK, &msg);
      AU_CHECK_INT(changed, >, 0);
      double ksum = 0;
      for (int i = 0; i < c.n; i++) ksum += 2 * PI - c.angle[i];
      if (loops == 0) AU_CHECK_NEAR(ksum, 2 * PI * (2 - 2 * genus), 1e-9);
      AU_CHECK_STATUS(au_atlas_cetm(m, t, &c, &o, u, NULL, &msg), AU_OK, &msg);
      au_atlas_edge_lengths(m, t, u, len);
      sh = au_atlas_holonomy_fix(m, t, &c, len, &hi, &msg);
    }
    AU_CHECK_STATUS(sh, AU_OK, &msg);
    AU_CHECK_INT(hi.loops, ==, 2 * genus + (loops > 0 ? loops - 1 : 0));
    AU_CHECK_INT(hi.fixed, ==, hi.loops);
    if (hi.loops > 0) AU_CHECK_DBL(hi.err, <=, 1e-11);
  }
  au_atlas_layout L;
  AU_CHECK_STATUS(au_atlas_layout_make(m, t, &c, len, 2.0 / 1024, quarter, 1, &L, &msg), AU_OK, &msg);
  free(len);
  for (int i = 0; i < 2 * L.nvt; i++) AU_CHECK(L.vt[i] >= 0 && L.vt[i] <= 1);
  AU_CHECK_INT(L.folds, ==, 0);
  long covered = 0, twice = au_atlas_overlap_texels(m->nf, L.vt, L.Ft, 1024, &covered);
  if (getenv("AU_ATLAS_PROBE"))
    fprintf(stderr, "nf %d cones %d charts %d cut %d seams %d coverage %.3f twice %ld covered %ld lendev %.2e rotdev %.2e\n",
            m->nf, c.n, L.ncharts, L.ncut, L.nseams, L.coverage, twice, covered, L.seam_len_dev, L.seam_rot_dev);
  AU_CHECK_INT(twice, ==, 0);
  AU_CHECK_DBL(L.coverage, >=, min_cover);
  AU_CHECK_NEAR((double)covered / (1024.0 * 1024.0), L.coverage, 0.02);
  AU_CHECK_DBL(L.seam_len_dev, <=, 1e-9);
  AU_CHECK_DBL(L.seam_rot_dev, <=, 1e-8);
  for (int s = 0; quarter && s < L.nseams; s++) {
    double q = L.seam_rot[s] / (PI / 2);
    AU_CHECK_NEAR(q, round(q), 1e-9);
  }
  /* A surface without cut edges is one disk-like chart; every cut edge belongs to a seam. */
  for (int e = 0; e < t->ne; e++) AU_CHECK((L.seam_edge[e] >= 0) == (L.cut[e] != 0));
  if (out) *out = L;
  else au_atlas_layout_free(&L);
  free(u);
  au_atlas_cones_clear(&c);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}

static int layout_sphere(void) {
  /* One chart each (a cut tree through the cones); the star's arms make the layout overlap itself, which
   * splits it into charts that still meet at multiples of 90 degrees with quarter cones. */
  if (check_layout(au_test_data_mesh("ellipsoid"), 0, 0, 0, 0.15, NULL)) return 1;
  if (check_layout(au_test_data_mesh("ellipsoid"), 0, 0, 1, 0.15, NULL)) return 1;
  au_atlas_layout L;
  if (check_layout(au_test_data_mesh("bumpy_star"), 0, 0, 1, 0.1, &L)) return 1;
  if (getenv("AU_ATLAS_PROBE")) fprintf(stderr, "bumpy_star quarter: %d charts\n", L.ncharts);
  au_atlas_layout_free(&L);
  return 0;
}

static int layout_torus(void) { return check_layout(au_test_data_mesh("torus_r3"), 1, 0, 0, 0.25, NULL); }

static int layout_genus(void) {
  if (check_layout(holed_plate(2, 3), 2, 0, 0, 0.2, NULL)) return 1;
  if (check_layout(holed_plate(2, 3), 2, 0, 1, 0.2, NULL)) return 1;
  return check_layout(holed_plate(3, 2), 3, 0, 0, 0.2, NULL);
}

static int layout_open(void) {
  au_atlas_layout L;
  /* A disk is one chart with no cut edge. */
  if (check_layout(au_test_data_mesh("disk_bump"), 0, 1, 0, 0.3, &L)) return 1;
  AU_CHECK_INT(L.ncharts, ==, 1);
  au_atlas_layout_free(&L);
  if (check_layout(au_test_data_mesh("annulus_bump"), 0, 2, 0, 0.3, &L)) return 1;
  AU_CHECK_INT(L.ncharts, ==, 1);
  AU_CHECK_INT(L.ncut, >=, 1);
  au_atlas_layout_free(&L);
  return 0;
}


/* The equal-area flow on the start of check_layout: the per-face mean |r - 1| at most max_err (from well
 * above it), no fold, no texel twice after the charts are separated and packed again, both sides of every
 * seam still congruent (lengths to 1e-9, one rotation per seam to 1e-8), vt in [0, 1]^2. */
static int check_flow(au_mesh *m, int genus, int loops, double max_err) {
  au_atlas_layout L;
  AU_CHECK(m);
  au_mesh *mc = NULL;
  AU_CHECK_STATUS(au_mesh_copy(m, &mc), AU_OK, NULL);
  if (check_layout(m, genus, loops, 0, 0.1, &L)) return 1; /* frees m */
  au_topo *t = NULL;
  au_msg msg;
  au_mesh_expect x = au_mesh_expect_default();
  x.genus = genus, x.loops = loops;
  AU_CHECK_STATUS(au_mesh_validate(mc, &x, &t, &msg), AU_OK, &msg);
  au_atlas_cones c;
  AU_CHECK_STATUS(au_atlas_place_cones(mc, t, NULL, &c, &msg), AU_OK, &msg);
  au_atlas_flow_info fi;
  AU_CHECK_STATUS(au_atlas_flow(mc, t, &c, &L, NULL, &fi, &msg), AU_OK, &msg);
  AU_CHECK_DBL(fi.err0, >, 5 * max_err);
  AU_CHECK_DBL(fi.err, <=, max_err);
  AU_CHECK_NEAR(au_atlas_face_error(mc, &L), fi.err, 1e-9);
  AU_CHECK_STATUS(au_atlas_separate(mc, t, &L, 0, 2.0 / 1024, NULL, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_atlas_measure(mc, t, &c, &L, &msg), AU_OK, &msg);
  AU_CHECK_NEAR(au_atlas_face_error(mc, &L), fi.err, 1e-9); /* packing moves charts rigidly, at one scale */
  AU_CHECK_INT(L.folds, ==, 0);
  AU_CHECK_INT(au_atlas_overlap_texels(mc->nf, L.vt, L.Ft, 1024, NULL), ==, 0);
  for (int i = 0; i < 2 * L.nvt; i++) AU_CHECK(L.vt[i] >= 0 && L.vt[i] <= 1);
  AU_CHECK_DBL(L.seam_len_dev, <=, 1e-9);
  AU_CHECK_DBL(L.seam_rot_dev, <=, 1e-8);
  au_atlas_layout_free(&L);
  au_atlas_cones_clear(&c);
  au_topo_free(&t);
  au_mesh_free(&mc);
  return 0;
}

static int flow_closed(void) {
  if (check_flow(au_test_data_mesh("ellipsoid"), 0, 0, 0.012)) return 1;
  return check_flow(au_test_data_mesh("genus2"), 2, 0, 0.012);
}

static int flow_open(void) {
  if (check_flow(au_test_data_mesh("disk_bump"), 0, 1, 0.012)) return 1;
  return check_flow(au_test_data_mesh("genus2_2loops"), 2, 2, 0.012);
}

/* Nonsense options and inputs of the module's stages (not reachable through the public API, whose options are
 * checked): AU_E_ARG naming the fault, nothing changed, never a silent result. Each case was accepted before
 * the checks (NaN tolerances made the loops stop at once; non-finite lengths went into Newton's method). */
static int bad_inputs(void) {
  au_mesh *m = au_test_data_mesh("torus_r3");
  AU_CHECK(m);
  au_topo *t = NULL;
  au_msg msg;
  au_mesh_expect x = au_mesh_expect_default();
  x.genus = 1;
  AU_CHECK_STATUS(au_mesh_validate(m, &x, &t, &msg), AU_OK, &msg);
  const int ne = t->ne;
  double *u = malloc((size_t)m->nv * sizeof *u), *len = malloc((size_t)ne * sizeof *len);
  double *len0 = malloc((size_t)ne * sizeof *len0);
  AU_CHECK(u && len && len0);
  /* The metric's options. */
  au_atlas_opts o = au_atlas_opts_default();
  AU_CHECK_STATUS(au_atlas_opts_check(&o, &msg), AU_OK, &msg);
  au_atlas_cones c;
  memset(&c, 0, sizeof c);
  o.max_cones = -1;
  AU_CHECK_STATUS(au_atlas_place_cones(m, t, &o, &c, &msg), AU_E_ARG, &msg);
  AU_CHECK(strstr(msg.text, "max_cones -1"));
  o = au_atlas_opts_default(), o.u_range = NAN;
  AU_CHECK_STATUS(au_atlas_place_cones(m, t, &o, &c, &msg), AU_E_ARG, &msg);
  AU_CHECK(strstr(msg.text, "u_range"));
  o = au_atlas_opts_default(), o.quarter = 7;
  AU_CHECK_STATUS(au_atlas_place_cones(m, t, &o, &c, &msg), AU_E_ARG, &msg);
  AU_CHECK(c.n == 0 && !c.v);
  AU_CHECK_STATUS(au_atlas_place_cones(m, t, NULL, &c, &msg), AU_OK, &msg);
  double tols[3] = {NAN, -1e-10, INFINITY};
  for (int i = 0; i < 3; i++) {
    o = au_atlas_opts_default(), o.tol = tols[i];
    AU_CHECK_STATUS(au_atlas_cetm(m, t, &c, &o, u, NULL, &msg), AU_E_ARG, &msg);
    AU_CHECK(strstr(msg.text, "tol"));
  }
  o = au_atlas_opts_default(), o.max_newton = 0;
  AU_CHECK_STATUS(au_atlas_cetm(m, t, &c, &o, u, NULL, &msg), AU_E_ARG, &msg);
  AU_CHECK_STATUS(au_atlas_cetm(m, t, &c, NULL, u, NULL, &msg), AU_OK, &msg);
  au_atlas_edge_lengths(m, t, u, len);
  memcpy(len0, len, (size_t)ne * sizeof *len0);
  /* The holonomy stage's lengths and cones: refused, the lengths left as they were. */
  double badlen[4] = {NAN, 0, -1, INFINITY};
  au_atlas_holonomy_info hi;
  for (int i = 0; i < 4; i++) {
    len[ne / 2] = badlen[i];
    AU_CHECK_STATUS(au_atlas_holonomy_fix(m, t, &c, len, &hi, &msg), AU_E_ARG, &msg);
    AU_CHECK(strstr(msg.text, "finite length"));
    AU_CHECK_INT(hi.fixed, ==, 0);
    AU_CHECK_STATUS(au_atlas_holonomy_balance(m, t, &c, len, 1, NULL, &msg), AU_E_ARG, &msg);
    au_atlas_layout L;
    AU_CHECK_STATUS(au_atlas_layout_make(m, t, &c, len, 2.0 / 1024, 0, 1, &L, &msg), AU_E_ARG, &msg);
    len[ne / 2] = len0[ne / 2];
  }
  /* Cones: two at one vertex, one past the vertices, a NaN angle (curvatures +-0.1 sum to 0, as on a torus). */
  int bv[2] = {m->F[0], m->F[0]};
  double ba[2] = {2 * PI - 0.1, 2 * PI + 0.1};
  au_atlas_cones bc = {2, bv, ba};
  AU_CHECK_STATUS(au_atlas_holonomy_fix(m, t, &bc, len, &hi, &msg), AU_E_ARG, &msg);
  AU_CHECK(strstr(msg.text, "both at vertex"));
  bv[1] = m->nv;
  AU_CHECK_STATUS(au_atlas_holonomy_balance(m, t, &bc, len, 1, NULL, &msg), AU_E_ARG, &msg);
  bv[1] = m->F[1], ba[0] = NAN;
  AU_CHECK_STATUS(au_atlas_holonomy_fix(m, t, &bc, len, &hi, &msg), AU_E_ARG, &msg);
  AU_CHECK(strstr(msg.text, "positive angle"));
  /* A topology that does not fit the mesh (genus 2 said of a torus): 4 loops expected, 2 found. */
  t->genus = 2;
  AU_CHECK_STATUS(au_atlas_holonomy_fix(m, t, &c, len, &hi, &msg), AU_E_ARG, &msg);
  AU_CHECK(strstr(msg.text, "2 generator loops found, 4 expected"));
  t->genus = 1;
  for (int e = 0; e < ne; e++) AU_CHECK(len[e] == len0[e]);
  AU_CHECK_STATUS(au_atlas_holonomy_fix(m, t, &c, len, &hi, &msg), AU_OK, &msg);
  /* The flow's options, on a real layout: refused before anything moves. */
  au_atlas_layout L;
  AU_CHECK_STATUS(au_atlas_layout_make(m, t, &c, len, 2.0 / 1024, 0, 0, &L, &msg), AU_OK, &msg);
  double *vt0 = malloc(2 * (size_t)L.nvt * sizeof *vt0);
  AU_CHECK(vt0);
  memcpy(vt0, L.vt, 2 * (size_t)L.nvt * sizeof *vt0);
  for (int k = 0; k < 8; k++) {
    au_atlas_flow_opts fo = au_atlas_flow_opts_default();
    const char *what = "";
    switch (k) {
    case 0: fo.max_steps = -1, what = "max_steps"; break;
    case 1: fo.face_tol = NAN, what = "face_tol"; break;
    case 2: fo.shear = 0, what = "shear"; break;
    case 3: fo.angles = -0.064, what = "angles"; break;
    case 4: fo.angles_face_tol = INFINITY, what = "angles_face_tol"; break;
    case 5: fo.angles_vertex_tol = NAN, what = "angles_vertex_tol"; break;
    case 6: fo.settle = 1, what = "settle"; break;
    default: fo.shear = NAN, what = "shear"; break;
    }
    au_atlas_flow_info fi;
    AU_CHECK_STATUS(au_atlas_flow(m, t, &c, &L, &fo, &fi, &msg), AU_E_ARG, &msg);
    AU_CHECK(strstr(msg.text, what));
    AU_CHECK_INT(fi.steps, ==, 0);
  }
  AU_CHECK(memcmp(vt0, L.vt, 2 * (size_t)L.nvt * sizeof *vt0) == 0);
  free(vt0);
  au_atlas_layout_free(&L);
  au_atlas_cones_clear(&c);
  free(u), free(len), free(len0);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}

int main(int argc, char **argv) {
  static const au_test_case cases[] = {
      {"metric_sphere", metric_sphere}, {"metric_quarter", metric_quarter}, {"metric_torus", metric_torus},
      {"metric_genus", metric_genus},   {"metric_open", metric_open},       {"metric_bad_cones", metric_bad_cones},
      {"layout_sphere", layout_sphere}, {"layout_torus", layout_torus},     {"layout_genus", layout_genus},
      {"layout_open", layout_open},     {"flow_closed", flow_closed},       {"flow_open", flow_open},
      {"bad_inputs", bad_inputs},
  };
  return au_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0]));
}
