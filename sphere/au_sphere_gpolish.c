/* au_sphere_gpolish.c - the global polish: a sphere map's chord triangles brought nearer their shares
 * by a Levenberg-Marquardt iteration over every vertex at once, after the vertex polish.
 *
 * Why: the vertex polish moves one vertex at a time, and on a refined mesh of a thin-limbed shape it
 * stops where a vertex cannot gain without its neighbours moving with it: the bands around a limb's
 * base must widen or narrow together (docs/sphere.md). A joint step over all vertices
 * does that. Its unknowns are each vertex's displacement in its tangent plane; its residuals are the
 * faces' log(chord share / surface share), the vertex cells' (weighted, as the metrics' vertex error is
 * the harder of the two) and, for a face whose triple product has come below a threshold, a log
 * barrier that lets the Gauss-Newton model see a face nearing its turn-over before a step turns it;
 * with an angle weight also each face's log conformal distortion (the MIPS energy of the affine map
 * from the surface's triangle to the chord triangle: (sum of cot(surface angle) x chord edge^2) / (4 x
 * chord area), 1 for a similarity), so that among maps of about equal area it goes to the less sheared.
 * A step that would still take a triple product below its least (min_orient of the share, or where it
 * started if lower: the vertex polish's rule, kept for the textures' sake) is halved until it does not,
 * or tried again with more damping; every map it returns is fold-free.
 *
 * The normal matrix J^T J couples vertices two rings apart (a vertex cell's residual involves the
 * faces around it); its pattern is analyzed once and refactored for every damping tried. The derivative
 * of the chord triangles' total, which only rescales all shares alike, is left out of J. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_dec.h"
#include "au_solver.h"
#include "au_sphere.h"

enum { GP_MAX_STAR = 64 }; /* faces around a vertex; a mesh with more is not polished */
#define GP_DAMP_TRIES 20      /* dampings tried (each 4x the last) before the iteration gives up */
#define GP_HALVINGS 30        /* step halvings before a step is given up as turning a face over */
#define GP_STALL 1e-4         /* stop when 5 steps in a row each lower the cost by less than this part */
/* au_gpolish_opts.min_gain compares the errors with theirs this many steps back. With 10 the generated
 * limbs4 stopped in a pause at step 93 (vertex 0.0283) and then would have gone on to 0.0201. */
#define GP_GAIN_WINDOW 20

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross(const double *a, const double *b, double *r) {
  r[0] = a[1] * b[2] - a[2] * b[1];
  r[1] = a[2] * b[0] - a[0] * b[2];
  r[2] = a[0] * b[1] - a[1] * b[0];
}

typedef struct gp {
  int nv, nf;
  const int *F;
  const double *share;  /* [nf] surface shares (sum 1) */
  const double *cshare; /* [nv] vertex cells' shares */
  const double *lo;     /* [nf] least triple product allowed */
  const double *tau;    /* [nf] the barrier acts where a triple product is less than this above lo */
  double wv, mu;
  int *colstart, *rows; /* upper triangle of the 2nv x 2nv pattern, by column */
  double *C, *cell, *orient;
  double *Gf; /* [9 nf] assemble's chord-area gradients of each face's corners, for the cells' rows */
  const double *cot; /* [3 nf] the surface's cotangents, corner by corner (with an angle weight) */
  double beta;       /* the angle weight */
  double verr; /* cost()'s vertex error: the cells' mean |log ratio| (the metrics') */
  double ferr; /* cost()'s face error: the faces' mean |r - 1| (the metrics') */
  double delta;  /* au_gpolish_opts.robust */
  int *fidx;            /* [36 nf] add_row's index table of each face's row */
  size_t *vidx_start;   /* [nv + 1] where each cell's row's table starts in vidx */
  int *vidx;
} gp;

/* Triple products of every face at P; returns 1 if each is above its least allowed value. */
static int orients_ok(const gp *g, const double *P, double *orient) {
  int ok = 1;
  for (int f = 0; f < g->nf; f++) {
    const int *v = g->F + 3 * f;
    orient[f] = au_dec_sphere_orient(P + 3 * v[0], P + 3 * v[1], P + 3 * v[2]);
    if (!(orient[f] > 0) || !(orient[f] >= g->lo[f])) ok = 0;
  }
  return ok;
}

