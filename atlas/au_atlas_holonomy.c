/* au_atlas_holonomy.c - the cone metric's holonomy around the homology loops made a multiple of pi/2 (au_atlas.h).
 *
 * With quarter cones every vertex's angle sum is a multiple of pi/2, so the rotation of a seam around a cone
 * is a quarter turn; the rotation of a seam that crosses a handle (or runs between two boundary loops) is the
 * holonomy of the metric along a loop of that homology class, which the conformal metric leaves arbitrary:
 * with the cones fixed, its n log scale factors are spent on the n - 1 independent angle sums. The lengths are
 * therefore let go of conformality: Newton's method on the log edge lengths lambda, each step the least change
 * |d lambda| that satisfies the linearized constraints J d lambda = -r (d lambda = J^T (J J^T)^-1 (-r), one
 * sparse SPD solve by CHOLMOD), the constraints being every interior vertex's angle sum = its target (2 pi or
 * the cone's angle) and every generator loop's holonomy = the multiple of pi/2 nearest to the conformal
 * metric's. This is the linearized form of the holonomy constraints of seamless parametrization (Campen, Shen,
 * Zhou & Zorin 2019, "Seamless parametrization with arbitrary cones for arbitrary genus", ACM TOG 39(1)), and
 * the dual loops are those of trivial connections (Crane, Desbrun & Schroeder 2010, "Trivial connections on
 * discrete surfaces", SGP): a tree-cotree basis (Eppstein 2003). The holonomy of a dual loop is a signed sum of
 * corner angles: in each face it crosses, + the angle at the shared vertex of the entering and leaving edges
 * when that vertex is on the loop's left, - when it is on its right.
 * Corner angles depend on log lengths as d alpha_i / d lambda_i = cot alpha_j + cot alpha_k and
 * d alpha_i / d lambda_j = -cot alpha_k ({i, j, k} the corners, lambda_i the log length opposite i).
 * The change a holonomy needs can be more than the triangles bear (bob's loops are 43 degrees off): then
 * au_atlas_holonomy_balance changes the cones instead, by the linearized response of the conformal metric to its
 * cone angles (the holonomy's derivative in the angle targets is -zeta = -L^-1 B^T h, one Laplacian solve per
 * loop): quarter turns of a few cones' angles and moves of cones by one edge, chosen greedily so that the
 * predicted holonomies come near multiples of pi/2 and the lengths have little left to do. */

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_atlas.h"
#include "au_solver.h"
#include "au_treecotree.h"

#define AU_PI 3.14159265358979323846

void au_atlas_edge_lengths(const au_mesh *m, const au_topo *t, const double *u, double *elen) {
  for (int e = 0; e < t->ne; e++) {
    int a = t->E[2 * e], b = t->E[2 * e + 1];
    const double *p = m->X + 3 * (size_t)a, *q = m->X + 3 * (size_t)b;
    double d = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
    elen[e] = u ? d * exp(0.5 * (u[a] + u[b])) : d;
  }
}

/* The inputs of the holonomy stage: every edge length finite and > 0, the cones at distinct interior vertices
 * with finite positive angles. AU_OK or AU_E_ARG naming the first fault (who: the function). */
static au_status check_inputs(const char *who, const au_topo *t, const au_atlas_cones *c, const double *elen,
                              au_msg *msg) {
  for (int e = 0; e < t->ne; e++)
    if (!(elen[e] > 0) || !isfinite(elen[e]))
      return au_msg_set(msg, AU_E_ARG, "%s: edge %d (%d, %d) has length %g: expected a finite length > 0", who, e,
                        t->E[2 * e], t->E[2 * e + 1], elen[e]);
  if (!c) return AU_OK;
  if (c->n < 0 || (c->n > 0 && (!c->v || !c->angle))) return au_msg_set(msg, AU_E_ARG, "%s: bad cones (%d)", who, c->n);
  for (int i = 0; i < c->n; i++) {
    int v = c->v[i];
    if (v < 0 || v >= t->nv || !t->vused[v] || t->vb[v] || !(c->angle[i] > 0) || !isfinite(c->angle[i]))
      return au_msg_set(msg, AU_E_ARG, "%s: cone %d: vertex %d with angle %g is not an interior vertex with a positive angle",
                        who, i, v, c->angle[i]);
    for (int j = 0; j < i; j++)
      if (c->v[j] == v) return au_msg_set(msg, AU_E_ARG, "%s: cones %d and %d are both at vertex %d", who, j, i, v);
  }
  return AU_OK;
}

