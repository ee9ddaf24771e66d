/* au_metrics.c - distortion (Upsilon, Lambda), area-ratio and fold statistics of a map, as param-eval. */
#include "au_metrics.h"

#include "au_dec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Same exclusion threshold as param-eval's DEGEN_REL: a triangle whose area is at most this
 * fraction of the total is degenerate and left out of the per-face statistics. */
#define AU_DEGEN_REL 1e-14

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static void sub3(const double *a, const double *b, double *d) {
  d[0] = a[0] - b[0], d[1] = a[1] - b[1], d[2] = a[2] - b[2];
}
static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}
static double norm3(const double *a) { return sqrt(dot3(a, a)); }

/* Corner k of face f in the domain: planar domains drop z, as param-eval does. */
static void domain_corner(const double *P, const int *F, size_t f, int k, au_domain dom, double *q) {
  const double *p = P + 3 * (size_t)F[3 * f + k];
  q[0] = p[0], q[1] = p[1], q[2] = dom == AU_DOMAIN_PLANE ? 0.0 : p[2];
}

static double mean(const double *a, size_t n) {
  double s = 0;
  for (size_t i = 0; i < n; i++) s += a[i];
  return n ? s / (double)n : NAN;
}

/* Population standard deviation (numpy's default ddof = 0), two passes like np.std. */
static double pstd(const double *a, size_t n) {
  double m = mean(a, n), s = 0;
  for (size_t i = 0; i < n; i++) s += (a[i] - m) * (a[i] - m);
  return n ? sqrt(s / (double)n) : NAN;
}

static double amax(const double *a, size_t n) {
  double m = n ? a[0] : NAN;
  for (size_t i = 1; i < n; i++)
    if (a[i] > m) m = a[i];
  return m;
}

/* The k-th smallest of a[0..n-1] (Hoare partition around a median of three, expected O(n));
 * afterwards a[k+1..n-1] are all >= a[k]. Equal keys split evenly, so constant data stays fast. */
static double select_kth(double *a, ptrdiff_t n, ptrdiff_t k) {
  ptrdiff_t lo = 0, hi = n - 1;
  while (lo < hi) {
    double x = a[lo], y = a[lo + (hi - lo) / 2], z = a[hi];
    double piv = x < y ? (y < z ? y : (x < z ? z : x)) : (x < z ? x : (y < z ? z : y));
    ptrdiff_t i = lo, j = hi;
    while (i <= j) {
      while (a[i] < piv) i++;
      while (piv < a[j]) j--;
      if (i <= j) {
        double t = a[i];
        a[i++] = a[j], a[j--] = t;
      }
    }
    if (j < k) lo = i;
    if (k < i) hi = j;
  }
  return a[k];
}

/* numpy's default percentile (method 'linear'): position (n-1)*q/100 between the sorted values,
 * interpolated the way numpy's _lerp does. a is reordered; it must hold no NaN. */
static double percentile(double *a, size_t n, double q) {
  if (n == 0) return NAN;
  double pos = (double)(n - 1) * (q / 100.0), t = pos - floor(pos);
  ptrdiff_t i = (ptrdiff_t)floor(pos);
  double lo = select_kth(a, (ptrdiff_t)n, i), hi = lo;
  if ((size_t)i + 1 < n) {
    hi = a[i + 1];
    for (size_t j = (size_t)i + 2; j < n; j++)
      if (a[j] < hi) hi = a[j];
  }
  double d = hi - lo;
  return t >= 0.5 ? hi - d * (1.0 - t) : lo + d * t;
}

/* Singular values of the affine map from domain triangle q onto surface triangle x, computed as
 * param-eval's singular_values (domain edge frame, then the 2x2 metric's eigenvalues), so rounding
 * matches too. cd is twice the domain area; gmax * gmin is the area ratio. */