/* Sum over face f's edges of cot(surface angle) x chord edge^2 at P: 4 x chord area x its MIPS energy. */
static double mips_num(const gp *g, const double *P, int f) {
  const int *v = g->F + 3 * f;
  double N = 0;
  for (int i = 0; i < 3; i++) {
    const double *a = P + 3 * v[(i + 1) % 3], *b = P + 3 * v[(i + 2) % 3];
    double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    N += g->cot[3 * f + i] * dot(e, e);
  }
  return N;
}

/* The residual of a log ratio r and its derivative: with a robust delta, rho = r sqrt(2 / (1 + s)), s =
 * sqrt(1 + (r / delta)^2), so that rho^2 = 2 delta^2 (s - 1), the pseudo-Huber loss: quadratic below
 * delta and growing as |r| above it, like the metrics' mean |r - 1| and mean |log ratio|. Squares let a
 * few faces that cannot reach their share (a long edge's floor) pull many others off theirs. */
static double rho(const gp *g, double r, double *drho) {
  if (!(g->delta > 0)) {
    if (drho) *drho = 1;
    return r;
  }
  double s = sqrt(1 + (r / g->delta) * (r / g->delta));
  if (drho) *drho = sqrt((1 + s) / 2) / s;
  return r * sqrt(2 / (1 + s));
}

/* The cost at P (faces' squared log ratios, the weighted cells', the barriers'); fills C, cell and
 * orient, and the chord total in *Cs. INFINITY where a chord triangle or a cell is empty. */
