/* au_ang.c - the angle step: after the flow, a Gauss-Newton step on the map's Dirichlet energy that
 * holds the vertex cells at their areas and the triangles near theirs.
 *
 * Among the maps whose barycentric vertex cells have the wanted areas there is room left: V constraints
 * on 2V unknowns. The flow uses it step by step (least shear), which is greedy. This step uses it for
 * the map itself: of the maps with the wanted cell areas, it moves towards the one of least Dirichlet
 * energy E_D = sum over the surface's edges of w_ij |p_i - p_j|^2 (w_ij the surface's cotan weights),
 * i.e. the integral of s1^2 + s2^2 over the surface (s1, s2 the map's singular values). With the area
 * s1 s2 held, that is the least anisotropy, so the least angle distortion in the mean. The triangles'
 * own areas (F ~ 2V of them, the checkerboard of per-face constraints: au_lm.c) are held softly, with
 * the weight beta against E_D. Linearized at P, in the directions the domain allows (tangent planes,
 * the boundary circles' tangents), the step x minimizes
 *     sum_ij w_ij |d_ij + u_i - u_j|^2                       (d_ij = p_i - p_j; E_D at P + u)
 *   + beta  sum_f (g_f . u - dA_f)^2 / T_f                   (faces: T_f target area, dA_f = T_f - A_f)
 *   + gamma sum_i (c_i . u - dV_i)^2 / V_i                   (cells: c_i = a third of the faces' g_f)
 *   + mu    sum_i (sum_j |w_ij|) |u_i|^2                     (Levenberg-Marquardt trust region)
 * with g_f the exact gradient of the (chord) triangle's area. Every term is an integral over the domain
 * of the same degree in its scale, so beta, gamma and mu are scale-free. The cell term couples vertices
 * two rings apart: the pattern of the 2V x 2V system is the 2-ring's, analyzed once. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_advect_internal.h"
#include "au_solver.h"

struct au_ang {
  int nv, nf;
  const int *F;
  const double *X;     /* the surface */
  int *lstart, *list;  /* per vertex c: the vertices r <= c within two rings, sorted (c last) */
  int *vfstart, *vf;   /* per vertex: its faces */
  int *colstart, *rows;
  double *wc;          /* [0..3nf-1]: the surface's half cotangent at each corner (weight of the opposite edge) */
  double *B;           /* [0..6nv-1]: allowed directions */
  double *rhs, *x, *diag;
  au_spd *spd;
};

void au__ang_free(au_ang **ap) {
  if (!ap || !*ap) return;
  au_ang *a = *ap;
  free(a->lstart), free(a->list), free(a->vfstart), free(a->vf), free(a->colstart), free(a->rows), free(a->wc);
  free(a->B), free(a->rhs), free(a->x), free(a->diag);
  au_spd_free(&a->spd);
  free(a);
  *ap = NULL;
}

