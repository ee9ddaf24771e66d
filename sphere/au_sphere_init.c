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

/* The plane map is computed and projected in extended precision: the conformal map squeezes long
 * protrusions exponentially (cow's legs to triangles of ~1e-12 on the unit sphere), below what the
 * absolute rounding of a double solve (~1e-16 of the map's extent) resolves; those triangles came
 * out "folded" by rounding alone. */
typedef long double xreal;

/* The compressed start (attempt 2): the largest jump of the flat log scale across a triangle left where
 * protrusions are compressed (docs/sphere.md). */
#define AU_SQUEEZE_JUMP 0.3
/* The strong twisted start (a start for meshes whose every other start folds, tpose): compressed and
 * sheared down to this jump, in both halves of u. */
#define AU_STRONG_JUMP 0.1

/* Inverse stereographic projection of the plane points (x[i], y[i]) scaled by s onto the unit sphere. */
static void inverse_stereo(int nv, const unsigned char *used, const xreal *x, const xreal *y, xreal s, double *P) {
  for (int i = 0; i < nv; i++) {
    double *p = P + 3 * i;
    if (!used[i]) {
      p[0] = 0, p[1] = 0, p[2] = 1;
      continue;
    }
    xreal u = s * x[i], v = s * y[i], r2 = u * u + v * v;
    p[0] = (double)(2 * u / (1 + r2));
    p[1] = (double)(2 * v / (1 + r2));
    p[2] = (double)((r2 - 1) / (r2 + 1));
  }
}

/* Solve the Laplacian system (edge weights w, Dirichlet values at fixed vertices already in z) for
 * two right-hand sides b (2nv) to extended precision: a double solve, then iterative refinement
 * with residuals computed in extended precision (the double factorization as preconditioner).
 * zx [0..2nv-1] gets the solution; r, dz are scratch of 2nv doubles. */
static au_status solve_refined(au_solver *solver, const au_topo *t, const unsigned char *fixed, const double *w,
                               const double *b, double *z, xreal *zx, double *r, double *dz, au_msg *msg) {
  const int nv = t->nv;
  au_status st = au_solver_solve(solver, 2, b, z, msg);
  if (st != AU_OK) return st;
  for (int i = 0; i < 2 * nv; i++) zx[i] = z[i];
  xreal *res = malloc(sizeof(xreal) * 2 * (size_t)nv);
  if (!res) return au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
  for (int it = 0; it < 3 && st == AU_OK; it++) {
    /* res = b - A z over the free vertices, A z = sum_e w_e (z_i - z_j). */
    for (int c = 0; c < 2; c++)
      for (int i = 0; i < nv; i++) res[c * nv + i] = b[c * nv + i];
    for (int e = 0; e < t->ne; e++) {
      int i = t->E[2 * e], j = t->E[2 * e + 1];
      for (int c = 0; c < 2; c++) {
        xreal d = (xreal)w[e] * (zx[c * nv + i] - zx[c * nv + j]);
        res[c * nv + i] -= d;
        res[c * nv + j] += d;
      }
    }
    for (int k = 0; k < 2 * nv; k++) {
      r[k] = fixed[k % nv] ? 0 : (double)res[k];
      dz[k] = 0;
    }
    st = au_solver_solve(solver, 2, r, dz, msg);
    if (st == AU_OK)
      for (int k = 0; k < 2 * nv; k++) zx[k] += dz[k];
  }
  free(res);
  return st;
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
    double det = au_dec_sphere_orient(a, b, c);
    if (det > 0) pos++;
    else neg++;
  }
  if (npos) *npos = pos;
  return neg;
}

/* Lay the plane map (x, y) on the sphere: scale so the median radius is 1 (half the vertices on each
 * hemisphere), reflect if the map came out orientation-reversing. A plane triangle maps to a region
 * bounded by circular arcs, but the mesh's triangle on the sphere is the one through its three
 * corners: a wide, very obtuse triangle of the expanded region (near the puncture) can come out
 * turned over (cow: two such). The scale moves triangles between the expanded and the squeezed part,
 * so scales 2^k times the median one are tried, nearest first, until one has no fold.
 * Returns the fold count of the scale kept. */
