/* au_locate.c - exact point location on the unit sphere in the triangles of a sphere map.
 *
 * A point p lies in the spherical triangle (a, b, c) of positive orientation exactly when the three
 * orientations det[a b p], det[b c p], det[c a p] are >= 0; this is the point-in-triangle test of
 * the gnomonic chart, where great-circle arcs are straight. The signs are computed exactly:
 * a floating-point filter (the error bound of Shewchuk's orient3d, Discrete Comput. Geom. 18, 1997)
 * settles nearly every case, the rest is summed exactly from error-free products (fma) and sums,
 * so neighbouring triangles never leave a gap or a point between them. Candidate triangles come from
 * a cube-map grid: every cube face is an N x N grid in its gnomonic coordinates, and a triangle
 * inside the face's hemisphere is flat there, so the bounding box of its three projected corners
 * bounds it exactly. Compile this file without floating-point contraction (-ffp-contract=off). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_texture.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

struct au_locator {
  int nv, nf;
  double *Pc;      /* Pc [0..3*nv-1]: copy of the map */
  int *F;          /* F [0..3*nf-1]: copy of the faces */
  int flip;        /* 1 when most triangles are negatively oriented (an inward-facing mesh, or a
                      mirrored map): corners 1 and 2 are then swapped internally */
  int N;           /* cells per cube-face side */
  int *start;      /* start [0..6*N*N]: CSR offsets of the buckets */
  int *tri;        /* tri [0..start[6*N*N]-1]: triangles of each bucket */
};

/* ---------------------------------------------------------------- exact orientation */

/* Grow an expansion e[0..n-1] (nonoverlapping, increasing magnitude) by b: Shewchuk's
 * Grow-Expansion with Two-Sum. h must hold n + 1 terms; returns the new length. */
static int grow_expansion(int n, const double *e, double b, double *h) {
  double q = b;
  for (int i = 0; i < n; i++) {
    double s = q + e[i];
    double bv = s - q;
    double av = s - bv;
    double err = (q - av) + (e[i] - bv);
    h[i] = err;
    q = s;
  }
  h[n] = q;
  return n + 1;
}

/* The exact sign of the sum of the six signed triple products of the determinant. */
static int orient_exact(const double a[3], const double b[3], const double c[3]) {
  /* det = a0(b1 c2 - b2 c1) + a1(b2 c0 - b0 c2) + a2(b0 c1 - b1 c0): six products x*y*z, each
   * split exactly into four doubles with fma. */
  const double t[6][4] = {{a[0], b[1], c[2], 1}, {a[0], b[2], c[1], -1}, {a[1], b[2], c[0], 1},
                          {a[1], b[0], c[2], -1}, {a[2], b[0], c[1], 1}, {a[2], b[1], c[0], -1}};
  double e[32], h[32];
  int n = 0;
  for (int k = 0; k < 6; k++) {
    double x = t[k][0] * t[k][3], y = t[k][1], z = t[k][2];
    double p = x * y, pe = fma(x, y, -p); /* x*y = p + pe exactly */
    double terms[4];
    terms[0] = p * z;
    terms[1] = fma(p, z, -terms[0]);
    terms[2] = pe * z;
    terms[3] = fma(pe, z, -terms[2]);
    for (int j = 0; j < 4; j++) {
      if (terms[j] == 0) continue;
      n = grow_expansion(n, e, terms[j], h);
      memcpy(e, h, (size_t)n * sizeof *e);
    }
  }
  /* The expansion is nonoverlapping with increasing magnitude: its sign is that of its largest
   * nonzero term. */
  for (int i = n - 1; i >= 0; i--)
    if (e[i] != 0) return e[i] > 0 ? 1 : -1;
  return 0;
}

int au_sph_orient(const double a[3], const double b[3], const double c[3]) {
  double m0 = b[1] * c[2], m1 = b[2] * c[1];
  double m2 = b[2] * c[0], m3 = b[0] * c[2];
  double m4 = b[0] * c[1], m5 = b[1] * c[0];
  double det = a[0] * (m0 - m1) + a[1] * (m2 - m3) + a[2] * (m4 - m5);
  double perm = fabs(a[0]) * (fabs(m0) + fabs(m1)) + fabs(a[1]) * (fabs(m2) + fabs(m3)) +
                fabs(a[2]) * (fabs(m4) + fabs(m5));
  const double eps = 1.1102230246251565e-16; /* 2^-53 */
  double bound = (7.0 + 56.0 * eps) * eps * perm;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  if (perm == 0) return 0;
  return orient_exact(a, b, c);
}

/* ---------------------------------------------------------------- the cube-map grid */

/* Cube face of a point: 0..5 = +x, -x, +y, -y, +z, -z (the largest |coordinate|), and its gnomonic
 * coordinates on that face. */
