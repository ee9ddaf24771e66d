/* au_gn.c - the exact Gauss-Newton step on the barycentric vertex areas (the polish phase of the flow).
 *
 * The paper's step moves vertices along an averaged gradient of the Poisson potential, which is only
 * approximately the derivative of the cell areas; near the end this mismatch makes the error stall.
 * Here D is that derivative exactly: cell i changes by sum_j c_ij . u_j with c_ij = (1/3) sum over the
 * faces f of both i and j of d(area f)/d(p_j), projected onto the domain's constraint at j. The step
 * of least weighted kinetic energy that realizes dA is u_j = W_j sum_i g_i c_ij with (D W D^T) g = dA:
 * with W = 1/(vertex area) it is the discrete counterpart of the paper's potential flow, and it
 * converges quadratically. D W D^T couples vertices up to two rings apart; its pattern is analyzed once. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_advect_internal.h"
#include "au_solver.h"

/* The relative Tikhonov term of the Gauss-Newton system (see au__gn_step): far above the rounding of
 * the largest diagonal entry, far below any entry that carries the step. */
#define AU_GN_REG 1e-10

struct au_gn {
  int nv, nf;
  int faces;    /* 0: cells are the barycentric vertex cells; 1: cells are the triangles */
  int nc;       /* number of cells */
  const int *F;
  int *Lstart;  /* [0..nv]: vertex j's list L_j = {j} + its neighbours is Lv[Lstart[j]..Lstart[j+1]-1] */
  int *Lv;
  double *c;    /* [0..3*Lstart[nv]-1]: c_ij for the entries of L_j */
  int *colstart, *rows;
  au_spd *spd;
};

void au__gn_free(au_gn **gp) {
  if (!gp || !*gp) return;
  au_gn *g = *gp;
  free(g->Lstart), free(g->Lv), free(g->c), free(g->colstart), free(g->rows);
  au_spd_free(&g->spd);
  free(g);
  *gp = NULL;
}

au_status au__gn_create(const au_mesh *m, const au_topo *t, int faces, au_gn **out, au_msg *msg) {
  *out = NULL;
  int nv = m->nv;
  au_gn *g = calloc(1, sizeof *g);
  if (!g) return au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
  g->nv = nv, g->nf = m->nf, g->F = m->F, g->faces = faces, g->nc = faces ? m->nf : nv;
  int nc = g->nc;
  g->Lstart = calloc((size_t)nv + 1, sizeof(int));
  int *cnt = calloc((size_t)(nc > nv ? nc : nv) + 1, sizeof(int));
  if (!g->Lstart || !cnt) goto nomem;
  if (faces) {
    for (int f = 0; f < m->nf; f++)
      for (int k = 0; k < 3; k++) g->Lstart[m->F[3 * f + k] + 1]++;
    for (int j = 0; j < nv; j++) g->Lstart[j + 1] += g->Lstart[j];
  } else {
    for (int e = 0; e < t->ne; e++) g->Lstart[t->E[2 * e] + 1]++, g->Lstart[t->E[2 * e + 1] + 1]++;
    for (int j = 0; j < nv; j++) g->Lstart[j + 1] += g->Lstart[j] + 1;
  }
  g->Lv = malloc(sizeof(int) * (size_t)(g->Lstart[nv] > 0 ? g->Lstart[nv] : 1));
  g->c = malloc(sizeof(double) * 3 * (size_t)(g->Lstart[nv] > 0 ? g->Lstart[nv] : 1));
  if (!g->Lv || !g->c) goto nomem;
  if (faces) {
    for (int f = 0; f < m->nf; f++)
      for (int k = 0; k < 3; k++) {
        int j = m->F[3 * f + k];
        g->Lv[g->Lstart[j] + cnt[j]++] = f;
      }
  } else {
    for (int j = 0; j < nv; j++) g->Lv[g->Lstart[j]] = j, cnt[j] = 1;
    for (int e = 0; e < t->ne; e++) {
      int a = t->E[2 * e], b = t->E[2 * e + 1];
      g->Lv[g->Lstart[a] + cnt[a]++] = b;
      g->Lv[g->Lstart[b] + cnt[b]++] = a;
    }
  }
  /* Pattern of D W D^T: (i, k) for cells i, k in a common L_j; per column k the rows i <= k. */
  memset(cnt, 0, sizeof(int) * ((size_t)nc + 1));
  for (int j = 0; j < nv; j++)
    for (int s = g->Lstart[j]; s < g->Lstart[j + 1]; s++) cnt[g->Lv[s]] += g->Lstart[j + 1] - g->Lstart[j];
  long long tot = 0;
  for (int k = 0; k < nc; k++) tot += cnt[k];
  int *start = malloc(sizeof(int) * ((size_t)nc + 1)), *buf = malloc(sizeof(int) * (size_t)(tot > 0 ? tot : 1));
  if (!start || !buf) {
    free(start), free(buf);
    goto nomem;
  }
  start[0] = 0;
  for (int k = 0; k < nc; k++) start[k + 1] = start[k] + cnt[k], cnt[k] = 0;
  for (int j = 0; j < nv; j++)
    for (int s = g->Lstart[j]; s < g->Lstart[j + 1]; s++)
      for (int u = g->Lstart[j]; u < g->Lstart[j + 1]; u++) {
        int i = g->Lv[u], k = g->Lv[s];
        if (i <= k) buf[start[k] + cnt[k]++] = i;
      }
  g->colstart = malloc(sizeof(int) * ((size_t)nc + 1));
  g->rows = malloc(sizeof(int) * (size_t)(tot > 0 ? tot : 1));
  if (!g->colstart || !g->rows) {
    free(start), free(buf);
    goto nomem;
  }
  g->colstart[0] = 0;
  int nz = 0;
  for (int k = 0; k < nc; k++) {
    int *col = buf + start[k], n = cnt[k];
    qsort(col, (size_t)n, sizeof(int), au__cmp_int);
    for (int r = 0; r < n; r++)
      if (r == 0 || col[r] != col[r - 1]) g->rows[nz++] = col[r];
    g->colstart[k + 1] = nz;
  }
  free(start), free(buf), free(cnt);
  cnt = NULL;
  au_status st = au_spd_create(nc, g->colstart, g->rows, NULL, &g->spd, msg);
  if (st != AU_OK) {
    au__gn_free(&g);
    return st;
  }
  *out = g;
  return AU_OK;
nomem:
  free(cnt);
  au__gn_free(&g);
  return au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
}

