/* au_lm.c - the least-shear area step: the velocity of the Lie advection chosen, among the fields
 * whose discrete Lie derivative of the area form is the wanted per-face change, as the one that
 * distorts angles least (Zou et al. 2011, sec. 3, with the velocity's freedom used for the angles).
 *
 * In DEC terms the area form is a 2-form on the faces and its Lie derivative along a P1 velocity u is
 * the per-face divergence: face f changes by d_f . u = sum_k g_fk . u_k, g_fk = n_f x (opposite edge)/2
 * (exact to first order). The paper takes u = grad g (curl-free) with a Poisson solve; that field
 * shears triangles, and over many steps the shear accumulates into slivers that stop the flow. Here
 * u minimizes, in the tangent spaces the domain allows (sphere: tangent plane; disk boundary: the
 * circle's tangent; fixed: none),
 *     E(u) = sum_f (d_f . u - dA_f)^2 / A_f  +  alpha sum_f A_f |C_f u|^2  +  eps sum_i A_i |u_i|^2,
 * (A_f the current area; with face weights w_f the sums weigh face f by w_f instead of A_f, i.e. the
 * first term becomes w_f ((d_f . u - dA_f) / A_f)^2), where C_f u = (J11 - J22, J12 + J21) is the anti-conformal part of the velocity's Jacobian on face f
 * (zero for an infinitesimally conformal motion) and the last term only fixes the rigid rotations, which
 * change neither areas nor angles. The first two terms are integrals of (div u - rate)^2 and of the
 * shear rate, so the step is scale invariant. On the sphere A_f is by default the spherical triangle's
 * area, whose gradient is exact (au_dec_sphere_area), and C_f is taken in the tangent plane at the
 * face's centroid direction (the chord triangle's own plane tips over as its corners approach one
 * great circle). Normal equations: (sum d d^T/A + alpha A C^T C + eps M) u
 * = sum d dA/A, symmetric positive definite with the one-ring pattern of the mesh (2x2 blocks), which is
 * analyzed once. As a Gauss-Newton/Levenberg-Marquardt iteration it converges to exact per-face areas;
 * the shear term only shapes the path (and damps the checkerboard modes a plain Gauss-Newton on the
 * face areas excites). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_advect_internal.h"
#include "au_dec.h"
#include "au_par.h"
#include "au_solver.h"

/* From this many faces the assembly runs on two threads (with the factorization's split). */
#define AU_LM_THREAD_MIN 8000

/* Planar domains: a relative diagonal term that bounds the condition number where the shear weight is
 * small and a global mode (a rotation of a sliding boundary) is nearly free; without it the last pivot
 * can come out non-positive in double precision. Not on the sphere: it pulls every vertex towards
 * standing still in proportion to its stiffness, and a cluster of tiny squeezed triangles that must
 * travel far is torn by that pull (docs/flow.md). */
#define AU_LM_PLANAR_DIAG 1e-8

/* An axis whose constrained, orthogonalized remainder is shorter than this is not an allowed direction:
 * the axes have unit length, so anything shorter is the constraint's rounding, not a direction. */
#define AU_BASIS_MIN 1e-6

/* Added to every diagonal entry so that a slot whose terms all vanish (a vertex with zero area) still
 * has a positive pivot; far below any real entry, it changes nothing else. */
#define AU_LM_DIAG_TINY 1e-300

struct au_lm {
  int nv, nf;
  const int *F;
  const double *X;      /* the surface's positions (for the shape-restoring target) */
  int *colstart, *rows; /* upper triangle of the 2nv x 2nv matrix, column by column */
  int *fidx;            /* [0..12*nf-1]: per face, per vertex pair (00 11 22 01 12 20), the value index
                           of the block's first column entry and of its second column entry */
  double *B;            /* [0..6*nv-1]: per vertex, two orthonormal allowed directions (or zero) */
  double *rhs, *x;      /* [0..2nv-1] */
  double *val1;         /* the second assembly thread's matrix values, rhs and mass (large meshes) */
  au_spd *spd;
};

void au__lm_free(au_lm **lp) {
  if (!lp || !*lp) return;
  au_lm *l = *lp;
  free(l->colstart), free(l->rows), free(l->fidx), free(l->B), free(l->rhs), free(l->x), free(l->val1);
  au_spd_free(&l->spd);
  free(l);
  *lp = NULL;
}

/* Index of row r in column c of the pattern (r <= c, present). */
static int find(const au_lm *l, int r, int c) {
  const int *col = l->rows + l->colstart[c];
  const int *hit = bsearch(&r, col, (size_t)(l->colstart[c + 1] - l->colstart[c]), sizeof(int), au__cmp_int);
  return hit ? l->colstart[c] + (int)(hit - col) : -1;
}

