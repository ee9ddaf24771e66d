/* test_dec.c - invariants of the DEC operators and the CHOLMOD wrapper. */
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "au_dec.h"
#include "au_mesh.h"
#include "au_par.h"
#include "au_solver.h"
#include "cli_threads.h"
#include "au_test.h"

/* A bumpy closed test surface: an octahedron refined n times, pushed onto an ellipsoid with bumps,
 * so that triangles are irregular (some obtuse). */
static au_mesh *make_surface(int levels, double scale) {
  int nv = 6, nf = 8;
  double *X = malloc(sizeof(double) * 3 * 6);
  int *F = malloc(sizeof(int) * 3 * 8);
  const double v0[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  const int f0[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  memcpy(X, v0, sizeof v0);
  memcpy(F, f0, sizeof f0);
  for (int l = 0; l < levels; l++) {
    /* Midpoint subdivision with a simple edge table (quadratic but the meshes are small). */
    int *mid = malloc(sizeof(int) * 3 * nf);
    double *X2 = malloc(sizeof(double) * 3 * (nv + 3 * nf));
    int *F2 = malloc(sizeof(int) * 12 * nf), nv2 = nv;
    int *ea = malloc(sizeof(int) * 3 * nf), *eb = malloc(sizeof(int) * 3 * nf), *em = malloc(sizeof(int) * 3 * nf), ne = 0;
    memcpy(X2, X, sizeof(double) * 3 * nv);
    for (int f = 0; f < nf; f++)
      for (int k = 0; k < 3; k++) {
        int a = F[3 * f + (k + 1) % 3], b = F[3 * f + (k + 2) % 3], lo = a < b ? a : b, hi = a < b ? b : a, found = -1;
        for (int e = 0; e < ne; e++)
          if (ea[e] == lo && eb[e] == hi) found = em[e];
        if (found < 0) {
          for (int d = 0; d < 3; d++) X2[3 * nv2 + d] = 0.5 * (X[3 * a + d] + X[3 * b + d]);
          ea[ne] = lo, eb[ne] = hi, em[ne++] = found = nv2++;
        }
        mid[3 * f + k] = found;
      }
    for (int f = 0; f < nf; f++) {
      int a = F[3 * f], b = F[3 * f + 1], c = F[3 * f + 2], ma = mid[3 * f], mb = mid[3 * f + 1], mc = mid[3 * f + 2];
      int t[12] = {a, mc, mb, mc, b, ma, mb, ma, c, ma, mb, mc};
      memcpy(F2 + 12 * f, t, sizeof t);
    }
    free(X), free(F), free(mid), free(ea), free(eb), free(em);
    X = X2, F = F2, nv = nv2, nf *= 4;
  }
  au_mesh *m = NULL;
  if (au_mesh_alloc(nv, nf, &m) != AU_OK) return NULL;
  for (int i = 0; i < nv; i++) {
    double *p = X + 3 * i, r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    double bump = 1 + 0.3 * sin(3 * p[0] / r) * cos(2 * p[1] / r);
    m->X[3 * i] = scale * 1.0 * bump * p[0] / r;
    m->X[3 * i + 1] = scale * 0.7 * bump * p[1] / r;
    m->X[3 * i + 2] = scale * 1.6 * bump * p[2] / r;
  }
  memcpy(m->F, F, sizeof(int) * 3 * nf);
  free(X), free(F);
  return m;
}

static double rnd(unsigned *s) {
  *s = *s * 1664525u + 1013904223u;
  return (*s >> 8) / 16777216.0;
}

static int with_mesh(int (*fn)(au_mesh *, au_topo *), double scale) {
  au_mesh *m = make_surface(3, scale);
  au_topo *t = NULL;
  AU_CHECK(m != NULL);
  AU_CHECK_STATUS(au_mesh_topology(m, &t, NULL), AU_OK, (au_msg *)NULL);
  int r = fn(m, t);
  au_topo_free(&t);
  au_mesh_free(&m);
  return r;
}

/* C 1 = 0, C symmetric (x'Cy = y'Cx), x'Cx >= 0. */
static int stiffness_props(au_mesh *m, au_topo *t) {
  int nv = m->nv;
  double *w = malloc(sizeof(double) * t->ne), *x = malloc(sizeof(double) * nv), *y = malloc(sizeof(double) * nv);
  double *Cx = malloc(sizeof(double) * nv), *Cy = malloc(sizeof(double) * nv);
  au_dec_cotan(t, m->F, m->X, w);
  unsigned s = 1;
  for (int i = 0; i < nv; i++) x[i] = 1;
  au_dec_stiffness_apply(t, w, x, Cx);
  double mx = 0;
  for (int i = 0; i < nv; i++) mx = fmax(mx, fabs(Cx[i]));
  AU_CHECK_DBL(mx, <=, 1e-12);
  for (int i = 0; i < nv; i++) x[i] = rnd(&s) - 0.5, y[i] = rnd(&s) - 0.5;
  au_dec_stiffness_apply(t, w, x, Cx);
  au_dec_stiffness_apply(t, w, y, Cy);
  double xCy = 0, yCx = 0, xCx = 0;
  for (int i = 0; i < nv; i++) xCy += x[i] * Cy[i], yCx += y[i] * Cx[i], xCx += x[i] * Cx[i];
  AU_CHECK_NEAR(xCy, yCx, 1e-12 * fabs(xCy) + 1e-14);
  AU_CHECK_DBL(xCx, >, 0);
  free(w), free(x), free(y), free(Cx), free(Cy);
  return 0;
}

/* x'Cx equals the Dirichlet energy sum over faces of area*|grad x|^2 (div grad = Laplacian). */
static int stiffness_is_dirichlet(au_mesh *m, au_topo *t) {
  int nv = m->nv, nf = m->nf;
  double *w = malloc(sizeof(double) * t->ne), *x = malloc(sizeof(double) * nv), *Cx = malloc(sizeof(double) * nv);
  double *G = malloc(sizeof(double) * 3 * nf), *a = malloc(sizeof(double) * nf);
  unsigned s = 7;
  for (int i = 0; i < nv; i++) x[i] = rnd(&s);
  au_dec_cotan(t, m->F, m->X, w);
  au_dec_stiffness_apply(t, w, x, Cx);
  au_dec_face_grad(nf, m->F, m->X, x, G);
  au_dec_face_areas(nf, m->F, m->X, a);
  double e1 = 0, e2 = 0;
  for (int i = 0; i < nv; i++) e1 += x[i] * Cx[i];
  for (int f = 0; f < nf; f++) e2 += a[f] * (G[3 * f] * G[3 * f] + G[3 * f + 1] * G[3 * f + 1] + G[3 * f + 2] * G[3 * f + 2]);
  AU_CHECK_NEAR(e1, e2, 1e-10 * e2);
  free(w), free(x), free(Cx), free(G), free(a);
  return 0;
}

/* The gradient of a linear function is its gradient projected into each triangle's plane, exactly. */
static int grad_linear_exact(au_mesh *m, au_topo *t) {
  (void)t;
  int nv = m->nv, nf = m->nf;
  double *g = malloc(sizeof(double) * nv), *G = malloc(sizeof(double) * 3 * nf);
  const double c[3] = {0.3, -1.2, 2.5};
  for (int i = 0; i < nv; i++) g[i] = c[0] * m->X[3 * i] + c[1] * m->X[3 * i + 1] + c[2] * m->X[3 * i + 2] + 4;
  au_dec_face_grad(nf, m->F, m->X, g, G);
  double worst = 0;
  for (int f = 0; f < nf; f++) {
    const double *p = m->X + 3 * m->F[3 * f], *q = m->X + 3 * m->F[3 * f + 1], *r = m->X + 3 * m->F[3 * f + 2];
    double e1[3], e2[3], n[3];
    for (int d = 0; d < 3; d++) e1[d] = q[d] - p[d], e2[d] = r[d] - p[d];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), cn = (c[0] * n[0] + c[1] * n[1] + c[2] * n[2]) / nn;
    for (int d = 0; d < 3; d++) worst = fmax(worst, fabs(G[3 * f + d] - (c[d] - cn * n[d] / nn)));
  }
  AU_CHECK_DBL(worst, <=, 1e-9);
  free(g), free(G);
  return 0;
}

/* Vertex areas sum to the total area; the vertex gradient of a linear function on a plane is exact. */
static int areas_sum(au_mesh *m, au_topo *t) {
  (void)t;
  double *a = malloc(sizeof(double) * m->nf), *A = malloc(sizeof(double) * m->nv), s1 = 0, s2 = 0;
  au_dec_face_areas(m->nf, m->F, m->X, a);
  au_dec_vertex_areas(m->nv, m->nf, m->F, m->X, a, A);
  for (int f = 0; f < m->nf; f++) s1 += a[f];
  for (int i = 0; i < m->nv; i++) {
    s2 += A[i];
    AU_CHECK_DBL(A[i], >, 0);
  }
  AU_CHECK_NEAR(s1, s2, 1e-12 * s1);
  free(a), free(A);
  return 0;
}

/* Solver: Dirichlet problem with a linear function as boundary data on a flat grid is solved exactly
 * (linear functions are discrete harmonic for the cotan Laplacian on planar meshes). */
static int solver_linear_exact(void) {
  int n = 12, nv = n * n, nf = 2 * (n - 1) * (n - 1);
  au_mesh *m = NULL;
  AU_CHECK_STATUS(au_mesh_alloc(nv, nf, &m), AU_OK, (au_msg *)NULL);
  unsigned s = 3;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double jit = (i > 0 && j > 0 && i < n - 1 && j < n - 1) ? 0.3 : 0;
      m->X[3 * (j * n + i)] = i + jit * (rnd(&s) - 0.5);
      m->X[3 * (j * n + i) + 1] = j + jit * (rnd(&s) - 0.5);
    }
  int f = 0;
  for (int j = 0; j + 1 < n; j++)
    for (int i = 0; i + 1 < n; i++) {
      int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      int t2[6] = {a, b, d, a, d, c};
      memcpy(m->F + 3 * f, t2, sizeof t2);
      f += 2;
    }
  au_topo *t = NULL;
  AU_CHECK_STATUS(au_mesh_topology(m, &t, NULL), AU_OK, (au_msg *)NULL);
  double *w = malloc(sizeof(double) * t->ne), *b = calloc((size_t)nv, sizeof(double)), *x = calloc((size_t)nv, sizeof(double));
  au_dec_cotan(t, m->F, m->X, w);
  au_solver *sv = NULL;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_solver_create(nv, t->ne, t->E, t->vb, AU_ORDER_FILL, &sv, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_solver_factor(sv, w, NULL, &msg), AU_OK, &msg);
  for (int i = 0; i < nv; i++)
    if (t->vb[i]) x[i] = 2 * m->X[3 * i] - 3 * m->X[3 * i + 1] + 1;
  AU_CHECK_STATUS(au_solver_solve(sv, 1, b, x, &msg), AU_OK, &msg);
  double worst = 0;
  for (int i = 0; i < nv; i++) worst = fmax(worst, fabs(x[i] - (2 * m->X[3 * i] - 3 * m->X[3 * i + 1] + 1)));
  AU_CHECK_DBL(worst, <=, 1e-10);
  /* Refactoring with new weights reuses the analysis and still solves. */
  for (int e = 0; e < t->ne; e++) w[e] *= 2;
  AU_CHECK_STATUS(au_solver_factor(sv, w, NULL, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_solver_solve(sv, 1, b, x, &msg), AU_OK, &msg);
  worst = 0;
  for (int i = 0; i < nv; i++) worst = fmax(worst, fabs(x[i] - (2 * m->X[3 * i] - 3 * m->X[3 * i + 1] + 1)));
  AU_CHECK_DBL(worst, <=, 1e-10);
  /* An indefinite matrix (negated weights) must be reported, not factored into garbage
   * (cholmod_factorize itself returns TRUE on it). */
  au_solver *sv2 = NULL;
  AU_CHECK_STATUS(au_solver_create(nv, t->ne, t->E, t->vb, AU_ORDER_FILL, &sv2, &msg), AU_OK, &msg);
  for (int e = 0; e < t->ne; e++) w[e] = -w[e];
  au_status st = au_solver_factor(sv2, w, NULL, &msg);
  if (st != AU_E_NOT_SPD) fprintf(stderr, "factor of an indefinite matrix returned %s (%s)\n", au_status_name(st), msg.text);
  AU_CHECK(st == AU_E_NOT_SPD);
  au_solver_free(&sv2);
  au_solver_free(&sv);
  au_solver_free(&sv); /* NULL-safe */
  free(w), free(b), free(x);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}

static int stiffness_props_case(void) { return with_mesh(stiffness_props, 1); }
static int stiffness_dirichlet_case(void) { return with_mesh(stiffness_is_dirichlet, 1); }
static int grad_linear_case(void) { return with_mesh(grad_linear_exact, 1); }
static int areas_sum_case(void) { return with_mesh(areas_sum, 1); }
/* Scale invariance: cotan weights are unchanged by scaling the mesh by 1e6 and 1e-6. */
static int cotan_scale_case(void) {
  au_mesh *m1 = make_surface(2, 1), *m2 = make_surface(2, 1e6), *m3 = make_surface(2, 1e-6);
  au_topo *t = NULL;
  AU_CHECK_STATUS(au_mesh_topology(m1, &t, NULL), AU_OK, (au_msg *)NULL);
  double *w1 = malloc(sizeof(double) * t->ne), *w2 = malloc(sizeof(double) * t->ne), *w3 = malloc(sizeof(double) * t->ne);
  au_dec_cotan(t, m1->F, m1->X, w1);
  au_dec_cotan(t, m2->F, m2->X, w2);
  au_dec_cotan(t, m3->F, m3->X, w3);
  for (int e = 0; e < t->ne; e++) {
    AU_CHECK_NEAR(w1[e], w2[e], 1e-9 * fabs(w1[e]) + 1e-12);
    AU_CHECK_NEAR(w1[e], w3[e], 1e-9 * fabs(w1[e]) + 1e-12);
  }
  free(w1), free(w2), free(w3);
  au_topo_free(&t);
  au_mesh_free(&m1), au_mesh_free(&m2), au_mesh_free(&m3);
  return 0;
}

/* Spherical triangle areas: on the refined octahedron projected onto the unit sphere they sum to
 * 4 pi; an octant is pi/2; corners on one great circle give 0; a tiny triangle's area is its chord
 * area; the gradient matches central differences, also for a triangle of size 1e-9, where the
 * direct cross product of its corners would have lost the digits. */
static int sphere_area_case(void) {
  au_mesh *m = make_surface(3, 1.0);
  AU_CHECK(m != NULL);
  for (int i = 0; i < m->nv; i++) {
    double *p = m->X + 3 * i, r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int d = 0; d < 3; d++) p[d] /= r;
  }
  double *area = malloc(sizeof(double) * m->nf), sum = 0;
  au_dec_sphere_face_areas(m->nf, m->F, m->X, area);
  for (int f = 0; f < m->nf; f++) {
    AU_CHECK_DBL(area[f], >, 0);
    sum += area[f];
  }
  AU_CHECK_NEAR(sum, 4 * M_PI, 1e-12);
  free(area);
  au_mesh_free(&m);
  const double x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1};
  AU_CHECK_NEAR(au_dec_sphere_area(x, y, z, NULL), M_PI / 2, 1e-15);
  AU_CHECK_NEAR(au_dec_sphere_area(y, x, z, NULL), -M_PI / 2, 1e-15);
  const double g1[3] = {cos(0.3), sin(0.3), 0}, g2[3] = {cos(1.1), sin(1.1), 0};
  AU_CHECK_NEAR(au_dec_sphere_area(x, g1, g2, NULL), 0, 1e-16);
  unsigned seed = 7;
  for (int trial = 0; trial < 200; trial++) {
    double size = trial < 100 ? 0.3 : 1e-9, p[3][3], grad[9];
    double c[3] = {rnd(&seed) - 0.5, rnd(&seed) - 0.5, rnd(&seed) - 0.5}, cn = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (int k = 0; k < 3; k++) {
      double r = 0;
      for (int d = 0; d < 3; d++) p[k][d] = c[d] / cn + size * (rnd(&seed) - 0.5), r += p[k][d] * p[k][d];
      for (int d = 0; d < 3; d++) p[k][d] /= sqrt(r);
    }
    double E = au_dec_sphere_area(p[0], p[1], p[2], grad);
    if (size < 1e-6) {
      /* Tiny: the area is the chord triangle's, and the gradient's tangential part is the planar
       * one, 1/2 n x (opposite edge), both from edge differences (finite differences would need
       * steps below the coordinates' rounding). */
      double e1[3], e2[3];
      for (int d = 0; d < 3; d++) e1[d] = p[1][d] - p[0][d], e2[d] = p[2][d] - p[0][d];
      double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), chord = 0.5 * nn;
      AU_CHECK_NEAR(fabs(E), chord, 1e-6 * chord);
      for (int k = 0; k < 3; k++) {
        const double *a = p[(k + 1) % 3], *b = p[(k + 2) % 3];
        double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, g[3], t[3];
        g[0] = 0.5 * (n[1] * e[2] - n[2] * e[1]) / nn, g[1] = 0.5 * (n[2] * e[0] - n[0] * e[2]) / nn;
        g[2] = 0.5 * (n[0] * e[1] - n[1] * e[0]) / nn;
        for (int d = 0; d < 3; d++) g[d] *= E < 0 ? -1 : 1; /* E is signed, the chord area is not */
        double gd = g[0] * p[k][0] + g[1] * p[k][1] + g[2] * p[k][2];
        double sd = grad[3 * k] * p[k][0] + grad[3 * k + 1] * p[k][1] + grad[3 * k + 2] * p[k][2];
        double gl = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        for (int d = 0; d < 3; d++) {
          t[d] = (grad[3 * k + d] - sd * p[k][d]) - (g[d] - gd * p[k][d]);
          AU_CHECK_NEAR(t[d], 0, 1e-6 * gl);
        }
      }
      continue;
    }
    /* Central differences with a step proportional to the triangle (the area is cubic-smooth). */
    double h = 1e-4 * size, gmax = 0;
    for (int q = 0; q < 9; q++) gmax = fmax(gmax, fabs(grad[q]));
    for (int k = 0; k < 3; k++)
      for (int d = 0; d < 3; d++) {
        double keep = p[k][d];
        p[k][d] = keep + h;
        double ep = au_dec_sphere_area(p[0], p[1], p[2], NULL);
        p[k][d] = keep - h;
        double em = au_dec_sphere_area(p[0], p[1], p[2], NULL);
        p[k][d] = keep;
        AU_CHECK_NEAR(grad[3 * k + d], (ep - em) / (2 * h), 1e-5 * gmax);
      }
  }
  return 0;
}