/* Angles and cotangents of every corner from the log edge lengths lam; returns the smallest angle, or -1 when a
 * triangle breaks the triangle inequality (it gets the extended angles 0, 0, pi and no cotangent weight, the
 * convex extension of Springborn, Schroeder & Pinkall 2008, so that a conformal solve can go on from it). */
static double angles(const au_topo *t, int nf, const double *lam, double *ang, double *cot) {
  double amin = AU_PI;
  int bad = 0;
  for (int f = 0; f < nf; f++) {
    double l[3];
    int deg = -1;
    for (int k = 0; k < 3; k++) l[k] = exp(lam[t->FE[3 * f + k]]);
    for (int k = 0; k < 3; k++)
      if (l[k] >= l[(k + 1) % 3] + l[(k + 2) % 3]) deg = k;
    if (deg >= 0) {
      for (int k = 0; k < 3; k++) ang[3 * f + k] = k == deg ? AU_PI : 0, cot[3 * f + k] = 0;
      bad = 1;
      continue;
    }
    double a = l[0], b = l[1], c = l[2];
    double four_area = sqrt((a + b + c) * (-a + b + c) * (a - b + c) * (a + b - c));
    for (int k = 0; k < 3; k++) {
      double x = l[k], y = l[(k + 1) % 3], z = l[(k + 2) % 3], num = y * y + z * z - x * x;
      ang[3 * f + k] = atan2(four_area, num);
      cot[3 * f + k] = num / four_area;
      if (ang[3 * f + k] < amin) amin = ang[3 * f + k];
    }
  }
  return bad ? -1 : amin;
}

/* The constraints: row r is sum over its terms (corner c, sign s) of s alpha_c, minus target[r]; J their
 * Jacobian in the log edge lengths, row by row. */
typedef struct rows {
  int n;             /* rows: the vertex rows, then the loops' */
  int *start;        /* start [0..n]: the terms of row r */
  int *corner;       /* corner, sign of each term */
  signed char *sign;
  double *target;
  int *jstart;       /* jstart [0..n]: row r of J at jedge / jval [jstart[r]..jstart[r+1]-1] (sorted edges) */
  int *jedge;
  double *jval;
  int *tpos;         /* tpos [3 * term + k]: the entry of jval of the edge opposite corner k of the term's face */
} rows;

static void residual(const rows *R, const double *ang, double *r, double *rmax, double *rnorm) {
  double mx = 0, s = 0;
  for (int i = 0; i < R->n; i++) {
    double v = -R->target[i];
    for (int k = R->start[i]; k < R->start[i + 1]; k++) v += R->sign[k] * ang[R->corner[k]];
    r[i] = v;
    mx = fabs(v) > mx ? fabs(v) : mx, s += v * v;
  }
  *rmax = mx, *rnorm = sqrt(s);
}

/* J from the cotangents: d alpha_i / d lambda_i = cot alpha_j + cot alpha_k, d alpha_i / d lambda_j = -cot alpha_k. */
static void jacobian(const rows *R, const double *cot) {
  memset(R->jval, 0, (size_t)R->jstart[R->n] * sizeof *R->jval);
  for (int k = 0; k < R->start[R->n]; k++) {
    int c = R->corner[k], f = c / 3, i = c % 3, j = (i + 1) % 3, l = (i + 2) % 3;
    double s = R->sign[k];
    R->jval[R->tpos[3 * k + i]] += s * (cot[3 * f + j] + cot[3 * f + l]);
    R->jval[R->tpos[3 * k + j]] -= s * cot[3 * f + l];
    R->jval[R->tpos[3 * k + l]] -= s * cot[3 * f + j];
  }
}

static void rows_free(rows *R) {
  free(R->start), free(R->corner), free(R->sign), free(R->target), free(R->jstart), free(R->jedge), free(R->jval),
      free(R->tpos);
}

/* The position of corner k of face f in face order: which k has FE[3f+k] == e. */
static int opposite(const au_topo *t, int f, int e) {
  for (int k = 0; k < 3; k++)
    if (t->FE[3 * f + k] == e) return k;
  return -1;
}

