/* au_circles.c - equal-area maps of genus-0 surfaces with k >= 1 boundary loops onto a circle domain:
 * the unit disk with k - 1 round holes (Zou et al. 2011, sec. 4.5.1, "non-closed surfaces, possibly
 * with holes"), with sliding circles.
 *
 * Hole sizes: a hole's area is the area of the flat cap over its loop (the vector area of the loop's
 * polygon on the surface), scaled with the surface so that surface and caps fill the unit disk; the
 * radius follows (au_circles_radii). The flow's targets are shares of the domain's area and do not see
 * the holes' sizes, so the sizes are set in the start and kept by the flow.
 *
 * Start (k >= 3): each hole is filled with a fan about the centroid of its loop, the filled disk is
 * mapped harmonically with the outer loop on the unit circle by arc length (cotan, positive mean-value
 * weights if that folds: then a bijection onto the convex disk, Tutte 1963, Floater 2003), so each
 * hole's loop is a polygon star-shaped about its fan vertex; the loop's vertices are put on a circle
 * about the fan vertex just inside that polygon, along their rays; then each hole is grown to its
 * prescribed radius by a radial map about its centre within its share of the room between its
 * neighbours (a homeomorphism of the plane). Triangles these turn are mended by local harmonic sweeps.
 * k = 2 starts from the annulus's conformal map (au_annulus_init) with the prescribed inner radius;
 * k = 1 is au_disk_map.
 *
 * Flow: the shared Lie-advection loop. Boundary vertices slide along their circle (tangential velocity,
 * radial projection, as the disk's). Before each of the flow's first moves the domain moves each hole
 * (begin_move) by the translation that best fits the tangential motion of its loop (material flowing
 * past a hole carries it along), scaled by the smallest step fraction on the loop, so that a loop whose
 * vertex the step control holds keeps still, and only as far as the hole stays inside the unit circle
 * and apart from the others. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_disk_internal.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* The holes move with the flow's first moves (backtracking tries count), where the bulk of the area is
 * moved; then they keep still (docs/circles.md has the measurements). */
#define AU_CIRCLES_MOVES 16
/* Holes keep this distance from each other and from the unit circle (relative to the smaller radius). */
#define AU_CIRCLES_GAP 1e-3

typedef struct circ_dom {
  const au_topo *t;
  int outer, pinned, fixed; /* fixed: AU_DISK_FIXED, nothing on a loop moves */
  int *loop_of;             /* [nv]: the loop of a boundary vertex, -1 inside */
  au_circle *c;             /* [nloops]: the circles now */
  const double *target;     /* [nloops]: prescribed radii */
  int moves;                /* begin_move calls so far */
} circ_dom;

static double dist3(const double *a, const double *b) {
  return sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
}

/* Solve the 3x3 system A x = b (row-major) by Gaussian elimination with partial pivoting; 0 if singular. */
static int solve3(double A[9], double b[3], double x[3]) {
  for (int c = 0; c < 3; c++) {
    int p = c;
    for (int r = c + 1; r < 3; r++)
      if (fabs(A[3 * r + c]) > fabs(A[3 * p + c])) p = r;
    if (!(fabs(A[3 * p + c]) > 0)) return 0;
    if (p != c) {
      for (int k = 0; k < 3; k++) {
        double tmp = A[3 * c + k];
        A[3 * c + k] = A[3 * p + k], A[3 * p + k] = tmp;
      }
      double tmp = b[c];
      b[c] = b[p], b[p] = tmp;
    }
    for (int r = c + 1; r < 3; r++) {
      double f = A[3 * r + c] / A[3 * c + c];
      for (int k = c; k < 3; k++) A[3 * r + k] -= f * A[3 * c + k];
      b[r] -= f * b[c];
    }
  }
  for (int c = 2; c >= 0; c--) {
    double s = b[c];
    for (int k = c + 1; k < 3; k++) s -= A[3 * c + k] * x[k];
    x[c] = s / A[3 * c + c];
  }
  return 1;
}

/* The least-squares circle through the loop's points (algebraic fit, exact for points on a circle), in
 * coordinates about their mean. row: as au_advect_domain.begin_move. */
