/* au_dec.c - DEC operators: areas, cotan weights, gradients (Zou et al. 2011, eq. 11-16). */
#include "au_dec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static inline void sub3(const double *a, const double *b, double *r) {
  r[0] = a[0] - b[0];
  r[1] = a[1] - b[1];
  r[2] = a[2] - b[2];
}
static inline void cross3(const double *a, const double *b, double *r) {
  r[0] = a[1] * b[2] - a[2] * b[1];
  r[1] = a[2] * b[0] - a[0] * b[2];
  r[2] = a[0] * b[1] - a[1] * b[0];
}
static inline double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline double norm3(const double *a) { return sqrt(dot3(a, a)); }

void au_dec_face_areas(int nf, const int *F, const double *V, double *area) {
  for (int f = 0; f < nf; f++) {
    const double *a = V + 3 * F[3 * f], *b = V + 3 * F[3 * f + 1], *c = V + 3 * F[3 * f + 2];
    double e1[3], e2[3], n[3];
    sub3(b, a, e1);
    sub3(c, a, e2);
    cross3(e1, e2, n);
    area[f] = 0.5 * norm3(n);
  }
}

void au_dec_vertex_areas(int nv, int nf, const int *F, const double *V, const double *area, double *A) {
  memset(A, 0, sizeof(double) * (size_t)nv);
  for (int f = 0; f < nf; f++) {
    double af;
    if (area) {
      af = area[f];
    } else {
      au_dec_face_areas(1, F + 3 * f, V, &af);
    }
    for (int k = 0; k < 3; k++) A[F[3 * f + k]] += af / 3.0;
  }
}

/* cot of the angle at corner k of face f: dot/|cross| of the two edges leaving that corner. */
static double corner_cot(const int *F, const double *V, int f, int k) {
  const double *p = V + 3 * F[3 * f + k], *q = V + 3 * F[3 * f + (k + 1) % 3], *r = V + 3 * F[3 * f + (k + 2) % 3];
  double e1[3], e2[3], n[3];
  sub3(q, p, e1);
  sub3(r, p, e2);
  cross3(e1, e2, n);
  double s = norm3(n);
  /* A degenerate triangle has no meaningful angle; a tiny floor keeps the weight finite. */
  if (s < 1e-300) s = 1e-300;
  return dot3(e1, e2) / s;
}

void au_dec_cotan(const au_topo *t, const int *F, const double *V, double *w) {
  for (int e = 0; e < t->ne; e++) {
    double s = 0;
    for (int j = 0; j < 2; j++) {
      int f = t->EF[2 * e + j];
      if (f >= 0) s += 0.5 * corner_cot(F, V, f, t->EC[2 * e + j]);
    }
    w[e] = s;
  }
}

void au_dec_stiffness_apply(const au_topo *t, const double *w, const double *x, double *y) {
  memset(y, 0, sizeof(double) * (size_t)t->nv);
  for (int e = 0; e < t->ne; e++) {
    int i = t->E[2 * e], j = t->E[2 * e + 1];
    double d = w[e] * (x[i] - x[j]);
    y[i] += d;
    y[j] -= d;
  }
}

void au_dec_face_grad(int nf, const int *F, const double *V, const double *g, double *G) {
  for (int f = 0; f < nf; f++) {
    int i = F[3 * f], j = F[3 * f + 1], k = F[3 * f + 2];
    const double *a = V + 3 * i, *b = V + 3 * j, *c = V + 3 * k;
    double e1[3], e2[3], n[3];
    sub3(b, a, e1);
    sub3(c, a, e2);
    cross3(e1, e2, n);
    double n2 = dot3(n, n);
    double *out = G + 3 * f;
    if (n2 < 1e-300) {
      out[0] = out[1] = out[2] = 0;
      continue;
    }
    /* grad g = ((g_j - g_i) (e2 x n) + (g_k - g_i) (n x e1)) / |n|^2: the unique vector in the
     * triangle's plane whose dot products with e1 and e2 are the value differences. */
    double u[3], v[3];
    cross3(e2, n, u);
    cross3(n, e1, v);
    double dj = g[j] - g[i], dk = g[k] - g[i];
    for (int d = 0; d < 3; d++) out[d] = (dj * u[d] + dk * v[d]) / n2;
  }
}