static double cost(gp *g, const double *P, double *Cs) {
  const int nf = g->nf, nv = g->nv, *F = g->F;
  double s = 0, E = 0;
  for (int f = 0; f < nf; f++) {
    const int *v = F + 3 * f;
    const double *a = P + 3 * v[0], *b = P + 3 * v[1], *c = P + 3 * v[2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, n[3];
    cross(u, w, n);
    g->C[f] = 0.5 * sqrt(dot(n, n));
    g->orient[f] = au_dec_sphere_orient(a, b, c);
    s += g->C[f];
  }
  memset(g->cell, 0, sizeof(double) * (size_t)nv);
  for (int f = 0; f < nf; f++) {
    if (!(g->C[f] > 0)) return INFINITY;
    double r = rho(g, log(g->C[f] / s / g->share[f]), NULL);
    E += r * r;
    for (int k = 0; k < 3; k++) g->cell[F[3 * f + k]] += g->C[f] / (3 * s);
    if (g->beta > 0) {
      double q = log(mips_num(g, P, f) / (4 * g->C[f]));
      E += g->beta * q * q;
    }
    double gap = g->orient[f] - g->lo[f];
    if (gap < g->tau[f]) {
      double b = g->mu * log(g->tau[f] / (gap > 0 ? gap : 1e-300));
      E += b * b;
    }
  }
  g->ferr = 0;
  for (int f = 0; f < nf; f++) g->ferr += fabs(g->C[f] / s / g->share[f] - 1);
  g->ferr /= nf;
  int nc = 0;
  g->verr = 0;
  for (int v = 0; v < nv; v++)
    if (g->cshare[v] > 0) {
      if (!(g->cell[v] > 0)) return INFINITY;
      double l = log(g->cell[v] / g->cshare[v]), r = g->wv * rho(g, l, NULL);
      E += r * r, g->verr += fabs(l), nc++;
    }
  g->verr = nc ? g->verr / nc : 0;
  *Cs = s;
  return E;
}

/* Index of row r in column c (r <= c) of the pattern; -1 if absent (cannot happen for J's pairs). */
static int find(const gp *g, int r, int c) {
  const int *col = g->rows + g->colstart[c];
  const int *hit = bsearch(&r, col, (size_t)(g->colstart[c + 1] - g->colstart[c]), sizeof(int), au__cmp_int);
  return hit ? g->colstart[c] + (int)(hit - col) : -1;
}

/* One residual row with entries (col[k], val[k]), k < n (columns distinct), and value r: its outer
 * product into H and r * row into grad; idx[a * n + b] is the pattern's index of (col[a], col[b]) where
 * col[a] <= col[b] (row_index). */
static void add_row(double *H, double *grad, int n, const int *col, const double *val, double r, const int *idx) {
  for (int a = 0; a < n; a++) {
    grad[col[a]] += r * val[a];
    for (int b = 0; b < n; b++)
      if (col[a] <= col[b]) H[idx[a * n + b]] += val[a] * val[b];
  }
}

/* The index table of add_row for the columns col[0..n-1]. */
static void row_index(const gp *g, int n, const int *col, int *idx) {
  for (int a = 0; a < n; a++)
    for (int b = 0; b < n; b++) idx[a * n + b] = col[a] <= col[b] ? find(g, col[a], col[b]) : -1;
}

/* A face's columns: its corners' two unknowns each. */
static void face_cols(const int *v, int *col) {
  for (int k = 0; k < 3; k++) col[2 * k] = 2 * v[k], col[2 * k + 1] = 2 * v[k] + 1;
}

/* A vertex cell's columns: the unknowns of the vertices of the faces around v, in the order met;
 * slot[3 i + k] is the column of corner k of v's i-th face. Returns the number of columns. */
static int cell_cols(const int *F, const int *vf_start, const int *vf, int v, int *col, int *slot) {
  int n = 0;
  for (int i = vf_start[v]; i < vf_start[v + 1]; i++)
    for (int k = 0; k < 3; k++) {
      int u = F[3 * vf[i] + k], c = 0;
      while (c < n && col[c] != 2 * u) c += 2;
      if (c == n) col[n] = 2 * u, col[n + 1] = 2 * u + 1, n += 2;
      slot[3 * (i - vf_start[v]) + k] = c;
    }
  return n;
}

/* The tangent basis at p: e1 orthogonal to p and to an axis p is not near, e2 = p x e1. */
static void basis(const double *p, double *e1, double *e2) {
  double ax[3] = {fabs(p[0]) < 0.9 ? 1.0 : 0.0, fabs(p[0]) < 0.9 ? 0.0 : 1.0, 0};
  cross(p, ax, e1);
  double l = sqrt(dot(e1, e1));
  e1[0] /= l, e1[1] /= l, e1[2] /= l;
  cross(p, e1, e2);
}

/* Gradient of the chord area of face f with respect to its corner k at P (half of n^ x (p_k+2 - p_k+1))
 * and of its triple product (p_k+1 x p_k+2). */
static void face_grads(const double *P, const int *v, double G[3][3], double D[3][3]) {
  const double *p[3] = {P + 3 * v[0], P + 3 * v[1], P + 3 * v[2]};
  double u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
  double w[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]}, n[3];
  cross(u, w, n);
  double l = sqrt(dot(n, n));
  if (l > 0) n[0] /= l, n[1] /= l, n[2] /= l;
  for (int k = 0; k < 3; k++) {
    const double *a = p[(k + 1) % 3], *b = p[(k + 2) % 3];
    double e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    cross(n, e, G[k]);
    G[k][0] *= 0.5, G[k][1] *= 0.5, G[k][2] *= 0.5;
    cross(a, b, D[k]);
  }
}

