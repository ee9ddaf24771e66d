/* au_atlas_flow.c - the equal-area flow of an atlas with per-corner rigid motions (au_atlas.h). */
#include "au_atlas.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_solver.h"

#define AU_PI 3.14159265358979323846

au_atlas_flow_opts au_atlas_flow_opts_default(void) {
  au_atlas_flow_opts o;
  memset(&o, 0, sizeof o);
  o.max_steps = 200;
  o.face_tol = 0.005;
  o.shear = 1.0;
  /* docs/atlas-angles.md: a first weight of 0.064 or 0.016 ends within 0.03 of each other's Lambda (0.25
   * and 1 worse); the bounds keep a margin below the (per-face 0.02, vertex 0.005), as the charts'
   * splits after the flow add cells (vertex error up to 0.0005 higher in param-eval). */
  o.angles = 0.064;
  o.angles_face_tol = 0.012;
  o.angles_vertex_tol = 0.003;
  o.settle = 1e-3;
  return o;
}

au_status au_atlas_flow_opts_check(const au_atlas_flow_opts *o, au_msg *msg) {
  if (!o) return au_msg_set(msg, AU_E_ARG, "atlas flow options: NULL");
  if (o->max_steps < 0) return au_msg_set(msg, AU_E_ARG, "atlas flow options: max_steps %d: expected >= 0", o->max_steps);
  const struct {
    const char *name;
    double v;
  } nonneg[] = {{"face_tol", o->face_tol}, {"angles", o->angles}, {"angles_face_tol", o->angles_face_tol},
                {"angles_vertex_tol", o->angles_vertex_tol}};
  for (size_t i = 0; i < sizeof nonneg / sizeof nonneg[0]; i++)
    if (!(nonneg[i].v >= 0) || !isfinite(nonneg[i].v))
      return au_msg_set(msg, AU_E_ARG, "atlas flow options: %s %g: expected a finite value >= 0", nonneg[i].name, nonneg[i].v);
  /* The Dirichlet weight is the damping that grows on a stall: 0 would never grow. */
  if (!(o->shear > 0) || !isfinite(o->shear))
    return au_msg_set(msg, AU_E_ARG, "atlas flow options: shear %g: expected a finite value > 0", o->shear);
  if (!(o->settle >= 0 && o->settle < 1))
    return au_msg_set(msg, AU_E_ARG, "atlas flow options: settle %g: expected a value in [0, 1)", o->settle);
  return AU_OK;
}

/* The corner positions q = R p + t of every corner. */
static void corners(int nf, const int *F, const double *p, const double *rot, const double *tr, double *q) {
  for (int c = 0; c < 3 * nf; c++) {
    const double *x = p + 2 * (size_t)F[c], *R = rot + 4 * (size_t)c;
    q[2 * c] = R[0] * x[0] + R[1] * x[1] + tr[2 * c];
    q[2 * c + 1] = R[2] * x[0] + R[3] * x[1] + tr[2 * c + 1];
  }
}

static double face_area(const double *q, int f) {
  const double *a = q + 6 * (size_t)f, *b = a + 2, *c = a + 4;
  return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
}

/* Per-face mean |r - 1| with r = (area / total) / (surface area / surface total); -1 if a face is not positive. */
static double face_error(int nf, const double *q, const double *S, double Stot, double *A, double *Atot, double *sq) {
  double tot = 0;
  for (int f = 0; f < nf; f++) {
    A[f] = face_area(q, f);
    if (!(A[f] > 0)) return -1;
    tot += A[f];
  }
  double e = 0, e2 = 0;
  for (int f = 0; f < nf; f++) {
    double r = A[f] / tot * Stot / S[f] - 1, lr = log1p(r);
    e += fabs(r), e2 += lr * lr;
  }
  *Atot = tot;
  if (sq) *sq = e2 / nf;
  return e / nf;
}