static void singular_values(const double q[3][3], const double x[3][3], double *gmax, double *gmin) {
  double e1[3], e2[3], p1[3], p2[3], c[3], j1[3], j2[3];
  sub3(q[1], q[0], e1), sub3(q[2], q[0], e2), sub3(x[1], x[0], p1), sub3(x[2], x[0], p2);
  double l1 = norm3(e1);
  cross3(e1, e2, c);
  double cd = norm3(c), x2 = dot3(e1, e2) / l1, y2 = cd / l1;
  for (int d = 0; d < 3; d++) j1[d] = p1[d] / l1, j2[d] = (p2[d] - (x2 / l1) * p1[d]) / y2;
  double a = dot3(j1, j1), b = dot3(j1, j2), cc = dot3(j2, j2);
  *gmax = sqrt(0.5 * (a + cc) + sqrt(0.25 * (a - cc) * (a - cc) + b * b));
  cross3(p1, p2, c);
  *gmin = norm3(c) / cd / *gmax;
}

/* Signed area of the spherical triangle through the normalized corners (Van Oosterom & Strackee
 * 1983), as param-eval's spherical_areas. */
static double spherical_area(const double q[3][3]) {
  double u[3][3], bc[3];
  for (int k = 0; k < 3; k++) {
    double l = norm3(q[k]);
    for (int d = 0; d < 3; d++) u[k][d] = q[k][d] / l;
  }
  cross3(u[1], u[2], bc);
  double det = dot3(u[0], bc);
  double den = 1 + dot3(u[0], u[1]) + dot3(u[1], u[2]) + dot3(u[2], u[0]);
  double sgn = det > 0 ? 1.0 : det < 0 ? -1.0 : 0.0;
  return sgn * 2 * atan2(fabs(det), den);
}

/* Interior angle at corner k of triangle t, from atan2(|cross|, dot): accurate at any size. */
static double corner_angle(const double t[3][3], int k) {
  double a[3], b[3], c[3];
  sub3(t[(k + 1) % 3], t[k], a), sub3(t[(k + 2) % 3], t[k], b);
  cross3(a, b, c);
  return atan2(norm3(c), dot3(a, b));
}

/* param-eval's ratio_stats for areas Ad (domain) and As (surface): r = (Ad share)/(As share) over
 * the faces marked ok. r is scratch of nf doubles. */
static void ratio_stats(size_t nf, const double *Ad, const double *As, const unsigned char *ok, double *r,
                        double *logr_mean_abs, double *r_std, double *r_mad, double *r_cv, double *energy) {
  double sd = 0, ss = 0, e = 0, l = 0, m = 0;
  size_t n = 0;
  for (size_t f = 0; f < nf; f++) sd += Ad[f], ss += As[f];
  for (size_t f = 0; f < nf; f++) {
    double fd = Ad[f] / sd, fs = As[f] / ss;
    e += fabs(fd - fs);
    if (ok[f]) r[n++] = fd / fs;
  }
  for (size_t i = 0; i < n; i++) l += fabs(log(r[i])), m += fabs(r[i] - 1);
  double sdv = pstd(r, n);
  if (logr_mean_abs) *logr_mean_abs = n ? l / (double)n : NAN;
  if (r_std) *r_std = sdv;
  if (r_mad) *r_mad = n ? m / (double)n : NAN;
  if (r_cv) *r_cv = n ? sdv / mean(r, n) : NAN;
  if (energy) *energy = e;
}

/* param-eval's vertex_stats: each face gives a third of its area to each corner; |ln| of the
 * vertex's domain share over its surface share, for vertices whose two cells are not degenerate.
 * vd, vs are scratch of nv doubles. */