au_status au__ang_create(const au_mesh *m, au_ang **out, au_msg *msg) {
  *out = NULL;
  const int nv = m->nv, nf = m->nf, n = 2 * nv, *F = m->F;
  au_ang *a = calloc(1, sizeof *a);
  int *mark = NULL, *buf = NULL, *perm = NULL, *vperm = NULL;
  if (!a) return au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
  a->nv = nv, a->nf = nf, a->F = F, a->X = m->X;
  a->vfstart = calloc((size_t)nv + 1, sizeof(int));
  a->vf = malloc(sizeof(int) * 3 * (size_t)(nf > 0 ? nf : 1));
  a->lstart = malloc(sizeof(int) * ((size_t)nv + 1));
  a->colstart = malloc(sizeof(int) * ((size_t)n + 1));
  a->wc = malloc(sizeof(double) * 3 * (size_t)(nf > 0 ? nf : 1));
  a->B = calloc(6 * (size_t)nv, sizeof(double));
  a->rhs = malloc(sizeof(double) * (size_t)n), a->x = malloc(sizeof(double) * (size_t)n);
  a->diag = malloc(sizeof(double) * (size_t)nv);
  mark = malloc(sizeof(int) * (size_t)nv), buf = malloc(sizeof(int) * (size_t)nv);
  if (!a->vfstart || !a->vf || !a->lstart || !a->colstart || !a->wc || !a->B || !a->rhs || !a->x || !a->diag || !mark || !buf)
    goto nomem;
  /* Faces per vertex. */
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) a->vfstart[F[3 * f + k] + 1]++;
  for (int i = 0; i < nv; i++) a->vfstart[i + 1] += a->vfstart[i];
  for (int i = 0; i < nv; i++) mark[i] = a->vfstart[i];
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) a->vf[mark[F[3 * f + k]]++] = f;
  /* The surface's cotangents, per corner (the flow never changes them). */
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) {
      const double *o = m->X + 3 * F[3 * f + k], *p = m->X + 3 * F[3 * f + (k + 1) % 3], *q = m->X + 3 * F[3 * f + (k + 2) % 3];
      double u[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]}, v[3] = {q[0] - o[0], q[1] - o[1], q[2] - o[2]};
      double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
      double s = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
      a->wc[3 * f + k] = s > 0 ? 0.5 * (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / s : 0;
    }
  /* Two rings: the vertices of the faces at the vertices of the faces at c. Counted, then listed. */
  for (int i = 0; i < nv; i++) mark[i] = -1;
  size_t total = 0;
  for (int pass = 0; pass < 2; pass++) {
    total = 0;
    for (int c = 0; c < nv; c++) {
      int cnt = 0;
      if (pass) a->lstart[c] = (int)total;
      for (int s = a->vfstart[c]; s < a->vfstart[c + 1]; s++) {
        const int *fv = F + 3 * a->vf[s];
        for (int k = 0; k < 3; k++) {
          int i = fv[k];
          for (int s2 = a->vfstart[i]; s2 < a->vfstart[i + 1]; s2++) {
            const int *gv = F + 3 * a->vf[s2];
            for (int k2 = 0; k2 < 3; k2++) {
              int r = gv[k2];
              if (r > c || mark[r] == c + pass * nv) continue;
              mark[r] = c + pass * nv;
              if (pass) buf[cnt] = r;
              cnt++;
            }
          }
        }
      }
      if (cnt == 0 && pass) buf[cnt] = c; /* an unreferenced vertex: its diagonal only */
      if (cnt == 0) cnt = 1;
      if (pass) {
        qsort(buf, (size_t)cnt, sizeof(int), au__cmp_int);
        memcpy(a->list + total, buf, sizeof(int) * (size_t)cnt);
      }
      total += (size_t)cnt;
    }
    if (!pass) {
      a->list = malloc(sizeof(int) * total);
      if (!a->list) goto nomem;
      for (int i = 0; i < nv; i++) mark[i] = -1;
    }
  }
  a->lstart[nv] = (int)total;
  /* Column 2c + b: rows 2r, 2r + 1 for each r < c in the list, then 2c (and 2c + 1 if b = 1). */
  size_t nz = 4 * total;
  a->rows = malloc(sizeof(int) * nz);
  if (!a->rows) goto nomem;
  int p = 0;
  for (int c = 0; c < nv; c++)
    for (int b = 0; b < 2; b++) {
      a->colstart[2 * c + b] = p;
      for (int s = a->lstart[c]; s < a->lstart[c + 1] - 1; s++) a->rows[p++] = 2 * a->list[s], a->rows[p++] = 2 * a->list[s] + 1;
      a->rows[p++] = 2 * c;
      if (b) a->rows[p++] = 2 * c + 1;
    }
  a->colstart[n] = p;
  /* The elimination order: nested dissection of the 2-ring graph (the separators of the mesh's own
   * graph are one ring wide and do not separate this one, and the factorization took ten times as long
   * with them), each vertex's two unknowns side by side. */
  perm = malloc(sizeof(int) * (size_t)n), vperm = malloc(sizeof(int) * (size_t)nv);
  int *E2 = malloc(sizeof(int) * 2 * (total - (size_t)nv + 1));
  if (!perm || !vperm || !E2) {
    free(E2);
    goto nomem;
  }
  int ne2 = 0;
  for (int c = 0; c < nv; c++)
    for (int s = a->lstart[c]; s < a->lstart[c + 1]; s++)
      if (a->list[s] != c) E2[2 * ne2] = a->list[s], E2[2 * ne2 + 1] = c, ne2++;
  au_status st = au_graph_order(nv, ne2, E2, vperm, msg);
  free(E2);
  for (int k = 0; k < nv && st == AU_OK; k++) perm[2 * k] = 2 * vperm[k], perm[2 * k + 1] = 2 * vperm[k] + 1;
  if (st == AU_OK) st = au_spd_create(n, a->colstart, a->rows, perm, &a->spd, msg);
  free(perm), free(vperm), free(mark), free(buf);
  if (st != AU_OK) {
    au__ang_free(&a);
    return st;
  }
  *out = a;
  return AU_OK;