/* J^T J into H (values of the pattern) and J^T r into grad, at P (cost() has filled C, cell, orient). */
static void assemble(const gp *g, const double *P, const double *B, double Cs, const int *vf_start, const int *vf,
                     double *H, double *grad) {
  const int nf = g->nf, nv = g->nv, *F = g->F;
  memset(H, 0, sizeof(double) * (size_t)g->colstart[2 * nv]);
  memset(grad, 0, sizeof(double) * 2 * (size_t)nv);
  double G[3][3], D[3][3], val[2 * (GP_MAX_STAR + 2)];
  int col[2 * (GP_MAX_STAR + 2)], slot[3 * GP_MAX_STAR];
  for (int f = 0; f < nf; f++) {
    face_grads(P, F + 3 * f, G, D);
    memcpy(g->Gf + 9 * (size_t)f, G, sizeof G);
    const int *v = F + 3 * f, *idx = g->fidx + 36 * (size_t)f;
    face_cols(v, col);
    double dr, r = rho(g, log(g->C[f] / Cs / g->share[f]), &dr);
    for (int k = 0; k < 3; k++)
      for (int d = 0; d < 2; d++) val[2 * k + d] = dr * dot(G[k], B + 6 * v[k] + 3 * d) / g->C[f];
    add_row(H, grad, 6, col, val, r, idx);
    if (g->beta > 0) {
      const double *p[3] = {P + 3 * v[0], P + 3 * v[1], P + 3 * v[2]};
      double N = mips_num(g, P, f), sb = sqrt(g->beta);
      for (int k = 0; k < 3; k++) {
        const double *pk = p[k], *p1 = p[(k + 1) % 3], *p2 = p[(k + 2) % 3];
        double c1 = g->cot[3 * f + (k + 1) % 3], c2 = g->cot[3 * f + (k + 2) % 3], dN[3];
        for (int c = 0; c < 3; c++) dN[c] = 2 * c1 * (pk[c] - p2[c]) + 2 * c2 * (pk[c] - p1[c]);
        for (int d = 0; d < 2; d++) {
          const double *e = B + 6 * v[k] + 3 * d;
          val[2 * k + d] = sb * (dot(dN, e) / N - dot(G[k], e) / g->C[f]);
        }
      }
      add_row(H, grad, 6, col, val, sb * log(N / (4 * g->C[f])), idx);
    }
    if (g->orient[f] - g->lo[f] < g->tau[f]) {
      double o = g->orient[f] - g->lo[f];
      for (int k = 0; k < 3; k++)
        for (int d = 0; d < 2; d++) val[2 * k + d] = -g->mu * dot(D[k], B + 6 * v[k] + 3 * d) / o;
      add_row(H, grad, 6, col, val, g->mu * log(g->tau[f] / o), idx);
    }
  }
  /* A vertex cell's row: a third of each face's chord area around it, over the cell. */
  for (int v = 0; v < nv; v++) {
    if (!(g->cshare[v] > 0)) continue;
    int n = cell_cols(F, vf_start, vf, v, col, slot);
    double dr, r = rho(g, log(g->cell[v] / g->cshare[v]), &dr);
    memset(val, 0, sizeof(double) * (size_t)n);
    for (int i = vf_start[v]; i < vf_start[v + 1]; i++) {
      const double *Gi = g->Gf + 9 * (size_t)vf[i];
      for (int k = 0; k < 3; k++) {
        int u = F[3 * vf[i] + k], c = slot[3 * (i - vf_start[v]) + k];
        for (int d = 0; d < 2; d++) val[c + d] += dr * g->wv * dot(Gi + 3 * k, B + 6 * u + 3 * d) / (3 * Cs * g->cell[v]);
      }
    }
    add_row(H, grad, n, col, val, g->wv * r, g->vidx + g->vidx_start[v]);
  }
}

/* The index tables of the faces' rows and the cells' rows (g->fidx, g->vidx_start, g->vidx). */
static int build_index(gp *g, const int *vf_start, const int *vf) {
  const int nf = g->nf, nv = g->nv;
  int col[2 * (GP_MAX_STAR + 2)], slot[3 * GP_MAX_STAR];
  g->fidx = malloc(sizeof(int) * 36 * (size_t)(nf > 0 ? nf : 1));
  g->vidx_start = malloc(sizeof(size_t) * ((size_t)nv + 1));
  if (!g->fidx || !g->vidx_start) return 0;
  for (int f = 0; f < nf; f++) {
    face_cols(g->F + 3 * f, col);
    row_index(g, 6, col, g->fidx + 36 * (size_t)f);
  }
  g->vidx_start[0] = 0;
  for (int v = 0; v < nv; v++) {
    int n = cell_cols(g->F, vf_start, vf, v, col, slot);
    g->vidx_start[v + 1] = g->vidx_start[v] + (size_t)n * (size_t)n;
  }
  g->vidx = malloc(sizeof(int) * (g->vidx_start[nv] > 0 ? g->vidx_start[nv] : 1));
  if (!g->vidx) return 0;
  for (int v = 0; v < nv; v++) {
    int n = cell_cols(g->F, vf_start, vf, v, col, slot);
    row_index(g, n, col, g->vidx + g->vidx_start[v]);
  }
  return 1;
}

