/* au_torus_init.c - the conformal start of a closed genus-1 mesh on its flat torus, with no cut:
 * harmonic 1-forms from the tree-cotree basis (au_torus_homology.c), the conjugate by the Gram
 * system, the period lattice reduced and normalized, and the seamless texture coordinates.
 * Method: Gu & Yau 2003 ("Global conformal surface parameterization"), discretized as in
 * ../shared/DESIGN.md ("Genus 1"); the positive-weight fallback is Gortler, Gotsman & Thurston 2006
 * ("Discrete one-forms on meshes and applications to 3D mesh parameterization"). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_dec.h"
#include "au_disk_internal.h"
#include "au_solver.h"
#include "au_torus.h"

void au_torus_start_free(au_torus_start **s) {
  if (!s || !*s) return;
  free((*s)->U), free((*s)->off);
  free(*s);
  *s = NULL;
}

/* The value of h_k = omega_k + dU_k on edge e directed E[2e] -> E[2e+1]; U is column-major (nv x 2). */
static double edge_h(const au_topo *t, const double *U, const int *omega, int k, int e) {
  int i = t->E[2 * e], j = t->E[2 * e + 1];
  return U[(size_t)k * t->nv + j] - U[(size_t)k * t->nv + i] + omega[(size_t)k * t->ne + e];
}

/* The lattice coordinates U (column-major nv x 2) of the harmonic forms with weights w: the
 * divergence of h_k = omega_k + dU_k vanishes at every vertex, C U_k = b_k with
 * b_i = sum_j w_ij omega_k(i -> j); one vertex pinned at 0, one factorization for both columns. */
static au_status solve_coords(const au_topo *t, const double *w, const int *omega, double *U, au_msg *msg) {
  int nv = t->nv, ne = t->ne;
  unsigned char *fixed = malloc((size_t)nv);
  double *b = calloc(2 * (size_t)nv, sizeof *b);
  au_solver *s = NULL;
  au_status st = AU_OK;
  if (!fixed || !b) {
    st = au_msg_set(msg, AU_E_NOMEM, "torus: out of memory for the harmonic forms");
    goto done;
  }
  int pinned = -1;
  for (int i = 0; i < nv; i++) {
    fixed[i] = !t->vused[i];
    if (!fixed[i] && pinned < 0) pinned = i, fixed[i] = 1;
  }
  for (int k = 0; k < 2; k++)
    for (int e = 0; e < ne; e++) {
      double q = w[e] * omega[(size_t)k * ne + e];
      b[(size_t)k * nv + t->E[2 * e]] += q, b[(size_t)k * nv + t->E[2 * e + 1]] -= q;
    }
  memset(U, 0, 2 * (size_t)nv * sizeof *U);
  st = au_solver_create(nv, ne, t->E, fixed, AU_ORDER_FAST, &s, msg);
  if (st == AU_OK) st = au_solver_factor(s, w, NULL, msg);
  if (st == AU_OK) st = au_solver_solve(s, 2, b, U, msg);
done:
  au_solver_free(&s);
  free(fixed), free(b);
  return st;
}

/* The values of h_k on the two edges of face f leaving corner 0: d[k][0] on c0 -> c1, d[k][1] on c0 -> c2. */
static void face_h(const au_topo *t, const int *F, const double *U, const int *omega, int f, double d[2][2]) {
  int e2 = t->FE[3 * f + 2], e1 = t->FE[3 * f + 1]; /* e2 joins c0, c1; e1 joins c2, c0 */
  double s2 = t->E[2 * e2] == F[3 * f] ? 1 : -1, s1 = t->E[2 * e1] == F[3 * f] ? 1 : -1;
  for (int k = 0; k < 2; k++) d[k][0] = s2 * edge_h(t, U, omega, k, e2), d[k][1] = s1 * edge_h(t, U, omega, k, e1);
}

/* The conjugate *h_1 = a h_1 + b h_2: G (a, b)^T = (int h_1 ^ h_1, int h_1 ^ h_2) = (0, W) with the
 * Gram matrix G of the cotan inner product and W the Whitney wedge of closed forms, per face
 * (d1(c0c1) d2(c0c2) - d1(c0c2) d2(c0c1)) / 2. gap gets the relative distance of the per-face
 * rotated gradient of h_1 (its star) from a h_1 + b h_2. Returns 0, or -1 for a singular system. */