static au_circle fit_circle(const au_topo *t, int l, const int *row, const double *P) {
  int a = t->loop_start[l], b = t->loop_start[l + 1], n = b - a;
  double mx = 0, my = 0;
  for (int k = a; k < b; k++) {
    int v = row ? row[t->loop_vert[k]] : t->loop_vert[k];
    mx += P[3 * v], my += P[3 * v + 1];
  }
  mx /= n, my /= n;
  double A[9] = {0}, rhs[3] = {0}, x[3] = {0};
  for (int k = a; k < b; k++) {
    int v = row ? row[t->loop_vert[k]] : t->loop_vert[k];
    double qx = P[3 * v] - mx, qy = P[3 * v + 1] - my, q2 = qx * qx + qy * qy;
    double g[3] = {qx, qy, 1};
    for (int i = 0; i < 3; i++) {
      for (int j = 0; j < 3; j++) A[3 * i + j] += g[i] * g[j];
      rhs[i] -= q2 * g[i];
    }
  }
  au_circle c = {mx, my, 0};
  if (!solve3(A, rhs, x)) return c;
  c.cx = mx - 0.5 * x[0], c.cy = my - 0.5 * x[1];
  double r2 = 0.25 * (x[0] * x[0] + x[1] * x[1]) - x[2];
  c.r = r2 > 0 ? sqrt(r2) : 0;
  return c;
}

/* 1 if hole l's circle c lies inside the unit circle and apart from the other holes. */
static int circle_fits(const circ_dom *d, int l, au_circle c) {
  if (!(hypot(c.cx, c.cy) + c.r * (1 + AU_CIRCLES_GAP) < 1)) return 0;
  for (int h = 0; h < d->t->nloops; h++) {
    if (h == l || h == d->outer) continue;
    double gap = AU_CIRCLES_GAP * fmin(c.r, d->c[h].r);
    if (!(hypot(c.cx - d->c[h].cx, c.cy - d->c[h].cy) > c.r + d->c[h].r + gap)) return 0;
  }
  return 1;
}

static void circ_constrain(void *ctx, int i, const double *p, double *d) {
  const circ_dom *cd = ctx;
  d[2] = 0;
  int l = cd->loop_of[i];
  if (l < 0) return;
  if (cd->fixed || i == cd->pinned) {
    d[0] = d[1] = 0;
    return;
  }
  double nx = p[0] - cd->c[l].cx, ny = p[1] - cd->c[l].cy, r2 = nx * nx + ny * ny;
  if (r2 > 0) {
    double s = (d[0] * nx + d[1] * ny) / r2;
    d[0] -= s * nx, d[1] -= s * ny;
  }
}

static void circ_retract(void *ctx, int i, double *p) {
  const circ_dom *cd = ctx;
  p[2] = 0;
  int l = cd->loop_of[i];
  if (l < 0) return;
  double nx = p[0] - cd->c[l].cx, ny = p[1] - cd->c[l].cy, r = hypot(nx, ny);
  if (r > 0) p[0] = cd->c[l].cx + nx * (cd->c[l].r / r), p[1] = cd->c[l].cy + ny * (cd->c[l].r / r);
}

/* Move each hole with its loop (see the banner). */
static void circ_begin_move(void *ctx, const int *row, const double *P, const double *D, const double *lim) {
  circ_dom *cd = ctx;
  const au_topo *t = cd->t;
  cd->moves++;
  for (int l = 0; l < t->nloops; l++) {
    if (l == cd->outer) continue;
    au_circle c = fit_circle(t, l, row, P);
    cd->c[l] = c;
    if (cd->fixed || !(c.r > 0)) continue;
    double lmin = 1, A[9] = {0}, rhs[3] = {0}, x[3] = {0};
    for (int k = t->loop_start[l]; k < t->loop_start[l + 1]; k++) {
      int v = row ? row[t->loop_vert[k]] : t->loop_vert[k];
      if (lim[v] < lmin) lmin = lim[v];
      double nx = P[3 * v] - c.cx, ny = P[3 * v + 1] - c.cy, r = hypot(nx, ny);
      if (!(r > 0)) continue;
      /* Tangential motion s = D.tau against a translation's v.tau plus a turn w. */
      double g[3] = {-ny / r, nx / r, 1}, s = D[3 * v] * g[0] + D[3 * v + 1] * g[1];
      for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) A[3 * i + j] += g[i] * g[j];
        rhs[i] += s * g[i];
      }
    }
    if (!(lmin > 0) || cd->moves > AU_CIRCLES_MOVES || !solve3(A, rhs, x)) continue;
    double dx = lmin * x[0], dy = lmin * x[1];
    for (int h = 0; h < 30; h++, dx *= 0.5, dy *= 0.5) {
      au_circle n = {c.cx + dx, c.cy + dy, c.r};
      if (circle_fits(cd, l, n)) {
        cd->c[l] = n;
        break;
      }
    }
  }
}