static int to_sphere(const au_mesh *m, const au_topo *t, xreal *x, xreal *y, double *P, double *work) {
  int n = 0;
  for (int i = 0; i < m->nv; i++)
    if (t->vused[i]) work[n++] = (double)(x[i] * x[i] + y[i] * y[i]);
  qsort(work, (size_t)n, sizeof(double), cmp_dbl);
  double med = sqrt(work[n / 2]);
  xreal s0 = med > 0 ? 1.0L / med : 1.0L;
  static const int tries[] = {0, -1, 1, -2, 2, -3, -4, -5, -6};
  int best_neg = -1, best_k = 0;
  for (int a = 0; a < (int)(sizeof tries / sizeof tries[0]); a++) {
    xreal s = ldexpl(s0, tries[a]);
    inverse_stereo(m->nv, t->vused, x, y, s, P);
    int pos;
    int neg = sphere_folds(P, m->F, m->nf, &pos);
    if (neg > pos) {
      for (int i = 0; i < m->nv; i++) y[i] = -y[i];
      inverse_stereo(m->nv, t->vused, x, y, s, P);
      neg = sphere_folds(P, m->F, m->nf, &pos);
    }
    if (best_neg < 0 || neg < best_neg) best_neg = neg, best_k = tries[a];
    if (neg == 0) return 0;
  }
  /* None is fold-free: keep the best (the caller reports the folds). */
  xreal s = ldexpl(s0, best_k);
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


/* The log length scale u of the flat metric conformal to the surface with all its curvature at the
 * puncture: (L u)_i = -K_i (K the angle defect) at every vertex but the puncture's corners, which take
 * the 4 pi of Gauss-Bonnet. One solve with the factored cotan Laplacian; u is a plain scalar, so it
 * holds squeezes of e^-80 that no map's coordinates can. */
static au_status flat_log_scale(const au_mesh *m, const au_topo *t, au_solver *solver, const int *c, double *u,
                                double *b, au_msg *msg) {
  const int nv = m->nv;
  for (int i = 0; i < nv; i++) b[i] = t->vused[i] ? -2 * M_PI : 0;
  for (int f = 0; f < m->nf; f++) {
    const int *v = m->F + 3 * f;
    for (int k = 0; k < 3; k++) {
      const double *p = m->X + 3 * v[k], *q = m->X + 3 * v[(k + 1) % 3], *r = m->X + 3 * v[(k + 2) % 3];
      double e1[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, e2[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
      double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      b[v[k]] += atan2(sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]), e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]);
    }
  }
  for (int k = 0; k < 3; k++) b[c[k]] += 4 * M_PI / 3;
  memset(u, 0, sizeof(double) * nv);
  return au_solver_solve(solver, 1, b, u, msg);
}

/* Cotan weights of the surface changed face by face where the flat log scale u jumps across a triangle:
 * the protrusions, which the conformal map squeezes along their length.
 * - compress > 0: where u jumps by more than compress in the squeezed half (below umid, the median of u;
 *   near the puncture u also jumps, but there the map expands; both halves when both is 1), the face
 *   is compressed along grad u by the factor
 *   compress / jump. A protrusion of length L and girth C is squeezed like e^(-2 pi L / C); compressed
 *   along its length by beta, like e^(-2 pi beta L / C), so its triangles stay representable.
 * - twist > 0: where u jumps by more than twist, the face is sheared along J grad u (the girth
 *   direction, one handedness everywhere) until its corner off the edge most across grad u stands over
 *   an end of that edge. An antiprism band (each ring turned half a step, the usual tube) becomes a prism
 *   band. The flow later stretches a limb's girth many times over; a band whose corners stand over the
 *   middle of the stretched edges folds to and fro beneath the sphere (a Schwarz lantern, whose chord
 *   area no flow can bring down), and the flow cannot turn a ring against the next one (its velocity
 *   is a gradient, whose circulation around a ring is zero). So the turn is made in the start, in both
 *   halves (a limb near the puncture is stretched along its girth by the flow as well).
 * The map stays a harmonic map with positive (after clamping) weights, only not conformal.
 * w [0..ne-1] out; returns the number of faces sheared. */
