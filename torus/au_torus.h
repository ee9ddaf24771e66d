/* au_torus.h - closed genus-1 surfaces onto a flat torus R^2 / Lambda: the homology basis, the
 * conformal start and its seamless texture coordinates.
 *
 * A closed genus-1 surface has a conformal map onto a flat torus, unique up to translation and scale
 * (Gu & Yau 2003). It is computed here with no cut anywhere (../shared/DESIGN.md, "Genus 1"):
 * 1. a homology basis by tree-cotree (Eppstein 2003): the two edges in neither the vertex spanning
 *    tree nor the face spanning tree (au_torus_homology);
 * 2. per generator k, an integer closed 1-form omega_k: 0 on the tree, 1 on generator k, 0 on the
 *    other generator, and on the cotree whatever makes d omega_k = 0 on every triangle; its period
 *    along the loop of generator j is delta_jk;
 * 3. its harmonic part h_k = omega_k - d alpha_k (cotan Laplacian, one factorization for both);
 * 4. the conjugate *h_1 = a h_1 + b h_2 by the 2 x 2 Gram system <h_i, h_j> (cotan weights) against
 *    <*h_1, h_j> = integral of h_1 ^ h_j;
 * 5. the integrals U_k = integral of h_k along the tree: the universal cover in lattice coordinates,
 *    where the lattice is Z^2 and crossing edge i -> j adds the integer pair omega(i -> j); the
 *    conformal map is p = M U with M = [[1, 0], [a, b]], the lattice's basis its columns.
 * The basis is then reduced (Lagrange-Gauss), oriented like the surface, rotated so that a1 lies on
 * +x and scaled so that det = 1. With positive edge weights the harmonic map is an embedding
 * (Gortler, Gotsman & Thurston 2006); cotan weights can fold at obtuse triangles, and then U is
 * solved again with symmetrized mean-value weights (the lattice stays the cotan one).
 *
 * Representation: a vertex has lattice coordinates U (u1, u2) in [0, 1)^2; a face's corner k lies at
 * U[F[3f+k]] + (i, j), the integers (i, j) being the face's corner offsets. In the plane with lattice
 * (a1, a2), a point of lattice coordinates (u1, u2) is u1 a1 + u2 a2. Two faces sharing an edge
 * place its two ends at positions that differ by the same lattice vector (seamless); the lifted
 * triangles tile the plane periodically and cover a fundamental domain of area |det| exactly once. */
#ifndef AU_TORUS_H
#define AU_TORUS_H

#include "au_advect.h"
#include "au_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Which lattice the map is drawn in. */
typedef enum au_torus_shape {
  AU_TORUS_CONFORMAL = 0, /* the conformal modulus's lattice, det 1, a1 along +x (default) */
  AU_TORUS_SQUARE = 1     /* the unit square's: a1 = (1, 0), a2 = (0, 1). The linear map from the
                             conformal lattice, so no longer conformal unless the modulus is square */
} au_torus_shape;

/* How the start's lattice coordinates were solved (the lattice is always the cotan one). */
typedef enum au_torus_weights {
  AU_TORUS_COTAN = 0,
  AU_TORUS_MEANVALUE = 1, /* the cotan start folded */
  AU_TORUS_COMPRESSED = 2 /* the start squeezed a triangle below e^-20 of its share: cotan weights of the
                             surface with its protrusions compressed along their length, clamped positive */
} au_torus_weights;

/* The conformal start. Arrays are owned by the struct (au_torus_start_free). */
typedef struct au_torus_start {
  int nv, nf;
  double *U;              /* U [0..2*nv-1]: lattice coordinates of vertex i at U[2i..2i+1], in [0, 1)^2;
                             unreferenced vertices get (0, 0) */
  int *off;               /* off [0..6*nf-1]: the lattice offset (i, j) of corner k of face f at
                             off[6f+2k..6f+2k+1]; the face's lifted centroid lies in [0, 1)^2 */
  double conformal[2][2]; /* the conformal lattice: a1 = conformal[0], a2 = conformal[1]; a1 = (|a1|, 0),
                             det = 1, reduced (|a1| <= |a2|, |a1 . a2| <= |a1|^2 / 2) */
  au_torus_weights weights; /* cotan, or mean-value after the cotan start folded */
  int cotan_folds;        /* folded triangles of the cotan start (0 unless it folded) */
  double squeeze;         /* the least log of a face's domain share over its surface share (-inf: a fold) */
  double squeeze_before;  /* COMPRESSED: squeeze of the start it replaced; else 0 */
  int folds;              /* folded triangles of the start returned (0 on success) */
  int gen[2];             /* the generator edges of the homology basis (indices into the topology) */
  double star_gap;        /* how far *h_1 is from span(h_1, h_2): |*h_1 - (a h_1 + b h_2)| / |h_1| in the
                             cotan norm, with *h_1 estimated per face (a measure of the discrete
                             star's inexactness, typically a few percent) */
} au_torus_start;