static volatile sig_atomic_t terms;
static void on_term(int sig) {
  (void)sig;
  terms++;
}

/* METIS turns a SIGTERM that arrives while it orders into an error return; au_graph_order holds the
 * signal back for that time, so the ordering succeeds and the signal reaches the program's handler
 * afterwards. A timer sends SIGTERM every millisecond while a 400 x 400 grid is ordered (without the
 * hold: "ordering failed (CHOLMOD status -4)"). */
static int ordering_holds_sigterm(void) {
  const int nx = 400, n = nx * nx;
  int *E = malloc(sizeof(int) * 6 * (size_t)n), *perm = malloc(sizeof(int) * (size_t)n), ne = 0;
  AU_CHECK(E && perm);
  for (int y = 0; y < nx; y++)
    for (int x = 0; x < nx; x++) {
      int i = y * nx + x;
      if (x + 1 < nx) E[2 * ne] = i, E[2 * ne + 1] = i + 1, ne++;
      if (y + 1 < nx) E[2 * ne] = i, E[2 * ne + 1] = i + nx, ne++;
      if (x + 1 < nx && y + 1 < nx) E[2 * ne] = i, E[2 * ne + 1] = i + nx + 1, ne++;
    }
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_term;
  sigemptyset(&sa.sa_mask);
  AU_CHECK(sigaction(SIGTERM, &sa, NULL) == 0);
  struct sigevent ev;
  memset(&ev, 0, sizeof ev);
  ev.sigev_notify = SIGEV_SIGNAL, ev.sigev_signo = SIGTERM;
  timer_t tm;
  AU_CHECK(timer_create(CLOCK_MONOTONIC, &ev, &tm) == 0);
  struct itimerspec its = {{0, 1000000}, {0, 1000000}}, off = {{0, 0}, {0, 0}};
  terms = 0;
  AU_CHECK(timer_settime(tm, 0, &its, NULL) == 0);
  au_msg msg = {{0}};
  au_status st = au_graph_order(n, ne, E, perm, &msg);
  timer_settime(tm, 0, &off, NULL);
  timer_delete(tm);
  /* The counting handler stays: a tick already on its way must not end the test process. */
  fprintf(stderr, "ordering: %s; %d SIGTERMs handled\n", au_status_name(st), (int)terms);
  AU_CHECK_STATUS(st, AU_OK, &msg);
  AU_CHECK_INT(terms, >=, 1);
  /* A permutation. */
  unsigned char *seen = calloc((size_t)n, 1);
  for (int k = 0; k < n; k++) {
    AU_CHECK(perm[k] >= 0 && perm[k] < n && !seen[perm[k]]);
    seen[perm[k]] = 1;
  }
  free(seen), free(E), free(perm);
  return 0;
}