static int conjugate(const au_mesh *m, const au_topo *t, const double *w, const double *U, const int *omega,
                     double *a, double *b, double *gap) {
  double G[2][2] = {{0, 0}, {0, 0}}, W = 0;
  for (int e = 0; e < t->ne; e++) {
    double h1 = edge_h(t, U, omega, 0, e), h2 = edge_h(t, U, omega, 1, e);
    G[0][0] += w[e] * h1 * h1, G[0][1] += w[e] * h1 * h2, G[1][1] += w[e] * h2 * h2;
  }
  for (int f = 0; f < m->nf; f++) {
    double d[2][2];
    face_h(t, m->F, U, omega, f, d);
    W += 0.5 * (d[0][0] * d[1][1] - d[0][1] * d[1][0]);
  }
  double det = G[0][0] * G[1][1] - G[0][1] * G[0][1];
  if (!(fabs(det) > 1e-300) || !isfinite(det)) return -1;
  *a = -G[0][1] * W / det, *b = G[0][0] * W / det;
  /* The star's inexactness: per face, gradients g_k of h_k, the star n x g_1 / |n|. */
  double num = 0, den = 0;
  for (int f = 0; f < m->nf; f++) {
    const double *x0 = m->X + 3 * (size_t)m->F[3 * f], *x1 = m->X + 3 * (size_t)m->F[3 * f + 1],
                 *x2 = m->X + 3 * (size_t)m->F[3 * f + 2];
    double e1[3] = {x1[0] - x0[0], x1[1] - x0[1], x1[2] - x0[2]}, e2[3] = {x2[0] - x0[0], x2[1] - x0[1], x2[2] - x0[2]};
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (!(nn > 0)) continue;
    double d[2][2], g[2][3];
    face_h(t, m->F, U, omega, f, d);
    for (int k = 0; k < 2; k++) /* g = (d1 (e2 x n) + d2 (n x e1)) / |n|^2 */
      for (int c = 0; c < 3; c++) {
        int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
        g[k][c] = (d[k][0] * (e2[c1] * n[c2] - e2[c2] * n[c1]) + d[k][1] * (n[c1] * e1[c2] - n[c2] * e1[c1])) / nn;
      }
    double rn = 1 / sqrt(nn), area = 0.5 * sqrt(nn), r2 = 0, g2 = 0;
    for (int c = 0; c < 3; c++) {
      int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
      double star = (n[c1] * g[0][c2] - n[c2] * g[0][c1]) * rn;
      double diff = star - (*a * g[0][c] + *b * g[1][c]);
      r2 += diff * diff, g2 += g[0][c] * g[0][c];
    }
    num += area * r2, den += area * g2;
  }
  *gap = den > 0 ? sqrt(num / den) : 0;
  return 0;
}

/* Lattice coordinates of face f's corners lifted from corner 0: q[k] = U(c_k) + offset_k. */
static void lifted(const au_torus_start *s, const int *F, int f, double q[3][2]) {
  for (int k = 0; k < 3; k++) {
    const double *u = s->U + 2 * (size_t)F[3 * f + k];
    const int *o = s->off + 6 * (size_t)f + 2 * k;
    q[k][0] = u[0] + o[0], q[k][1] = u[1] + o[1];
  }
}

double au_torus_face_area(const au_torus_start *s, const int *F, int f) {
  double q[3][2];
  lifted(s, F, f, q);
  return 0.5 * ((q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]));
}

int au_torus_count_folds(const au_torus_start *s, const int *F) {
  int n = 0;
  for (int f = 0; f < s->nf; f++) n += !(au_torus_face_area(s, F, f) > 0);
  return n;
}