au_status au__lm_create(const au_mesh *m, const au_topo *t, au_lm **out, au_msg *msg) {
  *out = NULL;
  const int nv = m->nv, nf = m->nf, n = 2 * nv;
  au_lm *l = calloc(1, sizeof *l);
  if (!l) return au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
  l->nv = nv, l->nf = nf, l->F = m->F, l->X = m->X;
  /* Pattern: vertex i couples with itself and its edge neighbours; each coupling is a 2x2 block. */
  int *deg = calloc((size_t)nv + 1, sizeof(int));
  l->colstart = malloc(sizeof(int) * ((size_t)n + 1));
  l->fidx = malloc(sizeof(int) * 12 * (size_t)nf);
  l->B = calloc(6 * (size_t)nv, sizeof(double));
  l->rhs = malloc(sizeof(double) * (size_t)n);
  l->x = malloc(sizeof(double) * (size_t)n);
  if (!deg || !l->colstart || !l->fidx || !l->B || !l->rhs || !l->x) goto nomem;
  /* lower[k]: the neighbours i < k of vertex k. */
  for (int e = 0; e < t->ne; e++) {
    int a = t->E[2 * e], b = t->E[2 * e + 1];
    deg[a > b ? a : b]++;
  }
  int *lstart = malloc(sizeof(int) * ((size_t)nv + 1)), *lower = malloc(sizeof(int) * (size_t)(t->ne > 0 ? t->ne : 1));
  if (!lstart || !lower) {
    free(lstart), free(lower);
    goto nomem;
  }
  lstart[0] = 0;
  for (int k = 0; k < nv; k++) lstart[k + 1] = lstart[k] + deg[k], deg[k] = 0;
  for (int e = 0; e < t->ne; e++) {
    int a = t->E[2 * e], b = t->E[2 * e + 1];
    int hi = a > b ? a : b, lo = a > b ? b : a;
    lower[lstart[hi] + deg[hi]++] = lo;
  }
  for (int k = 0; k < nv; k++) qsort(lower + lstart[k], (size_t)deg[k], sizeof(int), au__cmp_int);
  /* Column 2k: rows 2i, 2i+1 for each lower neighbour i, then 2k. Column 2k+1: the same, then 2k, 2k+1. */
  size_t nz = 0;
  for (int k = 0; k < nv; k++) nz += 2 * (2 * (size_t)deg[k]) + 3;
  l->rows = malloc(sizeof(int) * (nz > 0 ? nz : 1));
  if (!l->rows) {
    free(lstart), free(lower);
    goto nomem;
  }
  int p = 0;
  for (int k = 0; k < nv; k++) {
    for (int c = 0; c < 2; c++) {
      l->colstart[2 * k + c] = p;
      for (int s = lstart[k]; s < lstart[k + 1]; s++) l->rows[p++] = 2 * lower[s], l->rows[p++] = 2 * lower[s] + 1;
      l->rows[p++] = 2 * k;
      if (c == 1) l->rows[p++] = 2 * k + 1;
    }
  }
  l->colstart[n] = p;
  free(lstart), free(lower), free(deg);
  deg = NULL;
  static const int pairs[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {2, 0}};
  for (int f = 0; f < nf; f++) {
    const int *v = m->F + 3 * f;
    for (int q = 0; q < 6; q++) {
      int i = v[pairs[q][0]], k = v[pairs[q][1]];
      if (i > k) {
        int tmp = i;
        i = k, k = tmp;
      }
      l->fidx[12 * f + 2 * q] = find(l, 2 * i, 2 * k);
      l->fidx[12 * f + 2 * q + 1] = find(l, 2 * i, 2 * k + 1);
    }
  }
  /* The elimination order: the vertex graph's, each vertex's two unknowns side by side. */
  int *perm = malloc(sizeof(int) * (size_t)n), *vperm = malloc(sizeof(int) * (size_t)nv);
  if (!perm || !vperm) {
    free(perm), free(vperm);
    goto nomem;
  }
  au_status st = au_graph_order(nv, t->ne, t->E, vperm, msg);
  for (int k = 0; k < nv && st == AU_OK; k++) perm[2 * k] = 2 * vperm[k], perm[2 * k + 1] = 2 * vperm[k] + 1;
  if (st == AU_OK) st = au_spd_create(n, l->colstart, l->rows, perm, &l->spd, msg);
  free(perm), free(vperm);
  if (st != AU_OK) {
    au__lm_free(&l);
    return st;
  }
  *out = l;
  return AU_OK;
nomem:
  free(deg);
  au__lm_free(&l);
  return au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
}

