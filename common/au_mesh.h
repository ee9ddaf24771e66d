/* au_mesh.h - triangle mesh as plain arrays, its topology, and validation.
 *
 * The flow never touches OpenMesh objects: a mesh is nv positions and nf index triples.
 * au_mesh_topology() derives edges, edge-face incidence, boundary loops, components and the
 * Euler characteristic; au_mesh_validate() checks what a map needs and names the first problem. */
#ifndef AU_MESH_H
#define AU_MESH_H

#include "au_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* au_mesh and au_mesh_alloc / au_mesh_copy / au_mesh_free are public (include/authalic.h). */

/* Topology of a triangle mesh. Edges are unordered vertex pairs; "corner k of face f" is
 * F[3f+k], and the edge opposite corner k joins corners k+1 and k+2 (mod 3). */
typedef struct au_topo {
  int nv, nf;
  int ne;            /* number of edges */
  int *E;            /* E [0..2*ne-1]: endpoints of edge e, E[2e] < E[2e+1] */
  int *EF;           /* EF [0..2*ne-1]: the (up to) two faces of edge e; -1 where absent */
  int *EC;           /* EC [0..2*ne-1]: corner (0..2) of face EF[2e+s] opposite edge e; -1 where absent */
  int *FE;           /* FE [0..3*nf-1]: edge opposite corner k of face f */
  unsigned char *vb; /* vb [0..nv-1]: 1 for vertices on a boundary edge */
  unsigned char *vused; /* vused [0..nv-1]: 1 for vertices referenced by some face */
  int nloops;        /* number of boundary loops */
  int *loop_start;   /* loop_start [0..nloops]: loop l is loop_vert[loop_start[l]..loop_start[l+1]-1] */
  int *loop_vert;    /* boundary vertices, each loop in the order of the faces' orientation */
  double *loop_len;  /* loop_len [0..nloops-1]: length of each loop in the mesh's positions (NULL if no X given) */
  int ncomponents;   /* connected components among referenced vertices */
  int nunreferenced; /* vertices referenced by no face */
  int euler;         /* V - E + F over referenced vertices */
  int genus;         /* (2*components - euler - loops)/2 */
} au_topo;

/* Compute the topology of m. Assumes indices are in range (au_mesh_validate checks that first);
 * edges shared by more than two faces are still recorded (EF holds the first two) and make the
 * function return AU_E_NONMANIFOLD_EDGE with the edge named in msg.
 * On success *out owns the topology; free with au_topo_free.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NONMANIFOLD_EDGE, AU_E_NONMANIFOLD_VERTEX, AU_E_ORIENTATION. */
au_status au_mesh_topology(const au_mesh *m, au_topo **out, au_msg *msg);
/* Free a topology and set *t to NULL; NULL-safe. */
void au_topo_free(au_topo **t);

/* What the caller expects of the mesh's topology. */
typedef struct au_mesh_expect {
  int loops;  /* required number of boundary loops: 0 sphere, 1 disk, 2 annulus; -1 any (default 0) */
  int genus;  /* required genus, -1 any (default 0) */
  const char *command; /* the target's name for messages ("sphere", "disk"); may be NULL */
} au_mesh_expect;

/* Defaults: loops 0, genus 0, command NULL. */
au_mesh_expect au_mesh_expect_default(void);

/* Validate m for mapping, in this order, and stop at the first problem:
 * empty (no vertices or faces), non-finite coordinates (names the vertex), index out of range
 * (names face and index), face with a repeated index (names the face), non-manifold edge (names the
 * two vertices and how many faces share it), non-manifold vertex (names it), inconsistent
 * orientation (names the edge), several components (says how many), boundary loop count (says
 * how many were found and, if a boundary is present for a closed-surface target, suggests the
 * disk or annulus, or the sphere for a closed mesh given to the disk), genus (says which was
 * found and what was expected; with genus 1 expected and a command, that the map needs a closed
 * genus-1 surface; a closed genus-1 mesh given to a genus-0 command is pointed at the torus), zero-area faces (names the first and says how many; a face whose
 * area is <= 1e-14 * total area counts as zero).
 * On success *topo (if topo is not NULL) receives the topology; free with au_topo_free.
 * Returns AU_OK, AU_W_UNREFERENCED (usable; msg says how many vertices), or one of the
 * AU_E_* input errors, AU_E_ARG, AU_E_NOMEM. */
au_status au_mesh_validate(const au_mesh *m, const au_mesh_expect *expect, au_topo **topo, au_msg *msg);

#ifdef __cplusplus
}
#endif
#endif