/* The generator loops: the dual loops of the tree-cotree decomposition (au_treecotree.h: its vertex tree grows
 * from the boundary, every boundary vertex a root, or from the first referenced vertex), one per generator,
 * 2g + boundary loops - 1 of them; at most maxloops are taken. Each loop's terms are appended to (corner, sign)
 * from *nterm (a loop has at most nf); lstart [0..*n] receives where each loop's terms start, *n the number of
 * loops. Returns AU_OK or the decomposition's status. */
static au_status loops(const au_topo *t, int *corner, signed char *sign, int *nterm, int *lstart, int maxloops, int *n,
                       au_msg *msg) {
  au_treecotree *tc = NULL;
  int *edges = malloc((size_t)t->nf * sizeof *edges), *faces = malloc((size_t)t->nf * sizeof *faces);
  au_status st = edges && faces ? au_treecotree_build(t, &tc, msg) : au_msg_set(msg, AU_E_NOMEM, "out of memory");
  *n = 0;
  if (st != AU_OK) goto done;
  lstart[0] = *nterm;
  for (int j = 0; j < tc->ngen && j < maxloops; j++) {
    int np = au_treecotree_dual_loop(t, tc, j, edges, faces);
    if (np < 2) { /* a dual loop crosses at least two faces; anything else is a topology that does not fit the mesh */
      st = au_msg_set(msg, AU_E_ARG, "holonomy: generator loop %d has length %d (expected >= 2)", j, np);
      goto done;
    }
    /* Face faces[i] of the loop is entered through edges[i] and left through edges[i + 1]. */
    for (int i = 0; i < np; i++) {
      int f = faces[i], kin = opposite(t, f, edges[i]), kout = opposite(t, f, edges[(i + 1) % np]);
      if (kin < 0 || kout < 0 || kin == kout) {
        st = au_msg_set(msg, AU_E_ARG, "holonomy: generator loop %d leaves face %d by an edge not its own", j, f);
        goto done;
      }
      int k = 3 - kin - kout;
      corner[*nterm] = 3 * f + k;
      /* The shared vertex is on the left when the loop enters opposite k + 2 and leaves opposite k + 1 (the
       * faces are counterclockwise). */
      sign[*nterm] = (kin == (k + 2) % 3 && kout == (k + 1) % 3) ? 1 : -1;
      (*nterm)++;
    }
    lstart[++*n] = *nterm;
  }
done:
  au_treecotree_free(&tc);
  free(edges), free(faces);
  return st;
}