/* Upper-triangle pattern of J^T J: vertices within two rings, 2x2 blocks. */
static int build_pattern(gp *g, const au_topo *t) {
  const int nv = g->nv, ne = t->ne;
  int *astart = calloc((size_t)nv + 1, sizeof(int)), *adj = malloc(sizeof(int) * (2 * (size_t)ne + 1));
  int *mark = malloc(sizeof(int) * (size_t)nv), *list = malloc(sizeof(int) * (size_t)nv);
  int ok = astart && adj && mark && list;
  size_t cap = 0, nz = 0;
  if (ok) {
    for (int e = 0; e < ne; e++) astart[t->E[2 * e] + 1]++, astart[t->E[2 * e + 1] + 1]++;
    for (int v = 0; v < nv; v++) astart[v + 1] += astart[v];
    for (int v = 0; v < nv; v++) mark[v] = 0;
    for (int e = 0; e < ne; e++) {
      int a = t->E[2 * e], b = t->E[2 * e + 1];
      adj[astart[a] + mark[a]++] = b, adj[astart[b] + mark[b]++] = a;
    }
    for (int v = 0; v < nv; v++) mark[v] = -1;
    g->colstart = malloc(sizeof(int) * (2 * (size_t)nv + 1));
    cap = 64 * (size_t)nv + 16;
    g->rows = malloc(sizeof(int) * cap);
    ok = g->colstart && g->rows;
  }
  for (int k = 0; ok && k < nv; k++) {
    /* The vertices u <= k within two rings of k. */
    int n = 0;
    mark[k] = k, list[n++] = k;
    for (int i = astart[k]; i < astart[k + 1]; i++) {
      int a = adj[i];
      if (mark[a] != k) mark[a] = k, list[n++] = a;
      for (int j = astart[a]; j < astart[a + 1]; j++)
        if (mark[adj[j]] != k) mark[adj[j]] = k, list[n++] = adj[j];
    }
    int m = 0;
    for (int i = 0; i < n; i++)
      if (list[i] <= k) list[m++] = list[i];
    qsort(list, (size_t)m, sizeof(int), au__cmp_int);
    if (nz + 4 * (size_t)m + 4 > cap) {
      cap = 2 * cap + 4 * (size_t)m;
      int *r = realloc(g->rows, sizeof(int) * cap);
      if (!r) {
        ok = 0;
        break;
      }
      g->rows = r;
    }
    for (int c = 0; c < 2; c++) {
      g->colstart[2 * k + c] = (int)nz;
      for (int i = 0; i < m; i++) {
        int u = list[i];
        g->rows[nz++] = 2 * u;
        if (u < k || c == 1) g->rows[nz++] = 2 * u + 1;
      }
    }
  }
  if (ok) g->colstart[2 * nv] = (int)nz;
  free(astart), free(adj), free(mark), free(list);
  return ok;
}

/* Faces by vertex: vf[vf_start[v]..vf_start[v+1]-1] are v's faces. Returns 0 when a vertex has more
 * than GP_MAX_STAR faces (its cell's row would not fit), -1 out of memory, 1 done. */
static int faces_by_vertex(int nv, int nf, const int *F, int *vf_start, int *vf) {
  for (int i = 0; i < 3 * nf; i++) vf_start[F[i] + 1]++;
  for (int v = 0; v < nv; v++) {
    if (vf_start[v + 1] > GP_MAX_STAR) return 0;
    vf_start[v + 1] += vf_start[v];
  }
  int *fill = calloc((size_t)nv, sizeof(int));
  if (!fill) return -1;
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) vf[vf_start[F[3 * f + k]] + fill[F[3 * f + k]]++] = f;
  free(fill);
  return 1;
}

/* The surface's side of the residuals: each face's share of the (weighted) area, each vertex cell's
 * (a third of its faces'), and with an angle weight the cotangents of the surface's angles (g->cot,
 * owned by g). Returns 0 out of memory. */