/* The anti-conformal part of face f's map from the surface to the atlas (corners q; G the gradients of the
 * surface triangle's hat functions in a frame of its plane), over sigma: c[0] = (J11 - J22) / sigma,
 * c[1] = (J12 + J21) / sigma. Its length is sigma_1 - sigma_2 over sigma (sigma_1 >= sigma_2 the singular
 * values of J): 2 sinh(Lambda / 2) for a face of the area sigma^2 times its surface area. */
static void face_shear(const double *q, const double *G, int f, double sigma, double c[2]) {
  const double *qa = q + 6 * (size_t)f, *g = G + 6 * (size_t)f;
  c[0] = c[1] = 0;
  for (int k = 0; k < 3; k++) {
    c[0] += qa[2 * k] * g[2 * k] - qa[2 * k + 1] * g[2 * k + 1];
    c[1] += qa[2 * k] * g[2 * k + 1] + qa[2 * k + 1] * g[2 * k];
  }
  c[0] /= sigma, c[1] /= sigma;
}

/* The mean over the faces of |c|^2 (face_shear) with sigma^2 = Atot / Stot. */
static double shear_mean(int nf, const double *q, const double *G, double Atot, double Stot) {
  double sigma = sqrt(Atot / Stot), e = 0, c[2];
  for (int f = 0; f < nf; f++) face_shear(q, G, f, sigma, c), e += c[0] * c[0] + c[1] * c[1];
  return nf > 0 ? e / nf : 0;
}

/* The vertex cells' mean |log r| as param-eval measures it on the output (`--coords vt`): the surface cut
 * along the seams, a cell per row of vt (Ft: the row of each corner; nvt rows), a third of each of its
 * faces; r its share of the atlas over its share of the surface. cell: scratch of 2 nvt. */
static double vertex_error(int nvt, int nf, const int *Ft, const double *A, const double *S, double *cell) {
  memset(cell, 0, 2 * (size_t)nvt * sizeof *cell);
  double at = 0, st = 0;
  for (int f = 0; f < nf; f++) {
    for (int k = 0; k < 3; k++) cell[2 * Ft[3 * f + k]] += A[f] / 3, cell[2 * Ft[3 * f + k] + 1] += S[f] / 3;
    at += A[f], st += S[f];
  }
  double e = 0;
  int n = 0;
  for (int v = 0; v < nvt; v++)
    if (cell[2 * v] > 0 && cell[2 * v + 1] > 0) e += fabs(log(cell[2 * v] / at * st / cell[2 * v + 1])), n++;
  return n > 0 ? e / n : 0;
}

/* Position of entry (i, j), i <= j, in the upper-triangle pattern. */
static int entry(const int *colstart, const int *rows, int i, int j) {
  int lo = colstart[j], hi = colstart[j + 1] - 1;
  while (lo <= hi) {
    int mid = (lo + hi) / 2;
    if (rows[mid] == i) return mid;
    if (rows[mid] < i) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1;
}

/* Move every free vertex's home position p by a fixed pseudo-random offset of 1% of the square root of the
 * smallest area among its faces (A: the faces' current areas; q, q2: corner positions, q updated; pmin:
 * scratch of 3 nv), halved until no face loses half its area (at most 8 times).
 * Why: a mesh and start with a symmetry (the torus of revolution's rotations) keep it under the flow,
 * whose steps are equivariant; a symmetric map can be a stationary point that is not equal area (there,
 * every quad stays a parallelogram, whose two triangles are equal, while on the surface they differ by the
 * ratio of the quad's parallel sides). The offsets break the symmetry. Returns 1 if p moved, 0 if not. */
static int jitter(int nv, int nf, const int *F, const unsigned char *pin, double *p, const double *rot,
                  const double *tr, double *q, double *q2, const double *A, double *pmin) {
  for (int v = 0; v < nv; v++) pmin[v] = INFINITY;
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) pmin[F[3 * f + k]] = fmin(pmin[F[3 * f + k]], A[f]);
  double *p0 = pmin + nv;
  for (double amp = 0.01; amp > 0.01 / 256; amp *= 0.5) {
    unsigned long long x = 88172645463325252ULL; /* xorshift64: the same offsets on every run */
    for (int v = 0; v < nv; v++)
      for (int a = 0; a < 2; a++) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;
        p0[2 * v + a] = p[2 * v + a];
        if (!pin[v] && isfinite(pmin[v])) p0[2 * v + a] += amp * sqrt(pmin[v]) * ((double)(x % 2001) / 1000 - 1);
      }
    corners(nf, F, p0, rot, tr, q2);
    int ok = 1;
    for (int f = 0; f < nf && ok; f++) ok = face_area(q2, f) > 0.5 * A[f];
    if (ok) {
      memcpy(p, p0, 2 * (size_t)nv * sizeof *p);
      memcpy(q, q2, 6 * (size_t)nf * sizeof *q);
      return 1;
    }
  }
  return 0;
}