/* Slot of vertex i in L_j (i == j or a neighbour of j). */
static int slot_of(const au_gn *g, int j, int i) {
  for (int s = g->Lstart[j]; s < g->Lstart[j + 1]; s++)
    if (g->Lv[s] == i) return s;
  return -1;
}

au_status au__gn_step(au_gn *g, const au_advect_domain *dom, const double *P, const double *W, const double *dA,
                      double damping, double *D, au_msg *msg) {
  const int nv = g->nv, nc = g->nc, *F = g->F;
  memset(g->c, 0, sizeof(double) * 3 * (size_t)g->Lstart[nv]);
  for (int f = 0; f < g->nf; f++) {
    const int *v = F + 3 * f;
    const double *a = P + 3 * v[0], *b = P + 3 * v[1], *cc = P + 3 * v[2];
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]}, n[3];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(nn > 0)) continue;
    n[0] /= nn, n[1] /= nn, n[2] /= nn;
    for (int q = 0; q < 3; q++) {
      int j = v[q];
      const double *p1 = P + 3 * v[(q + 1) % 3], *p2 = P + 3 * v[(q + 2) % 3];
      double e[3] = {p2[0] - p1[0], p2[1] - p1[1], p2[2] - p1[2]};
      /* d(area)/d(p_j) = n x (opposite edge) / 2; a third of it goes to each corner's cell. */
      double gr[3] = {(n[1] * e[2] - n[2] * e[1]) / 6, (n[2] * e[0] - n[0] * e[2]) / 6, (n[0] * e[1] - n[1] * e[0]) / 6};
      if (g->faces) {
        double *c = g->c + 3 * slot_of(g, j, f);
        c[0] += 3 * gr[0], c[1] += 3 * gr[1], c[2] += 3 * gr[2];
        continue;
      }
      for (int r = 0; r < 3; r++) {
        int s = slot_of(g, j, v[r]);
        double *c = g->c + 3 * s;
        c[0] += gr[0], c[1] += gr[1], c[2] += gr[2];
      }
    }
  }
  for (int j = 0; j < nv; j++)
    for (int s = g->Lstart[j]; s < g->Lstart[j + 1]; s++) dom->constrain(dom->ctx, j, P + 3 * j, g->c + 3 * s);

  double *val = au_spd_values(g->spd);
  memset(val, 0, sizeof(double) * (size_t)g->colstart[nc]);
  for (int j = 0; j < nv; j++) {
    for (int s = g->Lstart[j]; s < g->Lstart[j + 1]; s++) {
      int k = g->Lv[s];
      const double *ck = g->c + 3 * s;
      const int *col = g->rows + g->colstart[k];
      int ncol = g->colstart[k + 1] - g->colstart[k];
      for (int u = g->Lstart[j]; u < g->Lstart[j + 1]; u++) {
        int i = g->Lv[u];
        if (i > k) continue;
        const double *ci = g->c + 3 * u;
        int *hit = bsearch(&i, col, (size_t)ncol, sizeof(int), au__cmp_int);
        val[g->colstart[k] + (hit - col)] += W[j] * (ci[0] * ck[0] + ci[1] * ck[1] + ci[2] * ck[2]);
      }
    }
  }
  /* A relative Tikhonov term keeps the system definite where D W D^T is singular (unreferenced
   * vertices, the near-constant mode) without changing the step noticeably. */
  double dmax = 0;
  for (int k = 0; k < nc; k++) dmax = fmax(dmax, val[g->colstart[k + 1] - 1]);
  /* Levenberg-Marquardt damping (relative to each diagonal) tames the near-null checkerboard modes of
   * the face areas. */
  for (int k = 0; k < nc; k++) val[g->colstart[k + 1] - 1] *= 1 + damping;
  for (int k = 0; k < nc; k++) val[g->colstart[k + 1] - 1] += AU_GN_REG * dmax + (dmax > 0 ? 0 : 1);
  au_status st = au_spd_factor(g->spd, msg);
  double *gv = malloc(sizeof(double) * (size_t)nc);
  if (!gv) return au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
  if (st == AU_OK) st = au_spd_solve(g->spd, dA, gv, msg);
  if (st == AU_OK) {
    for (int j = 0; j < nv; j++) {
      double *d = D + 3 * j;
      d[0] = d[1] = d[2] = 0;
      for (int s = g->Lstart[j]; s < g->Lstart[j + 1]; s++) {
        const double *c = g->c + 3 * s;
        double gi = gv[g->Lv[s]] * W[j];
        d[0] += gi * c[0], d[1] += gi * c[1], d[2] += gi * c[2];
      }
    }
  }
  free(gv);
  return st;
}