/* Corner offsets from the integer forms: corner 0 at (0, 0), corner k at omega(c0 -> ck). */
static void corner_offsets(const au_topo *t, const int *F, const int *omega, int *off) {
  for (int f = 0; f < t->nf; f++) {
    int e2 = t->FE[3 * f + 2], e1 = t->FE[3 * f + 1];
    int s2 = t->E[2 * e2] == F[3 * f] ? 1 : -1, s1 = t->E[2 * e1] == F[3 * f] ? 1 : -1;
    int *o = off + 6 * (size_t)f;
    for (int k = 0; k < 2; k++) o[k] = 0, o[2 + k] = s2 * omega[(size_t)k * t->ne + e2], o[4 + k] = s1 * omega[(size_t)k * t->ne + e1];
  }
}

/* Apply the integer change of lattice coordinates u' = T u to every vertex and corner offset. */
static void transform(au_torus_start *s, const long T[2][2]) {
  for (int i = 0; i < s->nv; i++) {
    double *u = s->U + 2 * (size_t)i, u0 = u[0], u1 = u[1];
    u[0] = (double)T[0][0] * u0 + (double)T[0][1] * u1, u[1] = (double)T[1][0] * u0 + (double)T[1][1] * u1;
  }
  for (size_t c = 0; c < 3 * (size_t)s->nf; c++) {
    int *o = s->off + 2 * c;
    long o0 = o[0], o1 = o[1];
    o[0] = (int)(T[0][0] * o0 + T[0][1] * o1), o[1] = (int)(T[1][0] * o0 + T[1][1] * o1);
  }
}

/* Orient, reduce, rotate and scale the period lattice, whose basis is the columns of M (the plane
 * map is p = M u). On return s->U and s->off are in the reduced basis, s->conformal holds it.
 * Returns 0, or -1 if the lattice is degenerate. */
static int normalize_lattice(au_torus_start *s, const int *F, double M[2][2]) {
  double S = 0;
  for (int f = 0; f < s->nf; f++) S += au_torus_face_area(s, F, f);
  if (S < 0) { /* the generators came in the surface's clockwise order: swap them */
    transform(s, (const long[2][2]){{0, 1}, {1, 0}});
    for (int r = 0; r < 2; r++) {
      double x = M[r][0];
      M[r][0] = M[r][1], M[r][1] = x;
    }
  }
  if (M[0][0] * M[1][1] - M[0][1] * M[1][0] < 0) M[1][0] = -M[1][0], M[1][1] = -M[1][1];
  double m1[2] = {M[0][0], M[1][0]}, m2[2] = {M[0][1], M[1][1]};
  long T[2][2] = {{1, 0}, {0, 1}}; /* u' = T u, accumulated */
  for (int it = 0; it < 200; it++) { /* Lagrange-Gauss reduction, det kept */
    if (m1[0] * m1[0] + m1[1] * m1[1] > m2[0] * m2[0] + m2[1] * m2[1]) {
      double x0 = m1[0], x1 = m1[1];
      m1[0] = m2[0], m1[1] = m2[1], m2[0] = -x0, m2[1] = -x1; /* (m1, m2) <- (m2, -m1): u' = (u2, -u1) */
      long r0[2] = {T[0][0], T[0][1]};
      T[0][0] = T[1][0], T[0][1] = T[1][1], T[1][0] = -r0[0], T[1][1] = -r0[1];
    }
    double mu = nearbyint((m1[0] * m2[0] + m1[1] * m2[1]) / (m1[0] * m1[0] + m1[1] * m1[1]));
    if (mu == 0 || !isfinite(mu)) break;
    m2[0] -= mu * m1[0], m2[1] -= mu * m1[1]; /* u1' = u1 + mu u2 */
    T[0][0] += (long)mu * T[1][0], T[0][1] += (long)mu * T[1][1];
  }
  double det = m1[0] * m2[1] - m1[1] * m2[0], l1 = hypot(m1[0], m1[1]);
  if (!(det > 0) || !isfinite(det) || !(l1 > 0)) return -1;
  transform(s, (const long(*)[2])T);
  double c = m1[0] / l1, sn = m1[1] / l1, sc = 1 / sqrt(det);
  s->conformal[0][0] = sc * l1, s->conformal[0][1] = 0;
  s->conformal[1][0] = sc * (c * m2[0] + sn * m2[1]), s->conformal[1][1] = sc * (-sn * m2[0] + c * m2[1]);
  return 0;
}

