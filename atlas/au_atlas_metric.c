/* au_atlas_metric.c - cone placement and the flat cone metric (au_atlas.h). */
#include "au_atlas.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_solver.h"

#define AU_PI 3.14159265358979323846

au_atlas_opts au_atlas_opts_default(void) {
  au_atlas_opts o;
  memset(&o, 0, sizeof o);
  o.max_cones = 24;
  o.u_range = 1.5;
  o.quarter = 0;
  o.max_newton = 50;
  o.tol = 1e-10;
  return o;
}

au_status au_atlas_opts_check(const au_atlas_opts *o, au_msg *msg) {
  if (!o) return au_msg_set(msg, AU_E_ARG, "atlas options: NULL");
  if (o->max_cones < 0) return au_msg_set(msg, AU_E_ARG, "atlas options: max_cones %d: expected >= 0", o->max_cones);
  if (!(o->u_range > 0) || !isfinite(o->u_range))
    return au_msg_set(msg, AU_E_ARG, "atlas options: u_range %g: expected a finite value > 0", o->u_range);
  if (o->quarter != 0 && o->quarter != 1) return au_msg_set(msg, AU_E_ARG, "atlas options: quarter %d: expected 0 or 1", o->quarter);
  if (o->max_newton < 1) return au_msg_set(msg, AU_E_ARG, "atlas options: max_newton %d: expected >= 1", o->max_newton);
  if (!(o->tol > 0) || !isfinite(o->tol)) return au_msg_set(msg, AU_E_ARG, "atlas options: tol %g: expected a finite value > 0", o->tol);
  return AU_OK;
}

void au_atlas_cones_clear(au_atlas_cones *c) {
  if (!c) return;
  free(c->v);
  free(c->angle);
  memset(c, 0, sizeof *c);
}

/* Length of the edge opposite corner k of face f, in the mesh's positions. */
static double edge_len(const au_mesh *m, int f, int k) {
  const double *p = m->X + 3 * (size_t)m->F[3 * (size_t)f + (k + 1) % 3];
  const double *q = m->X + 3 * (size_t)m->F[3 * (size_t)f + (k + 2) % 3];
  return sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
}

/* Angles and cotangents of a triangle with side lengths l[k] opposite corner k. A triangle that violates
 * the triangle inequality gets the extended angles (pi at the long side, 0 elsewhere) and zero cotangents:
 * the convex extension of the energy (Springborn, Schroeder & Pinkall 2008, sec. 4). Returns 1 then. */
static int tri_angles(const double l[3], double ang[3], double cot[3]) {
  for (int k = 0; k < 3; k++) {
    double a = l[k], b = l[(k + 1) % 3], c = l[(k + 2) % 3];
    if (a >= b + c) {
      ang[0] = ang[1] = ang[2] = 0;
      ang[k] = AU_PI;
      cot[0] = cot[1] = cot[2] = 0;
      return 1;
    }
  }
  double a = l[0], b = l[1], c = l[2];
  double h = (a + b + c) * (-a + b + c) * (a - b + c) * (a + b - c);
  double four_area = sqrt(h > 0 ? h : 0);
  for (int k = 0; k < 3; k++) {
    double x = l[k], y = l[(k + 1) % 3], z = l[(k + 2) % 3];
    double num = y * y + z * z - x * x;
    ang[k] = atan2(four_area, num);
    cot[k] = four_area > 0 ? num / four_area : 0;
  }
  return 0;
}

/* Corner lengths scaled by u (NULL: none), then angles and cotangents of every face. */
static int all_angles(const au_mesh *m, const double *len0, const double *u, double *ang, double *cot) {
  int bad = 0;
  for (int f = 0; f < m->nf; f++) {
    double l[3], c[3];
    const int *F = m->F + 3 * (size_t)f;
    for (int k = 0; k < 3; k++) {
      l[k] = len0[3 * (size_t)f + k];
      if (u) l[k] *= exp(0.5 * (u[F[(k + 1) % 3]] + u[F[(k + 2) % 3]]));
    }
    bad += tri_angles(l, ang + 3 * (size_t)f, cot ? cot + 3 * (size_t)f : c);
  }
  return bad;
}