/* The tree-cotree homology basis of a closed genus-1 mesh and its two integer closed 1-forms.
 * t: the topology of a validated closed genus-1 mesh (one component, no boundary). F: its faces.
 * gen: out [0..1], the two generator edges. omega: out [0..2*ne-1]: omega[k*ne + e] is the value of
 * omega_k on edge e directed E[2e] -> E[2e+1] (integers; 0 on tree edges; omega_k(gen[j]) = delta_jk).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_GENUS (not exactly two edges left: msg says how many). */
au_status au_torus_homology(const au_topo *t, const int *F, int gen[2], int *omega, au_msg *msg);

/* The conformal start of the closed genus-1 mesh m (validated for genus 1, topology t), as described
 * at the top of this header. On success *out owns the start (au_torus_start_free).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_GENUS (msg names the genus found and says that the torus
 * map needs a closed genus-1 surface), AU_E_BOUNDARY (a boundary: msg says how many loops),
 * AU_E_NOT_SPD, AU_E_NUMERIC (a degenerate period lattice), AU_E_FOLD (even the positive weights
 * folded in floating point: msg says how many triangles). */
au_status au_torus_init(const au_mesh *m, const au_topo *t, au_torus_start **out, au_msg *msg);

/* Free a start and set *s to NULL; NULL-safe. */
void au_torus_start_free(au_torus_start **s);

/* The lattice of shape sh for start s into L (rows a1, a2). */
void au_torus_lattice(const au_torus_start *s, au_torus_shape sh, double L[2][2]);

/* Plane positions of the vertices, P [0..3*nv-1] (z = 0): U[i] in the lattice L (rows a1, a2). */
void au_torus_positions(const au_torus_start *s, const double L[2][2], double *P);

/* Signed area of face f's lifted triangle in lattice coordinates (multiply by det L for the plane). */
double au_torus_face_area(const au_torus_start *s, const int *F, int f);

/* Folded faces (lifted signed area <= 0) of s with faces F. */
int au_torus_count_folds(const au_torus_start *s, const int *F);

/* The plane translation of every corner in lattice L, for a flow that keeps the faces' lattice
 * translations fixed while the vertices move (DESIGN.md "Genus 1", step 7): corner k of face f lies
 * at P[F[3f+k]] + shift[9f+3k..9f+3k+2] (z = 0), P from au_torus_positions. shift: out [0..9*nf-1]. */
void au_torus_corner_shifts(const au_torus_start *s, const double L[2][2], double *shift);

/* The torus as an advection domain (common/au_advect.h): planar, no boundary; constrain zeroes the
 * displacement's z, retract sets z = 0; shift (from au_torus_corner_shifts, kept by the caller for the
 * run; NULL: none) places every face's corners across the seams. Vertices are not wrapped during the
 * flow: they may leave the fundamental domain, the shifts stay (au_torus_set_positions wraps them after).
 * The 2-D translations are free (no boundary): the least-shear step's kinetic term fixes them. */
au_advect_domain au_torus_domain(const double *shift);

/* After a flow in lattice L: the vertices' plane positions P [0..3*nv-1] (any translation of the
 * fundamental domain) into s->U, each vertex moved into [0, 1)^2 by whole lattice vectors that its
 * corners' offsets take up, then each face moved by the whole lattice vector that puts its lifted
 * centroid back into [0, 1)^2 (so every face keeps its shape and the map on the torus is unchanged,
 * to rounding), and s->folds recounted. L must be the lattice s->off was made for. */
void au_torus_set_positions(au_torus_start *s, const int *F, const double L[2][2], const double *P);

/* Seamless per-corner texture coordinates in lattice L: vertex i's own copy is vt row i (its
 * position in the fundamental domain); each distinct nonzero corner offset of a vertex adds one row,
 * shifted by that exact lattice vector. *nvt gets the row count (>= nv); *vt [0..2*nvt-1] and
 * *Ft [0..3*nf-1] (the row of each corner) are malloc'ed, the caller frees them with free().
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM. */
au_status au_torus_texcoords(const au_torus_start *s, const int *F, const double L[2][2], int *nvt, double **vt,
                             int **Ft, au_msg *msg);

#ifdef __cplusplus
}
#endif
#endif