static int cube_face(const double p[3], double *u, double *v) {
  double ax = fabs(p[0]), ay = fabs(p[1]), az = fabs(p[2]);
  int k;
  if (ax >= ay && ax >= az) k = p[0] >= 0 ? 0 : 1;
  else if (ay >= az) k = p[1] >= 0 ? 2 : 3;
  else k = p[2] >= 0 ? 4 : 5;
  int ax0 = k / 2, a1 = (ax0 + 1) % 3, a2 = (ax0 + 2) % 3;
  double w = fabs(p[ax0]);
  *u = p[a1] / w;
  *v = p[a2] / w;
  return k;
}

static int cell_of(double u, int N) {
  int i = (int)floor((u + 1) * 0.5 * N);
  return i < 0 ? 0 : i >= N ? N - 1 : i;
}

/* Visit the buckets of triangle f: mode 0 counts into cnt, mode 1 fills tri at pos. */
static void visit_triangle(au_locator *L, int f, int mode, int *cnt, int *pos) {
  const double *a = L->Pc + 3 * L->F[3 * f], *b = L->Pc + 3 * L->F[3 * f + 1], *c = L->Pc + 3 * L->F[3 * f + 2];
  const double *q[3] = {a, b, c};
  int N = L->N;
  /* Circumcap of the triangle (for corners outside a face's hemisphere). */
  double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  double capang = M_PI; /* a degenerate or folded triangle: assume anything */
  if (nn > 0) {
    for (int i = 0; i < 3; i++) n[i] /= nn;
    double cr = n[0] * a[0] + n[1] * a[1] + n[2] * a[2];
    if (cr > 0) capang = acos(fmin(1.0, cr)) + 1e-9;
  }
  for (int k = 0; k < 6; k++) {
    int ax = k / 2, a1 = (ax + 1) % 3, a2 = (ax + 2) % 3;
    double s = (k % 2) ? -1.0 : 1.0;
    double w[3];
    int npos = 0;
    for (int j = 0; j < 3; j++) {
      w[j] = s * q[j][ax];
      npos += w[j] > 1e-12;
    }
    int i0, i1, j0, j1;
    if (npos == 3) {
      double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
      for (int j = 0; j < 3; j++) {
        double u = q[j][a1] / w[j], v = q[j][a2] / w[j];
        umin = fmin(umin, u), umax = fmax(umax, u), vmin = fmin(vmin, v), vmax = fmax(vmax, v);
      }
      const double pad = 1e-9;
      if (umin > 1 + pad || umax < -1 - pad || vmin > 1 + pad || vmax < -1 - pad) continue;
      i0 = cell_of(umin - pad, N), i1 = cell_of(umax + pad, N);
      j0 = cell_of(vmin - pad, N), j1 = cell_of(vmax + pad, N);
    } else if (npos == 0) {
      continue; /* the triangle's cone lies in the closed half-space w <= 0; the face region has w > 0 */
    } else {
      /* Corners on both sides of the face's great circle: use the circumcap against the cap that
       * holds the face region (54.74 degrees around the axis), and take the whole face if they meet. */
      double cosang = s * n[ax];
      double ang = nn > 0 ? acos(fmax(-1.0, fmin(1.0, cosang))) : 0;
      if (capang < M_PI && ang > capang + 0.9553166181245093 + 1e-6) continue;
      i0 = 0, i1 = N - 1, j0 = 0, j1 = N - 1;
    }
    for (int i = i0; i <= i1; i++)
      for (int j = j0; j <= j1; j++) {
        int cell = (k * N + i) * N + j;
        if (mode == 0) cnt[cell]++;
        else L->tri[pos[cell]++] = f;
      }
  }
}

