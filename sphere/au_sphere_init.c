/* au_sphere_init.c - fold-free spherical conformal initialization and Moebius balancing.
 *
 * The conformal map follows Haker, Angenent, Tannenbaum, Kikinis, Sapiro & Halle (2000): puncture the
 * surface at the centre of one well-shaped triangle, solve the cotan Poisson problem whose source is
 * the derivative of a delta at the puncture (a complex function z with a simple pole there), and
 * map z to the sphere by inverse stereographic projection. One factorization, two solves.
 * If obtuse triangles (negative cotan weights) fold the result, the weights are clamped positive and
 * the map recomputed; as a last resort the punctured triangle is fixed in the plane and the rest laid
 * out with positive weights (Tutte/Floater: a planar embedding, hence no folds), as in the first
 * stage of Choi, Lam & Lui (2015). Balancing moves the area-weighted centroid of the image to the
 * origin with hyperbolic translations of the ball (Moebius maps of the sphere), which spreads the
 * squeezed regions before the flow starts. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_dec.h"
#include "au_solver.h"
#include "au_sphere.h"

/* Index of a well-shaped face of about average size: the puncture. */
static int pick_face(const au_mesh *m, const double *area) {
  double mean = 0;
  for (int f = 0; f < m->nf; f++) mean += area[f];
  mean /= m->nf;
  int best = 0;
  double bestq = -1;
  for (int pass = 0; pass < 2 && bestq < 0; pass++) {
    for (int f = 0; f < m->nf; f++) {
      if (pass == 0 && (area[f] < 0.5 * mean || area[f] > 2 * mean)) continue;
      const double *a = m->X + 3 * m->F[3 * f], *b = m->X + 3 * m->F[3 * f + 1], *c = m->X + 3 * m->F[3 * f + 2];
      double l2 = 0;
      for (int d = 0; d < 3; d++) l2 += (b[d] - a[d]) * (b[d] - a[d]) + (c[d] - b[d]) * (c[d] - b[d]) + (a[d] - c[d]) * (a[d] - c[d]);
      double q = l2 > 0 ? 4 * sqrt(3.0) * area[f] / l2 : 0; /* 1 for an equilateral triangle */
      /* Ties (symmetric meshes) go to the lowest index whatever the rounding, so the map does not
       * depend on the unit of the input. */
      if (q > bestq + 1e-9) bestq = q, best = f;
    }
  }
  return best;
}

/* Inverse stereographic projection of the plane points (x[i], y[i]) scaled by s onto the unit sphere. */
static void inverse_stereo(int nv, const unsigned char *used, const double *x, const double *y, double s, double *P) {
  for (int i = 0; i < nv; i++) {
    double *p = P + 3 * i;
    if (!used[i]) {
      p[0] = 0, p[1] = 0, p[2] = 1;
      continue;
    }
    double u = s * x[i], v = s * y[i], r2 = u * u + v * v;
    p[0] = 2 * u / (1 + r2);
    p[1] = 2 * v / (1 + r2);
    p[2] = (r2 - 1) / (r2 + 1);
  }
}