au_status au_dec_vertex_grad(int nv, int nf, const int *F, const double *V, const double *Gf, double *Gv) {
  double *wsum = calloc((size_t)nv, sizeof(double));
  if (!wsum) return AU_E_NOMEM;
  memset(Gv, 0, sizeof(double) * 3 * (size_t)nv);
  for (int f = 0; f < nf; f++) {
    for (int k = 0; k < 3; k++) {
      int i = F[3 * f + k];
      const double *p = V + 3 * i, *q = V + 3 * F[3 * f + (k + 1) % 3], *r = V + 3 * F[3 * f + (k + 2) % 3];
      double e1[3], e2[3], n[3];
      sub3(q, p, e1);
      sub3(r, p, e2);
      cross3(e1, e2, n);
      double ang = atan2(norm3(n), dot3(e1, e2));
      wsum[i] += ang;
      for (int d = 0; d < 3; d++) Gv[3 * i + d] += ang * Gf[3 * f + d];
    }
  }
  for (int i = 0; i < nv; i++) {
    if (wsum[i] > 0)
      for (int d = 0; d < 3; d++) Gv[3 * i + d] /= wsum[i];
  }
  free(wsum);
  return AU_OK;
}

double au_dec_sphere_orient(const double *a, const double *b, const double *c) {
  double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  return (n[0] * (a[0] + b[0] + c[0]) + n[1] * (a[1] + b[1] + c[1]) + n[2] * (a[2] + b[2] + c[2])) / 3.0;
}

double au_dec_sphere_area(const double *a, const double *b, const double *c, double *grad) {
  double N = au_dec_sphere_orient(a, b, c);
  double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2], bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2],
         ca = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
  double Dn = 1 + ab + bc + ca;
  if (grad) {
    /* dE = 2 (Dn dN - N dDn) / (N^2 + Dn^2), with dN/da = b x c and dDn/da = b + c (cyclically).
     * b x c is formed as (b - a) x (c - a) + a x (c - b), from edge differences: the direct cross
     * product of two nearly equal unit vectors loses all its digits on tiny triangles. */
    const double *p[3] = {a, b, c};
    double q = N * N + Dn * Dn, s = q > 0 ? 2 / q : 0;
    for (int k = 0; k < 3; k++) {
      const double *w = p[k], *u = p[(k + 1) % 3], *v = p[(k + 2) % 3];
      double e1[3] = {u[0] - w[0], u[1] - w[1], u[2] - w[2]}, e2[3] = {v[0] - w[0], v[1] - w[1], v[2] - w[2]};
      double e3[3] = {v[0] - u[0], v[1] - u[1], v[2] - u[2]};
      double x[3] = {e1[1] * e2[2] - e1[2] * e2[1] + w[1] * e3[2] - w[2] * e3[1],
                     e1[2] * e2[0] - e1[0] * e2[2] + w[2] * e3[0] - w[0] * e3[2],
                     e1[0] * e2[1] - e1[1] * e2[0] + w[0] * e3[1] - w[1] * e3[0]};
      for (int d = 0; d < 3; d++) grad[3 * k + d] = s * (Dn * x[d] - N * (u[d] + v[d]));
    }
  }
  return 2 * atan2(N, Dn);
}

void au_dec_sphere_face_areas(int nf, const int *F, const double *V, double *area) {
  for (int f = 0; f < nf; f++)
    area[f] = au_dec_sphere_area(V + 3 * F[3 * f], V + 3 * F[3 * f + 1], V + 3 * F[3 * f + 2], NULL);
}

double au_dec_sphere_floor_excess(size_t nf, const int *F, const double *P, const double *As, double sAs, double sAd,
                                  int *nfaces) {
  double excess = 0;
  int n = 0;
  for (size_t f = 0; f < nf; f++) {
    const double *a = P + 3 * (size_t)F[3 * f], *b = P + 3 * (size_t)F[3 * f + 1], *c = P + 3 * (size_t)F[3 * f + 2];
    double over = au_dec_sphere_chord_floor(a, b, c) - As[f] / sAs * sAd;
    if (over > 0) n++, excess += over / sAd;
  }
  if (nfaces) *nfaces = n;
  return excess;
}