static void vertex_stats(size_t nv, size_t nf, const int *F, const double *Ad, const double *As, double *vd,
                         double *vs, double *lr_mean, double *lr_max) {
  memset(vd, 0, nv * sizeof *vd), memset(vs, 0, nv * sizeof *vs);
  for (size_t f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) vd[F[3 * f + k]] += Ad[f] / 3, vs[F[3 * f + k]] += As[f] / 3;
  double sd = 0, ss = 0, s = 0, mx = NAN;
  size_t n = 0;
  for (size_t v = 0; v < nv; v++) sd += vd[v], ss += vs[v];
  for (size_t v = 0; v < nv; v++) {
    if (!(vd[v] > AU_DEGEN_REL * sd && vs[v] > AU_DEGEN_REL * ss)) continue;
    double l = fabs(log((vd[v] / sd) / (vs[v] / ss)));
    s += l, n++;
    if (n == 1 || l > mx) mx = l;
  }
  *lr_mean = n ? s / (double)n : NAN;
  if (lr_max) *lr_max = mx;
}

/* The sphere's own statistics (au_metrics' sph_* fields, the chord floor, the radius): the ratios with
 * exact spherical areas Ao [0..nf-1] (total sAo); As, sAd, sAs as in au_metrics_compute. ok [0..nf-1],
 * W [0..nf-1], vd, vs [0..nv-1]: scratch; used [0..nv-1]: the referenced vertices. */
static void sphere_stats(size_t n, size_t nvs, const int *F, const double *P, const double *As, const double *Ao,
                         double sAd, double sAs, double sAo, const unsigned char *used,
                         unsigned char *ok, double *W, double *vd, double *vs, au_metrics *out) {
  /* The same ratios with exact spherical areas; a face is kept when neither its surface area nor
   * its spherical area is degenerate (param-eval's `oks`). */
  for (size_t f = 0; f < n; f++) ok[f] = As[f] > AU_DEGEN_REL * sAs && Ao[f] > AU_DEGEN_REL * sAo;
  ratio_stats(n, Ao, As, ok, W, NULL, NULL, &out->sph_r_mean_abs_dev, &out->sph_r_cv, NULL);
  vertex_stats(nvs, n, F, Ao, As, vd, vs, &out->sph_vertex_logr_mean_abs, NULL);
  out->chord_floor_excess = au_dec_sphere_floor_excess(n, F, P, As, sAs, sAd, &out->chord_floor_faces);
  for (size_t v = 0; v < nvs; v++) {
    if (!used[v]) continue;
    double dev = fabs(norm3(P + 3 * v) - 1);
    if (dev > out->sphere_radius_max_dev) out->sphere_radius_max_dev = dev;
  }
}