static double *corner_lengths(const au_mesh *m) {
  double *len = malloc(3 * (size_t)(m->nf > 0 ? m->nf : 1) * sizeof *len);
  if (len)
    for (int f = 0; f < m->nf; f++)
      for (int k = 0; k < 3; k++) len[3 * (size_t)f + k] = edge_len(m, f, k);
  return len;
}

int au_atlas_corner_angles(const au_mesh *m, const double *u, double *ang) {
  double *len = corner_lengths(m), *cot = malloc(3 * (size_t)(m->nf > 0 ? m->nf : 1) * sizeof *cot);
  int bad = -1;
  if (len && cot) bad = all_angles(m, len, u, ang, cot);
  free(len);
  free(cot);
  return bad;
}

/* Edge weights w [0..ne-1]: half the sum of the cotangents opposite each edge. */
static void cot_weights(const au_mesh *m, const au_topo *t, const double *cot, double *w) {
  memset(w, 0, (size_t)t->ne * sizeof *w);
  for (size_t c = 0; c < 3 * (size_t)m->nf; c++) w[t->FE[c]] += 0.5 * cot[c];
}

/* Angle defect K_v = 2 pi - angle sum at every interior vertex, 0 on the boundary and at unreferenced ones. */
static void defects(const au_mesh *m, const au_topo *t, const double *ang, double *K) {
  for (int v = 0; v < m->nv; v++) K[v] = t->vused[v] && !t->vb[v] ? 2 * AU_PI : 0;
  for (size_t c = 0; c < 3 * (size_t)m->nf; c++)
    if (!t->vb[m->F[c]]) K[m->F[c]] -= ang[c];
}

/* Solve L u = b with u = 0 where fixed (the weights w), and the residual curvature (L u)_v where fixed. */
static au_status laplace_solve(const au_topo *t, const unsigned char *fixed, const double *w, const double *b, double *u,
                               au_msg *msg) {
  au_solver *s = NULL;
  au_status st = au_solver_create(t->nv, t->ne, t->E, fixed, AU_ORDER_FAST, &s, msg);
  if (st == AU_OK) st = au_solver_factor(s, w, NULL, msg);
  if (st == AU_OK) {
    memset(u, 0, (size_t)t->nv * sizeof *u);
    st = au_solver_solve(s, 1, b, u, msg);
  }
  au_solver_free(&s);
  return st;
}

/* (L u)_v for every vertex. */
static void apply_laplacian(const au_topo *t, const double *w, const double *u, double *Lu) {
  memset(Lu, 0, (size_t)t->nv * sizeof *Lu);
  for (int e = 0; e < t->ne; e++) {
    int i = t->E[2 * e], j = t->E[2 * e + 1];
    double d = w[e] * (u[i] - u[j]);
    Lu[i] += d, Lu[j] -= d;
  }
}

/* Round curvatures to multiples of pi/2; on a closed surface the sum stays the Gauss-Bonnet total
 * (the rounding's shortfall goes to the cones whose rounding moved them most the other way). */
static void quarter_round(double *kappa, int n, int closed) {
  const double q = AU_PI / 2;
  double sum = 0;
  int *r = malloc((size_t)(n > 0 ? n : 1) * sizeof *r);
  if (!r) return;
  for (int i = 0; i < n; i++) sum += kappa[i];
  long target = lround(sum / q), have = 0;
  for (int i = 0; i < n; i++) {
    r[i] = (int)lround(kappa[i] / q);
    if (r[i] >= 4) r[i] = 3; /* a cone's angle stays positive */
    have += r[i];
  }
  while (closed && have != target) {
    int dir = have < target ? 1 : -1, best = -1;
    double bestd = -1e300;
    for (int i = 0; i < n; i++) {
      if (dir > 0 && r[i] >= 3) continue;
      double d = dir * (kappa[i] / q - r[i]);
      if (d > bestd) bestd = d, best = i;
    }
    if (best < 0) break;
    r[best] += dir, have += dir;
  }
  for (int i = 0; i < n; i++) kappa[i] = r[i] * q;
  free(r);
}

