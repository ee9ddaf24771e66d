/* au_treecotree.c - the tree-cotree decomposition and its dual generator loops (au_treecotree.h). */
#include <stdlib.h>
#include <string.h>

#include "au_treecotree.h"

/* The other face of interior edge e than f. */
static int across(const au_topo *t, int e, int f) { return t->EF[2 * e] == f ? t->EF[2 * e + 1] : t->EF[2 * e]; }

/* Breadth-first spanning forest of the referenced vertices into tc->kind (AU_TCT_TREE) and tc->vparent, its roots
 * the boundary vertices, or the first referenced vertex when there are none. Returns 0, -1 when out of memory. */
static int vertex_tree(const au_topo *t, au_treecotree *tc) {
  const int nv = t->nv, ne = t->ne;
  int *start = calloc((size_t)nv + 1, sizeof *start), *adj = malloc(2 * (size_t)ne * sizeof *adj);
  int *queue = malloc((size_t)nv * sizeof *queue);
  unsigned char *seen = calloc((size_t)nv, 1);
  if (!start || !adj || !queue || !seen) {
    free(start), free(adj), free(queue), free(seen);
    return -1;
  }
  /* Every vertex's edges by increasing index: the order the search takes them in. */
  for (int e = 0; e < ne; e++) start[t->E[2 * e] + 1]++, start[t->E[2 * e + 1] + 1]++;
  for (int v = 0; v < nv; v++) start[v + 1] += start[v];
  int *fill = queue; /* the insertion cursors, before the queue is needed */
  memcpy(fill, start, (size_t)nv * sizeof *fill);
  for (int e = 0; e < ne; e++) adj[fill[t->E[2 * e]]++] = e, adj[fill[t->E[2 * e + 1]]++] = e;
  for (int v = 0; v < nv; v++) tc->vparent[v] = -1;
  int head = 0, tail = 0;
  if (t->nloops > 0) {
    for (int v = 0; v < nv; v++)
      if (t->vb[v]) seen[v] = 1, queue[tail++] = v;
  } else {
    int root = 0;
    while (root < nv - 1 && !t->vused[root]) root++; /* a face references some vertex */
    seen[root] = 1, queue[tail++] = root;
  }
  while (head < tail) {
    int v = queue[head++];
    for (int k = start[v]; k < start[v + 1]; k++) {
      int e = adj[k], w = t->E[2 * e] == v ? t->E[2 * e + 1] : t->E[2 * e];
      if (seen[w]) continue;
      seen[w] = 1, tc->kind[e] = AU_TCT_TREE, tc->vparent[w] = e, queue[tail++] = w;
    }
  }
  free(start), free(adj), free(queue), free(seen);
  return 0;
}

/* Breadth-first spanning tree of the faces from face 0 across the interior edges off the vertex tree into
 * tc->kind (AU_TCT_COTREE), forder, fparent and fdepth. Returns the number of faces reached. */
static int face_tree(const au_topo *t, au_treecotree *tc) {
  const int nf = t->nf;
  for (int f = 0; f < nf; f++) tc->fparent[f] = -2; /* not reached yet */
  int head = 0, tail = 0;
  tc->fparent[0] = -1, tc->fdepth[0] = 0, tc->forder[tail++] = 0;
  while (head < tail) {
    int f = tc->forder[head++];
    for (int k = 0; k < 3; k++) {
      int e = t->FE[3 * f + k];
      if (t->EF[2 * e + 1] < 0 || tc->kind[e] == AU_TCT_TREE) continue;
      int g = across(t, e, f);
      if (tc->fparent[g] != -2) continue;
      tc->fparent[g] = e, tc->fdepth[g] = tc->fdepth[f] + 1, tc->kind[e] = AU_TCT_COTREE, tc->forder[tail++] = g;
    }
  }
  return tail;
}