au_status au_metrics_compute(int nv, int nf, const double *X, const double *P, const int *F, au_domain domain,
                             au_metrics *out, double *ups, double *lam) {
  if (!X || !P || !F || !out || nv <= 0 || nf <= 0) return AU_E_ARG;
  if (domain != AU_DOMAIN_SPHERE && domain != AU_DOMAIN_PLANE) return AU_E_ARG;
  for (size_t i = 0; i < 3 * (size_t)nf; i++)
    if (F[i] < 0 || F[i] >= nv) return AU_E_ARG;
  const int sphere = domain == AU_DOMAIN_SPHERE;
  size_t n = (size_t)nf, nvs = (size_t)nv;

  /* Per-face arrays: domain (chordal) area, surface area, |spherical area|, and compact buffers for
   * the non-excluded faces' Upsilon, Lambda, weights; vertex cells. */
  double *Ad = malloc(n * sizeof *Ad), *As = malloc(n * sizeof *As), *Ao = sphere ? malloc(n * sizeof *Ao) : NULL;
  double *U = malloc(n * sizeof *U), *L = malloc(n * sizeof *L), *W = malloc(n * sizeof *W);
  double *vd = malloc(nvs * sizeof *vd), *vs = malloc(nvs * sizeof *vs);
  unsigned char *ok = malloc(n), *used = calloc(nvs, 1);
  au_status st = AU_OK;
  if (!Ad || !As || (sphere && !Ao) || !U || !L || !W || !vd || !vs || !ok || !used) {
    st = AU_E_NOMEM;
    goto done;
  }

  /* Pass 1: areas, orientation, totals. */
  double sAd = 0, sAs = 0, sAo = 0;
  int npos = 0, nneg = 0;
  double q[3][3], x[3][3], c[3], e1[3], e2[3];
  for (size_t f = 0; f < n; f++) {
    for (int k = 0; k < 3; k++) {
      domain_corner(P, F, f, k, domain, q[k]);
      memcpy(x[k], X + 3 * (size_t)F[3 * f + k], sizeof x[k]);
      used[F[3 * f + k]] = 1;
    }
    sub3(q[1], q[0], e1), sub3(q[2], q[0], e2), cross3(e1, e2, c);
    Ad[f] = norm3(c) / 2;
    double orient = c[2];
    if (sphere) {
      for (int k = 0; k < 3; k++)
        if (norm3(q[k]) == 0) {
          st = AU_E_ARG; /* a vertex at the origin: not a sphere map */
          goto done;
        }
      orient = spherical_area(q);
      Ao[f] = fabs(orient);
      sAo += Ao[f];
    }
    W[f] = orient; /* kept until the fold count below */
    sub3(x[1], x[0], e1), sub3(x[2], x[0], e2), cross3(e1, e2, c);
    As[f] = norm3(c) / 2;
    sAd += Ad[f], sAs += As[f];
    npos += orient > 0, nneg += orient < 0;
  }
  if (!(sAs > 0 && sAd > 0)) {
    st = AU_E_ARG;
    goto done;
  }

  /* Folds: faces whose orientation disagrees with the majority's (or is zero), as param-eval. */
  memset(out, 0, sizeof *out);
  out->nv = nv, out->nf = nf, out->domain = domain;
  const double major = npos >= nneg ? 1.0 : -1.0;
  for (size_t f = 0; f < n; f++) out->folds += W[f] * major <= 0;

  /* Pass 2: per-face distortion of the non-excluded faces. */
  size_t m = 0;
  double wsum = 0, wups = 0, adiff = 0;
  for (size_t f = 0; f < n; f++) {
    ok[f] = Ad[f] > AU_DEGEN_REL * sAd && As[f] > AU_DEGEN_REL * sAs;
    if (!ok[f]) {
      out->excluded++;
      if (ups) ups[f] = NAN;
      if (lam) lam[f] = NAN;
      continue;
    }
    for (int k = 0; k < 3; k++) {
      domain_corner(P, F, f, k, domain, q[k]);
      memcpy(x[k], X + 3 * (size_t)F[3 * f + k], sizeof x[k]);
    }
    double gmax, gmin;
    singular_values((const double(*)[3])q, (const double(*)[3])x, &gmax, &gmin);
    U[m] = log(gmax * gmin * (sAd / sAs)); /* surface scaled to the domain's total area */
    L[m] = log(gmax / gmin);
    wups += fabs(U[m]) * As[f], wsum += As[f];
    if (ups) ups[f] = U[m];
    if (lam) lam[f] = L[m];
    /* angle_diff_mean_deg: the mean, over the three corners of every non-excluded face, of
     * |corner angle in the domain triangle - corner angle in the surface triangle| in degrees. On the
     * sphere the domain triangle is the chordal one (the triangle J is defined on), not the spherical. */
    for (int k = 0; k < 3; k++)
      adiff += fabs(corner_angle((const double(*)[3])q, k) - corner_angle((const double(*)[3])x, k));
    m++;
  }

  out->upsilon_std = pstd(U, m);
  out->lambda_mean = mean(L, m), out->lambda_std = pstd(L, m), out->lambda_max = amax(L, m);
  out->lambda_p95 = percentile(L, m, 95);
  for (size_t i = 0; i < m; i++) U[i] = fabs(U[i]);
  out->upsilon_mean_abs = mean(U, m), out->upsilon_max_abs = amax(U, m);
  out->upsilon_p99_abs = percentile(U, m, 99), out->upsilon_p95_abs = percentile(U, m, 95);
  out->upsilon_wmean_abs = m ? wups / wsum : NAN;
  out->angle_diff_mean_deg = m ? adiff / (double)(3 * m) * (180.0 / M_PI) : NAN;
  out->surface_area = sAs, out->domain_area = sAd;

  ratio_stats(n, Ad, As, ok, W, &out->logr_mean_abs, &out->r_std, &out->r_mean_abs_dev, &out->r_cv,
              &out->authalic_energy);
  vertex_stats(nvs, n, F, Ad, As, vd, vs, &out->vertex_logr_mean_abs, &out->vertex_logr_max_abs);

  if (sphere) sphere_stats(n, nvs, F, P, As, Ao, sAd, sAs, sAo, used, ok, W, vd, vs, out);

done:
  free(Ad), free(As), free(Ao), free(U), free(L), free(W), free(vd), free(vs), free(ok), free(used);
  return st;
}