nomem:
  free(perm), free(vperm), free(mark), free(buf);
  au__ang_free(&a);
  return au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
}

/* Add the 2x2 block M (rows: vertex r's unknowns, columns: c's) to the matrix. */
static void add_block(const au_ang *a, double *val, int r, int c, const double M[2][2]) {
  double T[2][2];
  if (r > c) {
    int tmp = r;
    r = c, c = tmp;
    T[0][0] = M[0][0], T[0][1] = M[1][0], T[1][0] = M[0][1], T[1][1] = M[1][1];
    M = (const double(*)[2])T;
  }
  const int *lo = a->list + a->lstart[c];
  const int *hit = bsearch(&r, lo, (size_t)(a->lstart[c + 1] - a->lstart[c]), sizeof(int), au__cmp_int);
  if (!hit) return; /* cannot happen: the pattern holds every pair two rings apart */
  int pos = (int)(hit - lo);
  for (int b = 0; b < 2; b++)
    for (int i = 0; i < 2; i++) {
      if (r == c && i > b) continue;
      val[a->colstart[2 * c + b] + 2 * pos + i] += M[i][b];
    }
}

static inline double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Add weight * (row . x - target)^2 for a sparse row over n distinct vertices (2 coefficients each). */
static void add_row(const au_ang *a, double *val, int n, const int *v, const double (*row)[2], double weight, double target) {
  for (int p = 0; p < n; p++) {
    for (int q = p; q < n; q++) {
      double M[2][2] = {{weight * row[p][0] * row[q][0], weight * row[p][0] * row[q][1]},
                        {weight * row[p][1] * row[q][0], weight * row[p][1] * row[q][1]}};
      add_block(a, val, v[p], v[q], M);
    }
    a->rhs[2 * v[p]] += weight * row[p][0] * target, a->rhs[2 * v[p] + 1] += weight * row[p][1] * target;
  }
}