static int surface_terms(gp *g, const double *X, const double *face_w, double *share, double *cshare) {
  const int nf = g->nf, *F = g->F;
  au_dec_face_areas(nf, F, X, share);
  double sA = 0;
  for (int f = 0; f < nf; f++) share[f] *= face_w ? face_w[f] : 1.0, sA += share[f];
  for (int f = 0; f < nf; f++) {
    share[f] /= sA;
    for (int k = 0; k < 3; k++) cshare[F[3 * f + k]] += share[f] / 3;
  }
  g->share = share, g->cshare = cshare;
  if (!(g->beta > 0)) return 1;
  double *cot = malloc(sizeof(double) * 3 * (size_t)nf);
  if (!cot) return 0;
  for (int f = 0; f < nf; f++)
    for (int i = 0; i < 3; i++) {
      const double *x0 = X + 3 * F[3 * f + i], *x1 = X + 3 * F[3 * f + (i + 1) % 3], *x2 = X + 3 * F[3 * f + (i + 2) % 3];
      double a[3] = {x1[0] - x0[0], x1[1] - x0[1], x1[2] - x0[2]}, b[3] = {x2[0] - x0[0], x2[1] - x0[1], x2[2] - x0[2]}, n[3];
      cross(a, b, n);
      cot[3 * f + i] = dot(a, b) / sqrt(dot(n, n));
    }
  g->cot = cot;
  return 1;
}

/* Y: P moved by s dx in its tangent bases B, back on the sphere; a vertex with no move stays exactly. */
static void move_along(int nv, const double *P, const double *B, const double *dx, double s, double *Y) {
  for (int v = 0; v < nv; v++) {
    if (dx[2 * v] == 0 && dx[2 * v + 1] == 0) {
      memcpy(Y + 3 * v, P + 3 * v, sizeof(double) * 3);
      continue;
    }
    const double *e1 = B + 6 * v, *e2 = e1 + 3;
    double q[3];
    for (int c = 0; c < 3; c++) q[c] = P[3 * v + c] + s * (dx[2 * v] * e1[c] + dx[2 * v + 1] * e2[c]);
    double l = sqrt(dot(q, q));
    for (int c = 0; c < 3; c++) Y[3 * v + c] = q[c] / l;
  }
}

/* One damped step from P: (H + lam diag H) dx = rhs on the system spd (g's pattern), then dx halved
 * until no triple product falls below its least; the moved map in Y (g->orient at Y). Returns 1 with Y,
 * 0 if every halving turned a face, -1 if the solve failed. */
static int damped_step(gp *g, au_spd *spd, const double *H, const double *rhs, double lam, const double *P,
                       const double *B, double *dx, double *Y) {
  const int n = 2 * g->nv, *cs = g->colstart;
  double *val = au_spd_values(spd);
  memcpy(val, H, sizeof(double) * (size_t)cs[n]);
  for (int j = 0; j < n; j++) {
    int d = cs[j + 1] - 1; /* the diagonal closes each column */
    val[d] = val[d] * (1 + lam) + 1e-300;
  }
  if (au_spd_factor(spd, NULL) != AU_OK || au_spd_solve(spd, rhs, dx, NULL) != AU_OK) return -1;
  double s = 1;
  for (int h = 0; h < GP_HALVINGS; h++, s *= 0.5) {
    move_along(g->nv, P, B, dx, s, Y);
    if (orients_ok(g, Y, g->orient)) return 1;
  }
  return 0;
}

/* Damped steps from lam up (4x each) until one lowers the cost below c0: 1 with Y, its cost *c1 and
 * chord total *Cs1, and *lam 4x the accepted damping; 0 if none did (or a solve failed). */
static int try_steps(gp *g, au_spd *spd, const double *H, const double *rhs, double *lam, const double *P,
                     const double *B, double *dx, double *Y, double c0, double *c1, double *Cs1) {
  for (int tr = 0; tr < GP_DAMP_TRIES; tr++, *lam *= 4) {
    int ok = damped_step(g, spd, H, rhs, *lam, P, B, dx, Y);
    if (ok < 0) return 0;
    if (!ok) continue;
    *c1 = cost(g, Y, Cs1);
    if (*c1 < c0) {
      *lam *= 4;
      return 1;
    }
  }
  return 0;
}