/* The vertex distortion of both public forms: the domain triangle of face f has corners P[F[3f+k]]
 * (vt NULL) or, per corner, vt[Ft[3f+k]] in the plane (a torus map, whose faces across the
 * fundamental domain's edge have their own corner copies). The cells are the input's vertices' in
 * both: a third of every incident face's area, on the domain and on the surface. */
static au_status vertex_distortion(int nv, int nf, const double *X, const double *P, const int *F, au_domain domain,
                                   const double *vt, const int *Ft, double *out, int *ndegenerate) {
  size_t nvs = (size_t)nv;
  double *vs = calloc(nvs, sizeof *vs);
  if (!vs) return AU_E_NOMEM;
  /* out accumulates the domain cells, vs the surface cells. */
  memset(out, 0, nvs * sizeof *out);
  double sd = 0, ss = 0, q[3][3], x[3][3], e1[3], e2[3], c[3];
  for (size_t f = 0; f < (size_t)nf; f++) {
    for (int k = 0; k < 3; k++) {
      if (vt) {
        const double *t = vt + 2 * (size_t)Ft[3 * f + k];
        q[k][0] = t[0], q[k][1] = t[1], q[k][2] = 0;
      } else {
        domain_corner(P, F, f, k, domain, q[k]);
      }
      memcpy(x[k], X + 3 * (size_t)F[3 * f + k], sizeof x[k]);
    }
    sub3(q[1], q[0], e1), sub3(q[2], q[0], e2), cross3(e1, e2, c);
    double ad = 0.5 * norm3(c);
    sub3(x[1], x[0], e1), sub3(x[2], x[0], e2), cross3(e1, e2, c);
    double as = 0.5 * norm3(c);
    for (int k = 0; k < 3; k++) out[F[3 * f + k]] += ad / 3, vs[F[3 * f + k]] += as / 3;
    sd += ad, ss += as;
  }
  if (!(sd > 0 && ss > 0 && isfinite(sd) && isfinite(ss))) {
    free(vs);
    return AU_E_ARG;
  }
  int ndeg = 0;
  for (size_t v = 0; v < nvs; v++) {
    if (out[v] > AU_DEGEN_REL * sd && vs[v] > AU_DEGEN_REL * ss) {
      out[v] = log2((out[v] / sd) / (vs[v] / ss));
    } else {
      out[v] = 0;
      ndeg++;
    }
  }
  free(vs);
  if (ndegenerate) *ndegenerate = ndeg;
  return AU_OK;
}

au_status au_metrics_vertex_distortion(int nv, int nf, const double *X, const double *P, const int *F, au_domain domain,
                                       double *out, int *ndegenerate) {
  if (!X || !P || !F || !out || nv <= 0 || nf <= 0) return AU_E_ARG;
  if (domain != AU_DOMAIN_SPHERE && domain != AU_DOMAIN_PLANE) return AU_E_ARG;
  for (size_t i = 0; i < 3 * (size_t)nf; i++)
    if (F[i] < 0 || F[i] >= nv) return AU_E_ARG;
  return vertex_distortion(nv, nf, X, P, F, domain, NULL, NULL, out, ndegenerate);
}