/* Range (max - min over used vertices) of u0 + sum_i (q r_i - kappa_i) G_i, into u. */
static double rounded_range(const au_topo *t, int n, const double *u0, const double *G, const int *r, const double *kappa,
                            double *u) {
  const double q = AU_PI / 2;
  memcpy(u, u0, (size_t)t->nv * sizeof *u);
  for (int i = 0; i < n; i++) {
    double d = q * r[i] - kappa[i];
    if (d == 0) continue;
    const double *g = G + (size_t)i * t->nv;
    for (int v = 0; v < t->nv; v++) u[v] += d * g[v];
  }
  double lo = 1e300, hi = -1e300;
  for (int v = 0; v < t->nv; v++)
    if (t->vused[v]) lo = u[v] < lo ? u[v] : lo, hi = u[v] > hi ? u[v] : hi;
  return hi - lo;
}

/* Range of cur + q (G_i - G_j) over used vertices (i or j < 0: that term left out): one candidate change of
 * quarter_choose from the current flattening cur, in O(nv) instead of summing every cone's response again. */
static double moved_range(const au_topo *t, const double *cur, const double *G, int i, int j) {
  const double q = AU_PI / 2;
  const double *gi = i >= 0 ? G + (size_t)i * t->nv : NULL, *gj = j >= 0 ? G + (size_t)j * t->nv : NULL;
  double lo = 1e300, hi = -1e300;
  for (int v = 0; v < t->nv; v++) {
    if (!t->vused[v]) continue;
    double x = cur[v];
    if (gi) x += q * gi[v];
    if (gj) x -= q * gj[v];
    lo = x < lo ? x : lo, hi = x > hi ? x : hi;
  }
  return hi - lo;
}

/* Quarter curvatures for the cones cv (continuous curvatures kappa): each rounded down or up (the flattening
 * is linear in them: u = u0 + sum_i (q r_i - kappa_i) G_i, G_i the response to cone i), starting from the
 * nearest with the Gauss-Bonnet total kept, then changed greedily, one cone up and another down (on an open
 * surface also one alone), while that narrows the range of u: the nearest rounding of each cone alone can
 * leave a wide range that the flow then cannot undo. Returns the range in *range and the rounded curvatures
 * in kappa; u receives the flattening.
 * s: the Laplacian factored with the held vertices (the same for every call of one placement); X [nv * (n + 1)]:
 * column 0 the flattening with the continuous curvatures, column 1 + i the response to cone i. Cones keep their
 * vertices from call to call and the held vertices do not change, so the responses of the first *nresp cones
 * are kept from the calls before and only column 0 and the new cones' are solved; *nresp becomes n. */