double au_dec_sphere_chord_floor(const double *a, const double *b, const double *c) {
  const double *q[3] = {a, b, c};
  double l2 = 0;
  int e = 0;
  for (int k = 0; k < 3; k++) {
    const double *u = q[k], *v = q[(k + 1) % 3];
    double d2 = (u[0] - v[0]) * (u[0] - v[0]) + (u[1] - v[1]) * (u[1] - v[1]) + (u[2] - v[2]) * (u[2] - v[2]);
    if (d2 > l2) l2 = d2, e = k;
  }
  if (!(l2 > 0)) return 0;
  const double *u = q[e], *v = q[(e + 1) % 3], *w = q[(e + 2) % 3];
  double d[3] = {v[0] - u[0], v[1] - u[1], v[2] - u[2]};
  double t = ((w[0] - u[0]) * d[0] + (w[1] - u[1]) * d[1] + (w[2] - u[2]) * d[2]) / l2;
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  double m[3] = {u[0] + t * d[0], u[1] + t * d[1], u[2] + t * d[2]};
  double depth = 1 - sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
  return depth > 0 ? 0.5 * sqrt(l2) * depth : 0;
}

void au_dec_tri_compress(double x[3][3], const double *g, double gn, double beta) {
  for (int k = 0; k < 3; k++) {
    const double s = (x[k][0] * g[0] + x[k][1] * g[1] + x[k][2] * g[2]) / (gn * gn);
    for (int d = 0; d < 3; d++) x[k][d] -= (1 - beta) * s * g[d];
  }
}

int au_dec_tri_twist(double x[3][3], const double *n, double nn, const double *g, double gn) {
  /* Frame: gy along g, gx = n x gy (the girth); X, Y the corners' coordinates in it. */
  const double gy[3] = {g[0] / gn, g[1] / gn, g[2] / gn};
  const double gx[3] = {(n[1] * gy[2] - n[2] * gy[1]) / nn, (n[2] * gy[0] - n[0] * gy[2]) / nn,
                        (n[0] * gy[1] - n[1] * gy[0]) / nn};
  double X[3], Y[3];
  for (int k = 0; k < 3; k++) {
    X[k] = x[k][0] * gx[0] + x[k][1] * gx[1] + x[k][2] * gx[2];
    Y[k] = x[k][0] * gy[0] + x[k][1] * gy[1] + x[k][2] * gy[2];
  }
  int a = 0;
  for (int k = 1; k < 3; k++)
    if (fabs(Y[(k + 1) % 3] - Y[(k + 2) % 3]) < fabs(Y[(a + 1) % 3] - Y[(a + 2) % 3])) a = k;
  const int p = (a + 1) % 3, q = (a + 2) % 3;
  const double xl = fmin(X[p], X[q]), xr = fmax(X[p], X[q]), ye = 0.5 * (Y[p] + Y[q]), dy = Y[a] - ye;
  const double k = dy > 0 ? (xr - X[a]) / dy : dy < 0 ? (X[a] - xl) / -dy : 0;
  if (!(k > 0)) return 0;
  for (int j = 0; j < 3; j++)
    for (int d = 0; d < 3; d++) x[j][d] += k * (Y[j] - ye) * gx[d];
  return 1;
}

void au_dec_tri_cotans(const double x[3][3], double c[3]) {
  for (int k = 0; k < 3; k++) {
    const double *p = x[k], *q = x[(k + 1) % 3], *r = x[(k + 2) % 3];
    const double a1[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, a2[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    const double c2[3] = {a1[1] * a2[2] - a1[2] * a2[1], a1[2] * a2[0] - a1[0] * a2[2], a1[0] * a2[1] - a1[1] * a2[0]};
    const double sn = sqrt(c2[0] * c2[0] + c2[1] * c2[1] + c2[2] * c2[2]);
    c[k] = sn > 0 ? 0.5 * (a1[0] * a2[0] + a1[1] * a2[1] + a1[2] * a2[2]) / sn : 0;
  }
}