/* The chord floor (au_dec_sphere_chord_floor): never above the chord triangle's area, for random
 * triangles of every size on the unit sphere; reached when the third corner sits right above its
 * foot on the long edge; for a long edge l with the corner above its middle it is l/2 times the
 * chord's depth 1 - sqrt(1 - l^2/4) (about l^3/16), however flat the triangle; a small, round
 * triangle's floor is a small part of its area (about l / 7, l its edge). */
static int sphere_chord_floor_case(void) {
  unsigned seed = 11;
  for (int trial = 0; trial < 3000; trial++) {
    double size = trial % 3 == 0 ? 1.5 : trial % 3 == 1 ? 0.2 : 1e-3, p[3][3];
    double c[3] = {rnd(&seed) - 0.5, rnd(&seed) - 0.5, rnd(&seed) - 0.5}, cn = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (int k = 0; k < 3; k++) {
      double r = 0;
      for (int d = 0; d < 3; d++) p[k][d] = c[d] / cn + size * (rnd(&seed) - 0.5), r += p[k][d] * p[k][d];
      for (int d = 0; d < 3; d++) p[k][d] /= sqrt(r);
    }
    double e1[3], e2[3];
    for (int d = 0; d < 3; d++) e1[d] = p[1][d] - p[0][d], e2[d] = p[2][d] - p[0][d];
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double chord = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double fl = au_dec_sphere_chord_floor(p[0], p[1], p[2]);
    AU_CHECK_DBL(fl, >=, 0);
    AU_CHECK_DBL(fl, <=, chord * (1 + 1e-12) + 1e-300);
    /* Invariant under the order of the corners. */
    AU_CHECK_NEAR(au_dec_sphere_chord_floor(p[2], p[0], p[1]), fl, 1e-15);
  }
  /* A long edge on the equator, the third corner above its middle, a little off the great circle:
   * the chord area tends to the floor as the triangle flattens. */
  for (int i = 0; i < 4; i++) {
    double l = 0.1 + 0.2 * i, h = asin(l / 2);
    double a[3] = {cos(h), -sin(h), 0}, b[3] = {cos(h), sin(h), 0}, c[3] = {cos(1e-6), 0, sin(1e-6)};
    double want = 0.5 * l * (1 - sqrt(1 - l * l / 4));
    AU_CHECK_NEAR(au_dec_sphere_chord_floor(a, b, c), want, 1e-12);
    AU_CHECK_NEAR(want, l * l * l / 16, 0.02 * l * l * l / 16 + l * l * l * l * l / 100);
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double chord = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    AU_CHECK_NEAR(chord, want, 1e-3 * want);
  }
  /* A small equilateral triangle: its floor is a tiny part of its area. */
  double s = 0.01, q[3][3];
  for (int k = 0; k < 3; k++) {
    double ang = 2 * M_PI * k / 3;
    q[k][0] = s * cos(ang), q[k][1] = s * sin(ang), q[k][2] = 1;
    double r = sqrt(q[k][0] * q[k][0] + q[k][1] * q[k][1] + 1);
    for (int d = 0; d < 3; d++) q[k][d] /= r;
  }
  double area = 0.75 * sqrt(3.0) * s * s; /* about: the corners were pushed onto the sphere */
  AU_CHECK_DBL(au_dec_sphere_chord_floor(q[0], q[1], q[2]), <, 0.01 * area); /* about l / 7 of it */
  AU_CHECK_DBL(au_dec_sphere_chord_floor(q[0], q[1], q[2]), >, 0);
  return 0;
}

