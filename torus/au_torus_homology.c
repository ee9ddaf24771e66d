/* au_torus_homology.c - the tree-cotree homology basis of a closed genus-1 mesh and its integer
 * closed 1-forms (Eppstein 2003, "Dynamic generators of topologically embedded graphs"; Erickson &
 * Whittlesey 2005).
 *
 * A spanning tree T of the vertices, then a spanning tree T* of the faces over the edges not in T:
 * by Euler's formula exactly 2g edges are left, 2 on a torus. Each closes a primal loop (the edge and
 * the tree paths to its ends). The 1-form omega_k is 0 on T, 1 on generator k and 0 on the other;
 * on the cotree edges it is fixed by closedness, face by face from the leaves of T* to its root (a
 * leaf face has one unknown edge, its dual tree edge). Closed on every face but the root by
 * construction, and on the root because the faces' d omega sum to zero on a closed surface. Its
 * integral along the loop of generator j is delta_jk (the loop is tree edges and generator j). */
#include <stdlib.h>
#include <string.h>

#include "au_torus.h"

/* +1 if edge e, directed E[2e] -> E[2e+1], runs along face f's counter-clockwise order, else -1;
 * the edge opposite corner k joins corners k+1 and k+2. */
static int edge_sign(const au_topo *t, const int *F, int f, int k) {
  int e = t->FE[3 * f + k];
  return t->E[2 * e] == F[3 * f + (k + 1) % 3] ? 1 : -1;
}

/* Breadth-first spanning tree of the referenced vertices: intree[e] = 1 for its edges. */
static au_status vertex_tree(const au_topo *t, unsigned char *intree, au_msg *msg) {
  int nv = t->nv, ne = t->ne;
  int *start = calloc((size_t)nv + 1, sizeof(int)), *adj = malloc(sizeof(int) * 2 * (size_t)ne);
  int *queue = malloc(sizeof(int) * (size_t)nv);
  unsigned char *seen = calloc((size_t)nv, 1);
  if (!start || !adj || !queue || !seen) {
    free(start), free(adj), free(queue), free(seen);
    return au_msg_set(msg, AU_E_NOMEM, "torus: out of memory for the spanning tree");
  }
  for (int e = 0; e < ne; e++) start[t->E[2 * e] + 1]++, start[t->E[2 * e + 1] + 1]++;
  for (int i = 0; i < nv; i++) start[i + 1] += start[i];
  int *fill = queue; /* reused as insertion cursors before the search */
  memcpy(fill, start, sizeof(int) * (size_t)nv);
  for (int e = 0; e < ne; e++) adj[fill[t->E[2 * e]]++] = e, adj[fill[t->E[2 * e + 1]]++] = e;
  int root = 0;
  while (root < nv && !t->vused[root]) root++;
  int qh = 0, qt = 0;
  seen[root] = 1, queue[qt++] = root;
  while (qh < qt) {
    int v = queue[qh++];
    for (int k = start[v]; k < start[v + 1]; k++) {
      int e = adj[k], w = t->E[2 * e] == v ? t->E[2 * e + 1] : t->E[2 * e];
      if (seen[w]) continue;
      seen[w] = 1, intree[e] = 1, queue[qt++] = w;
    }
  }
  free(start), free(adj), free(queue), free(seen);
  return AU_OK;
}

/* Breadth-first spanning tree of the faces over edges not in the vertex tree. order [0..nf-1]: the
 * faces in visiting order; pedge [0..nf-1]: the edge to each face's parent (-1 at the root).
 * incotree[e] = 1 for its edges. Returns the number of faces reached. */
static int face_tree(const au_topo *t, const unsigned char *intree, int *order, int *pedge, unsigned char *incotree) {
  int nf = t->nf;
  for (int f = 0; f < nf; f++) pedge[f] = -2;
  int qh = 0, qt = 0;
  pedge[0] = -1, order[qt++] = 0;
  while (qh < qt) {
    int f = order[qh++];
    for (int k = 0; k < 3; k++) {
      int e = t->FE[3 * f + k];
      if (intree[e] || t->EF[2 * e + 1] < 0) continue;
      int g = t->EF[2 * e] == f ? t->EF[2 * e + 1] : t->EF[2 * e];
      if (pedge[g] != -2) continue;
      pedge[g] = e, incotree[e] = 1, order[qt++] = g;
    }
  }
  return qt;
}

/* omega (one column, ne values) from its values on the tree (0) and the generators (set by the
 * caller), peeling the face tree from its leaves. */
static void close_form(const au_topo *t, const int *F, const int *order, const int *pedge, int *omega) {
  for (int q = t->nf - 1; q > 0; q--) {
    int f = order[q], s = 0, kp = -1;
    for (int k = 0; k < 3; k++) {
      int e = t->FE[3 * f + k];
      if (e == pedge[f]) kp = k;
      else s += edge_sign(t, F, f, k) * omega[e];
    }
    omega[pedge[f]] = -s * edge_sign(t, F, f, kp);
  }
}

au_status au_torus_homology(const au_topo *t, const int *F, int gen[2], int *omega, au_msg *msg) {
  if (!t || !F || !gen || !omega || t->nf <= 0 || t->ne <= 0) return au_msg_set(msg, AU_E_ARG, "torus: bad arguments");
  if (t->nloops != 0 || t->ncomponents != 1)
    return au_msg_set(msg, AU_E_ARG, "torus: the homology basis needs a closed connected mesh");
  int nf = t->nf, ne = t->ne;
  unsigned char *intree = calloc((size_t)ne, 1), *incotree = calloc((size_t)ne, 1);
  int *order = malloc(sizeof(int) * (size_t)nf), *pedge = malloc(sizeof(int) * (size_t)nf);
  au_status st = AU_OK;
  if (!intree || !incotree || !order || !pedge) {
    st = au_msg_set(msg, AU_E_NOMEM, "torus: out of memory for the homology basis");
    goto done;
  }
  if ((st = vertex_tree(t, intree, msg)) != AU_OK) goto done;
  if (face_tree(t, intree, order, pedge, incotree) != nf) {
    st = au_msg_set(msg, AU_E_INTERNAL, "torus: the face tree does not reach every face");
    goto done;
  }
  int ng = 0;
  for (int e = 0; e < ne; e++)
    if (!intree[e] && !incotree[e]) {
      if (ng < 2) gen[ng] = e;
      ng++;
    }
  if (ng != 2) {
    st = au_msg_set(msg, AU_E_GENUS, "torus: %d edges left outside the tree and cotree (genus %d); the torus map "
                                     "needs a closed genus-1 surface", ng, ng / 2);
    goto done;
  }
  for (int k = 0; k < 2; k++) {
    int *w = omega + (size_t)k * ne;
    memset(w, 0, sizeof(int) * (size_t)ne);
    w[gen[k]] = 1;
    close_form(t, F, order, pedge, w);
  }
done:
  free(intree), free(incotree), free(order), free(pedge);
  return st;
}