/* The step system's pattern: 2x2 blocks between the vertices of each face and the diagonal, upper
 * triangle, by columns (n = 2 nv unknowns). 0 for want of memory (nothing left allocated). */
static int face_block_pattern(int nf, const int *F, int n, int **colstart_out, int **rows_out) {
  int *cnt = calloc((size_t)n + 1, sizeof *cnt), *tmp = malloc(36 * (size_t)nf * sizeof *tmp * 2);
  int *rr = NULL, *fill = NULL, *colstart = NULL, *rows = NULL, ok = 0;
  if (!cnt || !tmp) goto done;
  size_t np = 0;
  for (int f = 0; f < nf; f++)
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        for (int a = 0; a < 2; a++)
          for (int bb = 0; bb < 2; bb++) {
            int r = 2 * F[3 * f + i] + a, col = 2 * F[3 * f + j] + bb;
            if (r > col) continue;
            tmp[2 * np] = col, tmp[2 * np + 1] = r, np++;
          }
  for (int i = 0; i < n; i++) tmp[2 * np] = i, tmp[2 * np + 1] = i, np++;
  /* Sort (col, row) pairs by a counting sort on col, then rows within each column. */
  for (size_t k = 0; k < np; k++) cnt[tmp[2 * k] + 1]++;
  for (int i = 0; i < n; i++) cnt[i + 1] += cnt[i];
  rr = malloc(np * sizeof *rr), fill = calloc((size_t)n, sizeof *fill);
  colstart = malloc(((size_t)n + 1) * sizeof *colstart), rows = malloc(np * sizeof *rows);
  if (!rr || !fill || !colstart || !rows) goto done;
  for (size_t k = 0; k < np; k++) rr[cnt[tmp[2 * k]] + fill[tmp[2 * k]]++] = tmp[2 * k + 1];
  int nn = 0;
  colstart[0] = 0;
  for (int j = 0; j < n; j++) {
    qsort(rr + cnt[j], (size_t)(cnt[j + 1] - cnt[j]), sizeof *rr, au__cmp_int);
    for (int k = cnt[j]; k < cnt[j + 1]; k++)
      if (k == cnt[j] || rr[k] != rr[k - 1]) rows[nn++] = rr[k];
    colstart[j + 1] = nn;
  }
  *colstart_out = colstart, *rows_out = rows, ok = 1;
done:
  if (!ok) free(colstart), free(rows);
  free(cnt), free(tmp), free(rr), free(fill);
  return ok;
}