/* The split factorization (two halves on two threads joined by a dense separator block) solves
 * what the whole one solves: a 2V system with 2 x 2 blocks on a refined sphere's edges (a Laplacian
 * with SPD blocks plus a small diagonal), split and whole, same solution to 1e-10 and a residual
 * below 1e-10; refactored with new values; an indefinite matrix is refused by both. */
static int spd_split_case(void) {
  au_mesh *m = make_surface(5, 1.0);
  AU_CHECK(m != NULL);
  au_topo *t = NULL;
  AU_CHECK_STATUS(au_mesh_topology(m, &t, NULL), AU_OK, (au_msg *)NULL);
  const int nv = m->nv, n = 2 * nv;
  /* Upper triangle pattern, column by column, rows sorted: the vertex's own block and its edges'. */
  int *cnt = calloc((size_t)n + 1, sizeof(int));
  for (int i = 0; i < nv; i++) cnt[2 * i + 1] += 1, cnt[2 * i + 2] += 2;
  for (int e = 0; e < t->ne; e++) {
    int b = t->E[2 * e + 1];
    cnt[2 * b + 1] += 2, cnt[2 * b + 2] += 2;
  }
  for (int j = 0; j < n; j++) cnt[j + 1] += cnt[j];
  int *rows = malloc(sizeof(int) * (size_t)cnt[n]), *fill = malloc(sizeof(int) * (size_t)n);
  memcpy(fill, cnt, sizeof(int) * (size_t)n);
  for (int e = 0; e < t->ne; e++) {
    int a = t->E[2 * e], b = t->E[2 * e + 1];
    for (int q = 0; q < 2; q++)
      for (int p = 0; p < 2; p++) rows[fill[2 * b + q]++] = 2 * a + p;
  }
  for (int i = 0; i < nv; i++) rows[fill[2 * i]++] = 2 * i, rows[fill[2 * i + 1]++] = 2 * i, rows[fill[2 * i + 1]++] = 2 * i + 1;
  for (int j = 0; j < n; j++) /* insertion sort */
    for (int q = cnt[j] + 1; q < cnt[j + 1]; q++)
      for (int r = q; r > cnt[j] && rows[r - 1] > rows[r]; r--) {
        int tmp = rows[r];
        rows[r] = rows[r - 1], rows[r - 1] = tmp;
      }
  au_spd *sp[2] = {NULL, NULL};
  au_msg msg = {{0}};
  const int keep = au__spd_split_min;
  au__spd_split_min = 0;
  AU_CHECK_STATUS(au_spd_create(n, cnt, rows, NULL, &sp[0], &msg), AU_OK, &msg);
  au__spd_split_min = 1 << 30;
  AU_CHECK_STATUS(au_spd_create(n, cnt, rows, NULL, &sp[1], &msg), AU_OK, &msg);
  au__spd_split_min = keep;
  int ns = au__spd_split_size(sp[0]);
  AU_CHECK_INT(ns, >, 0);
  AU_CHECK_INT(ns, <, n / 8);
  AU_CHECK_INT(au__spd_split_size(sp[1]), ==, 0);
  unsigned seed = 5;
  double *b = malloc(sizeof(double) * (size_t)n), *x[2] = {malloc(sizeof(double) * (size_t)n), malloc(sizeof(double) * (size_t)n)};
  double *ax = malloc(sizeof(double) * (size_t)n);
  for (int round = 0; round < 3; round++) {
    for (int k = 0; k < 2; k++) {
      double *v = au_spd_values(sp[k]);
      memset(v, 0, sizeof(double) * (size_t)cnt[n]);
      unsigned vs = 17 + (unsigned)round; /* the same values in both */
      for (int e = 0; e < t->ne; e++) {
        int a = t->E[2 * e], bb = t->E[2 * e + 1];
        double w = 0.5 + rnd(&vs), c = rnd(&vs) - 0.5, K[2][2] = {{2, c}, {c, 1}};
        for (int q = 0; q < 2; q++)
          for (int p = 0; p < 2; p++) {
            /* -w K at (2a+p, 2bb+q); +w K on both diagonal blocks */
            for (int r = cnt[2 * bb + q]; r < cnt[2 * bb + q + 1]; r++)
              if (rows[r] == 2 * a + p) v[r] -= w * K[p][q];
            if (p <= q) {
              for (int r = cnt[2 * a + q]; r < cnt[2 * a + q + 1]; r++)
                if (rows[r] == 2 * a + p) v[r] += w * K[p][q];
              for (int r = cnt[2 * bb + q]; r < cnt[2 * bb + q + 1]; r++)
                if (rows[r] == 2 * bb + p) v[r] += w * K[p][q];
            }
          }
      }
      for (int j = 0; j < n; j++) v[cnt[j + 1] - 1] += 0.01; /* the diagonal is last in its column */
      AU_CHECK_STATUS(au_spd_factor(sp[k], &msg), AU_OK, &msg);
    }
    double nb = 0;
    for (int i = 0; i < n; i++) b[i] = rnd(&seed) - 0.5, nb = fmax(nb, fabs(b[i]));
    for (int k = 0; k < 2; k++) AU_CHECK_STATUS(au_spd_solve(sp[k], b, x[k], &msg), AU_OK, &msg);
    double dx = 0, nx = 0;
    for (int i = 0; i < n; i++) dx = fmax(dx, fabs(x[0][i] - x[1][i])), nx = fmax(nx, fabs(x[1][i]));
    AU_CHECK_DBL(dx, <=, 1e-10 * nx);
    /* Residual of the split solution, with the upper triangle applied symmetrically. */
    const double *v = au_spd_values(sp[0]);
    memset(ax, 0, sizeof(double) * (size_t)n);
    for (int j = 0; j < n; j++)
      for (int r = cnt[j]; r < cnt[j + 1]; r++) {
        ax[rows[r]] += v[r] * x[0][j];
        if (rows[r] != j) ax[j] += v[r] * x[0][rows[r]];
      }
    double res = 0;
    for (int i = 0; i < n; i++) res = fmax(res, fabs(ax[i] - b[i]));
    AU_CHECK_DBL(res, <=, 1e-10 * nb);
  }
  /* Indefinite: one diagonal entry made negative. */
  for (int k = 0; k < 2; k++) {
    au_spd_values(sp[k])[cnt[n / 2 + 1] - 1] = -5;
    AU_CHECK_STATUS(au_spd_factor(sp[k], &msg), AU_E_NOT_SPD, &msg);
  }
  for (int k = 0; k < 2; k++) au_spd_free(&sp[k]), free(x[k]);
  free(b), free(ax), free(cnt), free(rows), free(fill);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}