static int cmp_dbl(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Triple-product orientation counts; returns the number of non-positive faces. */
static int sphere_folds(const double *P, const int *F, int nf, int *npos) {
  int neg = 0, pos = 0;
  for (int f = 0; f < nf; f++) {
    const double *a = P + 3 * F[3 * f], *b = P + 3 * F[3 * f + 1], *c = P + 3 * F[3 * f + 2];
    double det = a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
    if (det > 0) pos++;
    else neg++;
  }
  if (npos) *npos = pos;
  return neg;
}

/* Lay the plane map (x, y) on the sphere: scale so the median radius is 1 (half the vertices on each
 * hemisphere), reflect if the map came out orientation-reversing. Returns the fold count. */
static int to_sphere(const au_mesh *m, const au_topo *t, double *x, double *y, double *P, double *work) {
  int n = 0;
  for (int i = 0; i < m->nv; i++)
    if (t->vused[i]) work[n++] = x[i] * x[i] + y[i] * y[i];
  qsort(work, (size_t)n, sizeof(double), cmp_dbl);
  double med = sqrt(work[n / 2]);
  double s = med > 0 ? 1.0 / med : 1.0;
  inverse_stereo(m->nv, t->vused, x, y, s, P);
  int pos;
  int neg = sphere_folds(P, m->F, m->nf, &pos);
  if (neg > pos) {
    for (int i = 0; i < m->nv; i++) y[i] = -y[i];
    inverse_stereo(m->nv, t->vused, x, y, s, P);
    neg = sphere_folds(P, m->F, m->nf, &pos);
  }
  return neg;
}

au_status au_sphere_conformal(const au_mesh *m, const au_topo *t, double *P, au_msg *msg) {
  if (!m || !t || !P || m->nv < 4 || m->nf < 4 || t->nv != m->nv) return au_msg_set(msg, AU_E_ARG, "sphere: bad arguments");
  const int nv = m->nv, nf = m->nf;
  au_status st = AU_OK;
  au_solver *solver = NULL;
  double *area = malloc(sizeof(double) * nf), *w = malloc(sizeof(double) * (t->ne ? t->ne : 1));
  double *b = malloc(sizeof(double) * 2 * nv), *z = malloc(sizeof(double) * 2 * nv), *work = malloc(sizeof(double) * nv);
  unsigned char *fixed = calloc((size_t)nv, 1);
  if (!area || !w || !b || !z || !work || !fixed) {
    st = au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
    goto done;
  }
  au_dec_face_areas(nf, m->F, m->X, area);
  int f0 = pick_face(m, area);
  const int *c = m->F + 3 * f0;
  au_dec_cotan(t, m->F, m->X, w);

  /* Frame of the punctured triangle: u along edge 01, v in-plane perpendicular. */
  const double *A = m->X + 3 * c[0], *B = m->X + 3 * c[1], *C = m->X + 3 * c[2];
  double e1[3], e2[3], n[3], u[3], v[3];
  for (int d = 0; d < 3; d++) e1[d] = B[d] - A[d], e2[d] = C[d] - A[d];
  n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
  for (int d = 0; d < 3; d++) n[d] /= nn, u[d] = e1[d] / l1;
  v[0] = n[1] * u[2] - n[2] * u[1], v[1] = n[2] * u[0] - n[0] * u[2], v[2] = n[0] * u[1] - n[1] * u[0];

  /* Pin the vertex farthest from the puncture (z is defined up to a constant). */
  int pin = -1;
  double far = -1;
  for (int i = 0; i < nv; i++) {
    if (!t->vused[i]) {
      fixed[i] = 1;
      continue;
    }
    double d2 = 0;
    for (int d = 0; d < 3; d++) d2 += (m->X[3 * i + d] - A[d]) * (m->X[3 * i + d] - A[d]);
    if (d2 > far) far = d2, pin = i;
  }
  fixed[pin] = 1;

  for (int attempt = 0; attempt < 3; attempt++) {
    if (attempt == 1) {
      /* Obtuse triangles folded the map: clamp the weights positive (a small fraction of the mean). */
      double mean = 0;
      for (int e = 0; e < t->ne; e++) mean += fabs(w[e]);
      mean /= t->ne;
      for (int e = 0; e < t->ne; e++)
        if (w[e] < 1e-3 * mean) w[e] = 1e-3 * mean;
    }
    au_solver_free(&solver);
    memset(b, 0, sizeof(double) * 2 * nv);
    memset(z, 0, sizeof(double) * 2 * nv);
    if (attempt < 2) {
      /* Source: minus the (d/du - i d/dv) derivative of the hat functions at the puncture. The gradient of
       * the hat function of corner k is n x (opposite edge) / (2 area). */
      for (int k = 0; k < 3; k++) {
        const double *p = m->X + 3 * c[(k + 1) % 3], *q = m->X + 3 * c[(k + 2) % 3];
        double e[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, gr[3];
        gr[0] = (n[1] * e[2] - n[2] * e[1]) / nn, gr[1] = (n[2] * e[0] - n[0] * e[2]) / nn, gr[2] = (n[0] * e[1] - n[1] * e[0]) / nn;
        b[c[k]] = -(gr[0] * u[0] + gr[1] * u[1] + gr[2] * u[2]);
        b[nv + c[k]] = gr[0] * v[0] + gr[1] * v[1] + gr[2] * v[2];
      }
      st = au_solver_create(nv, t->ne, t->E, fixed, &solver, msg);
    } else {
      /* Last resort: the punctured triangle fixed as the outer boundary of a Tutte embedding. */
      memset(fixed, 0, (size_t)nv);
      for (int i = 0; i < nv; i++) fixed[i] = !t->vused[i];
      for (int k = 0; k < 3; k++) {
        fixed[c[k]] = 1;
        z[c[k]] = cos(2 * M_PI * k / 3.0);
        z[nv + c[k]] = sin(2 * M_PI * k / 3.0);
      }
      st = au_solver_create(nv, t->ne, t->E, fixed, &solver, msg);
    }
    if (st == AU_OK) st = au_solver_factor(solver, w, NULL, msg);
    if (st == AU_OK) st = au_solver_solve(solver, 2, b, z, msg);
    if (st != AU_OK) goto done;
    int folds = to_sphere(m, t, z, z + nv, P, work);
    if (folds == 0) goto done;
    if (attempt == 2) {
      st = au_msg_set(msg, AU_E_FOLD, "sphere: the conformal map has %d folded triangles", folds);
      goto done;
    }
  }
done:
  au_solver_free(&solver);
  free(area), free(w), free(b), free(z), free(work), free(fixed);
  return st;
}

au_status au_sphere_balance(const au_mesh *m, const au_topo *t, double *P, au_msg *msg) {
  if (!m || !t || !P) return au_msg_set(msg, AU_E_ARG, "sphere: bad arguments");
  const int nv = m->nv;
  double *A = malloc(sizeof(double) * nv);
  if (!A) return au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
  au_dec_vertex_areas(nv, m->nf, m->F, m->X, NULL, A);
  double tot = 0;
  for (int i = 0; i < nv; i++) tot += A[i];
  au_status st = AU_OK;
  for (int it = 0; it < 200; it++) {
    double a[3] = {0, 0, 0};
    for (int i = 0; i < nv; i++)
      for (int d = 0; d < 3; d++) a[d] += A[i] * P[3 * i + d] / tot;
    double a2 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
    if (a2 < 1e-16) break;
    if (!(a2 < 1)) {
      st = au_msg_set(msg, AU_E_NUMERIC, "sphere: balancing diverged");
      break;
    }
    /* x -> (1-|a|^2)(x-a)/|x-a|^2 - a maps the unit sphere to itself and a (inside the ball) to the
     * origin: it spreads out the region the centroid leans towards. */
    for (int i = 0; i < nv; i++) {
      if (!t->vused[i]) continue;
      double *p = P + 3 * i, y[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
      double y2 = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
      double s = (1 - a2) / y2, nrm = 0;
      for (int d = 0; d < 3; d++) p[d] = s * y[d] - a[d], nrm += p[d] * p[d];
      nrm = sqrt(nrm);
      for (int d = 0; d < 3; d++) p[d] /= nrm;
    }
  }
  free(A);
  return st;
}