/* Vertices into [0, 1)^2 (their corners' offsets compensate), then each face translated by the
 * lattice vector that puts its lifted centroid into [0, 1)^2. */
static void to_fundamental_domain(au_torus_start *s, const int *F) {
  for (int f = 0; f < s->nf; f++)
    for (int k = 0; k < 3; k++) {
      const double *u = s->U + 2 * (size_t)F[3 * f + k];
      int *o = s->off + 6 * (size_t)f + 2 * k;
      o[0] += (int)floor(u[0]), o[1] += (int)floor(u[1]);
    }
  for (int i = 0; i < 2 * s->nv; i++) s->U[i] -= floor(s->U[i]);
  for (int f = 0; f < s->nf; f++) {
    double q[3][2];
    lifted(s, F, f, q);
    int c0 = (int)floor((q[0][0] + q[1][0] + q[2][0]) / 3), c1 = (int)floor((q[0][1] + q[1][1] + q[2][1]) / 3);
    for (int k = 0; k < 3; k++) s->off[6 * (size_t)f + 2 * k] -= c0, s->off[6 * (size_t)f + 2 * k + 1] -= c1;
  }
}

/* The topology check of the torus map, in the words a user needs: the genus found and what is
 * supported. Returns AU_OK or AU_E_BOUNDARY / AU_E_GENUS / AU_E_ARG. */
static au_status check_torus(const au_mesh *m, const au_topo *t, au_msg *msg) {
  if (!m || !t || t->nv != m->nv || t->nf != m->nf || m->nf <= 0) return au_msg_set(msg, AU_E_ARG, "torus: bad arguments");
  if (t->ncomponents != 1)
    return au_msg_set(msg, AU_E_COMPONENTS, "mesh has %d connected components; the torus map needs one", t->ncomponents);
  if (t->nloops != 0)
    return au_msg_set(msg, AU_E_BOUNDARY, "mesh has %d boundary loop%s (genus %d); the torus map needs a closed genus-1 "
                                          "surface", t->nloops, t->nloops == 1 ? "" : "s", t->genus);
  if (t->genus != 1)
    return au_msg_set(msg, AU_E_GENUS, "mesh has genus %d; the torus map needs a closed genus-1 surface%s", t->genus,
                      t->genus == 0 ? " (map a genus-0 mesh onto the sphere)" : " (higher genus is not supported)");
  return AU_OK;
}

/* The start with weights w and the plane map M (columns: the generators' periods), into s. */
static au_status place(const au_mesh *m, const au_topo *t, const double *w, const int *omega, double M[2][2],
                       au_torus_start *s, double *Ucol, au_msg *msg) {
  au_status st = solve_coords(t, w, omega, Ucol, msg);
  if (st != AU_OK) return st;
  for (int i = 0; i < m->nv; i++) s->U[2 * i] = Ucol[i], s->U[2 * i + 1] = Ucol[(size_t)m->nv + i];
  corner_offsets(t, m->F, omega, s->off);
  if (normalize_lattice(s, m->F, M) != 0) return au_msg_set(msg, AU_E_NUMERIC, "torus: the period lattice is degenerate");
  to_fundamental_domain(s, m->F);
  s->folds = au_torus_count_folds(s, m->F);
  return AU_OK;
}

/* The compressed start is made when the start's most squeezed triangle has less than e^this of its
 * share of the area: the flow opens a protrusion from e^-9 (rocker_arm) but stalls at e^-57 (data/mug's
 * spout), and e^-37 is where a lattice coordinate of about 1 stops resolving a triangle's extent. */
#define AU_TORUS_SQUEEZE_LOG (-20.0)
/* The largest jump of the flat log scale across a squeezed triangle left by the compression: a protrusion
 * squeezed like e^-x comes out like e^-(x AU_TORUS_JUMP / its jump): data/mug's spout e^-56 into e^-16. */
#define AU_TORUS_JUMP 0.1
/* A clamped weight's floor, as a part of the face's largest cotan term: positive weights embed (GGT 2006). */
#define AU_TORUS_WEIGHT_FLOOR 1e-3