au_status au_metrics_vertex_distortion_vt(int nv, int nf, const double *X, const int *F, int nvt, const double *vt,
                                          const int *Ft, double *out, int *ndegenerate) {
  if (!X || !F || !vt || !Ft || !out || nv <= 0 || nf <= 0 || nvt <= 0) return AU_E_ARG;
  for (size_t i = 0; i < 3 * (size_t)nf; i++)
    if (F[i] < 0 || F[i] >= nv || Ft[i] < 0 || Ft[i] >= nvt) return AU_E_ARG;
  return vertex_distortion(nv, nf, X, NULL, F, AU_DOMAIN_PLANE, vt, Ft, out, ndegenerate);
}

au_status au__metrics_vt(int nv, int nf, const double *X, const int *F, int nvt, const double *vt, const int *Ft,
                         au_metrics *out, double *ups, double *lam) {
  if (!X || !F || !vt || !Ft || nv <= 0 || nf <= 0 || nvt < nv) return AU_E_ARG;
  for (size_t c = 0; c < 3 * (size_t)nf; c++)
    if (F[c] < 0 || F[c] >= nv || Ft[c] < 0 || Ft[c] >= nvt) return AU_E_ARG;
  /* Each vt row takes the surface position of the corners that use it: vt rows need not follow the
   * vertices' order (an atlas's do not; a torus map's first nv rows happen to). Rows no corner uses stay 0. */
  double *Xc = calloc(3 * (size_t)nvt, sizeof *Xc), *Pc = calloc(3 * (size_t)nvt, sizeof *Pc);
  au_status st = Xc && Pc ? AU_OK : AU_E_NOMEM;
  for (size_t c = 0; st == AU_OK && c < 3 * (size_t)nf; c++)
    memcpy(Xc + 3 * (size_t)Ft[c], X + 3 * (size_t)F[c], 3 * sizeof *Xc);
  for (int i = 0; st == AU_OK && i < nvt; i++) {
    Pc[3 * (size_t)i] = vt[2 * (size_t)i], Pc[3 * (size_t)i + 1] = vt[2 * (size_t)i + 1];
  }
  if (st == AU_OK) st = au_metrics_compute(nvt, nf, Xc, Pc, Ft, AU_DOMAIN_PLANE, out, ups, lam);
  free(Xc), free(Pc);
  return st;
}

double au__metrics_squeezed(int nv, int nf, const double *X, const double *P, const int *F, int *count) {
  double *A = calloc((size_t)(nv > 0 ? nv : 1), sizeof(double)), *B = calloc((size_t)(nv > 0 ? nv : 1), sizeof(double));
  double sa = 0, sb = 0, low = -1;
  *count = 0;
  if (A && B) {
    for (int f = 0; f < nf; f++) {
      const int *v = F + 3 * f;
      double e[3], g[3], c[3];
      sub3(X + 3 * v[1], X + 3 * v[0], e), sub3(X + 3 * v[2], X + 3 * v[0], g), cross3(e, g, c);
      double a = norm3(c);
      sub3(P + 3 * v[1], P + 3 * v[0], e), sub3(P + 3 * v[2], P + 3 * v[0], g), cross3(e, g, c);
      double b = norm3(c);
      for (int k = 0; k < 3; k++) A[v[k]] += a, B[v[k]] += b;
      sa += 3 * a, sb += 3 * b;
    }
    low = 0;
    for (int i = 0; i < nv; i++)
      if (A[i] > 0 && B[i] * sa < exp(-1.0) * A[i] * sb) low += A[i], (*count)++;
    low = sa > 0 ? low / sa : 0;
  }
  free(A), free(B);
  return low;
}
