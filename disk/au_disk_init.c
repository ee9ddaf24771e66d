/* au_disk_init.c - fold-free near-conformal initial maps onto the unit disk and onto an annulus.
 *
 * Disk: the boundary goes onto the unit circle by arc length and the interior is the harmonic
 * extension with cotan weights, the discrete conformal map for that boundary (Pinkall & Polthier
 * 1993; Eck et al. 1995). Obtuse triangles make some cotan weights negative and the map can fold;
 * then the interior is solved again with symmetrized mean-value weights (Floater 2003), which are
 * positive, so the map is a bijection onto the convex disk (Tutte 1963, Floater 2003).
 *
 * Annulus: u harmonic with u = 0 on the inner loop and 1 on the outer one; its Dirichlet energy E
 * gives the conformal modulus, ln(R/r) = 2 pi / E. The angle is the harmonic 1-form of period 1
 * around the annulus: theta per vertex plus a jump of 1 across the edges a dual path from loop to
 * loop crosses (Gortler, Gotsman & Thurston 2006). The map is r^(1-u) e^(2 pi i theta). */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "au_dec.h"
#include "au_disk_internal.h"
#include "au_solver.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

double au__disk_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void au__disk_meanvalue_weights(const au_topo *t, const int *F, const double *X, double *w) {
  memset(w, 0, sizeof(double) * (size_t)t->ne);
  for (int f = 0; f < t->nf; f++) {
    for (int k = 0; k < 3; k++) {
      int i = F[3 * f + k], j = F[3 * f + (k + 1) % 3], l = F[3 * f + (k + 2) % 3];
      const double *xi = X + 3 * i, *xj = X + 3 * j, *xl = X + 3 * l;
      double a[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
      double b[3] = {xl[0] - xi[0], xl[1] - xi[1], xl[2] - xi[2]};
      double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
      double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
      double s = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
      /* tan(alpha/2) = sin / (1 + cos), written without cancellation for acute angles. */
      double den = la * lb + d;
      double th = den > 0 ? s / den : 1e300;
      if (!(la > 0) || !(lb > 0)) continue;
      w[t->FE[3 * f + (k + 2) % 3]] += 0.5 * th / la; /* edge (i, j) is opposite corner k+2 */
      w[t->FE[3 * f + (k + 1) % 3]] += 0.5 * th / lb; /* edge (i, l) is opposite corner k+1 */
    }
  }
}

int au__disk_count_folds(int nf, const int *F, const double *P) {
  int n = 0;
  for (int f = 0; f < nf; f++) {
    const double *a = P + 3 * F[3 * f], *b = P + 3 * F[3 * f + 1], *c = P + 3 * F[3 * f + 2];
    double o = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    n += !(o > 0);
  }
  return n;
}

au_status au__disk_dirichlet(const au_topo *t, const double *w, const unsigned char *fixed, double *P, au_msg *msg) {
  int nv = t->nv;
  au_solver *s = NULL;
  double *x = malloc(sizeof(double) * 2 * (size_t)nv), *b = calloc(2 * (size_t)nv, sizeof(double));
  au_status st = AU_OK;
  if (!x || !b) {
    st = au_msg_set(msg, AU_E_NOMEM, "disk: out of memory");
    goto done;
  }
  for (int i = 0; i < nv; i++) x[i] = P[3 * i], x[nv + i] = P[3 * i + 1];
  st = au_solver_create(nv, t->ne, t->E, fixed, AU_ORDER_FAST, &s, msg);
  if (st == AU_OK) st = au_solver_factor(s, w, NULL, msg);
  if (st == AU_OK) st = au_solver_solve(s, 2, b, x, msg);
  if (st == AU_OK)
    for (int i = 0; i < nv; i++) P[3 * i] = x[i], P[3 * i + 1] = x[nv + i], P[3 * i + 2] = 0;
done:
  au_solver_free(&s);
  free(x), free(b);
  return st;
}

au_status au__disk_harmonic(const au_mesh *m, const au_topo *t, const unsigned char *fixed, double *P,
                            au_disk_init_method *method, const char *what, au_msg *msg) {
  double *w = malloc(sizeof(double) * (size_t)(t->ne > 0 ? t->ne : 1));
  double *P0 = malloc(sizeof(double) * 3 * (size_t)m->nv);
  if (!w || !P0) {
    free(w), free(P0);
    return au_msg_set(msg, AU_E_NOMEM, "%s: out of memory", what);
  }
  memcpy(P0, P, sizeof(double) * 3 * (size_t)m->nv);
  au_dec_cotan(t, m->F, m->X, w);
  au_status st = au__disk_dirichlet(t, w, fixed, P, msg);
  int folds = st == AU_OK ? au__disk_count_folds(m->nf, m->F, P) : -1;
  if (method) *method = AU_INIT_COTAN;
  if (folds != 0) {
    /* Negative cotan weights folded the map (or made the system indefinite): positive weights. */
    memcpy(P, P0, sizeof(double) * 3 * (size_t)m->nv);
    au__disk_meanvalue_weights(t, m->F, m->X, w);
    st = au__disk_dirichlet(t, w, fixed, P, msg);
    if (method) *method = AU_INIT_MEANVALUE;
    if (st == AU_OK && (folds = au__disk_count_folds(m->nf, m->F, P)) != 0)
      st = au_msg_set(msg, AU_E_FOLD, "%s: the initial map has %d folded triangles", what, folds);
  }
  free(w), free(P0);
  return st;
}

au_status au_disk_init(const au_mesh *m, const au_topo *t, double *P, au_disk_init_method *method, au_msg *msg) {
  if (!m || !t || !P || t->nv != m->nv || t->nloops != 1) return au_msg_set(msg, AU_E_ARG, "disk: bad arguments");
  int nv = m->nv;
  unsigned char *fixed = calloc((size_t)nv, 1);
  if (!fixed) return au_msg_set(msg, AU_E_NOMEM, "disk: out of memory");
  memset(P, 0, sizeof(double) * 3 * (size_t)nv);
  for (int i = 0; i < nv; i++) fixed[i] = !t->vused[i];
  /* The boundary by arc length, in the loop's order (the faces' orientation: counter-clockwise). */
  int n = t->loop_start[1] - t->loop_start[0];
  const int *L = t->loop_vert + t->loop_start[0];
  double len = 0;
  for (int k = 0; k < n; k++) {
    const double *a = m->X + 3 * L[k], *b = m->X + 3 * L[(k + 1) % n];
    len += sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
  }
  double s = 0;
  for (int k = 0; k < n; k++) {
    double phi = len > 0 ? 2 * M_PI * s / len : 2 * M_PI * k / n;
    P[3 * L[k]] = cos(phi), P[3 * L[k] + 1] = sin(phi);
    fixed[L[k]] = 1;
    const double *a = m->X + 3 * L[k], *b = m->X + 3 * L[(k + 1) % n];
    s += sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
  }
  au_status st = au__disk_harmonic(m, t, fixed, P, method, "disk", msg);
  free(fixed);
  return st;
}

/* +1 if edge e, directed E[2e] -> E[2e+1], runs along face f's counter-clockwise order, else -1. */
static int edge_dir_in_face(const au_mesh *m, const au_topo *t, int f, int e) {
  const int *c = m->F + 3 * f;
  int a = t->E[2 * e], b = t->E[2 * e + 1];
  for (int k = 0; k < 3; k++)
    if (c[k] == a && c[(k + 1) % 3] == b) return 1;
  return -1;
}

/* A dual path of faces from a boundary edge of loop `from` to one of loop `to` (breadth-first over
 * interior edges), as the list of crossed edges with their jump signs. cross [0..nf+1] receives
 * edge indices, sign the jump J of the edge directed from E[2e] to E[2e+1]. Returns the count, or
 * -1 if the loops are not connected (cannot happen on a connected mesh), -2 out of memory. */
static int dual_path(const au_mesh *m, const au_topo *t, const unsigned char *onloop_from,
                     const unsigned char *onloop_to, int *cross, int *sign) {
  int nf = m->nf, ne = t->ne;
  int *prev = malloc(sizeof(int) * (size_t)nf), *via = malloc(sizeof(int) * (size_t)nf), *queue = malloc(sizeof(int) * (size_t)nf);
  int *bstart = malloc(sizeof(int) * (size_t)nf);
  if (!prev || !via || !queue || !bstart) {
    free(prev), free(via), free(queue), free(bstart);
    return -2;
  }
  for (int f = 0; f < nf; f++) prev[f] = -2, bstart[f] = -1;
  int qh = 0, qt = 0;
  /* Seeds: faces with a boundary edge on the `from` loop. */
  for (int e = 0; e < ne; e++) {
    if (t->EF[2 * e + 1] >= 0) continue;
    int a = t->E[2 * e], b = t->E[2 * e + 1], f = t->EF[2 * e];
    if (onloop_from[a] && onloop_from[b] && prev[f] == -2) prev[f] = -1, bstart[f] = e, queue[qt++] = f;
  }
  int end = -1, eend = -1;
  while (qh < qt && end < 0) {
    int f = queue[qh++];
    for (int k = 0; k < 3; k++) {
      int e = t->FE[3 * f + k];
      if (t->EF[2 * e + 1] < 0) {
        if (onloop_to[t->E[2 * e]] && onloop_to[t->E[2 * e + 1]]) {
          end = f, eend = e;
          break;
        }
        continue;
      }
      int g = t->EF[2 * e] == f ? t->EF[2 * e + 1] : t->EF[2 * e];
      if (prev[g] != -2) continue;
      prev[g] = f, via[g] = e, queue[qt++] = g;
    }
  }
  int n = -1;
  if (end >= 0) {
    /* Walk back from the end. An edge crossed into face B has J = +1 along the edge as directed in B;
     * the exit through the `to` loop has J = -1 along the edge as directed in the last face. */
    n = 0;
    cross[n] = eend, sign[n] = -edge_dir_in_face(m, t, end, eend), n++;
    for (int f = end; f >= 0; f = prev[f]) {
      int e = prev[f] >= 0 ? via[f] : bstart[f];
      cross[n] = e, sign[n] = edge_dir_in_face(m, t, f, e), n++;
    }
  }
  free(prev), free(via), free(queue), free(bstart);
  return n;
}

au_status au_annulus_init(const au_mesh *m, const au_topo *t, int outer, double inner_radius, double *P,
                          double *radius_out, double *modulus_radius, au_disk_init_method *method, au_msg *msg) {
  if (!m || !t || !P || t->nv != m->nv || t->nloops != 2 || (outer != 0 && outer != 1) ||
      !(inner_radius >= 0 && inner_radius < 1))
    return au_msg_set(msg, AU_E_ARG, "annulus: bad arguments");
  int nv = m->nv, ne = t->ne, inner = 1 - outer;
  au_status st = AU_OK;
  au_solver *s = NULL;
  unsigned char *fixed = calloc((size_t)nv, 1), *on_in = calloc((size_t)nv, 1), *on_out = calloc((size_t)nv, 1);
  double *w = malloc(sizeof(double) * (size_t)(ne > 0 ? ne : 1)), *u = calloc((size_t)nv, sizeof(double));
  double *th = calloc((size_t)nv, sizeof(double)), *b = calloc((size_t)nv, sizeof(double));
  int *cross = malloc(sizeof(int) * ((size_t)m->nf + 2)), *sign = malloc(sizeof(int) * ((size_t)m->nf + 2));
  if (!fixed || !on_in || !on_out || !w || !u || !th || !b || !cross || !sign) {
    st = au_msg_set(msg, AU_E_NOMEM, "annulus: out of memory");
    goto done;
  }
  for (int k = t->loop_start[inner]; k < t->loop_start[inner + 1]; k++) on_in[t->loop_vert[k]] = 1;
  for (int k = t->loop_start[outer]; k < t->loop_start[outer + 1]; k++) on_out[t->loop_vert[k]] = 1;
  int ncross = dual_path(m, t, on_in, on_out, cross, sign);
  if (ncross == -2) {
    st = au_msg_set(msg, AU_E_NOMEM, "annulus: out of memory");
    goto done;
  }
  if (ncross < 0) {
    st = au_msg_set(msg, AU_E_INTERNAL, "annulus: no path of faces joins the two boundary loops");
    goto done;
  }
  double r_mod = 0;
  for (int pass = 0; pass < 2; pass++) {
    /* Pass 0: cotan weights (conformal); pass 1: symmetrized mean-value weights (positive). */
    if (pass == 0) au_dec_cotan(t, m->F, m->X, w);
    else au__disk_meanvalue_weights(t, m->F, m->X, w);
    if (method) *method = pass == 0 ? AU_INIT_COTAN : AU_INIT_MEANVALUE;
    /* u: 0 on the inner loop, 1 on the outer one. */
    for (int i = 0; i < nv; i++) fixed[i] = !t->vused[i] || on_in[i] || on_out[i], u[i] = on_out[i] ? 1 : 0;
    memset(b, 0, sizeof(double) * (size_t)nv);
    st = au_solver_create(nv, ne, t->E, fixed, AU_ORDER_FAST, &s, msg);
    if (st == AU_OK) st = au_solver_factor(s, w, NULL, msg);
    if (st == AU_OK) st = au_solver_solve(s, 1, b, u, msg);
    au_solver_free(&s);
    if (st != AU_OK) {
      if (pass == 0 && st == AU_E_NOT_SPD) continue;
      goto done;
    }
    double E = 0;
    for (int e = 0; e < ne; e++) {
      double d = u[t->E[2 * e]] - u[t->E[2 * e + 1]];
      E += w[e] * d * d;
    }
    if (pass == 0 || r_mod == 0) r_mod = E > 0 ? exp(-2 * M_PI / E) : 0;
    double r = inner_radius > 0 ? inner_radius : r_mod;
    if (!(r > 0 && r < 1)) {
      st = au_msg_set(msg, AU_E_NUMERIC, "annulus: the conformal modulus gives inner radius %g", r);
      goto done;
    }
    /* theta: the harmonic 1-form with period 1, C theta = sum_j w_ij J_ij; one vertex pinned. */
    memset(b, 0, sizeof(double) * (size_t)nv);
    for (int c = 0; c < ncross; c++) {
      int e = cross[c];
      b[t->E[2 * e]] += w[e] * sign[c];
      b[t->E[2 * e + 1]] -= w[e] * sign[c];
    }
    int pinned = -1;
    for (int i = 0; i < nv; i++) {
      fixed[i] = !t->vused[i];
      if (!fixed[i] && pinned < 0) pinned = i, fixed[i] = 1;
      th[i] = 0;
    }
    st = au_solver_create(nv, ne, t->E, fixed, AU_ORDER_FAST, &s, msg);
    if (st == AU_OK) st = au_solver_factor(s, w, NULL, msg);
    if (st == AU_OK) st = au_solver_solve(s, 1, b, th, msg);
    au_solver_free(&s);
    if (st != AU_OK) {
      if (pass == 0 && st == AU_E_NOT_SPD) continue;
      goto done;
    }
    double lr = log(r);
    for (int i = 0; i < nv; i++) {
      double rho = t->vused[i] ? exp((1 - u[i]) * lr) : 0;
      P[3 * i] = rho * cos(2 * M_PI * th[i]), P[3 * i + 1] = rho * sin(2 * M_PI * th[i]), P[3 * i + 2] = 0;
    }
    /* The jump's sign convention decides the sense of rotation: mirror if the map came out reversed. */
    int folds = au__disk_count_folds(m->nf, m->F, P);
    if (folds > m->nf / 2) {
      for (int i = 0; i < nv; i++) P[3 * i + 1] = -P[3 * i + 1];
      folds = au__disk_count_folds(m->nf, m->F, P);
    }
    /* Exactly on the circles. */
    for (int i = 0; i < nv; i++) {
      if (!on_in[i] && !on_out[i]) continue;
      double *p = P + 3 * i, rr = hypot(p[0], p[1]), want = on_out[i] ? 1.0 : r;
      p[0] *= want / rr, p[1] *= want / rr;
    }
    if (radius_out) *radius_out = r;
    if (modulus_radius) *modulus_radius = r_mod;
    if (folds == 0) {
      st = AU_OK;
      break;
    }
    st = au_msg_set(msg, AU_E_FOLD, "annulus: the initial map has %d folded triangles", folds);
  }
done:
  au_solver_free(&s);
  free(fixed), free(on_in), free(on_out), free(w), free(u), free(th), free(b), free(cross), free(sign);
  return st;
}