/* The allowed directions of vertex i at p: an orthonormal basis of the range of the domain's
 * (linear) constraint, found by constraining the axes and orthonormalizing; unused slots are zero. */
void au__allowed_basis(const au_advect_domain *dom, int i, const double *p, double *B) {
  double cand[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  int nb = 0;
  memset(B, 0, 6 * sizeof(double));
  for (int a = 0; a < 3 && nb < 2; a++) {
    double *d = cand[a];
    if (!dom->spherical) d[2] = 0; /* planar domains move in the plane */
    dom->constrain(dom->ctx, i, p, d);
    if (!dom->spherical) d[2] = 0;
    for (int b = 0; b < nb; b++) {
      const double *e = B + 3 * b;
      double dot = d[0] * e[0] + d[1] * e[1] + d[2] * e[2];
      d[0] -= dot * e[0], d[1] -= dot * e[1], d[2] -= dot * e[2];
    }
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len < AU_BASIS_MIN) continue;
    B[3 * nb] = d[0] / len, B[3 * nb + 1] = d[1] / len, B[3 * nb + 2] = d[2] / len;
    nb++;
  }
}

static inline double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* x minus its component along the unit vector n. */
static inline void project_out(double *x, const double *n) {
  double d = dot3(x, n);
  x[0] -= d * n[0], x[1] -= d * n[1], x[2] -= d * n[2];
}

/* The arguments of one assembly of the least-shear system (see au__lm_step). */
typedef struct lm_asm {
  const au_lm *l;
  const double *P, *dAf, *wf;
  const double *shift;   /* per-corner shifts of the domain, or NULL (au_advect_domain.shift) */
  double alpha, restore, lantern;
  int sph;               /* spherical areas and tangent-plane shear */
  int f0, f1;            /* the faces [f0, f1) */
  double *val, *rhs, *mass;
} lm_asm;