au_status au_atlas_flow(const au_mesh *m, const au_topo *t, const au_atlas_cones *c, au_atlas_layout *L,
                        const au_atlas_flow_opts *opts, au_atlas_flow_info *info, au_msg *msg) {
  if (info) memset(info, 0, sizeof *info);
  if (!m || !t || !L || !L->vt || !L->Ft || t->nv != m->nv || t->nf != m->nf || (c && c->n > 0 && (!c->v || !c->angle)))
    return au_msg_set(msg, AU_E_ARG, "au_atlas_flow: bad arguments");
  au_atlas_flow_opts o = opts ? *opts : au_atlas_flow_opts_default();
  au_status sc = au_atlas_flow_opts_check(&o, msg);
  if (sc != AU_OK) return sc;
  const int nv = m->nv, nf = m->nf, *F = m->F, *Ft = L->Ft, n = 2 * nv;
  double *vt = L->vt;
  au_status st = AU_OK;
  int *home = malloc((size_t)nv * sizeof *home), *colstart = NULL, *rows = NULL;
  double *p = calloc((size_t)n, sizeof *p), *rot = malloc(12 * (size_t)nf * sizeof *rot);
  double *tr = malloc(6 * (size_t)nf * sizeof *tr), *q = malloc(6 * (size_t)nf * sizeof *q);
  double *q2 = malloc(6 * (size_t)nf * sizeof *q2), *S = malloc((size_t)nf * sizeof *S);
  double *A = malloc((size_t)nf * sizeof *A), *b = malloc((size_t)n * sizeof *b), *d = malloc((size_t)n * sizeof *d);
  double *p2 = malloc((size_t)n * sizeof *p2), *A2 = malloc((size_t)nf * sizeof *A2);
  double *pmin = malloc(3 * (size_t)(nv > 0 ? nv : 1) * sizeof *pmin), *G = malloc(6 * (size_t)nf * sizeof *G);
  double *cell = malloc(2 * (size_t)(L->nvt > 0 ? L->nvt : 1) * sizeof *cell);
  unsigned char *pin = calloc((size_t)nv, 1), *known = calloc(3 * (size_t)nf, 1);
  au_spd *spd = NULL;
  if (!home || !p || !rot || !tr || !q || !q2 || !S || !A || !b || !d || !p2 || !A2 || !pmin || !G || !cell || !pin || !known) {
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory for the atlas flow");
    goto done;
  }
  /* Surface areas. */
  double Stot = 0;
  for (int f = 0; f < nf; f++) {
    const double *x0 = m->X + 3 * (size_t)F[3 * f], *x1 = m->X + 3 * (size_t)F[3 * f + 1], *x2 = m->X + 3 * (size_t)F[3 * f + 2];
    double u[3] = {x1[0] - x0[0], x1[1] - x0[1], x1[2] - x0[2]}, w[3] = {x2[0] - x0[0], x2[1] - x0[1], x2[2] - x0[2]};
    double cx = u[1] * w[2] - u[2] * w[1], cy = u[2] * w[0] - u[0] * w[2], cz = u[0] * w[1] - u[1] * w[0];
    S[f] = 0.5 * sqrt(cx * cx + cy * cy + cz * cz), Stot += S[f];
    /* The surface triangle in a frame of its own plane (corner 0 at the origin, corner 1 on the x axis,
     * counter-clockwise like the atlas) and the gradients of its corners' hat functions there. */
    double l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]), y[3][2];
    y[0][0] = y[0][1] = y[1][1] = 0, y[1][0] = l;
    y[2][0] = l > 0 ? (u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) / l : 0, y[2][1] = l > 0 ? 2 * S[f] / l : 0;
    for (int k = 0; k < 3; k++) {
      const double *y1 = y[(k + 1) % 3], *y2 = y[(k + 2) % 3];
      G[6 * (size_t)f + 2 * k] = S[f] > 0 ? -(y2[1] - y1[1]) / (2 * S[f]) : 0;
      G[6 * (size_t)f + 2 * k + 1] = S[f] > 0 ? (y2[0] - y1[0]) / (2 * S[f]) : 0;
    }
  }
  int npin = 0;
  for (int i = 0; c && i < c->n; i++)
    if (fabs(c->angle[i] - 2 * AU_PI) > 1e-12) pin[c->v[i]] = 1, npin++;
  /* Without a cone nothing holds the atlas in place: a translation of every vertex changes no area, and
   * that null space makes the steps' systems singular. One vertex is held. */
  if (npin == 0)
    for (int v = 0; v < nv; v++)
      if (t->vused[v]) {
        pin[v] = 1;
        break;
      }
  /* Each vertex's home: its first corner's coordinates. Every other corner of the vertex is a rigid motion
   * of it: the product of the seam rotations met going round the vertex from the home corner, through the
   * faces' corners (a wedge shares its vt; across a cut edge the rotation is measured from the edge's two
   * copies). */
  for (int v = 0; v < nv; v++) home[v] = -1;
  for (int cc = 0; cc < 3 * nf; cc++)
    if (home[F[cc]] < 0) home[F[cc]] = cc;
  for (int v = 0; v < nv; v++)
    if (home[v] >= 0) p[2 * v] = vt[2 * Ft[home[v]]], p[2 * v + 1] = vt[2 * Ft[home[v]] + 1];
  /* Rotation angle per corner (in q's storage until the corners are computed), propagated across the
   * faces around each vertex by sweeps over the edges. */
  double *cang = q;
  for (int cc = 0; cc < 3 * nf; cc++) cang[cc] = 0;
  for (int v = 0; v < nv; v++)
    if (home[v] >= 0) known[home[v]] = 1;
  for (int sweep = 0, changed = 1; changed && sweep < 1000; sweep++) {
    changed = 0;
    for (int e = 0; e < t->ne; e++) {
      if (t->EF[2 * e + 1] < 0) continue;
      int f0 = t->EF[2 * e], f1 = t->EF[2 * e + 1];
      int a = t->E[2 * e], bb = t->E[2 * e + 1];
      int ka0 = F[3 * f0] == a ? 0 : F[3 * f0 + 1] == a ? 1 : 2, kb0 = F[3 * f0] == bb ? 0 : F[3 * f0 + 1] == bb ? 1 : 2;
      int ka1 = F[3 * f1] == a ? 0 : F[3 * f1 + 1] == a ? 1 : 2, kb1 = F[3 * f1] == bb ? 0 : F[3 * f1 + 1] == bb ? 1 : 2;
      const double *pa0 = vt + 2 * Ft[3 * f0 + ka0], *pb0 = vt + 2 * Ft[3 * f0 + kb0];
      const double *pa1 = vt + 2 * Ft[3 * f1 + ka1], *pb1 = vt + 2 * Ft[3 * f1 + kb1];
      double d0x = pb0[0] - pa0[0], d0y = pb0[1] - pa0[1], d1x = pb1[0] - pa1[0], d1y = pb1[1] - pa1[1];
      double th = atan2(d0x * d1y - d0y * d1x, d0x * d1x + d0y * d1y); /* f0's copy -> f1's copy */
      int cs[2][2] = {{3 * f0 + ka0, 3 * f1 + ka1}, {3 * f0 + kb0, 3 * f1 + kb1}};
      for (int s = 0; s < 2; s++) {
        int c0 = cs[s][0], c1 = cs[s][1];
        if (known[c0] && !known[c1]) cang[c1] = cang[c0] + th, known[c1] = 1, changed = 1;
        else if (known[c1] && !known[c0]) cang[c0] = cang[c1] - th, known[c0] = 1, changed = 1;
      }
    }
  }
  for (int cc = 0; cc < 3 * nf; cc++) {
    double cs_ = cos(cang[cc]), sn = sin(cang[cc]), *R = rot + 4 * (size_t)cc;
    R[0] = cs_, R[1] = -sn, R[2] = sn, R[3] = cs_;
    const double *x = p + 2 * (size_t)F[cc];
    tr[2 * cc] = vt[2 * Ft[cc]] - (R[0] * x[0] + R[1] * x[1]);
    tr[2 * cc + 1] = vt[2 * Ft[cc] + 1] - (R[2] * x[0] + R[3] * x[1]);
  }
  corners(nf, F, p, rot, tr, q);
  if (!face_block_pattern(nf, F, n, &colstart, &rows)) {
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory for the atlas flow");
    goto done;
  }
  if ((st = au_spd_create(n, colstart, rows, NULL, &spd, msg)) != AU_OK) goto done;

  /* Gauss-Newton minimizes the squares of the residuals (the logs of the area ratios): a step is judged
   * by their mean (sq), while the per-face mean |r - 1| (err) is what is reported and what the tolerance
   * is on. */
  double Atot, sq = 0, err = face_error(nf, q, S, Stot, A, &Atot, &sq);
  double mu = o.angles;
  if (err >= 0 && mu > 0) sq += mu * shear_mean(nf, q, G, Atot, Stot);
  if (info) info->err0 = err;
  if (err < 0) {
    st = au_msg_set(msg, AU_E_FOLD, "the atlas flow's start has a folded face");
    goto done;
  }
  double lambda = o.shear;
  int steps = 0, jittered = 0;
  /* The angles (o.angles > 0): the steps lower the squared logs plus mu times the faces' mean squared shear
   * (face_shear), whose minimum, for a fixed mu, is the least-shear map at its area error. The flow goes
   * from the conformal start (large area error, no shear) towards the equal-area maps, the shear growing as
   * the area error falls, so it stops at the first step whose areas are within the angle bounds (per-face
   * angles_face_tol, vertex cells angles_vertex_tol). Where the objective has settled outside them (a step
   * lowers it by less than o.settle of itself), mu is quartered and the flow goes on from there. Below 1/200 of its first value mu stays: once, the symmetry is broken (jitter); then mu is
   * dropped and the plain flow ends at face_tol. Why the bounds are not the plain flow's 0.005: its last
   * steps buy the per-face error below 0.006 with much of the shear (bob, mu held at 0.001: Lambda 0.524
   * at per-face 0.0062; the plain flow: 0.627 at 0.0046). */
  while (steps < o.max_steps && (mu > 0 || err > o.face_tol)) {
    double *val = au_spd_values(spd);
    memset(val, 0, (size_t)colstart[n] * sizeof *val);
    memset(b, 0, (size_t)n * sizeof *b);
    /* Gauss-Newton on the logs of the face areas over their targets, plus lambda times the corners'
     * Dirichlet energy of the displacement (scaled by the mean target), all in the vertices' home frames.
     * The log: on the area ratio itself a squeezed face's gradient is its small edges over a large target,
     * and the flow stalled with such faces left squeezed (bob 0.13, fertility 0.28 per face). */
    double meanT = Atot / nf, sigma = sqrt(Atot / Stot);
    for (int f = 0; f < nf; f++) {
      double T = S[f] / Stot * Atot, r = log(A[f] / T);
      const double *qa = q + 6 * (size_t)f;
      double g[3][2], h1[3][2], h2[3][2], cf[2] = {0, 0};
      if (mu > 0) {
        /* The shear residuals' gradients, in the home frames (R^T of the corners' gradients). */
        face_shear(q, G, f, sigma, cf);
        for (int k = 0; k < 3; k++) {
          const double *gk = G + 6 * (size_t)f + 2 * k, *R = rot + 4 * (size_t)(3 * f + k);
          double ax = gk[0] / sigma, ay = -gk[1] / sigma, bx = gk[1] / sigma, by = gk[0] / sigma;
          h1[k][0] = R[0] * ax + R[2] * ay, h1[k][1] = R[1] * ax + R[3] * ay;
          h2[k][0] = R[0] * bx + R[2] * by, h2[k][1] = R[1] * bx + R[3] * by;
        }
      }
      for (int k = 0; k < 3; k++) {
        const double *q1 = qa + 2 * ((k + 1) % 3), *q2_ = qa + 2 * ((k + 2) % 3);
        double gx = 0.5 * (q1[1] - q2_[1]), gy = 0.5 * (q2_[0] - q1[0]);
        const double *R = rot + 4 * (size_t)(3 * f + k);
        g[k][0] = (R[0] * gx + R[2] * gy) / A[f]; /* R^T g, of the log of the area */
        g[k][1] = (R[1] * gx + R[3] * gy) / A[f];
      }
      for (int i = 0; i < 3; i++) {
        int vi = F[3 * f + i];
        if (pin[vi]) continue;
        for (int a = 0; a < 2; a++) b[2 * vi + a] -= g[i][a] * r + (mu > 0 ? mu * (h1[i][a] * cf[0] + h2[i][a] * cf[1]) : 0);
        for (int j = 0; j < 3; j++) {
          int vj = F[3 * f + j];
          if (pin[vj]) continue;
          for (int a = 0; a < 2; a++)
            for (int bb = 0; bb < 2; bb++) {
              int ri = 2 * vi + a, cj = 2 * vj + bb;
              if (ri > cj) continue;
              double h = g[i][a] * g[j][bb];
              if (mu > 0) h += mu * (h1[i][a] * h1[j][bb] + h2[i][a] * h2[j][bb]);
              /* Dirichlet energy of the corners' displacement: sum over the face's edges of |R_i d_i - R_j d_j|^2. */
              const double *Ri = rot + 4 * (size_t)(3 * f + i), *Rj = rot + 4 * (size_t)(3 * f + j);
              double rij = Ri[0 * 2 + a] * Rj[0 * 2 + bb] + Ri[1 * 2 + a] * Rj[1 * 2 + bb]; /* (R_i^T R_j)_{ab} */
              h += lambda / meanT * (i == j ? 2 * (a == bb) : -rij);
              val[entry(colstart, rows, ri, cj)] += h;
            }
        }
      }
    }
    for (int v = 0; v < nv; v++)
      for (int a = 0; a < 2; a++) val[entry(colstart, rows, 2 * v + a, 2 * v + a)] += pin[v] || !t->vused[v] ? 1 : 1e-9 * (1 + lambda) / meanT;
    int failed = (st = au_spd_factor(spd, msg)) == AU_E_NOT_SPD;
    double alpha = 1, err2 = -1;
    if (failed) {
      /* The area rows alone are rank-deficient; more of the Dirichlet term makes the system definite. */
      st = AU_OK;
      if (msg) msg->text[0] = '\0';
    } else {
      if (st != AU_OK) goto done;
      if ((st = au_spd_solve(spd, b, d, msg)) != AU_OK) goto done;
      /* The step is halved until the error falls and no face loses more than 9/10 of its area (nor turns
       * over): a face squeezed to nothing in one step is one rounding away from a fold. */
      memcpy(A2, A, (size_t)nf * sizeof *A2);
      for (int k = 0; k < 30; k++, alpha *= 0.5) {
        for (int i = 0; i < n; i++) p2[i] = p[i] + alpha * d[i];
        corners(nf, F, p2, rot, tr, q2);
        double At2;
        double sq2 = 0;
        err2 = face_error(nf, q2, S, Stot, A, &At2, &sq2);
        if (err2 >= 0 && mu > 0) sq2 += mu * shear_mean(nf, q2, G, At2, Stot);
        int shrunk = 0;
        for (int f = 0; err2 >= 0 && f < nf && !shrunk; f++) shrunk = A[f] < 0.1 * A2[f];
        if (err2 >= 0 && sq2 < sq && !shrunk) break;
        err2 = -1;
      }
      if (!(err2 >= 0)) {
        failed = 1;
        face_error(nf, q, S, Stot, A, &Atot, NULL);
      }
    }
    if (failed) {
      /* More damping; at its largest the flow is stalled: with the shear term on, mu is quartered (below
       * 1/200 of its first value dropped) and the flow goes on from there; then, once, the symmetry is broken
       * (jitter) and the flow goes on; then it stops where it is (the map so far is valid). */
      if (lambda > 1e8 * o.shear) {
        if (mu > 0) {
          mu = mu > o.angles / 200 ? mu * 0.25 : 0;
          lambda = o.shear;
          err = face_error(nf, q, S, Stot, A, &Atot, &sq);
          if (mu > 0) sq += mu * shear_mean(nf, q, G, Atot, Stot);
          continue;
        }
        if (jittered || !jitter(nv, nf, F, pin, p, rot, tr, q, q2, A, pmin)) break;
        jittered = 1, lambda = o.shear;
        err = face_error(nf, q, S, Stot, A, &Atot, &sq);
        if (mu > 0) sq += mu * shear_mean(nf, q, G, Atot, Stot);
        continue;
      }
      lambda *= 4;
      continue;
    }
    memcpy(p, p2, (size_t)n * sizeof *p);
    memcpy(q, q2, 6 * (size_t)nf * sizeof *q);
    double sq_prev = sq;
    err = face_error(nf, q, S, Stot, A, &Atot, &sq);
    if (mu > 0) sq += mu * shear_mean(nf, q, G, Atot, Stot);
    if (mu > 0) {
      if (err <= o.angles_face_tol && vertex_error(L->nvt, nf, Ft, A, S, cell) <= o.angles_vertex_tol) {
        steps++;
        break;
      }
      if (sq > (1 - o.settle) * sq_prev) {
        if (mu > o.angles / 200) mu *= 0.25;
        else if (!jittered && jitter(nv, nf, F, pin, p, rot, tr, q, q2, A, pmin)) jittered = 1;
        else mu = 0;
        err = face_error(nf, q, S, Stot, A, &Atot, &sq);
        if (mu > 0) sq += mu * shear_mean(nf, q, G, Atot, Stot);
      }
    }
    lambda = fmax(lambda * (alpha == 1 ? 0.5 : 1), 1e-6);
    steps++;
  }
  if (info) info->steps = steps, info->err = err;
  /* The corners' new coordinates; each vt row is one wedge of one vertex: its corners agree. */
  for (int cc = 0; cc < 3 * nf; cc++) vt[2 * Ft[cc]] = q[2 * cc], vt[2 * Ft[cc] + 1] = q[2 * cc + 1];