au_status au_atlas_holonomy_fix(const au_mesh *m, const au_topo *t, const au_atlas_cones *c, double *elen,
                                au_atlas_holonomy_info *info, au_msg *msg) {
  au_atlas_holonomy_info in;
  memset(&in, 0, sizeof in);
  if (info) *info = in;
  if (!m || !t || !elen || t->nv != m->nv || t->nf != m->nf)
    return au_msg_set(msg, AU_E_ARG, "au_atlas_holonomy_fix: bad arguments");
  au_status sc = check_inputs("au_atlas_holonomy_fix", t, c, elen, msg);
  if (sc != AU_OK) return sc;
  const int nv = m->nv, nf = m->nf, ne = t->ne, closed = t->nloops == 0;
  const int K = 2 * t->genus + (t->nloops > 0 ? t->nloops - 1 : 0);
  in.loops = K;
  if (K == 0) {
    if (info) *info = in;
    return AU_OK;
  }
  au_status st = AU_OK;
  rows R;
  memset(&R, 0, sizeof R);
  double *theta = malloc((size_t)nv * sizeof *theta), *lam = malloc((size_t)ne * sizeof *lam);
  double *lam0 = malloc((size_t)ne * sizeof *lam0), *lt = malloc((size_t)ne * sizeof *lt);
  double *ang = malloc(3 * (size_t)nf * sizeof *ang), *cot = malloc(3 * (size_t)nf * sizeof *cot);
  int *vrow = malloc((size_t)nv * sizeof *vrow), *lstart = malloc(((size_t)K + 1) * sizeof *lstart);
  int *cstart = calloc((size_t)nv + 1, sizeof *cstart), *cfill = calloc((size_t)nv, sizeof *cfill);
  int *vc = malloc(3 * (size_t)nf * sizeof *vc), *pos = malloc((size_t)ne * sizeof *pos);
  double *r = NULL, *y = NULL, *rhs = NULL, *dl = NULL, *wrow = NULL;
  int *acol = NULL, *arow = NULL, *mark = NULL, *estart = NULL, *erow = NULL;
  au_spd *S = NULL;
  if (!theta || !lam || !lam0 || !lt || !ang || !cot || !vrow || !lstart || !cstart || !cfill || !vc || !pos) goto nomem;
  for (int v = 0; v < nv; v++) theta[v] = 2 * AU_PI;
  for (int i = 0; c && i < c->n; i++) theta[c->v[i]] = c->angle[i];
  for (int e = 0; e < ne; e++) lam[e] = lam0[e] = log(elen[e]);
  double amin0 = angles(t, nf, lam, ang, cot);
  if (amin0 <= 0) {
    st = au_msg_set(msg, AU_W_NOT_CONVERGED, "holonomy: the cone metric has a degenerate triangle; the %d loops keep "
                    "their holonomy (seams across them are not quarter turns)", K);
    goto done;
  }
  /* The vertex rows: every interior vertex but, on a closed surface, one (its angle sum follows from the others
   * by Gauss-Bonnet, and J J^T would be singular with it). */
  int ref = 0;
  while (!t->vused[ref]) ref++;
  int nvr = 0;
  for (int v = 0; v < nv; v++) vrow[v] = t->vused[v] && !t->vb[v] && !(closed && v == ref) ? nvr++ : -1;
  for (int k = 0; k < 3 * nf; k++) cstart[m->F[k] + 1]++;
  for (int v = 0; v < nv; v++) cstart[v + 1] += cstart[v];
  for (int k = 0; k < 3 * nf; k++) vc[cstart[m->F[k]] + cfill[m->F[k]]++] = k;
  /* Terms: the vertex rows' corners, then the loops' (a loop crosses at most nf faces). */
  size_t maxterm = 3 * (size_t)nf + (size_t)K * (size_t)nf;
  R.n = nvr + K;
  R.start = malloc(((size_t)R.n + 1) * sizeof *R.start), R.target = malloc((size_t)R.n * sizeof *R.target);
  R.corner = malloc(maxterm * sizeof *R.corner), R.sign = malloc(maxterm);
  if (!R.start || !R.target || !R.corner || !R.sign) goto nomem;
  int nterm = 0;
  for (int v = 0; v < nv; v++) {
    if (vrow[v] < 0) continue;
    R.start[vrow[v]] = nterm, R.target[vrow[v]] = theta[v];
    for (int i = cstart[v]; i < cstart[v + 1]; i++) R.corner[nterm] = vc[i], R.sign[nterm++] = 1;
  }
  int got = 0;
  if ((st = loops(t, R.corner, R.sign, &nterm, lstart, K, &got, msg)) != AU_OK) {
    if (st == AU_E_NOMEM) goto nomem;
    goto done;
  }
  if (got != K) { /* the topology's genus and loops are not the mesh's */
    st = au_msg_set(msg, AU_E_ARG, "holonomy: %d generator loops found, %d expected from genus %d and %d boundary loops", got,
                    K, t->genus, t->nloops);
    goto done;
  }
  for (int j = 0; j < K; j++) {
    R.start[nvr + j] = lstart[j];
    double h = 0;
    for (int k = lstart[j]; k < lstart[j + 1]; k++) h += R.sign[k] * ang[R.corner[k]];
    R.target[nvr + j] = round(h / (AU_PI / 2)) * (AU_PI / 2);
    double d = fabs(h - R.target[nvr + j]);
    in.hol_dev = d > in.hol_dev ? d : in.hol_dev;
  }
  R.start[R.n] = nterm;
  /* The pattern of J: each row's distinct edges, sorted. */
  R.jstart = malloc(((size_t)R.n + 1) * sizeof *R.jstart);
  R.tpos = malloc(3 * (size_t)nterm * sizeof *R.tpos);
  R.jedge = malloc(3 * (size_t)nterm * sizeof *R.jedge);
  if (!R.jstart || !R.tpos || !R.jedge) goto nomem;
  for (int e = 0; e < ne; e++) pos[e] = -1;
  int nj = 0;
  for (int i = 0; i < R.n; i++) {
    R.jstart[i] = nj;
    for (int k = R.start[i]; k < R.start[i + 1]; k++)
      for (int q = 0; q < 3; q++) {
        int e = t->FE[3 * (R.corner[k] / 3) + q];
        if (pos[e] < 0) pos[e] = 1, R.jedge[nj++] = e;
      }
    qsort(R.jedge + R.jstart[i], (size_t)(nj - R.jstart[i]), sizeof *R.jedge, au__cmp_int);
    for (int p = R.jstart[i]; p < nj; p++) pos[R.jedge[p]] = p;
    for (int k = R.start[i]; k < R.start[i + 1]; k++)
      for (int q = 0; q < 3; q++) R.tpos[3 * k + q] = pos[t->FE[3 * (R.corner[k] / 3) + q]];
    for (int p = R.jstart[i]; p < nj; p++) pos[R.jedge[p]] = -1;
  }
  R.jstart[R.n] = nj;
  R.jval = malloc((size_t)(nj > 0 ? nj : 1) * sizeof *R.jval);
  /* The rows of every edge (J's columns), for the pattern and the values of J J^T. */
  estart = calloc((size_t)ne + 1, sizeof *estart), erow = malloc((size_t)(nj > 0 ? nj : 1) * sizeof *erow);
  mark = malloc((size_t)R.n * sizeof *mark), acol = malloc(((size_t)R.n + 1) * sizeof *acol);
  wrow = calloc((size_t)ne, sizeof *wrow);
  r = malloc((size_t)R.n * sizeof *r), y = malloc((size_t)R.n * sizeof *y), rhs = malloc((size_t)R.n * sizeof *rhs);
  dl = malloc((size_t)ne * sizeof *dl);
  if (!R.jval || !estart || !erow || !mark || !acol || !wrow || !r || !y || !rhs || !dl) goto nomem;
  for (int p = 0; p < nj; p++) estart[R.jedge[p] + 1]++;
  for (int e = 0; e < ne; e++) estart[e + 1] += estart[e];
  memset(pos, 0, (size_t)ne * sizeof *pos);
  for (int i = 0; i < R.n; i++)
    for (int p = R.jstart[i]; p < R.jstart[i + 1]; p++) erow[estart[R.jedge[p]] + pos[R.jedge[p]]++] = i;
  /* The upper triangle of J J^T by columns: the rows i <= j that share an edge with row j. */
  size_t cap = 16 * (size_t)R.n + 64, na = 0;
  arow = malloc(cap * sizeof *arow);
  if (!arow) goto nomem;
  for (int i = 0; i < R.n; i++) mark[i] = -1;
  for (int j = 0; j < R.n; j++) {
    acol[j] = (int)na;
    for (int p = R.jstart[j]; p < R.jstart[j + 1]; p++) {
      int e = R.jedge[p];
      for (int q = estart[e]; q < estart[e + 1]; q++) {
        int i = erow[q];
        if (i > j || mark[i] == j) continue;
        mark[i] = j;
        if (na == cap) {
          int *nb = realloc(arow, 2 * cap * sizeof *arow);
          if (!nb) goto nomem;
          arow = nb, cap *= 2;
        }
        arow[na++] = i;
      }
    }
    qsort(arow + acol[j], na - (size_t)acol[j], sizeof *arow, au__cmp_int);
  }
  acol[R.n] = (int)na;
  if ((st = au_spd_create(R.n, acol, arow, NULL, &S, msg)) != AU_OK) goto done;
  double *A = au_spd_values(S);
  double rmax, rn;
  residual(&R, ang, r, &rmax, &rn);
  /* Newton: the least change of the log lengths that meets the linearized constraints, halved until every angle
   * keeps a quarter of the start's smallest and the residual's norm falls. */
  const double tol = 1e-11, margin = 0.25 * amin0;
  int steps = 0, ok = rmax <= tol;
  while (!ok && steps < 30) {
    jacobian(&R, cot);
    for (int j = 0; j < R.n; j++) {
      for (int p = R.jstart[j]; p < R.jstart[j + 1]; p++) wrow[R.jedge[p]] = R.jval[p];
      for (int q = acol[j]; q < acol[j + 1]; q++) {
        int i = arow[q];
        double sum = 0;
        for (int p = R.jstart[i]; p < R.jstart[i + 1]; p++) sum += R.jval[p] * wrow[R.jedge[p]];
        A[q] = sum;
      }
      for (int p = R.jstart[j]; p < R.jstart[j + 1]; p++) wrow[R.jedge[p]] = 0;
    }
    au_msg fm;
    au_status sf = au_spd_factor(S, &fm);
    if (sf == AU_E_NOMEM) {
      if (msg) *msg = fm;
      st = sf;
      goto done;
    }
    if (sf != AU_OK) break; /* a singular J J^T: no step, the fallback below */
    for (int i = 0; i < R.n; i++) rhs[i] = -r[i];
    if ((st = au_spd_solve(S, rhs, y, msg)) != AU_OK) goto done;
    memset(dl, 0, (size_t)ne * sizeof *dl);
    for (int i = 0; i < R.n; i++)
      for (int p = R.jstart[i]; p < R.jstart[i + 1]; p++) dl[R.jedge[p]] += R.jval[p] * y[i];
    double tau = 1, rmax_new = rmax, rn_new = rn;
    int accepted = 0;
    for (int h = 0; h < 30 && !accepted; h++, tau *= 0.5) {
      for (int e = 0; e < ne; e++) lt[e] = lam[e] + tau * dl[e];
      if (angles(t, nf, lt, ang, cot) < margin) continue;
      residual(&R, ang, r, &rmax_new, &rn_new);
      accepted = rn_new < rn * (1 - 1e-4 * tau);
    }
    steps++;
    if (!accepted) break;
    memcpy(lam, lt, (size_t)ne * sizeof *lam);
    rmax = rmax_new, rn = rn_new;
    ok = rmax <= tol;
  }
  in.steps = steps, in.err = rmax;
  if (!ok) {
    st = au_msg_set(msg, AU_W_NOT_CONVERGED, "holonomy: the %d loops' holonomy could not be made a multiple of 90 degrees "
                    "(residual %.3g rad after %d steps); the conformal metric is kept, seams across them are not quarter turns",
                    K, rmax, steps);
    goto done;
  }
  in.fixed = K;
  for (int e = 0; e < ne; e++) {
    double d = fabs(expm1(lam[e] - lam0[e]));
    in.max_change = d > in.max_change ? d : in.max_change;
    elen[e] = exp(lam[e]);
  }
  goto done;
nomem:
  st = au_msg_set(msg, AU_E_NOMEM, "out of memory fixing the holonomy");
done:
  if (info) *info = in;
  au_spd_free(&S);
  rows_free(&R);
  free(theta), free(lam), free(lam0), free(lt), free(ang), free(cot), free(vrow), free(lstart), free(cstart), free(cfill),
      free(vc), free(pos), free(r), free(y), free(rhs), free(dl), free(wrow), free(acol), free(arow), free(mark),
      free(estart), free(erow);
  return st;
}