au_status au_treecotree_build(const au_topo *t, au_treecotree **out, au_msg *msg) {
  if (out) *out = NULL;
  if (!t || !out || t->nf <= 0 || t->ne <= 0 || !t->E || !t->EF || !t->FE || !t->vused || !t->vb)
    return au_msg_set(msg, AU_E_ARG, "tree-cotree: bad arguments");
  if (t->ncomponents != 1)
    return au_msg_set(msg, AU_E_ARG, "tree-cotree: the mesh has %d components; the decomposition needs one",
                      t->ncomponents);
  const int nv = t->nv, nf = t->nf, ne = t->ne;
  au_treecotree *tc = calloc(1, sizeof *tc);
  if (!tc) return au_msg_set(msg, AU_E_NOMEM, "tree-cotree: out of memory");
  tc->nv = nv, tc->nf = nf, tc->ne = ne;
  tc->kind = calloc((size_t)ne, 1); /* AU_TCT_BOUNDARY until found otherwise */
  tc->vparent = malloc((size_t)nv * sizeof *tc->vparent);
  tc->forder = malloc((size_t)nf * sizeof *tc->forder), tc->fparent = malloc((size_t)nf * sizeof *tc->fparent);
  tc->fdepth = malloc((size_t)nf * sizeof *tc->fdepth);
  if (!tc->kind || !tc->vparent || !tc->forder || !tc->fparent || !tc->fdepth || vertex_tree(t, tc) < 0) goto nomem;
  int reached = face_tree(t, tc);
  if (reached != nf) {
    au_treecotree_free(&tc);
    return au_msg_set(msg, AU_E_INTERNAL, "tree-cotree: the face tree reaches %d of %d faces", reached, nf);
  }
  for (int e = 0; e < ne; e++)
    if (t->EF[2 * e + 1] >= 0 && tc->kind[e] == AU_TCT_BOUNDARY) tc->kind[e] = AU_TCT_GENERATOR, tc->ngen++;
  if (tc->ngen > 0) {
    if (!(tc->gen = malloc((size_t)tc->ngen * sizeof *tc->gen))) goto nomem;
    for (int e = 0, k = 0; e < ne; e++)
      if (tc->kind[e] == AU_TCT_GENERATOR) tc->gen[k++] = e;
  }
  *out = tc;
  return AU_OK;
nomem:
  au_treecotree_free(&tc);
  return au_msg_set(msg, AU_E_NOMEM, "tree-cotree: out of memory");
}

void au_treecotree_free(au_treecotree **p) {
  if (!p || !*p) return;
  au_treecotree *tc = *p;
  free(tc->kind), free(tc->vparent), free(tc->forder), free(tc->fparent), free(tc->fdepth), free(tc->gen), free(tc);
  *p = NULL;
}

int au_treecotree_dual_loop(const au_topo *t, const au_treecotree *tc, int k, int *edges, int *faces) {
  if (k < 0 || k >= tc->ngen) return -1;
  const int g = tc->gen[k], a = t->EF[2 * g], b = t->EF[2 * g + 1];
  /* The common ancestor of a and b in the face tree, and how far each is below it. */
  int x = b, y = a, up = 0, down = 0;
  while (x != y) {
    if (tc->fdepth[x] >= tc->fdepth[y]) x = across(t, tc->fparent[x], x), up++;
    else y = across(t, tc->fparent[y], y), down++;
  }
  /* g, the edges up from b, then the edges down to a (climbed from a, so written from the end). */
  int n = 1 + up + down;
  edges[0] = g;
  x = b;
  for (int i = 1; i <= up; i++) edges[i] = tc->fparent[x], x = across(t, tc->fparent[x], x);
  y = a;
  for (int i = n - 1; i > up; i--) edges[i] = tc->fparent[y], y = across(t, tc->fparent[y], y);
  if (faces) {
    faces[0] = b;
    for (int i = 1; i < n; i++) faces[i] = across(t, edges[i], faces[i - 1]);
  }
  return n;
}