static au_status quarter_choose(const au_topo *t, au_solver *s, const double *K, int n, const int *cv, double *kappa,
                                int closed, double keep, double *range, double *u, double *X, int *nresp, au_msg *msg) {
  const double q = AU_PI / 2;
  int nv = t->nv, k0 = *nresp, nnew = n - k0;
  double *B = calloc((size_t)nv * (nnew > 0 ? nnew : 1), sizeof *B);
  int *r = malloc((size_t)(n > 0 ? n : 1) * sizeof *r), *lo = malloc((size_t)(n > 0 ? n : 1) * sizeof *lo);
  double *rk = malloc((size_t)(n > 0 ? n : 1) * sizeof *rk), *b0 = calloc((size_t)nv, sizeof *b0);
  au_status st = AU_OK;
  if (!B || !r || !lo || !rk || !b0) {
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory placing cones");
    goto done;
  }
  for (int v = 0; v < nv; v++) b0[v] = -K[v];
  for (int i = 0; i < n; i++) b0[cv[i]] += kappa[i];
  if ((st = au_solver_solve(s, 1, b0, X, msg)) != AU_OK) goto done;
  for (int i = k0; i < n; i++) B[(size_t)(i - k0) * nv + cv[i]] = 1;
  if (nnew > 0 && (st = au_solver_solve(s, nnew, B, X + (size_t)(k0 + 1) * nv, msg)) != AU_OK) goto done;
  *nresp = n;
  memcpy(rk, kappa, (size_t)n * sizeof *rk);
  quarter_round(rk, n, closed);
  for (int i = 0; i < n; i++) {
    r[i] = (int)lround(rk[i] / q);
    lo[i] = (int)floor(kappa[i] / q);
  }
  double best = rounded_range(t, n, X, X + nv, r, kappa, u);
  /* u holds the current flattening; each candidate is measured from it (moved_range), and u is summed again
   * from all responses once a pass, after the change is made. */
  for (int search = best > keep; search;) {
    int bi = -1, bj = -1;
    double bval = best * (1 - 1e-6);
    for (int i = 0; i < n; i++) {
      if (r[i] != lo[i] || r[i] + 1 >= 4) continue; /* i goes up: its angle stays positive */
      for (int j = closed ? 0 : -1; j < n; j++) {
        if (j == i || (j >= 0 && r[j] != lo[j] + 1)) continue; /* j goes down */
        double v = moved_range(t, u, X + nv, i, j);
        if (v < bval) bval = v, bi = i, bj = j;
      }
    }
    if (!closed)
      for (int j = 0; j < n; j++) {
        if (r[j] != lo[j] + 1) continue;
        double v = moved_range(t, u, X + nv, -1, j);
        if (v < bval) bval = v, bi = -1, bj = j;
      }
    if (bi < 0 && bj < 0) break;
    if (bi >= 0) r[bi]++;
    if (bj >= 0) r[bj]--;
    best = rounded_range(t, n, X, X + nv, r, kappa, u);
  }
  *range = rounded_range(t, n, X, X + nv, r, kappa, u);
  for (int i = 0; i < n; i++) kappa[i] = q * r[i];
done:
  free(B), free(r), free(lo), free(rk), free(b0);
  return st;
}