/* The cells weigh 3 against the faces, as the vertex error is the harder of the two to bring down; the
 * barrier acts from 0.15 of a face's share above its least triple product, the vertex polish's tenth of
 * the share; its weight matters little. Measured on the refined limbs4 and coil and on cow
 * (docs/sphere.md). */
au_gpolish_opts au_sphere_gpolish_settings(int max_iter, double angle_weight, double tol, const int *cancel) {
  au_gpolish_opts o = {max_iter, 3, 0.15, 0.05, 0.1, angle_weight, 0, tol, cancel, 0, 0, 0, 0};
  return o;
}

/* Written as "x >= 0" so that a NaN option fails too. */
static int opts_valid(const au_gpolish_opts *o) {
  return o && o->max_iter >= 0 && o->cell_weight >= 0 && o->barrier >= 0 && o->barrier_weight >= 0 && o->min_orient >= 0 &&
         o->angle_weight >= 0 && o->robust >= 0 && o->min_gain >= 0 && o->min_gain < 1 && o->face_window >= 0 &&
         o->face_window <= GP_GAIN_WINDOW && o->face_gain >= 0 && o->face_gain < 1 && o->face_target >= 0;
}

au_status au_sphere_global_polish(const au_mesh *m, const au_topo *t, const double *face_w, double *P,
                                  const au_gpolish_opts *o, int *iters, au_msg *msg) {
  if (iters) *iters = 0;
  if (!m || !t || !P || !opts_valid(o)) return au_msg_set(msg, AU_E_ARG, "global polish: bad arguments");
  const int nv = m->nv, nf = m->nf, n = 2 * nv, *F = m->F;
  gp g = {.nv = nv, .nf = nf, .F = F, .wv = o->cell_weight, .mu = o->barrier_weight, .delta = o->robust};
  double *share = malloc(sizeof(double) * (size_t)nf), *cshare = calloc((size_t)nv, sizeof(double));
  double *lo = malloc(sizeof(double) * (size_t)nf), *tau = malloc(sizeof(double) * (size_t)nf);
  double *B = malloc(sizeof(double) * 6 * (size_t)nv), *Y = malloc(sizeof(double) * 3 * (size_t)nv);
  double *grad = malloc(sizeof(double) * (size_t)n), *dx = malloc(sizeof(double) * (size_t)n);
  double *rhs = malloc(sizeof(double) * (size_t)n);
  int *vf_start = calloc((size_t)nv + 1, sizeof(int)), *vf = malloc(sizeof(int) * 3 * (size_t)nf);
  double *H = NULL;
  g.C = malloc(sizeof(double) * (size_t)nf), g.cell = malloc(sizeof(double) * (size_t)nv);
  g.orient = malloc(sizeof(double) * (size_t)nf), g.Gf = malloc(sizeof(double) * 9 * (size_t)nf);
  au_spd *spd = NULL;
  au_status st = AU_OK;
  if (!share || !cshare || !lo || !tau || !B || !Y || !grad || !dx || !rhs || !vf_start || !vf || !g.C ||
      !g.cell || !g.orient || !g.Gf || !build_pattern(&g, t)) {
    st = au_msg_set(msg, AU_E_NOMEM, "global polish: out of memory");
    goto done;
  }
  /* A vertex cell's row holds its star's vertices; past the fixed row size the polish does not run. */
  int fv = faces_by_vertex(nv, nf, F, vf_start, vf);
  if (fv == 0) goto done;
  H = malloc(sizeof(double) * (size_t)g.colstart[n]);
  g.lo = lo, g.tau = tau, g.beta = o->angle_weight;
  if (fv < 0 || !H || !build_index(&g, vf_start, vf) || !surface_terms(&g, m->X, face_w, share, cshare)) {
    st = au_msg_set(msg, AU_E_NOMEM, "global polish: out of memory");
    goto done;
  }
  double Cs = 0;
  for (int f = 0; f < nf; f++) lo[f] = 0, tau[f] = 0;
  double c0 = cost(&g, P, &Cs);
  /* Thresholds in triple products (about twice a small spherical triangle's area), against each face's
   * share of the chord total. */
  for (int f = 0; f < nf; f++) {
    double T = share[f] * Cs, ok_lo = o->min_orient * T;
    lo[f] = (g.orient[f] < ok_lo ? g.orient[f] : ok_lo) * (1 - 1e-9); /* a unit vector renormalized may move it by an ulp */
    tau[f] = 2 * o->barrier * T;
  }
  c0 = cost(&g, P, &Cs);
  if (!isfinite(c0) || g.verr <= o->tol) goto done;
  double lam = 1e-3, verr_hist[GP_GAIN_WINDOW], ferr_hist[GP_GAIN_WINDOW];
  int stall = 0;
  double fhist[GP_GAIN_WINDOW]; /* the face errors of the last face_window steps, by step % face_window */
  fhist[0] = g.ferr;
  for (int it = 0; it < o->max_iter; it++) {
    /* min_gain: the errors a user reads (param-eval's) against theirs GP_GAIN_WINDOW steps back. The cost
     * keeps falling where they have stopped: on screwdriver its last 77 of 200 steps took the faces
     * from 0.0223 to 0.0219 and the cells from 0.0040 to 0.0039 (docs/sphere-stages.md). */
    if (o->min_gain > 0 && it >= GP_GAIN_WINDOW && g.verr > (1 - o->min_gain) * verr_hist[it % GP_GAIN_WINDOW] &&
        g.ferr > (1 - o->min_gain) * ferr_hist[it % GP_GAIN_WINDOW])
      break;
    verr_hist[it % GP_GAIN_WINDOW] = g.verr, ferr_hist[it % GP_GAIN_WINDOW] = g.ferr;
    if (o->cancel && __atomic_load_n(o->cancel, __ATOMIC_ACQUIRE)) {
      st = au_msg_set(msg, AU_E_CANCELLED, "global polish: cancelled at step %d", it);
      break;
    }
    for (int v = 0; v < nv; v++) basis(P + 3 * v, B + 6 * v, B + 6 * v + 3);
    assemble(&g, P, B, Cs, vf_start, vf, H, grad);
    for (int i = 0; i < n; i++) rhs[i] = -grad[i];
    if (!spd && (st = au_spd_create(n, g.colstart, g.rows, NULL, &spd, msg)) != AU_OK) break;
    double c1 = INFINITY, Cs1 = 0;
    int found = try_steps(&g, spd, H, rhs, &lam, P, B, dx, Y, c0, &c1, &Cs1);
    if (!found) {
      cost(&g, P, &Cs); /* restore C, cell, orient at P */
      break;
    }
    lam /= 12; /* the loop's last lam *= 4 and a third of the accepted damping */
    if (lam < 1e-8) lam = 1e-8;
    stall = c1 > (1 - GP_STALL) * c0 ? stall + 1 : 0;
    memcpy(P, Y, sizeof(double) * 3 * (size_t)nv);
    c0 = c1, Cs = Cs1;
    if (iters) *iters = it + 1;
    if (stall >= 5) break;
    /* face_window: a step that brings the vertex error to the tolerance may leave the per-face error
     * where a few more steps still lower it (docs/sphere-polish-speed.md). */
    if (g.verr <= o->tol &&
        (o->face_window <= 0 || g.ferr <= o->face_target ||
         (it + 1 >= o->face_window && g.ferr > (1 - o->face_gain) * fhist[(it + 1) % o->face_window])))
      break;
    if (o->face_window > 0) fhist[(it + 1) % o->face_window] = g.ferr;
  }
done:
  au_spd_free(&spd);
  free(share), free(cshare), free(lo), free(tau), free(B), free(Y), free(grad), free(dx), free(rhs);
  free(vf_start), free(vf), free(H), free(g.C), free(g.cell), free(g.orient), free(g.Gf), free(g.colstart), free(g.rows);
  free(g.fidx), free(g.vidx_start), free(g.vidx), free((void *)g.cot);
  return st;
}