au_status au_atlas_holonomy_balance(const au_mesh *m, const au_topo *t, au_atlas_cones *c, const double *elen,
                                    int turns, int *nchanged, au_msg *msg) {
  if (nchanged) *nchanged = 0;
  if (!m || !t || !c || !elen || t->nv != m->nv || t->nf != m->nf)
    return au_msg_set(msg, AU_E_ARG, "au_atlas_holonomy_balance: bad arguments");
  au_status sc = check_inputs("au_atlas_holonomy_balance", t, c, elen, msg);
  if (sc != AU_OK) return sc;
  const int nv = m->nv, nf = m->nf, ne = t->ne, closed = t->nloops == 0, n = c->n;
  const int K = 2 * t->genus + (t->nloops > 0 ? t->nloops - 1 : 0);
  if (K == 0 || n == 0) return AU_OK;
  const double q4 = AU_PI / 2;
  au_status st = AU_OK;
  double *lam = malloc((size_t)ne * sizeof *lam), *ang = malloc(3 * (size_t)nf * sizeof *ang);
  double *cot = malloc(3 * (size_t)nf * sizeof *cot), *w = calloc((size_t)ne, sizeof *w);
  double *h = malloc((size_t)ne * sizeof *h), *qk = calloc((size_t)K * nv, sizeof *qk), *zk = calloc((size_t)K * nv, sizeof *zk);
  double *H = malloc((size_t)K * sizeof *H), *dH = calloc((size_t)K * n, sizeof *dH), *acc = calloc((size_t)K, sizeof *acc);
  int *corner = malloc((size_t)K * nf * sizeof *corner), *lstart = malloc(((size_t)K + 1) * sizeof *lstart);
  signed char *sign = malloc((size_t)K * nf);
  int *step = calloc((size_t)n, sizeof *step);
  unsigned char *fixed = malloc((size_t)nv);
  au_solver *S = NULL;
  if (!lam || !ang || !cot || !w || !h || !qk || !zk || !H || !dH || !acc || !corner || !lstart || !sign || !step || !fixed) {
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory balancing the holonomy");
    goto done;
  }
  for (int e = 0; e < ne; e++) lam[e] = log(elen[e]);
  if (angles(t, nf, lam, ang, cot) <= 0) goto done; /* a degenerate metric: nothing predicted */
  int ref = 0;
  while (!t->vused[ref]) ref++;
  int nterm = 0, got = 0;
  au_msg lm;
  au_status sl = loops(t, corner, sign, &nterm, lstart, K, &got, &lm);
  if (sl != AU_OK) {
    st = sl == AU_E_NOMEM ? au_msg_set(msg, AU_E_NOMEM, "out of memory balancing the holonomy") : au_msg_set(msg, sl, "%s", lm.text);
    goto done;
  }
  if (got != K) { /* the topology's genus and loops are not the mesh's */
    st = au_msg_set(msg, AU_E_ARG, "holonomy: %d generator loops found, %d expected from genus %d and %d boundary loops", got,
                    K, t->genus, t->nloops);
    goto done;
  }
  /* d H_k / d Theta_v = -zeta_k(v), zeta_k = L^-1 B^T h_k: a change of the angle targets moves the conformal
   * factors by du = -L^-1 dTheta, and the holonomy by h_k . B du. */
  for (int k = 0; k < K; k++) {
    H[k] = 0;
    memset(h, 0, (size_t)ne * sizeof *h);
    for (int p = lstart[k]; p < lstart[k + 1]; p++) {
      int cc = corner[p], f = cc / 3, i = cc % 3, j = (i + 1) % 3, l = (i + 2) % 3;
      H[k] += sign[p] * ang[cc];
      h[t->FE[3 * f + i]] += sign[p] * (cot[3 * f + j] + cot[3 * f + l]);
      h[t->FE[3 * f + j]] -= sign[p] * cot[3 * f + l];
      h[t->FE[3 * f + l]] -= sign[p] * cot[3 * f + j];
    }
    for (int e = 0; e < ne; e++) qk[(size_t)k * nv + t->E[2 * e]] += 0.5 * h[e], qk[(size_t)k * nv + t->E[2 * e + 1]] += 0.5 * h[e];
  }
  for (int cc = 0; cc < 3 * nf; cc++) w[t->FE[cc]] += 0.5 * cot[cc];
  for (int v = 0; v < nv; v++) fixed[v] = !t->vused[v] || t->vb[v] || (closed && v == ref);
  if ((st = au_solver_create(nv, ne, t->E, fixed, AU_ORDER_FAST, &S, msg)) != AU_OK) goto done;
  if ((st = au_solver_factor(S, w, NULL, msg)) != AU_OK) goto done;
  if ((st = au_solver_solve(S, K, qk, zk, msg)) != AU_OK) goto done;
  for (int i = 0; i < n; i++)
    for (int k = 0; k < K; k++) dH[(size_t)i * K + k] = -zk[(size_t)k * nv + c->v[i]] * q4;
  /* Greedy: the quarter turn up at one cone and down at another (on an open surface also one alone: the boundary
   * takes the difference) that brings the loops' holonomies, as predicted linearly, nearest to multiples of pi/2;
   * each cone moves by one quarter turn at most, keeps an angle of at least pi/2 and does not become flat. */
  for (int k = 0; k < K; k++) acc[k] = H[k];
  double cost = 0;
  for (int k = 0; k < K; k++) cost += pow(remainder(acc[k], q4), 2);
  for (int round = 0; turns && round < n; round++) {
    double best = cost * 0.8;
    int bi = -1, bj = -1;
    for (int i = 0; i < n; i++) {
      if (step[i] != 0 || c->angle[i] + q4 == 2 * AU_PI || fabs(c->angle[i] + q4 - 2 * AU_PI) < 1e-9) continue;
      for (int j = closed ? 0 : -1; j < n; j++) {
        if (j == i) continue;
        if (j >= 0 && (step[j] != 0 || c->angle[j] - q4 < q4 - 1e-9 || fabs(c->angle[j] - q4 - 2 * AU_PI) < 1e-9)) continue;
        double cst = 0;
        for (int k = 0; k < K; k++) {
          double x = acc[k] + dH[(size_t)i * K + k] - (j >= 0 ? dH[(size_t)j * K + k] : 0);
          cst += pow(remainder(x, q4), 2);
        }
        if (cst < best) best = cst, bi = i, bj = j;
      }
    }
    if (bi < 0 && !closed) /* one cone down alone */
      for (int j = 0; j < n; j++) {
        if (step[j] != 0 || c->angle[j] - q4 < q4 - 1e-9 || fabs(c->angle[j] - q4 - 2 * AU_PI) < 1e-9) continue;
        double cst = 0;
        for (int k = 0; k < K; k++) cst += pow(remainder(acc[k] - dH[(size_t)j * K + k], q4), 2);
        if (cst < best) best = cst, bi = -1, bj = j;
      }
    if (bi < 0 && bj < 0) break;
    if (bi >= 0) {
      step[bi] = 1, c->angle[bi] += q4;
      for (int k = 0; k < K; k++) acc[k] += dH[(size_t)bi * K + k];
    }
    if (bj >= 0) {
      step[bj] = -1, c->angle[bj] -= q4;
      for (int k = 0; k < K; k++) acc[k] -= dH[(size_t)bj * K + k];
    }
    cost = best;
    if (nchanged) *nchanged += (bi >= 0) + (bj >= 0);
  }
  /* Then the cones move, one edge at a time (to an interior vertex with no other cone, boundary or held vertex beside it),
   * where that brings the holonomies nearer: moving a cone of curvature kappa from a to b changes H_k by
   * kappa (zeta_k(b) - zeta_k(a)), a finer adjustment than a quarter turn. At most three edges a cone. */
  {
    int *vs = calloc((size_t)nv + 1, sizeof *vs), *va = malloc(2 * (size_t)ne * sizeof *va), *fill = calloc((size_t)nv, sizeof *fill);
    unsigned char *isc = calloc((size_t)nv, 1);
    if (!vs || !va || !fill || !isc) {
      free(vs), free(va), free(fill), free(isc);
      st = au_msg_set(msg, AU_E_NOMEM, "out of memory balancing the holonomy");
      goto done;
    }
    for (int e = 0; e < ne; e++) vs[t->E[2 * e] + 1]++, vs[t->E[2 * e + 1] + 1]++;
    for (int v = 0; v < nv; v++) vs[v + 1] += vs[v];
    for (int e = 0; e < ne; e++) va[vs[t->E[2 * e]] + fill[t->E[2 * e]]++] = t->E[2 * e + 1], va[vs[t->E[2 * e + 1]] + fill[t->E[2 * e + 1]]++] = t->E[2 * e];
    for (int i = 0; i < n; i++) isc[c->v[i]] = 1, step[i] = 0;
    for (int round = 0; round < 3 * n; round++) {
      double best = cost * 0.98;
      int bi = -1, bb = -1;
      for (int i = 0; i < n; i++) {
        if (step[i] >= 3) continue;
        int a = c->v[i];
        double kappa = 2 * AU_PI - c->angle[i];
        for (int p = vs[a]; p < vs[a + 1]; p++) {
          int b = va[p];
          int near = isc[b] || fixed[b];
          for (int p2 = vs[b]; p2 < vs[b + 1] && !near; p2++) near = va[p2] != a && (isc[va[p2]] || fixed[va[p2]]);
          if (near) continue; /* two cones side by side, or a cone by the boundary, squeeze a triangle to nothing */
          double cst = 0;
          for (int k = 0; k < K; k++)
            cst += pow(remainder(acc[k] + kappa * (zk[(size_t)k * nv + b] - zk[(size_t)k * nv + a]), q4), 2);
          if (cst < best) best = cst, bi = i, bb = b;
        }
      }
      if (bi < 0) break;
      int a = c->v[bi];
      double kappa = 2 * AU_PI - c->angle[bi];
      for (int k = 0; k < K; k++) acc[k] += kappa * (zk[(size_t)k * nv + bb] - zk[(size_t)k * nv + a]);
      isc[a] = 0, isc[bb] = 1, c->v[bi] = bb, step[bi]++;
      cost = best;
      if (nchanged) (*nchanged)++;
    }
    free(vs), free(va), free(fill), free(isc);
  }
done:
  au_solver_free(&S);
  free(lam), free(ang), free(cot), free(w), free(h), free(qk), free(zk), free(H), free(dH), free(acc), free(corner),
      free(lstart), free(sign), free(step), free(fixed);
  return st;
}