static int tube_weights(const au_mesh *m, const au_topo *t, const double *u, double umid, double compress, int both,
                        double twist, double *G, double *w) {
  const int nf = m->nf;
  int nsheared = 0;
  au_dec_face_grad(nf, m->F, m->X, u, G);
  memset(w, 0, sizeof(double) * (size_t)t->ne);
  for (int f = 0; f < nf; f++) {
    const int *v = m->F + 3 * f;
    double x[3][3], g[3] = {G[3 * f], G[3 * f + 1], G[3 * f + 2]};
    for (int k = 0; k < 3; k++) memcpy(x[k], m->X + 3 * v[k], sizeof x[k]);
    double e1[3], e2[3], cr[3];
    for (int d = 0; d < 3; d++) e1[d] = x[1][d] - x[0][d], e2[d] = x[2][d] - x[0][d];
    cr[0] = e1[1] * e2[2] - e1[2] * e2[1], cr[1] = e1[2] * e2[0] - e1[0] * e2[2], cr[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double cn = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    double gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]), h = sqrt(2 * cn / sqrt(3.0));
    double jump = gn * h;
    int squeezed = gn > 0 && cn > 0 && (both || u[v[0]] + u[v[1]] + u[v[2]] < 3 * umid);
    if (squeezed && compress > 0 && jump > compress) au_dec_tri_compress(x, g, gn, compress / jump);
    if (gn > 0 && cn > 0 && twist > 0 && jump > twist) nsheared += au_dec_tri_twist(x, cr, cn, g, gn);
    double c[3];
    au_dec_tri_cotans((const double(*)[3])x, c);
    for (int k = 0; k < 3; k++) w[t->FE[3 * f + k]] += c[k];
  }
  return nsheared;
}

/* The flat log scale u (into ul) and its median over the used vertices. solver: created with the pin
 * fixed; factored here with the cotan weights w0. */
static au_status log_scale(const au_mesh *m, const au_topo *t, au_solver *solver, const double *w0, const int *c,
                           double *ul, double *b, double *work, double *umid, au_msg *msg) {
  au_status st = au_solver_factor(solver, w0, NULL, msg);
  if (st == AU_OK) st = flat_log_scale(m, t, solver, c, ul, b, msg);
  if (st != AU_OK) return st;
  int n = 0;
  for (int i = 0; i < m->nv; i++)
    if (t->vused[i]) work[n++] = ul[i];
  qsort(work, (size_t)n, sizeof(double), cmp_dbl);
  *umid = work[n / 2];
  return AU_OK;
}

/* twist 0: the conformal start (au_sphere_conformal); 1: the twisted start (au_sphere_twisted); 2: the
 * strong twisted start (au_sphere_twisted_strong). */