static double tri_area(const double *X, const int *v) {
  const double *p = X + 3 * (size_t)v[0], *q = X + 3 * (size_t)v[1], *r = X + 3 * (size_t)v[2];
  double e1[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, e2[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
  double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  return 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

static int cmp_dbl(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The least log of a face's share of the domain over its share of the surface (-inf if one folded). */
static double min_log_ratio(const au_mesh *m, const au_torus_start *s) {
  double Ssurf = 0, Sdom = 0, lo = INFINITY;
  for (int f = 0; f < m->nf; f++) Ssurf += tri_area(m->X, m->F + 3 * f), Sdom += au_torus_face_area(s, m->F, f);
  for (int f = 0; f < m->nf; f++) {
    double a = au_torus_face_area(s, m->F, f), A = tri_area(m->X, m->F + 3 * f);
    if (!(a > 0)) return -INFINITY;
    if (A > 0) lo = fmin(lo, log((a / Sdom) / (A / Ssurf)));
  }
  return lo;
}

/* The flat log scale u of the surface: e^(2u) g is flat, so L u = -K with L the cotan Laplacian (w) and
 * K the angle defects (their sum is 0 on a torus: Gauss-Bonnet). A protrusion, which every harmonic map
 * squeezes, is where u falls fast; unlike the start's own areas, u does not underflow there. */
static au_status flat_log_scale(const au_mesh *m, const au_topo *t, const double *w, double *u, au_msg *msg) {
  int nv = m->nv, pinned = -1;
  unsigned char *fixed = malloc((size_t)nv);
  double *b = calloc((size_t)nv, sizeof *b);
  au_solver *sv = NULL;
  au_status st = AU_OK;
  if (!fixed || !b) {
    st = au_msg_set(msg, AU_E_NOMEM, "torus: out of memory for the flat log scale");
    goto done;
  }
  for (int i = 0; i < nv; i++) {
    fixed[i] = !t->vused[i];
    if (!fixed[i] && pinned < 0) pinned = i, fixed[i] = 1;
    if (t->vused[i]) b[i] = -2 * M_PI;
  }
  for (int f = 0; f < m->nf; f++)
    for (int k = 0; k < 3; k++) {
      const double *p = m->X + 3 * (size_t)m->F[3 * f + k], *q = m->X + 3 * (size_t)m->F[3 * f + (k + 1) % 3],
                   *r = m->X + 3 * (size_t)m->F[3 * f + (k + 2) % 3];
      double e1[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, e2[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
      double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      b[m->F[3 * f + k]] += atan2(sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]),
                                  e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]);
    }
  memset(u, 0, sizeof(double) * (size_t)nv);
  st = au_solver_create(nv, t->ne, t->E, fixed, AU_ORDER_FAST, &sv, msg);
  if (st == AU_OK) st = au_solver_factor(sv, w, NULL, msg);
  if (st == AU_OK) st = au_solver_solve(sv, 1, b, u, msg);
done:
  au_solver_free(&sv);
  free(fixed), free(b);
  return st;
}

/* Weights of the surface with its protrusions compressed along their length and their bands turned (as
 * the sphere's twisted start, sphere/au_sphere_init.c; docs/torus-hard-shapes.md): where u jumps by more
 * than AU_TORUS_JUMP across a triangle in the squeezed half (u below its median), the triangle is shrunk
 * along grad u by AU_TORUS_JUMP / jump, so a tube of length L and girth C, squeezed like e^(-4 pi L / C),
 * behaves like a shorter one, and then sheared along its girth (below). The cotan weights of the changed
 * triangles, clamped to a small positive floor when clamp is 1 (positive weights embed, GGT 2006); the
 * map is no longer conformal. Returns the number of faces changed, or -1 (out of memory). */
static int compressed_weights(const au_mesh *m, const au_topo *t, const double *u, int clamp, double *w) {
  int nf = m->nf, nv = m->nv, n = 0, nc = 0;
  double *G = malloc(3 * sizeof(double) * (size_t)nf), *us = malloc(sizeof(double) * (size_t)nv);
  if (!G || !us) {
    free(G), free(us);
    return -1;
  }
  for (int i = 0; i < nv; i++)
    if (t->vused[i]) us[n++] = u[i];
  qsort(us, (size_t)n, sizeof *us, cmp_dbl);
  double umid = n ? us[n / 2] : 0;
  au_dec_face_grad(nf, m->F, m->X, u, G);
  memset(w, 0, sizeof(double) * (size_t)t->ne);
  for (int f = 0; f < nf; f++) {
    const int *v = m->F + 3 * f;
    double x[3][3], g[3] = {G[3 * f], G[3 * f + 1], G[3 * f + 2]};
    for (int k = 0; k < 3; k++) memcpy(x[k], m->X + 3 * (size_t)v[k], sizeof x[k]);
    double cn = 2 * tri_area(m->X, v), gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    double jump = gn * sqrt(2 * cn / sqrt(3.0));
    int squeeze = cn > 0 && gn > 0 && jump > AU_TORUS_JUMP && u[v[0]] + u[v[1]] + u[v[2]] < 3 * umid;
    if (squeeze) {
      nc++;
      au_dec_tri_compress(x, g, gn, AU_TORUS_JUMP / jump);
      /* Sheared along the girth, as the sphere's twisted start (sphere/au_sphere_init.c), with the surface
       * triangle's normal. */
      const double *p0 = m->X + 3 * (size_t)v[0], *p1 = m->X + 3 * (size_t)v[1], *p2 = m->X + 3 * (size_t)v[2];
      double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]}, e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
      double nrm[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      au_dec_tri_twist(x, nrm, cn, g, gn);
    }
    double c[3], cmax = 0;
    au_dec_tri_cotans((const double(*)[3])x, c);
    for (int k = 0; k < 3; k++) cmax = fmax(cmax, c[k]);
    /* c[k] is the cotan of corner k: the weight of the opposite edge, FE[3f + k]. */
    for (int k = 0; k < 3; k++) w[t->FE[3 * f + k]] += clamp && squeeze ? fmax(c[k], AU_TORUS_WEIGHT_FLOOR * cmax) : c[k];
  }
  free(G), free(us);
  return nc;
}

au_status au_torus_init(const au_mesh *m, const au_topo *t, au_torus_start **out, au_msg *msg) {
  if (!out) return au_msg_set(msg, AU_E_ARG, "torus: out is NULL");
  *out = NULL;
  au_status st = check_torus(m, t, msg);
  if (st != AU_OK) return st;
  int nv = m->nv, ne = t->ne;
  au_torus_start *s = calloc(1, sizeof *s);
  int *omega = malloc(2 * sizeof(int) * (size_t)ne);
  double *w = malloc(sizeof(double) * (size_t)ne), *Ucol = malloc(2 * sizeof(double) * (size_t)nv);
  if (s) s->U = malloc(2 * sizeof(double) * (size_t)nv), s->off = malloc(6 * sizeof(int) * (size_t)m->nf);
  if (!s || !s->U || !s->off || !omega || !w || !Ucol) {
    st = au_msg_set(msg, AU_E_NOMEM, "torus: out of memory");
    goto done;
  }
  s->nv = nv, s->nf = m->nf;
  if ((st = au_torus_homology(t, m->F, s->gen, omega, msg)) != AU_OK) goto done;
  au_dec_cotan(t, m->F, m->X, w);
  if ((st = solve_coords(t, w, omega, Ucol, msg)) != AU_OK) goto done;
  double a, b, M[2][2], Mc[2][2];
  if (conjugate(m, t, w, Ucol, omega, &a, &b, &s->star_gap) != 0 || !(fabs(b) > 0)) {
    st = au_msg_set(msg, AU_E_NUMERIC, "torus: the harmonic forms are degenerate (singular Gram matrix)");
    goto done;
  }
  /* x = U_1 (the integral of h_1), y = a U_1 + b U_2 (the integral of *h_1). */
  memcpy(Mc, (double[2][2]){{1, 0}, {a, b}}, sizeof Mc);
  memcpy(M, Mc, sizeof M);
  s->weights = AU_TORUS_COTAN;
  if ((st = place(m, t, w, omega, M, s, Ucol, msg)) != AU_OK) goto done;
  if (s->folds > 0) {
    /* Negative cotan weights folded the start: positive weights embed (GGT 2006); the lattice stays. */
    s->cotan_folds = s->folds, s->weights = AU_TORUS_MEANVALUE;
    au__disk_meanvalue_weights(t, m->F, m->X, w);
    memcpy(M, Mc, sizeof M);
    if ((st = place(m, t, w, omega, M, s, Ucol, msg)) != AU_OK) goto done;
  }
  s->squeeze = min_log_ratio(m, s);
  if (s->squeeze < AU_TORUS_SQUEEZE_LOG) {
    /* A protrusion squeezed past what the flow opens (or past a double): the compressed start. */
    au_torus_start keep = *s;
    double *u = malloc(sizeof(double) * (size_t)nv), *U0 = malloc(2 * sizeof(double) * (size_t)nv);
    int *off0 = malloc(6 * sizeof(int) * (size_t)m->nf);
    if (!u || !U0 || !off0) {
      free(u), free(U0), free(off0);
      st = au_msg_set(msg, AU_E_NOMEM, "torus: out of memory");
      goto done;
    }
    memcpy(U0, s->U, 2 * sizeof(double) * (size_t)nv);
    memcpy(off0, s->off, 6 * sizeof(int) * (size_t)m->nf);
    au_dec_cotan(t, m->F, m->X, w);
    st = flat_log_scale(m, t, w, u, msg);
    /* Clamped first: positive weights, and the flow ends nearer equal area from them (docs/torus-hard-shapes.md);
     * where their start folds in floating point (they compress less), the unclamped cotan weights. */
    for (int clamp = 1; st == AU_OK && clamp >= 0; clamp--) {
      if (compressed_weights(m, t, u, clamp, w) < 0) st = au_msg_set(msg, AU_E_NOMEM, "torus: out of memory");
      memcpy(M, Mc, sizeof M);
      if (st == AU_OK) st = place(m, t, w, omega, M, s, Ucol, msg);
      if (st == AU_OK && s->folds == 0) break;
    }
    if (st == AU_OK && s->folds == 0) {
      s->weights = AU_TORUS_COMPRESSED, s->cotan_folds = keep.weights == AU_TORUS_COTAN ? 0 : keep.cotan_folds;
      s->squeeze_before = keep.squeeze;
      s->squeeze = min_log_ratio(m, s);
    } else if (st == AU_OK) { /* the compressed start folded in floating point: back to the one before */
      int folds = s->folds;
      memcpy(s->U, U0, 2 * sizeof(double) * (size_t)nv);
      memcpy(s->off, off0, 6 * sizeof(int) * (size_t)m->nf);
      memcpy(s->conformal, keep.conformal, sizeof s->conformal);
      s->folds = keep.folds;
      if (s->folds > 0)
        st = au_msg_set(msg, AU_E_FOLD, "torus: the start has %d folded triangles (%d with cotan weights, %d compressed)",
                        s->folds, s->cotan_folds, folds);
    }
    free(u), free(U0), free(off0);
  }
done:
  free(omega), free(w), free(Ucol);
  if (st == AU_OK) *out = s;
  else au_torus_start_free(&s);
  return st;
}

void au_torus_lattice(const au_torus_start *s, au_torus_shape sh, double L[2][2]) {
  if (sh == AU_TORUS_SQUARE) memcpy(L, (double[2][2]){{1, 0}, {0, 1}}, sizeof(double[2][2]));
  else memcpy(L, s->conformal, sizeof(double[2][2]));
}

void au_torus_positions(const au_torus_start *s, const double L[2][2], double *P) {
  for (int i = 0; i < s->nv; i++) {
    const double *u = s->U + 2 * (size_t)i;
    P[3 * i] = u[0] * L[0][0] + u[1] * L[1][0], P[3 * i + 1] = u[0] * L[0][1] + u[1] * L[1][1], P[3 * i + 2] = 0;
  }
}

/* A corner with a nonzero offset, for grouping equal (vertex, offset) copies. */
typedef struct corner_key {
  int v, o0, o1, corner;
} corner_key;

static int cmp_key(const void *pa, const void *pb) {
  const corner_key *a = pa, *b = pb;
  if (a->v != b->v) return a->v < b->v ? -1 : 1;
  if (a->o0 != b->o0) return a->o0 < b->o0 ? -1 : 1;
  return (a->o1 > b->o1) - (a->o1 < b->o1);
}

au_status au_torus_texcoords(const au_torus_start *s, const int *F, const double L[2][2], int *nvt, double **vt,
                             int **Ft, au_msg *msg) {
  if (!s || !F || !L || !nvt || !vt || !Ft) return au_msg_set(msg, AU_E_ARG, "torus: bad arguments");
  *vt = NULL, *Ft = NULL, *nvt = 0;
  size_t nc = 3 * (size_t)s->nf, nk = 0;
  corner_key *key = malloc(sizeof *key * (nc ? nc : 1));
  int *ft = malloc(sizeof(int) * (nc ? nc : 1));
  if (!key || !ft) goto nomem;
  for (size_t c = 0; c < nc; c++) {
    const int *o = s->off + 2 * c;
    ft[c] = F[c];
    if (o[0] || o[1]) key[nk++] = (corner_key){F[c], o[0], o[1], (int)c};
  }
  qsort(key, nk, sizeof *key, cmp_key);
  int n = s->nv;
  for (size_t q = 0; q < nk; q++) {
    if (q == 0 || cmp_key(&key[q - 1], &key[q]) != 0) n++;
    ft[key[q].corner] = n - 1;
  }
  double *t = malloc(2 * sizeof(double) * (size_t)n);
  if (!t) goto nomem;
  for (int i = 0; i < s->nv; i++) {
    const double *u = s->U + 2 * (size_t)i;
    t[2 * i] = u[0] * L[0][0] + u[1] * L[1][0], t[2 * i + 1] = u[0] * L[0][1] + u[1] * L[1][1];
  }
  for (size_t q = 0; q < nk; q++) {
    int r = ft[key[q].corner];
    /* The vertex's own copy plus the exact lattice vector (rounding of the sum aside). */
    t[2 * r] = t[2 * key[q].v] + (key[q].o0 * L[0][0] + key[q].o1 * L[1][0]);
    t[2 * r + 1] = t[2 * key[q].v + 1] + (key[q].o0 * L[0][1] + key[q].o1 * L[1][1]);
  }
  free(key);
  *nvt = n, *vt = t, *Ft = ft;
  return AU_OK;
nomem:
  free(key), free(ft);
  return au_msg_set(msg, AU_E_NOMEM, "torus: out of memory for the texture coordinates");
}

void au_torus_set_positions(au_torus_start *s, const int *F, const double L[2][2], const double *P) {
  const double det = L[0][0] * L[1][1] - L[0][1] * L[1][0];
  /* p = u1 a1 + u2 a2, solved for (u1, u2) by Cramer's rule. */
  for (int i = 0; i < s->nv; i++) {
    const double *p = P + 3 * (size_t)i;
    s->U[2 * i] = (p[0] * L[1][1] - p[1] * L[1][0]) / det;
    s->U[2 * i + 1] = (L[0][0] * p[1] - L[0][1] * p[0]) / det;
  }
  /* The flow let vertices wander out of the fundamental domain with the corners' offsets fixed: each
   * goes back by whole lattice vectors, which its corners' offsets take up, so no corner moves. */
  to_fundamental_domain(s, F);
  s->folds = au_torus_count_folds(s, F);
}

void au_torus_corner_shifts(const au_torus_start *s, const double L[2][2], double *shift) {
  for (size_t c = 0; c < 3 * (size_t)s->nf; c++) {
    const int *o = s->off + 2 * c;
    shift[3 * c] = o[0] * L[0][0] + o[1] * L[1][0], shift[3 * c + 1] = o[0] * L[0][1] + o[1] * L[1][1], shift[3 * c + 2] = 0;
  }
}

static void torus_constrain(void *ctx, int i, const double *p, double *d) {
  (void)ctx, (void)i, (void)p;
  d[2] = 0;
}

static void torus_retract(void *ctx, int i, double *p) {
  (void)ctx, (void)i;
  p[2] = 0;
}

au_advect_domain au_torus_domain(const double *shift) {
  au_advect_domain d;
  memset(&d, 0, sizeof d);
  d.constrain = torus_constrain, d.retract = torus_retract, d.spherical = 0, d.shift = shift;
  return d;
}