/* Add the faces [f0, f1) to val, rhs and mass. */
static void *assemble_faces(void *arg) {
  const lm_asm *a = arg;
  const au_lm *l = a->l;
  const double *P = a->P, *dAf = a->dAf, *wf = a->wf;
  const double alpha = a->alpha, restore = a->restore, lantern = a->lantern;
  const int sph = a->sph, *F = l->F;
  double *val = a->val, *rhs = a->rhs, *mass = a->mass;
  static const int pairs[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {2, 0}};
  for (int f = a->f0; f < a->f1; f++) {
    const int *v = F + 3 * f;
    double cbuf[3][3];
    const double *cp[3];
    for (int k = 0; k < 3; k++) cp[k] = au__corner(P, F, a->shift, f, k, cbuf[k]);
    const double *p0 = cp[0], *p1 = cp[1], *p2 = cp[2];
    double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]}, e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
    double nrm[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double nn = sqrt(dot3(nrm, nrm));
    if (!(nn > 0)) continue;
    double A = 0.5 * nn;
    for (int d = 0; d < 3; d++) nrm[d] /= nn;
    /* On the sphere the area is the spherical triangle's (its chord triangle keeps a sizeable area
     * when the corners come onto one great circle, where the spherical one vanishes), and the frame
     * of the shear term is the tangent plane at the centroid direction, the plane the step control
     * measures orientation in. Sg holds the area's gradient per corner. */
    double Sg[9], Es = 0;
    if (sph) {
      Es = au_dec_sphere_area(p0, p1, p2, Sg);
      double c[3] = {p0[0] + p1[0] + p2[0], p0[1] + p1[1] + p2[1], p0[2] + p1[2] + p2[2]};
      double cn = sqrt(dot3(c, c));
      if (!(Es > 0) || !(cn > 0)) continue;
      for (int d = 0; d < 3; d++) nrm[d] = c[d] / cn;
      project_out(e1, nrm);
      project_out(e2, nrm);
      double x[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      A = 0.5 * dot3(x, nrm); /* the projected triangle's area */
      if (!(A > 0)) continue;
    }
    double l1 = sqrt(dot3(e1, e1));
    if (!(l1 > 0)) continue;
    double u1[3] = {e1[0] / l1, e1[1] / l1, e1[2] / l1};
    double u2[3] = {nrm[1] * u1[2] - nrm[2] * u1[1], nrm[2] * u1[0] - nrm[0] * u1[2], nrm[0] * u1[1] - nrm[1] * u1[0]};
    /* Per corner k: the area gradient g_k (3D), then its rows in the allowed directions. */
    double rd[6], rc1[6], rc2[6];
    for (int k = 0; k < 3; k++) {
      const double *pa = cp[(k + 1) % 3], *pb = cp[(k + 2) % 3];
      double e[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
      if (sph) project_out(e, nrm);
      double g[3] = {0.5 * (nrm[1] * e[2] - nrm[2] * e[1]), 0.5 * (nrm[2] * e[0] - nrm[0] * e[2]),
                     0.5 * (nrm[0] * e[1] - nrm[1] * e[0])};
      /* grad phi_k = g_k / A; anti-conformal rows h1 = u1 (phi.u1) - u2 (phi.u2), h2 = u1 (phi.u2) + u2 (phi.u1). */
      double a1 = dot3(g, u1) / A, a2 = dot3(g, u2) / A;
      double h1[3], h2[3];
      for (int d = 0; d < 3; d++) h1[d] = u1[d] * a1 - u2[d] * a2, h2[d] = u1[d] * a2 + u2[d] * a1;
      const double *Bk = l->B + 6 * v[k];
      for (int b = 0; b < 2; b++) {
        rd[2 * k + b] = dot3(sph ? Sg + 3 * k : g, Bk + 3 * b);
        rc1[2 * k + b] = dot3(h1, Bk + 3 * b);
        rc2[2 * k + b] = dot3(h2, Bk + 3 * b);
      }
      mass[2 * v[k]] += A / 3;
    }
    /* Each face counts with its weight (its share of the surface): weighting by the current domain
     * area instead would let the squeezed faces, the ones that must change most, count for nothing. */
    if (sph) A = Es;
    double wgt = wf ? wf[f] : A, wd = wgt / (A * A), wc = alpha * wgt;
    for (int q = 0; q < 6; q++) {
      int a = pairs[q][0], b = pairs[q][1];
      int ia = v[a], ib = v[b];
      /* The block (ia, ib) with ia <= ib as stored: rows of the smaller vertex, columns of the larger. */
      int r = a, c = b;
      if (ia > ib) r = b, c = a;
      int j0 = l->fidx[12 * f + 2 * q], j1 = l->fidx[12 * f + 2 * q + 1];
      for (int cb = 0; cb < 2; cb++) {
        int base = cb == 0 ? j0 : j1;
        for (int rb = 0; rb < 2; rb++) {
          if (r == c && rb > cb) continue; /* diagonal block: upper triangle only */
          double vrc = wd * rd[2 * r + rb] * rd[2 * c + cb] + wc * (rc1[2 * r + rb] * rc1[2 * c + cb] + rc2[2 * r + rb] * rc2[2 * c + cb]);
          val[base + rb] += vrc;
        }
      }
    }
    for (int k = 0; k < 3; k++)
      for (int b = 0; b < 2; b++) rhs[2 * v[k] + b] += wd * rd[2 * k + b] * dAf[f];
    if (restore > 0) {
      /* Shape restoring: the shear target is the fraction `restore` of the linear motion that would
       * take the domain triangle to the similar copy of the surface triangle closest to it. */
      const double *x0 = l->X + 3 * v[0], *x1 = l->X + 3 * v[1], *x2 = l->X + 3 * v[2];
      double f1[3] = {x1[0] - x0[0], x1[1] - x0[1], x1[2] - x0[2]}, f2[3] = {x2[0] - x0[0], x2[1] - x0[1], x2[2] - x0[2]};
      double ns[3] = {f1[1] * f2[2] - f1[2] * f2[1], f1[2] * f2[0] - f1[0] * f2[2], f1[0] * f2[1] - f1[1] * f2[0]};
      double nsl = sqrt(dot3(ns, ns)), fl = sqrt(dot3(f1, f1));
      double d2x = dot3(e2, u1), d2y = dot3(e2, u2);
      if (nsl > 0 && fl > 0 && d2y > 0) {
        double s1x = fl, s2x = dot3(f2, f1) / fl, s2y = nsl / fl;
        double den = s1x * s1x + s2x * s2x + s2y * s2y;
        double zr = (s1x * l1 + s2x * d2x + s2y * d2y) / den, zi = (s2x * d2y - s2y * d2x) / den;
        /* M = Z S D^-1, S = [s1x s2x; 0 s2y], D = [l1 d2x; 0 d2y]. */
        double SD11 = s1x / l1, SD12 = (s2x - s1x * d2x / l1) / d2y, SD21 = 0, SD22 = s2y / d2y;
        double M11 = zr * SD11 - zi * SD21, M12 = zr * SD12 - zi * SD22, M21 = zi * SD11 + zr * SD21,
               M22 = zi * SD12 + zr * SD22;
        /* Lantern-aware: a face whose longest chord edge l has a floor l^3 / 16 near its share (see
         * au_advect_opts.lantern) is restored more, up to fully. */
        double rf = restore;
        if (lantern > 0 && wf && wf[f] > 0) {
          double l2 = 0;
          for (int k = 0; k < 3; k++) {
            const double *pa = cp[k], *pb = cp[(k + 1) % 3];
            double d2 = (pb[0] - pa[0]) * (pb[0] - pa[0]) + (pb[1] - pa[1]) * (pb[1] - pa[1]) + (pb[2] - pa[2]) * (pb[2] - pa[2]);
            if (d2 > l2) l2 = d2;
          }
          rf = fmin(1, restore * (1 + lantern * l2 * sqrt(l2) / (16 * wf[f])));
        }
        double t1 = rf * (M11 - M22), t2 = rf * (M12 + M21);
        for (int k = 0; k < 3; k++)
          for (int b = 0; b < 2; b++) rhs[2 * v[k] + b] += wc * (rc1[2 * k + b] * t1 + rc2[2 * k + b] * t2);
      }
    }
    }
  return NULL;
}

au_status au__lm_step(au_lm *l, const au_advect_domain *dom, const double *P, const double *dAf, const double *wf,
                      double alpha, double eps, int sphere_areas, double restore, double lantern, double *D,
                      au_msg *msg) {
  const int nv = l->nv, nf = l->nf, n = 2 * nv;
  double *val = au_spd_values(l->spd);
  memset(val, 0, sizeof(double) * (size_t)l->colstart[n]);
  memset(l->rhs, 0, sizeof(double) * (size_t)n);
  for (int i = 0; i < nv; i++) au__allowed_basis(dom, i, P + 3 * i, l->B + 6 * i);
  double *mass = l->x; /* scratch: the domain's vertex areas */
  memset(mass, 0, sizeof(double) * (size_t)n);
  const int sph = dom->spherical && sphere_areas;
  /* Large meshes: half of the faces on a second thread, into buffers of its own, added after. */
  lm_asm a0 = {l, P, dAf, wf, dom->shift, alpha, restore, lantern, sph, 0, nf, val, l->rhs, mass};
  lm_asm a1 = a0;
  if (nf >= AU_LM_THREAD_MIN && (l->val1 || (l->val1 = malloc(sizeof(double) * ((size_t)l->colstart[n] + 4 * (size_t)nv))))) {
    a0.f1 = a1.f0 = nf / 2;
    a1.val = l->val1, a1.rhs = l->val1 + l->colstart[n], a1.mass = a1.rhs + n;
    memset(a1.val, 0, sizeof(double) * ((size_t)l->colstart[n] + 4 * (size_t)nv));
    au__run_pair(assemble_faces, &a0, &a1);
    for (int q = 0; q < l->colstart[n]; q++) val[q] += a1.val[q];
    for (int q = 0; q < n; q++) l->rhs[q] += a1.rhs[q], mass[q] += a1.mass[q];
  } else {
    assemble_faces(&a0);
  }
  /* The rigid rotations (and any slot without an allowed direction) are fixed by the mass term; an
   * empty slot gets a unit diagonal so that its zero solution is exact.
   * Planar domains also get AU_LM_PLANAR_DIAG on the diagonal (see there). */
  const double diag_rel = dom->spherical ? 0 : AU_LM_PLANAR_DIAG;
  for (int i = 0; i < nv; i++) {
    for (int b = 0; b < 2; b++) {
      int c = 2 * i + b, dg = l->colstart[c + 1] - 1;
      const double *Bi = l->B + 6 * i + 3 * b;
      if (dot3(Bi, Bi) == 0) val[dg] = 1, l->rhs[c] = 0;
      else val[dg] = val[dg] * (1 + diag_rel) + eps * mass[2 * i] + AU_LM_DIAG_TINY;
    }
  }
  au_status st = au_spd_factor(l->spd, msg);
  if (st == AU_OK) st = au_spd_solve(l->spd, l->rhs, l->x, msg);
  if (st != AU_OK) return st;
  for (int i = 0; i < nv; i++) {
    const double *Bi = l->B + 6 * i;
    double x0 = l->x[2 * i], x1 = l->x[2 * i + 1];
    for (int d = 0; d < 3; d++) D[3 * i + d] = x0 * Bi[d] + x1 * Bi[3 + d];
  }
  return AU_OK;
}