done:
  au_spd_free(&spd);
  free(home), free(colstart), free(rows), free(p), free(rot), free(tr), free(q), free(q2), free(S), free(A), free(b), free(d),
      free(p2), free(A2), free(pmin), free(G), free(cell), free(pin), free(known);
  return st;
}

double au_atlas_face_error(const au_mesh *m, const au_atlas_layout *L) {
  double Stot = 0, Atot = 0, e = 0;
  double *S = malloc((size_t)(m->nf > 0 ? m->nf : 1) * 2 * sizeof *S);
  if (!S) return -1;
  double *A = S + m->nf;
  for (int f = 0; f < m->nf; f++) {
    const double *x0 = m->X + 3 * (size_t)m->F[3 * f], *x1 = m->X + 3 * (size_t)m->F[3 * f + 1], *x2 = m->X + 3 * (size_t)m->F[3 * f + 2];
    double u[3] = {x1[0] - x0[0], x1[1] - x0[1], x1[2] - x0[2]}, w[3] = {x2[0] - x0[0], x2[1] - x0[1], x2[2] - x0[2]};
    double cx = u[1] * w[2] - u[2] * w[1], cy = u[2] * w[0] - u[0] * w[2], cz = u[0] * w[1] - u[1] * w[0];
    S[f] = 0.5 * sqrt(cx * cx + cy * cy + cz * cz), Stot += S[f];
    const double *a = L->vt + 2 * L->Ft[3 * f], *b = L->vt + 2 * L->Ft[3 * f + 1], *c = L->vt + 2 * L->Ft[3 * f + 2];
    A[f] = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])), Atot += A[f];
  }
  for (int f = 0; f < m->nf; f++) e += fabs(A[f] / Atot * Stot / S[f] - 1);
  free(S);
  return m->nf > 0 ? e / m->nf : 0;
}