au_status au_locator_build(int nv, const double *P, int nf, const int *F, au_locator **out, au_msg *msg) {
  if (!out) return au_msg_set(msg, AU_E_ARG, "au_locator_build: out is NULL");
  *out = NULL;
  if (!P || !F || nv < 3 || nf < 1) return au_msg_set(msg, AU_E_ARG, "au_locator_build: bad arguments");
  for (long i = 0; i < 3L * nf; i++)
    if (F[i] < 0 || F[i] >= nv)
      return au_msg_set(msg, AU_E_ARG, "au_locator_build: face %ld has index %d out of range", i / 3, F[i]);
  au_locator *L = calloc(1, sizeof *L);
  if (!L) return au_msg_set(msg, AU_E_NOMEM, "au_locator_build: out of memory");
  L->nv = nv, L->nf = nf;
  int N = (int)ceil(sqrt(nf / 6.0 / 1.5));
  if (N < 1) N = 1;
  if (N > 1024) N = 1024;
  L->N = N;
  size_t ncell = 6 * (size_t)N * N;
  L->Pc = malloc(3 * (size_t)nv * sizeof *L->Pc);
  L->F = malloc(3 * (size_t)nf * sizeof *L->F);
  L->start = calloc(ncell + 1, sizeof *L->start);
  int *pos = malloc(ncell * sizeof *pos);
  if (!L->Pc || !L->F || !L->start || !pos) {
    free(pos);
    au_locator_free(&L);
    return au_msg_set(msg, AU_E_NOMEM, "au_locator_build: out of memory");
  }
  memcpy(L->Pc, P, 3 * (size_t)nv * sizeof *P);
  memcpy(L->F, F, 3 * (size_t)nf * sizeof *F);
  long npos = 0, nneg = 0;
  for (int f = 0; f < nf; f++) {
    int o = au_sph_orient(P + 3 * (size_t)F[3 * f], P + 3 * (size_t)F[3 * f + 1], P + 3 * (size_t)F[3 * f + 2]);
    npos += o > 0, nneg += o < 0;
  }
  L->flip = nneg > npos;
  if (L->flip)
    for (int f = 0; f < nf; f++) {
      int tmp = L->F[3 * f + 1];
      L->F[3 * f + 1] = L->F[3 * f + 2], L->F[3 * f + 2] = tmp;
    }
  int *cnt = L->start + 1;
  for (int f = 0; f < nf; f++) visit_triangle(L, f, 0, cnt, NULL);
  for (size_t c = 0; c < ncell; c++) {
    if (L->start[c + 1] > 2000000000 - L->start[c]) {
      free(pos);
      au_locator_free(&L);
      return au_msg_set(msg, AU_E_NOMEM, "au_locator_build: index too large");
    }
    L->start[c + 1] += L->start[c];
  }
  L->tri = malloc(((size_t)L->start[ncell] + 1) * sizeof *L->tri);
  if (!L->tri) {
    free(pos);
    au_locator_free(&L);
    return au_msg_set(msg, AU_E_NOMEM, "au_locator_build: out of memory");
  }
  memcpy(pos, L->start, ncell * sizeof *pos);
  for (int f = 0; f < nf; f++) visit_triangle(L, f, 1, NULL, pos);
  free(pos);
  *out = L;
  return AU_OK;
}

void au_locator_free(au_locator **loc) {
  if (!loc || !*loc) return;
  free((*loc)->Pc);
  free((*loc)->F);
  free((*loc)->start);
  free((*loc)->tri);
  free(*loc);
  *loc = NULL;
}

/* 1 if p is in triangle f (exact), and its barycentric coordinates. */
static int in_triangle(const au_locator *L, int f, const double p[3], double bary[3]) {
  const double *a = L->Pc + 3 * L->F[3 * f], *b = L->Pc + 3 * L->F[3 * f + 1], *c = L->Pc + 3 * L->F[3 * f + 2];
  if (au_sph_orient(a, b, p) < 0 || au_sph_orient(b, c, p) < 0 || au_sph_orient(c, a, p) < 0) return 0;
  if (bary) {
    /* det[p b c], det[a p c], det[a b p] are the (unnormalized) coordinates of p's ray in the flat
     * triangle; rounding can make an exact zero slightly negative, so clamp. */
    double w0 = p[0] * (b[1] * c[2] - b[2] * c[1]) + p[1] * (b[2] * c[0] - b[0] * c[2]) + p[2] * (b[0] * c[1] - b[1] * c[0]);
    double w1 = a[0] * (p[1] * c[2] - p[2] * c[1]) + a[1] * (p[2] * c[0] - p[0] * c[2]) + a[2] * (p[0] * c[1] - p[1] * c[0]);
    double w2 = a[0] * (b[1] * p[2] - b[2] * p[1]) + a[1] * (b[2] * p[0] - b[0] * p[2]) + a[2] * (b[0] * p[1] - b[1] * p[0]);
    w0 = fmax(w0, 0), w1 = fmax(w1, 0), w2 = fmax(w2, 0);
    double s = w0 + w1 + w2;
    if (s > 0) bary[0] = w0 / s, bary[1] = w1 / s, bary[2] = w2 / s;
    else bary[0] = bary[1] = bary[2] = 1.0 / 3;
    if (L->flip) {
      double tmp = bary[1];
      bary[1] = bary[2], bary[2] = tmp;
    }
  }
  return 1;
}

int au_locator_find(const au_locator *loc, const double p[3], int *hint, double bary[3]) {
  if (!loc || !p) return -1;
  if (hint && *hint >= 0 && *hint < loc->nf && in_triangle(loc, *hint, p, bary)) return *hint;
  double u, v;
  if (p[0] == 0 && p[1] == 0 && p[2] == 0) return -1;
  int k = cube_face(p, &u, &v);
  int N = loc->N;
  int cell = (k * N + cell_of(u, N)) * N + cell_of(v, N);
  for (int i = loc->start[cell]; i < loc->start[cell + 1]; i++) {
    int f = loc->tri[i];
    if (in_triangle(loc, f, p, bary)) {
      if (hint) *hint = f;
      return f;
    }
  }
  /* Not reached for a map that covers the sphere; a last exhaustive pass keeps the answer exact
   * even if the buckets' rounding margins were ever too thin. */
  for (int f = 0; f < loc->nf; f++)
    if (in_triangle(loc, f, p, bary)) {
      if (hint) *hint = f;
      return f;
    }
  return -1;
}