/* OpenMP regions (the program's tools/cli_threads.c): with OMP_THREAD_LIMIT=1 (set by ctest for gomp_inline, as the command
 * line sets it) a region's body runs once, on the calling thread, and CHOLMOD's supernodal
 * factorization reaches the program's GOMP_parallel; with a limit of 2 (gomp_forward) a region asked
 * for two threads gets them from libgomp. */
typedef struct gomp_probe {
  pthread_t caller;
  int calls, on_caller;
} gomp_probe;

static void gomp_body(void *arg) {
  gomp_probe *p = arg;
  __atomic_fetch_add(&p->calls, 1, __ATOMIC_RELAXED);
  if (pthread_equal(pthread_self(), p->caller)) __atomic_fetch_add(&p->on_caller, 1, __ATOMIC_RELAXED);
}

void GOMP_parallel(void (*fn)(void *), void *data, unsigned num_threads, unsigned flags);

static int gomp_case(int limit) {
  const char *e = getenv("OMP_THREAD_LIMIT");
  AU_CHECK(e != NULL && atoi(e) == limit);
  gomp_probe p = {pthread_self(), 0, 0};
  long before = cli_gomp_inline_regions();
  GOMP_parallel(gomp_body, &p, 2, 0);
  AU_CHECK_INT(p.calls, ==, limit == 1 ? 1 : 2);
  AU_CHECK_INT(p.on_caller, ==, 1);
  AU_CHECK_INT((int)(cli_gomp_inline_regions() - before), ==, limit == 1 ? 1 : 0);
  if (limit != 1) return 0;
  /* CHOLMOD's regions come here: a 40 x 40 grid's Laplacian, factored supernodally. */
  int n = 40, nv = n * n, ne = 0;
  int *E = malloc(sizeof(int) * 4 * (size_t)nv);
  unsigned char *fixed = calloc((size_t)nv, 1);
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      if (i + 1 < n) E[2 * ne] = j * n + i, E[2 * ne + 1] = j * n + i + 1, ne++;
      if (j + 1 < n) E[2 * ne] = j * n + i, E[2 * ne + 1] = (j + 1) * n + i, ne++;
    }
  fixed[0] = 1;
  double *w = malloc(sizeof(double) * (size_t)ne);
  for (int k = 0; k < ne; k++) w[k] = 1;
  au_solver *sv = NULL;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_solver_create(nv, ne, E, fixed, AU_ORDER_FILL, &sv, &msg), AU_OK, &msg);
  before = cli_gomp_inline_regions();
  AU_CHECK_STATUS(au_solver_factor(sv, w, NULL, &msg), AU_OK, &msg);
  AU_CHECK_INT((int)(cli_gomp_inline_regions() - before), >, 0);
  au_solver_free(&sv);
  free(E), free(fixed), free(w);
  return 0;
}

static int gomp_inline_case(void) { return gomp_case(1); }
static int gomp_forward_case(void) { return gomp_case(2); }

int main(int argc, char **argv) {
  static const au_test_case cases[] = {
      {"ordering_holds_sigterm", ordering_holds_sigterm},
      {"stiffness_props", stiffness_props_case},       {"stiffness_dirichlet", stiffness_dirichlet_case},
      {"grad_linear", grad_linear_case},               {"areas_sum", areas_sum_case},
      {"cotan_scale", cotan_scale_case},               {"solver_linear_exact", solver_linear_exact},
      {"sphere_area", sphere_area_case},               {"sphere_chord_floor", sphere_chord_floor_case},
      {"spd_split", spd_split_case},
      {"gomp_inline", gomp_inline_case},               {"gomp_forward", gomp_forward_case},
  };
  return au_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0]));
}