void au_circles_radii(const au_mesh *m, const au_topo *t, int outer, double *radius) {
  double area = 0, caps = 0;
  for (int f = 0; f < m->nf; f++) {
    const double *a = m->X + 3 * m->F[3 * f], *b = m->X + 3 * m->F[3 * f + 1], *c = m->X + 3 * m->F[3 * f + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    area += 0.5 * sqrt(pow(u[1] * w[2] - u[2] * w[1], 2) + pow(u[2] * w[0] - u[0] * w[2], 2) + pow(u[0] * w[1] - u[1] * w[0], 2));
  }
  for (int l = 0; l < t->nloops; l++) {
    /* The vector area of the loop's polygon: the area of the flattest cap over it. */
    double s[3] = {0, 0, 0};
    for (int k = t->loop_start[l]; k < t->loop_start[l + 1]; k++) {
      int k1 = k + 1 < t->loop_start[l + 1] ? k + 1 : t->loop_start[l];
      const double *a = m->X + 3 * t->loop_vert[k], *b = m->X + 3 * t->loop_vert[k1];
      s[0] += a[1] * b[2] - a[2] * b[1], s[1] += a[2] * b[0] - a[0] * b[2], s[2] += a[0] * b[1] - a[1] * b[0];
    }
    radius[l] = 0.5 * sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    if (l != outer) caps += radius[l];
  }
  for (int l = 0; l < t->nloops; l++) radius[l] = l == outer ? 1 : sqrt(radius[l] / (area + caps));
}

/* Mend the few triangles that rounding the holes turned: Gauss-Seidel sweeps of the harmonic equations
 * (positive weights w) over the interior vertices within two rings of a folded triangle, growing the
 * region while folds remain. Returns the folds left. */
static int repair_folds(const au_mesh *m, const au_topo *t, const double *w, double *P) {
  int nv = m->nv, ne = t->ne;
  int *start = calloc((size_t)nv + 1, sizeof(int)), *adj = malloc(sizeof(int) * 2 * (size_t)(ne > 0 ? ne : 1));
  unsigned char *mark = calloc((size_t)nv, 1), *next = calloc((size_t)nv, 1);
  int folds = au__disk_count_folds(m->nf, m->F, P);
  if (!start || !adj || !mark || !next) goto done;
  for (int e = 0; e < ne; e++) start[t->E[2 * e] + 1]++, start[t->E[2 * e + 1] + 1]++;
  for (int i = 0; i < nv; i++) start[i + 1] += start[i];
  {
    int *fill = malloc(sizeof(int) * (size_t)(nv > 0 ? nv : 1));
    if (!fill) goto done;
    memcpy(fill, start, sizeof(int) * (size_t)nv);
    for (int e = 0; e < ne; e++) adj[fill[t->E[2 * e]]++] = e, adj[fill[t->E[2 * e + 1]]++] = e;
    free(fill);
  }
  for (int round = 0; round < 8 && folds; round++) {
    for (int f = 0; f < m->nf; f++) {
      const double *a = P + 3 * m->F[3 * f], *b = P + 3 * m->F[3 * f + 1], *c = P + 3 * m->F[3 * f + 2];
      if (!((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0))
        for (int k = 0; k < 3; k++) mark[m->F[3 * f + k]] = 1;
    }
    for (int ring = 0; ring < 2 + round; ring++) {
      memcpy(next, mark, (size_t)nv);
      for (int i = 0; i < nv; i++)
        if (mark[i])
          for (int a = start[i]; a < start[i + 1]; a++) next[t->E[2 * adj[a]] ^ t->E[2 * adj[a] + 1] ^ i] = 1;
      memcpy(mark, next, (size_t)nv);
    }
    for (int sweep = 0; sweep < 200 && folds; sweep++) {
      for (int i = 0; i < nv; i++) {
        if (!mark[i] || t->vb[i] || !t->vused[i]) continue;
        double sx = 0, sy = 0, sw = 0;
        for (int a = start[i]; a < start[i + 1]; a++) {
          int e = adj[a], j = t->E[2 * e] ^ t->E[2 * e + 1] ^ i;
          sx += w[e] * P[3 * j], sy += w[e] * P[3 * j + 1], sw += w[e];
        }
        if (sw > 0) P[3 * i] = sx / sw, P[3 * i + 1] = sy / sw;
      }
      if (sweep % 10 == 9) folds = au__disk_count_folds(m->nf, m->F, P);
    }
    folds = au__disk_count_folds(m->nf, m->F, P);
  }
done:
  free(start), free(adj), free(mark), free(next);
  return folds;
}

/* Grow each hole of the start towards its prescribed radius by a radial map about its centre that
 * stretches [r0, R] onto [r, R] linearly and leaves the rest (R: the hole's own part of the room
 * between its neighbours and the unit circle, split in proportion to the prescribed radii). A
 * homeomorphism of the plane; triangles it turns are mended (repair_folds), or the hole grows half as
 * much, a quarter, else keeps its start radius. Returns the folds left (0). */
static int inflate_holes(const au_mesh *m, const au_topo *t, int outer, const double *target, const double *w,
                         double *P, au_circle *circ) {
  int nv = m->nv;
  double *keep = malloc(sizeof(double) * 3 * (size_t)nv);
  if (!keep) return 0;
  for (int l = 0; l < t->nloops; l++) {
    if (l == outer || !(target[l] > circ[l].r)) continue;
    double R = 1 - hypot(circ[l].cx, circ[l].cy);
    for (int h = 0; h < t->nloops; h++) {
      if (h == l || h == outer) continue;
      double d = hypot(circ[l].cx - circ[h].cx, circ[l].cy - circ[h].cy);
      R = fmin(R, d * fmax(target[l], circ[l].r) / (fmax(target[l], circ[l].r) + fmax(target[h], circ[h].r)));
    }
    double r0 = circ[l].r, want = fmin(target[l], 0.8 * R);
    if (!(want > r0) || !(R > want)) continue;
    /* The whole way, else half of it, else a quarter. */
    for (int part = 0; part < 3; part++) {
      double r = r0 + (want - r0) / (1 << part);
      memcpy(keep, P, sizeof(double) * 3 * (size_t)nv);
      for (int i = 0; i < nv; i++) {
        double *p = P + 3 * i, nx = p[0] - circ[l].cx, ny = p[1] - circ[l].cy, d = hypot(nx, ny);
        if (!t->vused[i] || d >= R || !(d > 0)) continue;
        double d2 = d <= r0 ? r : r + (d - r0) * (R - r) / (R - r0);
        p[0] = circ[l].cx + nx * d2 / d, p[1] = circ[l].cy + ny * d2 / d;
      }
      for (int k = t->loop_start[l]; k < t->loop_start[l + 1]; k++) {
        double *p = P + 3 * t->loop_vert[k], nx = p[0] - circ[l].cx, ny = p[1] - circ[l].cy, d = hypot(nx, ny);
        p[0] = circ[l].cx + nx * r / d, p[1] = circ[l].cy + ny * r / d;
      }
      if (!au__disk_count_folds(m->nf, m->F, P) || !repair_folds(m, t, w, P)) {
        circ[l].r = r;
        break;
      }
      memcpy(P, keep, sizeof(double) * 3 * (size_t)nv);
    }
  }
  free(keep);
  return au__disk_count_folds(m->nf, m->F, P);
}

/* The start for k >= 3 (see the banner). P: out, nv x 3; circ: out, the holes' start circles. */
static au_status circles_start(const au_mesh *m, const au_topo *t, int outer, const double *target, double *P,
                               au_circle *circ, au_disk_init_method *method, au_msg *msg) {
  int nv = m->nv, nh = t->nloops - 1, nfan = 0;
  for (int l = 0; l < t->nloops; l++)
    if (l != outer) nfan += t->loop_start[l + 1] - t->loop_start[l];
  au_mesh *mf = NULL;
  au_topo *tf = NULL;
  double *Pf = NULL, *w = NULL;
  unsigned char *fixed = NULL;
  int *hub = malloc(sizeof(int) * (size_t)t->nloops);
  au_status st = au_mesh_alloc(nv + nh, m->nf + nfan, &mf);
  if (st != AU_OK || !hub) {
    st = au_msg_set(msg, AU_E_NOMEM, "circles: out of memory");
    goto done;
  }
  memcpy(mf->X, m->X, sizeof(double) * 3 * (size_t)nv);
  memcpy(mf->F, m->F, sizeof(int) * 3 * (size_t)m->nf);
  int nf = m->nf, c = nv;
  for (int l = 0; l < t->nloops; l++) {
    hub[l] = -1;
    if (l == outer) continue;
    int a = t->loop_start[l], b = t->loop_start[l + 1];
    double *x = mf->X + 3 * c;
    x[0] = x[1] = x[2] = 0;
    for (int k = a; k < b; k++)
      for (int d = 0; d < 3; d++) x[d] += m->X[3 * t->loop_vert[k] + d] / (b - a);
    /* The loop runs along its faces' orientation; the fan's faces run against it. */
    for (int k = a; k < b; k++) {
      int *f = mf->F + 3 * nf++;
      f[0] = t->loop_vert[k + 1 < b ? k + 1 : a], f[1] = t->loop_vert[k], f[2] = c;
    }
    hub[l] = c++;
  }
  st = au_mesh_topology(mf, &tf, msg);
  if (st != AU_OK) goto done;
  int nvf = mf->nv;
  Pf = calloc(3 * (size_t)nvf, sizeof(double)), fixed = calloc((size_t)nvf, 1);
  w = malloc(sizeof(double) * (size_t)(t->ne > 0 ? t->ne : 1));
  if (!Pf || !fixed || !w) {
    st = au_msg_set(msg, AU_E_NOMEM, "circles: out of memory");
    goto done;
  }
  for (int i = 0; i < nvf; i++) fixed[i] = !tf->vused[i];
  {
    int a = t->loop_start[outer], n = t->loop_start[outer + 1] - a;
    const int *L = t->loop_vert + a;
    double len = 0, s = 0;
    for (int k = 0; k < n; k++) len += dist3(m->X + 3 * L[k], m->X + 3 * L[(k + 1) % n]);
    for (int k = 0; k < n; k++) {
      double phi = len > 0 ? 2 * M_PI * s / len : 2 * M_PI * k / n;
      Pf[3 * L[k]] = cos(phi), Pf[3 * L[k] + 1] = sin(phi), fixed[L[k]] = 1;
      s += dist3(m->X + 3 * L[k], m->X + 3 * L[(k + 1) % n]);
    }
  }
  st = au__disk_harmonic(mf, tf, fixed, Pf, method, "circles", msg);
  if (st != AU_OK) goto done;
  memcpy(P, Pf, sizeof(double) * 3 * (size_t)nv);
  /* Round each hole: a circle about its hub inside the star-shaped polygon, the loop's vertices along
   * their rays from the hub. Close to the polygon first (the least move); where that turns triangles, a
   * local repair, then smaller circles. */
  au__disk_meanvalue_weights(t, m->F, m->X, w);
  static const double shrink[3] = {0.97, 0.8, 0.5};
  int folds = 0;
  for (int attempt = 0; attempt < 3; attempt++) {
    memcpy(P, Pf, sizeof(double) * 3 * (size_t)nv);
    for (int l = 0; l < t->nloops; l++) {
      if (l == outer) continue;
      int a = t->loop_start[l], b = t->loop_start[l + 1];
      const double *o = Pf + 3 * hub[l];
      double rho = INFINITY;
      for (int k = a; k < b; k++) {
        const double *p = Pf + 3 * t->loop_vert[k], *q = Pf + 3 * t->loop_vert[k + 1 < b ? k + 1 : a];
        double ex = q[0] - p[0], ey = q[1] - p[1], e2 = ex * ex + ey * ey;
        double u = e2 > 0 ? ((o[0] - p[0]) * ex + (o[1] - p[1]) * ey) / e2 : 0;
        u = u < 0 ? 0 : u > 1 ? 1 : u;
        rho = fmin(rho, hypot(p[0] + u * ex - o[0], p[1] + u * ey - o[1]));
      }
      double r = fmin(shrink[attempt] * rho, target[l]);
      circ[l] = (au_circle){o[0], o[1], r};
      for (int k = a; k < b; k++) {
        double *p = P + 3 * t->loop_vert[k], nx = p[0] - o[0], ny = p[1] - o[1], d = hypot(nx, ny);
        p[0] = o[0] + r * nx / d, p[1] = o[1] + r * ny / d;
      }
    }
    folds = au__disk_count_folds(m->nf, m->F, P);
    if (folds) folds = repair_folds(m, t, w, P);
    if (!folds) break;
  }
  if (!folds) folds = inflate_holes(m, t, outer, target, w, P, circ);
  if (folds) st = au_msg_set(msg, AU_E_FOLD, "circles: the initial map has %d folded triangles", folds);
done:
  au_topo_free(&tf);
  au_mesh_free(&mf);
  free(Pf), free(w), free(fixed), free(hub);
  return st;
}

au_status au_circles_map(const au_mesh *m, const au_topo *t, const au_disk_opts *opts, int outer, double *P, double *P0,
                         au_circle *circles, au_disk_report *rep, au_msg *msg) {
  if (!m || !t || !P || t->nv != m->nv || t->nloops < 1 || outer >= t->nloops)
    return au_msg_set(msg, AU_E_ARG, "circles: bad arguments");
  au_disk_report local;
  if (!rep) rep = &local;
  if (outer < 0) {
    outer = 0;
    for (int l = 1; l < t->nloops; l++)
      if (t->loop_len ? t->loop_len[l] > t->loop_len[outer]
                      : t->loop_start[l + 1] - t->loop_start[l] > t->loop_start[outer + 1] - t->loop_start[outer])
        outer = l;
  }
  if (t->nloops == 1) {
    au_status st = au_disk_map(m, t, opts, P, P0, rep, msg);
    rep->outer_loop = 0;
    if (circles) circles[0] = (au_circle){0, 0, 1};
    return st;
  }
  au_disk_opts o = opts ? *opts : au_disk_opts_default();
  memset(rep, 0, sizeof *rep);
  rep->outer_loop = outer;
  int nl = t->nloops;
  circ_dom cd;
  memset(&cd, 0, sizeof cd);
  double *target = malloc(sizeof(double) * (size_t)nl);
  cd.c = calloc((size_t)nl, sizeof *cd.c), cd.loop_of = malloc(sizeof(int) * (size_t)m->nv);
  if (!target || !cd.c || !cd.loop_of) {
    free(target), free(cd.c), free(cd.loop_of);
    return au_msg_set(msg, AU_E_NOMEM, "circles: out of memory");
  }
  au_circles_radii(m, t, outer, target);
  cd.t = t, cd.outer = outer, cd.target = target, cd.fixed = o.boundary == AU_DISK_FIXED;
  cd.pinned = t->loop_vert[t->loop_start[outer]];
  for (int i = 0; i < m->nv; i++) cd.loop_of[i] = -1;
  for (int l = 0; l < nl; l++)
    for (int k = t->loop_start[l]; k < t->loop_start[l + 1]; k++) cd.loop_of[t->loop_vert[k]] = l;
  cd.c[outer] = (au_circle){0, 0, 1};
  /* An interior edge between two vertices of one hole's loop would be a chord of its circle, with the
   * triangles on one side inside the hole: no map onto the circle domain keeps them unfolded. */
  for (int e = 0; e < t->ne; e++) {
    int a = t->E[2 * e], b = t->E[2 * e + 1], l = cd.loop_of[a];
    if (t->EF[2 * e + 1] >= 0 && l >= 0 && l != outer && cd.loop_of[b] == l) {
      free(target), free(cd.c), free(cd.loop_of);
      return au_msg_set(msg, AU_E_BOUNDARY, "edge (%d, %d) joins two vertices of one hole's boundary loop across the "
                        "surface: on the hole's circle its triangles would fold (split the edge, or the triangles "
                        "beside it)", a, b);
    }
  }
  double t0 = au__disk_now();
  /* The flow's analysis needs only the mesh: it runs in a second thread beside the start. */
  au_advect_plan *plan = NULL;
  au_status st = au_advect_plan_start(m, t, &o.flow, &plan, msg);
  if (st == AU_OK) {
    if (nl == 2) {
      st = au_annulus_init(m, t, outer, target[1 - outer], P, NULL, NULL, &rep->init, msg);
      cd.c[1 - outer] = (au_circle){0, 0, target[1 - outer]};
    } else {
      st = circles_start(m, t, outer, target, P, cd.c, &rep->init, msg);
    }
  }
  rep->t_init = au__disk_now() - t0;
  if (st == AU_OK) {
    if (P0) memcpy(P0, P, sizeof(double) * 3 * (size_t)m->nv);
    /* Arcs about the origin for the outer circle's sliding, as the disk's (au_disk_bc_domain). */
    au_advect_domain dom = {circ_constrain, circ_retract, 0, &cd, 1.0, NULL, circ_begin_move};
    t0 = au__disk_now();
    st = au_advect_run_plan(plan, &dom, &o.flow, P, &rep->flow, msg);
    rep->t_flow = au__disk_now() - t0;
  }
  if (st >= 0 && circles) {
    for (int l = 0; l < nl; l++) circles[l] = l == outer ? (au_circle){0, 0, 1} : fit_circle(t, l, NULL, P);
  }
  au_advect_plan_free(&plan);
  free(target), free(cd.c), free(cd.loop_of);
  return st;
}