static au_status conformal(const au_mesh *m, const au_topo *t, int twist, double *P, int *nsheared, au_msg *msg) {
  if (!m || !t || !P || m->nv < 4 || m->nf < 4 || t->nv != m->nv) return au_msg_set(msg, AU_E_ARG, "sphere: bad arguments");
  const int nv = m->nv, nf = m->nf;
  au_status st = AU_OK;
  au_solver *solver = NULL;
  double *area = malloc(sizeof(double) * nf), *w = malloc(sizeof(double) * (t->ne ? t->ne : 1));
  double *w0 = malloc(sizeof(double) * (t->ne ? t->ne : 1));
  double *b = malloc(sizeof(double) * 2 * nv), *z = malloc(sizeof(double) * 2 * nv), *work = malloc(sizeof(double) * nv);
  double *r = malloc(sizeof(double) * 3 * (size_t)(nv > nf ? nv : nf)), *dz = malloc(sizeof(double) * 2 * nv);
  double *ul = malloc(sizeof(double) * nv), umid = 0;
  xreal *zx = malloc(sizeof(xreal) * 2 * nv);
  unsigned char *fixed = calloc((size_t)nv, 1);
  if (nsheared) *nsheared = 0;
  if (!area || !w || !w0 || !b || !z || !work || !fixed || !r || !dz || !zx || !ul) {
    st = au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
    goto done;
  }
  au_dec_face_areas(nf, m->F, m->X, area);
  int f0 = pick_face(m, area);
  const int *c = m->F + 3 * f0;
  au_dec_cotan(t, m->F, m->X, w);
  memcpy(w0, w, sizeof(double) * (size_t)t->ne);

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

  if (twist) {
    /* The twisted start: the protrusions' bands turned into prism bands (tube_weights). Nothing to turn:
     * nothing to map (*nsheared 0). */
    st = au_solver_create(nv, t->ne, t->E, fixed, AU_ORDER_FAST, &solver, msg);
    if (st == AU_OK) st = log_scale(m, t, solver, w0, c, ul, b, work, &umid, msg);
    if (st != AU_OK) goto done;
    int ns = tube_weights(m, t, ul, umid, 0, 0, twist == 2 ? AU_STRONG_JUMP : AU_SQUEEZE_JUMP, r, w);
    if (nsheared) *nsheared = ns;
    if (ns == 0) goto done;
  }
  for (int attempt = 0; attempt < 4; attempt++) {
    if (attempt == 2) {
      /* Cotan and clamped weights both folded: the protrusions are squeezed past what coordinates hold.
       * Compress them along their length (tube_weights), from the cotan solve's log scale. */
      if (!twist) st = log_scale(m, t, solver, w0, c, ul, b, work, &umid, msg);
      if (st != AU_OK) goto done;
      double jump = twist == 2 ? AU_STRONG_JUMP : AU_SQUEEZE_JUMP;
      tube_weights(m, t, ul, umid, jump, twist == 2, twist ? jump : 0, r, w);
    }
    if (attempt == 1 || attempt == 2) {
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
    if (attempt < 3) {
      /* Source: minus the (d/du - i d/dv) derivative of the hat functions at the puncture. The gradient of
       * the hat function of corner k is n x (opposite edge) / (2 area). */
      for (int k = 0; k < 3; k++) {
        const double *p = m->X + 3 * c[(k + 1) % 3], *q = m->X + 3 * c[(k + 2) % 3];
        double e[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, gr[3];
        gr[0] = (n[1] * e[2] - n[2] * e[1]) / nn, gr[1] = (n[2] * e[0] - n[0] * e[2]) / nn, gr[2] = (n[0] * e[1] - n[1] * e[0]) / nn;
        b[c[k]] = -(gr[0] * u[0] + gr[1] * u[1] + gr[2] * u[2]);
        b[nv + c[k]] = gr[0] * v[0] + gr[1] * v[1] + gr[2] * v[2];
      }
      st = au_solver_create(nv, t->ne, t->E, fixed, AU_ORDER_FAST, &solver, msg);
    } else {
      /* Last resort: the punctured triangle fixed as the outer boundary of a Tutte embedding. */
      memset(fixed, 0, (size_t)nv);
      for (int i = 0; i < nv; i++) fixed[i] = !t->vused[i];
      for (int k = 0; k < 3; k++) {
        fixed[c[k]] = 1;
        z[c[k]] = cos(2 * M_PI * k / 3.0);
        z[nv + c[k]] = sin(2 * M_PI * k / 3.0);
      }
      st = au_solver_create(nv, t->ne, t->E, fixed, AU_ORDER_FAST, &solver, msg);
    }
    if (st == AU_OK) st = au_solver_factor(solver, w, NULL, msg);
    if (st == AU_OK) st = solve_refined(solver, t, fixed, w, b, z, zx, r, dz, msg);
    if (st != AU_OK) goto done;
    int folds = to_sphere(m, t, zx, zx + nv, P, work);
    if (folds == 0) goto done;
    if (attempt == 3) {
      st = au_msg_set(msg, AU_E_FOLD, "sphere: the conformal map has %d folded triangles", folds);
      goto done;
    }
  }
done:
  au_solver_free(&solver);
  free(area), free(w), free(w0), free(b), free(z), free(work), free(fixed), free(r), free(dz), free(zx), free(ul);
  return st;
}

au_status au_sphere_conformal(const au_mesh *m, const au_topo *t, double *P, au_msg *msg) {
  return conformal(m, t, 0, P, NULL, msg);
}

au_status au_sphere_twisted(const au_mesh *m, const au_topo *t, double *P, int *nsheared, au_msg *msg) {
  return conformal(m, t, 1, P, nsheared, msg);
}

au_status au_sphere_twisted_strong(const au_mesh *m, const au_topo *t, double *P, int *nsheared, au_msg *msg) {
  return conformal(m, t, 2, P, nsheared, msg);
}

au_status au_sphere_balance(const au_mesh *m, const au_topo *t, double *P, au_msg *msg) {
  if (!m || !t || !P) return au_msg_set(msg, AU_E_ARG, "sphere: bad arguments");
  const int nv = m->nv;
  double *A = malloc(sizeof(double) * nv), *Q = malloc(sizeof(double) * 3 * (size_t)nv);
  if (!A || !Q) {
    free(A), free(Q);
    return au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
  }
  au_dec_vertex_areas(nv, m->nf, m->F, m->X, NULL, A);
  double tot = 0;
  for (int i = 0; i < nv; i++) tot += A[i];
  au_status st = AU_OK;
  double shrink = 1; /* a translation that turned a triangle over is retried shorter */
  for (int it = 0; it < 200; it++) {
    double a[3] = {0, 0, 0};
    for (int i = 0; i < nv; i++)
      for (int d = 0; d < 3; d++) a[d] += A[i] * P[3 * i + d] / tot;
    for (int d = 0; d < 3; d++) a[d] *= shrink;
    double a2 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
    if (a2 < 1e-16) break;
    if (!(a2 < 1)) {
      st = au_msg_set(msg, AU_E_NUMERIC, "sphere: balancing diverged");
      break;
    }
    /* x -> (1-|a|^2)(x-a)/|x-a|^2 - a maps the unit sphere to itself and a (inside the ball) to the
     * origin: it spreads out the region the centroid leans towards. Extended precision keeps the
     * tiny triangles of squeezed regions resolved. */
    for (int i = 0; i < nv; i++) {
      double *p = P + 3 * i, *q = Q + 3 * i;
      if (!t->vused[i]) {
        q[0] = p[0], q[1] = p[1], q[2] = p[2];
        continue;
      }
      xreal y[3] = {(xreal)p[0] - a[0], (xreal)p[1] - a[1], (xreal)p[2] - a[2]}, r[3];
      xreal y2 = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
      xreal sc = (1 - (xreal)a2) / y2, nrm = 0;
      for (int d = 0; d < 3; d++) r[d] = sc * y[d] - a[d], nrm += r[d] * r[d];
      nrm = sqrtl(nrm);
      for (int d = 0; d < 3; d++) q[d] = (double)(r[d] / nrm);
    }
    /* A Moebius map keeps circles, not the great circles of the mesh's triangles: a wide triangle
     * can turn over. Such a step is retried shorter; balancing stops after a few refusals. */
    if (sphere_folds(Q, m->F, m->nf, NULL) > 0) {
      shrink *= 0.5;
      if (shrink < 1.0 / 64) break;
      continue;
    }
    memcpy(P, Q, sizeof(double) * 3 * (size_t)nv);
  }
  free(A), free(Q);
  return st;
}