au_status au_atlas_place_cones(const au_mesh *m, const au_topo *t, const au_atlas_opts *o, au_atlas_cones *c,
                               au_msg *msg) {
  if (!m || !t || !c || t->nv != m->nv || t->nf != m->nf) return au_msg_set(msg, AU_E_ARG, "au_atlas_place_cones: bad arguments");
  memset(c, 0, sizeof *c);
  au_atlas_opts oo = o ? *o : au_atlas_opts_default();
  au_status sc = au_atlas_opts_check(&oo, msg);
  if (sc != AU_OK) return sc;
  int nv = m->nv, nf = m->nf, closed = t->nloops == 0;
  if (oo.max_cones < (closed ? 1 : 0)) return au_msg_set(msg, AU_E_ARG, "max_cones %d: a closed surface needs a cone", oo.max_cones);
  if (oo.max_cones > nv) oo.max_cones = nv; /* no more cones than vertices; keeps 2 max_cones below INT_MAX */
  double *len = corner_lengths(m), *ang = malloc(3 * (size_t)nf * sizeof *ang), *cot = malloc(3 * (size_t)nf * sizeof *cot);
  double *w = malloc((size_t)(t->ne > 0 ? t->ne : 1) * sizeof *w), *K = malloc((size_t)nv * sizeof *K);
  double *b = malloc((size_t)nv * sizeof *b), *u = malloc((size_t)nv * sizeof *u), *Lu = malloc((size_t)nv * sizeof *Lu);
  unsigned char *fixed = malloc((size_t)nv);
  int cap = oo.quarter ? 2 * oo.max_cones : oo.max_cones;
  int *cv = malloc((size_t)(cap > 0 ? cap : 1) * sizeof *cv);
  double *kappa = malloc((size_t)(cap > 0 ? cap : 1) * sizeof *kappa);
  au_status st = AU_OK;
  if (!len || !ang || !cot || !w || !K || !b || !u || !Lu || !fixed || !cv || !kappa) {
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory placing cones");
    goto done;
  }
  all_angles(m, len, NULL, ang, cot);
  cot_weights(m, t, cot, w);
  defects(m, t, ang, K);
  for (int v = 0; v < nv; v++) fixed[v] = !t->vused[v] || t->vb[v], b[v] = -K[v];
  int n = 0;
  if (closed) {
    /* The first cone: where the flattening of the curvature spread evenly (its total by area) is most
     * extreme. One vertex held at 0 makes the system definite; its curvature is then ~0. */
    double *area = Lu, total = 0, ksum = 0;
    memset(area, 0, (size_t)nv * sizeof *area);
    for (int f = 0; f < nf; f++) {
      double l[3] = {len[3 * f], len[3 * f + 1], len[3 * f + 2]}, s = 0.5 * (l[0] + l[1] + l[2]);
      double a2 = s * (s - l[0]) * (s - l[1]) * (s - l[2]), a = a2 > 0 ? sqrt(a2) : 0;
      for (int k = 0; k < 3; k++) area[m->F[3 * f + k]] += a / 3;
      total += a;
    }
    for (int v = 0; v < nv; v++) ksum += K[v];
    int ref = 0;
    while (!t->vused[ref]) ref++;
    for (int v = 0; v < nv; v++) b[v] = -(K[v] - ksum * area[v] / total);
    fixed[ref] = 1;
    if ((st = laplace_solve(t, fixed, w, b, u, msg)) != AU_OK) goto done;
    fixed[ref] = 0;
    double mean = 0;
    int nu = 0;
    for (int v = 0; v < nv; v++)
      if (t->vused[v]) mean += u[v], nu++;
    mean /= nu;
    int best = ref;
    for (int v = 0; v < nv; v++)
      if (t->vused[v] && fabs(u[v] - mean) > fabs(u[best] - mean)) best = v;
    cv[n++] = best;
    fixed[best] = 1;
    for (int v = 0; v < nv; v++) b[v] = -K[v];
  }
  /* Greedy: the vertex farthest from 0 in the flattening with the cones so far becomes a cone, until the
   * factor's range is small or the budget is spent. A cone whose curvature reaches 2 pi (a non-positive
   * angle) means too few cones, whatever the range says. */
  for (;;) {
    int any_free = 0;
    for (int v = 0; v < nv && !any_free; v++) any_free = !fixed[v];
    if (!any_free) {
      /* Every vertex a cone (a tetrahedron): u is 0 everywhere, each cone keeps its own curvature. */
      for (int i = 0; i < n; i++) kappa[i] = K[cv[i]];
      break;
    }
    if ((st = laplace_solve(t, fixed, w, b, u, msg)) != AU_OK) goto done;
    apply_laplacian(t, w, u, Lu);
    double lo = 0, hi = 0;
    int far = -1;
    for (int v = 0; v < nv; v++) {
      if (!t->vused[v]) continue;
      lo = u[v] < lo ? u[v] : lo, hi = u[v] > hi ? u[v] : hi;
      if (!fixed[v] && (far < 0 || fabs(u[v]) > fabs(u[far]))) far = v;
    }
    int sharp = 0;
    for (int i = 0; i < n; i++) sharp |= K[cv[i]] + Lu[cv[i]] >= 2 * AU_PI - 0.2;
    if ((hi - lo <= oo.u_range && !sharp) || n >= oo.max_cones || far < 0) {
      for (int i = 0; i < n; i++) kappa[i] = K[cv[i]] + Lu[cv[i]];
      break;
    }
    cv[n++] = far;
    fixed[far] = 1;
  }
  if (oo.quarter && n > 0) {
    /* Quarter cones: the rounding is chosen to keep the flattening's range small (quarter_choose); while it
     * stays above u_range a cone is added where u is most extreme and the curvatures solved again. */
    unsigned char *fq = malloc((size_t)nv);
    double *kq = malloc((size_t)cap * sizeof *kq), *kprev = malloc((size_t)cap * sizeof *kprev);
    /* Zeroed: au_solver_solve reads the held vertices' values from its x. */
    double *X = calloc((size_t)nv * ((size_t)cap + 1), sizeof *X);
    au_solver *sq = NULL;
    int nresp = 0;
    if (!fq || !kq || !kprev || !X) {
      free(fq), free(kq), free(kprev), free(X);
      st = au_msg_set(msg, AU_E_NOMEM, "out of memory placing cones");
      goto done;
    }
    /* quarter_choose's Laplacian holds the boundary (and one vertex of a closed surface) in every round: one
     * factorization serves them all. */
    int ref = 0;
    while (!t->vused[ref]) ref++;
    for (int v = 0; v < nv; v++) fq[v] = !t->vused[v] || t->vb[v];
    if (closed) fq[ref] = 1;
    if ((st = au_solver_create(nv, t->ne, t->E, fq, AU_ORDER_FAST, &sq, msg)) == AU_OK) st = au_solver_factor(sq, w, NULL, msg);
    int over = 1, added = 0;
    for (; st == AU_OK;) {
      for (int v = 0; v < nv; v++) fq[v] = !t->vused[v] || t->vb[v];
      double range = 0;
      memcpy(kq, kappa, (size_t)n * sizeof *kq);
      if ((st = quarter_choose(t, sq, K, n, cv, kq, closed, oo.u_range, &range, u, X, &nresp, msg)) != AU_OK) break;
      if (added && kq[n - 1] == 0) {
        /* The new cone came out flat: adding more where u is extreme does not narrow the range. */
        n--;
        memcpy(kappa, kprev, (size_t)n * sizeof *kq);
        break;
      }
      int far = -1;
      double lo = 1e300, hi = -1e300;
      for (int v = 0; v < nv; v++)
        if (t->vused[v]) lo = u[v] < lo ? u[v] : lo, hi = u[v] > hi ? u[v] : hi;
      for (int i = 0; i < n; i++) fq[cv[i]] = 2;
      for (int v = 0; v < nv; v++)
        if (t->vused[v] && !t->vb[v] && fq[v] != 2 && (far < 0 || fabs(u[v] - 0.5 * (lo + hi)) > fabs(u[far] - 0.5 * (lo + hi))))
          far = v;
      /* Past max_cones only from a range wider than u_range + 0.5: each cone adds charts and costs coverage, and
       * a range a little over u_range the flow undoes (fertility: 1.66 at 24 cones). */
      if (n == oo.max_cones && range <= oo.u_range + 0.5) over = 0;
      if (range <= oo.u_range || n >= (over ? cap : oo.max_cones) || far < 0) {
        memcpy(kappa, kq, (size_t)n * sizeof *kq);
        break;
      }
      memcpy(kprev, kq, (size_t)n * sizeof *kq);
      cv[n++] = far, added = 1;
      for (int v = 0; v < nv; v++) fq[v] = !t->vused[v] || t->vb[v];
      for (int i = 0; i < n; i++) fq[cv[i]] = 1;
      if ((st = laplace_solve(t, fq, w, b, u, msg)) != AU_OK) break;
      apply_laplacian(t, w, u, Lu);
      for (int i = 0; i < n; i++) kappa[i] = K[cv[i]] + Lu[cv[i]];
    }
    au_solver_free(&sq);
    free(fq), free(kq), free(kprev), free(X);
    if (st != AU_OK) goto done;
  }
  /* Cones that came out flat are no cones; on a closed surface their (small) curvature moves to the
   * strongest cone, so the total stays exact. */
  int strongest = -1;
  for (int i = 0; i < n; i++)
    if (strongest < 0 || fabs(kappa[i]) > fabs(kappa[strongest])) strongest = i;
  int keep = 0;
  double moved = 0;
  for (int i = 0; i < n; i++) {
    if (i != strongest && fabs(kappa[i]) < 1e-3) {
      moved += kappa[i];
      continue;
    }
    cv[keep] = cv[i], kappa[keep] = kappa[i];
    if (i == strongest) strongest = keep;
    keep++;
  }
  if (strongest >= 0 && closed) kappa[strongest] += moved;
  if (keep == 1 && fabs(kappa[0]) < 1e-3) keep = 0; /* a flat torus needs no cone */
  if (oo.quarter && closed) {
    /* Every vertex a cone (a tetrahedron): the flow pins cones, so nothing can move, and the metric is the
     * mesh's own only where every vertex's angle sum is already a multiple of pi/2. Otherwise the atlas cannot
     * come out equal area: refused as a fault of the input (too coarse for quarter turns). */
    int nused = 0, worst = -1;
    for (int v = 0; v < nv; v++) nused += t->vused[v] != 0;
    for (int i = 0; keep == nused && i < keep; i++)
      if (fabs(kappa[i] - K[cv[i]]) > 1e-9 && (worst < 0 || fabs(kappa[i] - K[cv[i]]) > fabs(kappa[worst] - K[cv[worst]])))
        worst = i;
    if (worst >= 0) {
      st = au_msg_set(msg, AU_E_TOO_COARSE, "quarter: every one of the %d vertices is a cone, so the flow has none to move, "
                      "and vertex %d's angle sum %.6g deg is not a multiple of 90 degrees: no equal-area atlas with "
                      "quarter-turn seams (refine the mesh, or drop --quarter)", nused, cv[worst],
                      (2 * AU_PI - K[cv[worst]]) * 180 / AU_PI);
      goto done;
    }
  }
  for (int i = 0; i < keep; i++)
    if (kappa[i] >= 2 * AU_PI) {
      st = au_msg_set(msg, AU_E_NUMERIC, "cone at vertex %d would have angle %g (<= 0): more cones are needed (max_cones %d)",
                      cv[i], 2 * AU_PI - kappa[i], oo.max_cones);
      goto done;
    }
  c->n = keep;
  c->v = malloc((size_t)(keep > 0 ? keep : 1) * sizeof *c->v);
  c->angle = malloc((size_t)(keep > 0 ? keep : 1) * sizeof *c->angle);
  if (!c->v || !c->angle) {
    au_atlas_cones_clear(c);
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory placing cones");
    goto done;
  }
  for (int i = 0; i < keep; i++) c->v[i] = cv[i], c->angle[i] = 2 * AU_PI - kappa[i];
done:
  free(len), free(ang), free(cot), free(w), free(K), free(b), free(u), free(Lu), free(fixed), free(cv), free(kappa);
  return st;
}