au_status au__ang_step(au_ang *a, const au_advect_domain *dom, const double *P, const double *T, const double *TV,
                       double beta, double gamma, double mu, double *D, au_msg *msg) {
  const int nv = a->nv, nf = a->nf, n = 2 * nv, *F = a->F;
  double *val = au_spd_values(a->spd);
  memset(val, 0, sizeof(double) * (size_t)a->colstart[n]);
  memset(a->rhs, 0, sizeof(double) * (size_t)n);
  memset(a->diag, 0, sizeof(double) * (size_t)nv);
  for (int i = 0; i < nv; i++) au__allowed_basis(dom, i, P + 3 * i, a->B + 6 * i);
  /* The cells' current areas and rows are gathered face by face; g holds each face's rows. */
  double *g = malloc(sizeof(double) * 6 * (size_t)(nf > 0 ? nf : 1)), *AV = calloc((size_t)nv, sizeof(double));
  if (!g || !AV) {
    free(g), free(AV);
    return au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
  }
  for (int f = 0; f < nf; f++) {
    const int *v = F + 3 * f;
    double cbuf[3][3];
    const double *cp[3];
    for (int k = 0; k < 3; k++) cp[k] = au__corner(P, F, dom->shift, f, k, cbuf[k]);
    const double *p0 = cp[0], *p1 = cp[1], *p2 = cp[2];
    double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]}, e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
    double nr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double nn = sqrt(dot3(nr, nr)), A = 0.5 * nn;
    for (int k = 0; k < 3; k++) AV[v[k]] += A / 3;
    memset(g + 6 * f, 0, 6 * sizeof(double));
    if (!(nn > 0)) continue;
    for (int d = 0; d < 3; d++) nr[d] /= nn;
    for (int k = 0; k < 3; k++) {
      const double *pa = cp[(k + 1) % 3], *pb = cp[(k + 2) % 3];
      double e[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
      double gr[3] = {0.5 * (nr[1] * e[2] - nr[2] * e[1]), 0.5 * (nr[2] * e[0] - nr[0] * e[2]), 0.5 * (nr[0] * e[1] - nr[1] * e[0])};
      const double *Bk = a->B + 6 * v[k];
      g[6 * f + 2 * k] = dot3(gr, Bk), g[6 * f + 2 * k + 1] = dot3(gr, Bk + 3);
    }
    /* Faces: beta (g . x - dA)^2 / T. */
    if (T[f] > 0) add_row(a, val, 3, v, (const double(*)[2])(g + 6 * f), beta / T[f], T[f] - A);
    /* Dirichlet: the edge opposite corner k, weight wc. */
    for (int k = 0; k < 3; k++) {
      int i = v[(k + 1) % 3], j = v[(k + 2) % 3];
      double w = a->wc[3 * f + k];
      /* The edge's two corners as this face places them (shifted on the flat torus). */
      const double *pi = cp[(k + 1) % 3], *pj = cp[(k + 2) % 3], *Bi = a->B + 6 * i, *Bj = a->B + 6 * j;
      double d[3] = {pi[0] - pj[0], pi[1] - pj[1], pi[2] - pj[2]};
      double Mii[2][2] = {{w * dot3(Bi, Bi), w * dot3(Bi, Bi + 3)}, {w * dot3(Bi + 3, Bi), w * dot3(Bi + 3, Bi + 3)}};
      double Mjj[2][2] = {{w * dot3(Bj, Bj), w * dot3(Bj, Bj + 3)}, {w * dot3(Bj + 3, Bj), w * dot3(Bj + 3, Bj + 3)}};
      double Mij[2][2] = {{-w * dot3(Bi, Bj), -w * dot3(Bi, Bj + 3)}, {-w * dot3(Bi + 3, Bj), -w * dot3(Bi + 3, Bj + 3)}};
      add_block(a, val, i, i, Mii), add_block(a, val, j, j, Mjj), add_block(a, val, i, j, Mij);
      a->rhs[2 * i] -= w * dot3(Bi, d), a->rhs[2 * i + 1] -= w * dot3(Bi + 3, d);
      a->rhs[2 * j] += w * dot3(Bj, d), a->rhs[2 * j + 1] += w * dot3(Bj + 3, d);
      a->diag[i] += fabs(w), a->diag[j] += fabs(w);
    }
  }
  /* Cells: gamma (c . x - dV)^2 / V, c_i a third of the rows of i's faces, gathered over its star. A
   * vertex with more than 63 neighbours keeps no cell term (its faces' and the energy's still hold it). */
  int sv[64];
  double sr[64][2];
  for (int i = 0; i < nv; i++) {
    if (!(TV[i] > 0)) continue;
    int ns = 0, over = 0;
    for (int s = a->vfstart[i]; s < a->vfstart[i + 1] && !over; s++) {
      int f = a->vf[s];
      for (int k = 0; k < 3; k++) {
        int vk = F[3 * f + k], q = 0;
        while (q < ns && sv[q] != vk) q++;
        if (q == ns) {
          if (ns == 64) {
            over = 1;
            break;
          }
          sv[ns] = vk, sr[ns][0] = sr[ns][1] = 0, ns++;
        }
        sr[q][0] += g[6 * f + 2 * k] / 3, sr[q][1] += g[6 * f + 2 * k + 1] / 3;
      }
    }
    if (!over) add_row(a, val, ns, sv, (const double(*)[2])sr, gamma / TV[i], TV[i] - AV[i]);
  }
  free(g), free(AV);
  /* The trust region on each vertex, and a unit diagonal where nothing may move. */
  for (int i = 0; i < nv; i++)
    for (int b = 0; b < 2; b++) {
      int c = 2 * i + b, dg = a->colstart[c + 1] - 1;
      const double *Bi = a->B + 6 * i + 3 * b;
      if (dot3(Bi, Bi) == 0 || a->diag[i] == 0) val[dg] = 1, a->rhs[c] = 0;
      else val[dg] += mu * a->diag[i];
    }
  au_status st = au_spd_factor(a->spd, msg);
  if (st == AU_OK) st = au_spd_solve(a->spd, a->rhs, a->x, msg);
  if (st != AU_OK) return st;
  for (int i = 0; i < nv; i++) {
    const double *Bi = a->B + 6 * i;
    for (int d = 0; d < 3; d++) D[3 * i + d] = a->x[2 * i] * Bi[d] + a->x[2 * i + 1] * Bi[3 + d];
  }
  return AU_OK;
}
