/* au_torus_homology.c - the tree-cotree homology basis of a closed genus-1 mesh and its integer
 * closed 1-forms (Eppstein 2003, "Dynamic generators of topologically embedded graphs"; Erickson &
 * Whittlesey 2005).
 *
 * The vertex spanning tree T, the face spanning tree T* over the edges not in T and the 2g edges left
 * in neither, 2 on a torus, are common/au_treecotree.h's. Each generator closes a primal loop (the
 * edge and the tree paths to its ends). The 1-form omega_k is 0 on T, 1 on generator k and 0 on the
 * other; on the cotree edges it is fixed by closedness, face by face from the leaves of T* to its root
 * (a leaf face has one unknown edge, its dual tree edge). Closed on every face but the root by
 * construction, and on the root because the faces' d omega sum to zero on a closed surface. Its
 * integral along the loop of generator j is delta_jk (the loop is tree edges and generator j). */
#include <string.h>

#include "au_torus.h"
#include "au_treecotree.h"

/* +1 if edge e, directed E[2e] -> E[2e+1], runs along face f's counter-clockwise order, else -1;
 * the edge opposite corner k joins corners k+1 and k+2. */
static int edge_sign(const au_topo *t, const int *F, int f, int k) {
  int e = t->FE[3 * f + k];
  return t->E[2 * e] == F[3 * f + (k + 1) % 3] ? 1 : -1;
}

/* omega (one column, ne values) from its values on the tree (0) and the generators (set by the
 * caller), peeling the face tree from its leaves. */
static void close_form(const au_topo *t, const int *F, const au_treecotree *tc, int *omega) {
  const int *order = tc->forder, *pedge = tc->fparent;
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
  const int ne = t->ne;
  au_treecotree *tc = NULL;
  au_status st = au_treecotree_build(t, &tc, msg);
  if (st != AU_OK) return st;
  if (tc->ngen != 2) {
    st = au_msg_set(msg, AU_E_GENUS, "torus: %d edges left outside the tree and cotree (genus %d); the torus map "
                                     "needs a closed genus-1 surface", tc->ngen, tc->ngen / 2);
    goto done;
  }
  for (int k = 0; k < 2; k++) {
    int *w = omega + (size_t)k * ne;
    gen[k] = tc->gen[k];
    memset(w, 0, sizeof(int) * (size_t)ne);
    w[gen[k]] = 1;
    close_form(t, F, tc, w);
  }
done:
  au_treecotree_free(&tc);
  return st;
}
