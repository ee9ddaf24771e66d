/* au_disk_square.c - the square domain's initial map (Zou et al. 2011, sec. 4.1): corners at
 * boundary vertices, the boundary on the sides by arc length, edge splits where a triangle would lie
 * on one side, and a harmonic interior (cotan; positive mean-value weights if that folds, which is
 * then a bijection: the square is convex and no interior edge joins two vertices of one side). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_disk_internal.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static double dist3(const double *a, const double *b) {
  return sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) + (b[2] - a[2]) * (b[2] - a[2]));
}

/* Position of vertex v in loop 0, or -1. */
static int loop_pos(const au_topo *t, int v) {
  for (int k = t->loop_start[0]; k < t->loop_start[1]; k++)
    if (t->loop_vert[k] == v) return k - t->loop_start[0];
  return -1;
}

au_status au_square_corners(const au_mesh *m, const au_topo *t, int corners[4], au_msg *msg) {
  if (!m || !t || !corners || t->nloops != 1) return au_msg_set(msg, AU_E_ARG, "square: bad arguments");
  int n = t->loop_start[1] - t->loop_start[0];
  const int *L = t->loop_vert + t->loop_start[0];
  if (n < 4) return au_msg_set(msg, AU_E_ARG, "square: the boundary has %d vertices; four corners need at least 4", n);
  double *ang = calloc((size_t)m->nv, sizeof(double)), *s = malloc(sizeof(double) * ((size_t)n + 1));
  if (!ang || !s) {
    free(ang), free(s);
    return au_msg_set(msg, AU_E_NOMEM, "square: out of memory");
  }
  /* Surface angle sum at each vertex: pi - (turning angle of the boundary there). */
  for (int f = 0; f < m->nf; f++)
    for (int k = 0; k < 3; k++) {
      int i = m->F[3 * f + k];
      if (!t->vb[i]) continue;
      const double *p = m->X + 3 * i, *q = m->X + 3 * m->F[3 * f + (k + 1) % 3], *r = m->X + 3 * m->F[3 * f + (k + 2) % 3];
      double a[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, b[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
      double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
      ang[i] += atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
    }
  s[0] = 0;
  for (int k = 0; k < n; k++) s[k + 1] = s[k] + dist3(m->X + 3 * L[k], m->X + 3 * L[(k + 1) % n]);
  double len = s[n];
  int c0 = 0;
  for (int k = 1; k < n; k++)
    if (ang[L[k]] < ang[L[c0]]) c0 = k;
  int pos[4] = {c0, -1, -1, -1};
  for (int q = 1; q < 4; q++) {
    double target = q * len / 4;
    int best_near = -1, best_sharp = -1;
    double dnear = INFINITY;
    for (int j = 1; j < n; j++) {
      int k = (c0 + j) % n;
      double arc = s[k] - s[c0];
      if (arc < 0) arc += len;
      double d = fabs(arc - target);
      if (d < dnear) dnear = d, best_near = k;
      if (d <= len / 8 && ang[L[k]] < 0.75 * M_PI && (best_sharp < 0 || ang[L[k]] < ang[L[best_sharp]])) best_sharp = k;
    }
    pos[q] = best_sharp >= 0 ? best_sharp : best_near;
  }
  /* Strictly increasing along the loop from c0, else equal spacing by vertex count. */
  int ok = 1;
  for (int q = 1; q < 4; q++) {
    int a = (pos[q - 1] - c0 + n) % n, b = (pos[q] - c0 + n) % n;
    if (q > 1 && !(b > a)) ok = 0;
    if (q == 1 && b == 0) ok = 0;
  }
  if (!ok)
    for (int q = 1; q < 4; q++) pos[q] = (c0 + q * n / 4) % n;
  for (int q = 0; q < 4; q++) corners[q] = L[pos[q]];
  free(ang), free(s);
  return AU_OK;
}

au_status au_square_order_corners(const au_topo *t, int corners[4], au_msg *msg) {
  if (!t || !corners || t->nloops != 1) return au_msg_set(msg, AU_E_ARG, "square: bad arguments");
  int n = t->loop_start[1] - t->loop_start[0], pos[4];
  for (int q = 0; q < 4; q++) {
    if (corners[q] < 0 || corners[q] >= t->nv || (pos[q] = loop_pos(t, corners[q])) < 0)
      return au_msg_set(msg, AU_E_ARG, "corner vertex %d is not on the boundary", corners[q]);
    for (int r = 0; r < q; r++)
      if (corners[r] == corners[q]) return au_msg_set(msg, AU_E_ARG, "corner vertex %d is given twice", corners[q]);
  }
  /* Insertion sort of corners 1..3 by their distance along the loop from corner 0. */
  for (int q = 1; q < 4; q++) pos[q] = (pos[q] - pos[0] + n) % n;
  for (int q = 2; q < 4; q++)
    for (int r = q; r > 1 && pos[r] < pos[r - 1]; r--) {
      int tp = pos[r];
      pos[r] = pos[r - 1], pos[r - 1] = tp;
      tp = corners[r], corners[r] = corners[r - 1], corners[r - 1] = tp;
    }
  return AU_OK;
}

/* Side membership bits of every vertex: bit s for side s (from corner s to corner s+1); a corner
 * has two bits; interior vertices none. mask [0..nv-1]. */
static void side_masks(const au_topo *t, const int corners[4], unsigned char *mask) {
  int n = t->loop_start[1] - t->loop_start[0];
  const int *L = t->loop_vert + t->loop_start[0];
  memset(mask, 0, (size_t)t->nv);
  int pos[4];
  for (int q = 0; q < 4; q++) pos[q] = loop_pos(t, corners[q]);
  for (int q = 0; q < 4; q++) {
    int k = pos[q];
    for (;;) {
      mask[L[k]] |= (unsigned char)(1u << q);
      if (k == pos[(q + 1) % 4]) break;
      k = (k + 1) % n;
    }
  }
}

au_status au_square_split(const au_mesh *m, const au_topo *t, const int corners[4], au_mesh **out, int *nsplit,
                          au_msg *msg) {
  if (!m || !t || !corners || !out || t->nloops != 1) return au_msg_set(msg, AU_E_ARG, "square: bad arguments");
  *out = NULL;
  if (nsplit) *nsplit = 0;
  for (int q = 0; q < 4; q++)
    if (corners[q] < 0 || corners[q] >= m->nv || loop_pos(t, corners[q]) < 0)
      return au_msg_set(msg, AU_E_ARG, "corner vertex %d is not on the boundary", corners[q]);
  unsigned char *mask0 = malloc((size_t)m->nv);
  if (!mask0) return au_msg_set(msg, AU_E_NOMEM, "square: out of memory");
  side_masks(t, corners, mask0);
  /* Count the edges to split first: each split adds one vertex and two faces, and no new bad edge
   * (the new vertex is interior), but a face with two bad edges is split in two passes. */
  int nbad = 0;
  for (int e = 0; e < t->ne; e++)
    if (t->EF[2 * e + 1] >= 0 && (mask0[t->E[2 * e]] & mask0[t->E[2 * e + 1]])) nbad++;
  au_status st = au_mesh_alloc(m->nv + nbad, m->nf + 2 * nbad, out);
  if (st != AU_OK) {
    free(mask0);
    return au_msg_set(msg, st, "square: out of memory");
  }
  au_mesh *o = *out;
  memcpy(o->X, m->X, sizeof(double) * 3 * (size_t)m->nv);
  memcpy(o->F, m->F, sizeof(int) * 3 * (size_t)m->nf);
  o->nv = m->nv, o->nf = m->nf;
  int added = 0;
  au_topo *tc = NULL;
  unsigned char *touched = NULL;
  while (added < nbad) {
    au_topo_free(&tc);
    st = au_mesh_topology(o, &tc, msg);
    if (st != AU_OK) break;
    free(touched);
    touched = calloc((size_t)o->nf, 1);
    if (!touched) {
      st = au_msg_set(msg, AU_E_NOMEM, "square: out of memory");
      break;
    }
    int did = 0;
    for (int e = 0; e < tc->ne && added < nbad; e++) {
      int a = tc->E[2 * e], b = tc->E[2 * e + 1], f1 = tc->EF[2 * e], f2 = tc->EF[2 * e + 1];
      if (f2 < 0 || a >= m->nv || b >= m->nv || !(mask0[a] & mask0[b]) || touched[f1] || touched[f2]) continue;
      /* Orient: in f1 the edge runs p -> q with third corner c; in f2 it runs q -> p with third d. */
      int *F1 = o->F + 3 * f1, *F2 = o->F + 3 * f2, k1 = 0, k2 = 0;
      while (F1[k1] == a || F1[k1] == b) k1++;
      while (F2[k2] == a || F2[k2] == b) k2++;
      int c = F1[k1], p = F1[(k1 + 1) % 3], q = F1[(k1 + 2) % 3], d = F2[k2];
      int v = o->nv++;
      for (int x = 0; x < 3; x++) o->X[3 * v + x] = 0.5 * (o->X[3 * a + x] + o->X[3 * b + x]);
      /* f1 = (c, p, q) -> (c, p, v) + (c, v, q); f2 = (d, q, p) -> (d, q, v) + (d, v, p). */
      F1[0] = c, F1[1] = p, F1[2] = v;
      int *n1 = o->F + 3 * o->nf++;
      n1[0] = c, n1[1] = v, n1[2] = q;
      F2[0] = d, F2[1] = q, F2[2] = v;
      int *n2 = o->F + 3 * o->nf++;
      n2[0] = d, n2[1] = v, n2[2] = p;
      touched[f1] = touched[f2] = 1;
      added++, did++;
    }
    if (!did) {
      st = au_msg_set(msg, AU_E_INTERNAL, "square: edge splitting made no progress");
      break;
    }
  }
  au_topo_free(&tc);
  free(touched), free(mask0);
  if (st != AU_OK) {
    au_mesh_free(out);
    return st;
  }
  if (nsplit) *nsplit = added;
  return AU_OK;
}

au_status au_square_init(const au_mesh *m, const au_topo *t, const int corners[4], double *P,
                         au_disk_init_method *method, au_msg *msg) {
  if (!m || !t || !corners || !P || t->nv != m->nv || t->nloops != 1) return au_msg_set(msg, AU_E_ARG, "square: bad arguments");
  int n = t->loop_start[1] - t->loop_start[0], nv = m->nv, pos[4];
  const int *L = t->loop_vert + t->loop_start[0];
  for (int q = 0; q < 4; q++)
    if (corners[q] < 0 || corners[q] >= nv || (pos[q] = loop_pos(t, corners[q])) < 0)
      return au_msg_set(msg, AU_E_ARG, "corner vertex %d is not on the boundary", corners[q]);
  unsigned char *fixed = calloc((size_t)nv, 1);
  if (!fixed) return au_msg_set(msg, AU_E_NOMEM, "square: out of memory");
  memset(P, 0, sizeof(double) * 3 * (size_t)nv);
  for (int i = 0; i < nv; i++) fixed[i] = !t->vused[i];
  static const double cx[5] = {0, 1, 1, 0, 0}, cy[5] = {0, 0, 1, 1, 0};
  for (int q = 0; q < 4; q++) {
    /* Side q from corner q to corner q+1, by arc length. */
    int k0 = pos[q], k1 = pos[(q + 1) % 4];
    double len = 0;
    for (int k = k0; k != k1; k = (k + 1) % n) len += dist3(m->X + 3 * L[k], m->X + 3 * L[(k + 1) % n]);
    double s = 0;
    for (int k = k0; k != k1; k = (k + 1) % n) {
      double u = len > 0 ? s / len : 0;
      int v = L[k];
      P[3 * v] = k == k0 ? cx[q] : cx[q] + u * (cx[q + 1] - cx[q]);
      P[3 * v + 1] = k == k0 ? cy[q] : cy[q] + u * (cy[q + 1] - cy[q]);
      fixed[v] = 1;
      s += dist3(m->X + 3 * v, m->X + 3 * L[(k + 1) % n]);
    }
  }
  au_status st = au__disk_harmonic(m, t, fixed, P, method, "square", msg);
  free(fixed);
  return st;
}