/* Largest |g_v| over the free vertices and the 2-norm. */
static double gradient(const au_mesh *m, const au_topo *t, const double *theta, const unsigned char *fixed,
                       const double *ang, double *g, double *norm2) {
  for (int v = 0; v < m->nv; v++) g[v] = fixed[v] ? 0 : theta[v];
  for (size_t c = 0; c < 3 * (size_t)m->nf; c++)
    if (!fixed[m->F[c]]) g[m->F[c]] -= ang[c];
  double mx = 0, s = 0;
  for (int v = 0; v < m->nv; v++) mx = fabs(g[v]) > mx ? fabs(g[v]) : mx, s += g[v] * g[v];
  (void)t;
  *norm2 = sqrt(s);
  return mx;
}

au_status au_atlas_cetm(const au_mesh *m, const au_topo *t, const au_atlas_cones *c, const au_atlas_opts *o, double *u,
                        au_atlas_cetm_info *info, au_msg *msg) {
  if (!m || !t || !u || t->nv != m->nv || t->nf != m->nf || (c && c->n > 0 && (!c->v || !c->angle)))
    return au_msg_set(msg, AU_E_ARG, "au_atlas_cetm: bad arguments");
  au_atlas_opts oo = o ? *o : au_atlas_opts_default();
  if (info) memset(info, 0, sizeof *info);
  au_status sc = au_atlas_opts_check(&oo, msg);
  if (sc != AU_OK) return sc;
  if (c && c->n < 0) return au_msg_set(msg, AU_E_ARG, "au_atlas_cetm: %d cones", c->n);
  int nv = m->nv, nf = m->nf, closed = t->nloops == 0, nc = c ? c->n : 0;
  double *theta = malloc((size_t)nv * sizeof *theta);
  unsigned char *fixed = malloc((size_t)nv);
  if (!theta || !fixed) {
    free(theta), free(fixed);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory for the cone metric");
  }
  double ksum = 0;
  for (int v = 0; v < nv; v++) theta[v] = 2 * AU_PI, fixed[v] = !t->vused[v] || t->vb[v], u[v] = 0;
  au_status st = AU_OK;
  for (int i = 0; i < nc; i++) {
    int v = c->v[i];
    if (v < 0 || v >= nv || !t->vused[v] || t->vb[v] || !(c->angle[i] > 0) || !isfinite(c->angle[i])) {
      st = au_msg_set(msg, AU_E_ARG, "cone %d: vertex %d with angle %g is not an interior vertex with a positive angle", i,
                      v, c->angle[i]);
      break;
    }
    /* A vertex given twice would count both curvatures in Gauss-Bonnet's sum but keep one angle. */
    if (fixed[v] == 2) {
      st = au_msg_set(msg, AU_E_ARG, "cone %d: vertex %d is already a cone", i, v);
      break;
    }
    fixed[v] = 2;
    theta[v] = c->angle[i];
    ksum += 2 * AU_PI - c->angle[i];
  }
  for (int i = 0; i < nc; i++)
    if (c->v[i] >= 0 && c->v[i] < nv && fixed[c->v[i]] == 2) fixed[c->v[i]] = 0; /* cones are interior vertices */
  if (st == AU_OK && closed && fabs(ksum - 2 * AU_PI * t->euler) > 1e-9)
    st = au_msg_set(msg, AU_E_ARG, "the cones' curvatures sum to %.12g, Gauss-Bonnet wants 2*pi*chi = %.12g (chi %d)",
                    ksum, 2 * AU_PI * t->euler, t->euler);
  if (st != AU_OK) {
    free(theta), free(fixed);
    return st;
  }
  if (closed) {
    int ref = 0;
    while (!t->vused[ref]) ref++;
    fixed[ref] = 1; /* the scale */
  }
  double *len = corner_lengths(m), *ang = malloc(3 * (size_t)nf * sizeof *ang), *cot = malloc(3 * (size_t)nf * sizeof *cot);
  double *w = malloc((size_t)(t->ne > 0 ? t->ne : 1) * sizeof *w), *g = malloc((size_t)nv * sizeof *g);
  double *b = malloc((size_t)nv * sizeof *b), *d = malloc((size_t)nv * sizeof *d), *ut = malloc((size_t)nv * sizeof *ut);
  au_solver *s = NULL;
  if (!len || !ang || !cot || !w || !g || !b || !d || !ut) {
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory for the cone metric");
    goto done;
  }
  if ((st = au_solver_create(nv, t->ne, t->E, fixed, AU_ORDER_FILL, &s, msg)) != AU_OK) goto done;
  int steps = 0;
  double gn, err;
  all_angles(m, len, u, ang, cot);
  err = gradient(m, t, theta, fixed, ang, g, &gn);
  while (err > oo.tol && steps < oo.max_newton) {
    cot_weights(m, t, cot, w);
    if ((st = au_solver_factor(s, w, NULL, msg)) != AU_OK) goto done;
    for (int v = 0; v < nv; v++) b[v] = -g[v], d[v] = 0;
    if ((st = au_solver_solve(s, 1, b, d, msg)) != AU_OK) goto done;
    /* Damped Newton on a convex energy: halve the step until the gradient shrinks. */
    double tstep = 1, gn_new = 0, err_new = err;
    for (int k = 0; k < 40; k++, tstep *= 0.5) {
      for (int v = 0; v < nv; v++) ut[v] = u[v] + tstep * d[v];
      all_angles(m, len, ut, ang, cot);
      err_new = gradient(m, t, theta, fixed, ang, g, &gn_new);
      if (gn_new < gn * (1 - 1e-4 * tstep)) break;
    }
    memcpy(u, ut, (size_t)nv * sizeof *u);
    steps++;
    if (!(gn_new < gn) && err_new > oo.tol) {
      err = err_new, gn = gn_new;
      break; /* no progress: the metric is as good as doubles make it */
    }
    err = err_new, gn = gn_new;
  }
  if (info) {
    info->steps = steps;
    info->err = err;
    info->degenerate = all_angles(m, len, u, ang, cot);
  }
  if (err > oo.tol)
    st = au_msg_set(msg, AU_W_NOT_CONVERGED, "cone metric: angle error %.3g after %d Newton steps", err, steps);
done:
  au_solver_free(&s);
  free(theta), free(fixed), free(len), free(ang), free(cot), free(w), free(g), free(b), free(d), free(ut);
  return st;
}
