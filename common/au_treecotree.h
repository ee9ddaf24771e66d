/* au_treecotree.h - the tree-cotree decomposition of a connected triangle mesh's edges and the generator
 * loops of its first homology (Eppstein 2003, "Dynamic generators of topologically embedded graphs";
 * Erickson & Whittlesey 2005, "Greedy optimal homotopy and homology generators").
 *
 * A spanning forest T of the vertices, grown breadth first from the boundary (every boundary vertex a root)
 * or, on a closed surface, from the first referenced vertex; then a spanning tree T* of the faces, grown
 * breadth first from face 0 across the interior edges not in T. By Euler's formula the interior edges left
 * in neither are 2 genus on a closed surface and 2 genus + loops - 1 with a boundary (whose edges are in
 * neither too and are no generators). Each such generator g closes a dual loop (g, then the face tree's path
 * back from the face beyond g to the face before it) and a primal loop (g and the vertex tree's paths from
 * its ends to their roots; with a boundary, a path between boundary vertices). A dual loop crosses only
 * face-tree edges and its own generator, a primal loop runs on vertex-tree edges and its own generator, so
 * dual loop i meets primal loop j once when i = j and never otherwise: the dual loops are a basis of the
 * surface's first homology, the primal ones of its homology relative to the boundary (of the homology
 * itself when closed).
 *
 * Both trees are breadth first in a fixed order (a vertex's edges by increasing index, a face's edges by
 * corner), so the decomposition is a function of the topology alone: the torus's integer 1-forms
 * (torus/au_torus_homology.c) and the atlas's holonomy loops (atlas/au_atlas_holonomy.c) are made from it. */
#ifndef AU_TREECOTREE_H
#define AU_TREECOTREE_H

#include "au_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What an edge is in the decomposition. */
typedef enum au_tct_kind {
  AU_TCT_BOUNDARY = 0,  /* a boundary edge (one face): in neither tree, no generator */
  AU_TCT_TREE = 1,      /* in the vertex forest T */
  AU_TCT_COTREE = 2,    /* in the face tree T* */
  AU_TCT_GENERATOR = 3  /* an interior edge in neither: one homology generator */
} au_tct_kind;

/* The decomposition. Arrays are owned by the struct (au_treecotree_free). */
typedef struct au_treecotree {
  int nv, nf, ne;        /* the topology's counts */
  unsigned char *kind;   /* kind [0..ne-1]: an au_tct_kind per edge */
  int *vparent;          /* vparent [0..nv-1]: the edge from vertex v to its parent in T; -1 at a root (a
                            boundary vertex, or the one root of a closed surface) and at unreferenced vertices */
  int *forder;           /* forder [0..nf-1]: the faces in the order T* reached them, forder[0] = 0; a face's
                            parent comes before it */
  int *fparent;          /* fparent [0..nf-1]: the edge from face f to its parent in T*; -1 at face 0 */
  int *fdepth;           /* fdepth [0..nf-1]: the number of T* edges from face f to face 0 */
  int ngen;              /* the number of generators: 2 genus when closed, 2 genus + loops - 1 with a boundary */
  int *gen;              /* gen [0..ngen-1]: the generator edges, by increasing index (NULL when ngen = 0) */
} au_treecotree;

/* The tree-cotree decomposition of the connected mesh with topology t (au_mesh_topology).
 * t: one component (t->ncomponents == 1), at least one face; unreferenced vertices are allowed (outside T).
 * out: on success owns the decomposition; free with au_treecotree_free.
 * Returns AU_OK, AU_E_ARG (t NULL, no faces, or several components: msg says how many), AU_E_NOMEM,
 * AU_E_INTERNAL (T* misses a face, which a manifold connected topology does not allow: msg says how many). */
au_status au_treecotree_build(const au_topo *t, au_treecotree **out, au_msg *msg);

/* Free a decomposition and set *p to NULL; NULL-safe. */
void au_treecotree_free(au_treecotree **p);

/* The dual loop of generator k: the edges it crosses, in order, and the faces it passes through. It leaves
 * face a = t->EF[2g] across g = tc->gen[k] into face b = t->EF[2g+1], climbs T* from b to the common ancestor
 * of a and b, and comes down T* to a. Face faces[i] is entered across edges[i] and left across
 * edges[(i+1) % n]; edges[0] = g and faces[0] = b. The faces are distinct, so n <= nf.
 * t, tc: the topology and its decomposition. k: 0..tc->ngen-1.
 * edges, faces: out, room for t->nf entries each; faces may be NULL.
 * Returns n, the loop's length (>= 2), or -1 when k is out of range. */
int au_treecotree_dual_loop(const au_topo *t, const au_treecotree *tc, int k, int *edges, int *faces);

#ifdef __cplusplus
}
#endif
#endif
