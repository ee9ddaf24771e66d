/* au_dec.h - discrete exterior calculus operators on triangle meshes (pure functions of V, F).
 *
 * Shapes: V is nv x 3 row-major, F is nf x 3, face vectors nf x 3, vertex vectors nv x 3.
 * The cotan stiffness C is (C g)_i = sum_j w_ij (g_i - g_j) with w_ij = (cot a_ij + cot b_ij)/2 over
 * the angles opposite edge ij: symmetric positive semidefinite, constants in its null space, and
 * (C g)_i = integral of grad g . grad phi_i (the Dirichlet form of piecewise-linear functions). */
#ifndef AU_DEC_H
#define AU_DEC_H

#include "au_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Triangle areas: area [0..nf-1]. */
void au_dec_face_areas(int nf, const int *F, const double *V, double *area);

/* Barycentric vertex areas (paper eq. 11): A [0..nv-1], a third of each incident triangle.
 * area: face areas from au_dec_face_areas, or NULL to compute them. Unreferenced vertices get 0. */
void au_dec_vertex_areas(int nv, int nf, const int *F, const double *V, const double *area, double *A);

/* Cotan edge weights w [0..t->ne-1]: w_e = (cot a + cot b)/2 over the (one or two) faces of edge e.
 * May be negative at obtuse angles; the assembled C is positive semidefinite all the same. */
void au_dec_cotan(const au_topo *t, const int *F, const double *V, double *w);

/* y = C x for the stiffness with edge weights w (y [0..nv-1]); x and y must not alias. */
void au_dec_stiffness_apply(const au_topo *t, const double *w, const double *x, double *y);

/* Per-face gradient of the piecewise-linear function g [0..nv-1] (paper eq. 15): G [0..3*nf-1], in the
 * plane of each triangle. Degenerate triangles get a zero gradient. */
void au_dec_face_grad(int nf, const int *F, const double *V, const double *g, double *G);

/* Per-vertex average of face vectors Gf, weighted by the triangle's angle at the vertex (paper
 * eq. 16): Gv [0..3*nv-1]. Unreferenced vertices get 0. Returns AU_OK or AU_E_NOMEM. */
au_status au_dec_vertex_grad(int nv, int nf, const int *F, const double *V, const double *Gf, double *Gv);

/* Orientation of the triangle (a, b, c) with corners on the unit sphere: the triple product
 * a . (b x c), positive for a counter-clockwise triangle seen from outside. Computed as
 * ((b - a) x (c - a)) . (a + b + c) / 3, which is the same number algebraically but keeps its relative
 * accuracy for tiny triangles (the direct formula loses it below ~1e-16). */
double au_dec_sphere_orient(const double *a, const double *b, const double *c);

/* Area of the spherical triangle (a, b, c) with corners on the unit sphere (its spherical excess),
 * signed like au_dec_sphere_orient: E = 2 atan2(det(a, b, c), 1 + a.b + b.c + c.a) (Van Oosterom and
 * Strackee). Unlike the chord triangle's area it vanishes when the corners come onto one great
 * circle, and the areas of a fold-free map sum to 4 pi exactly. If grad is not NULL it gets the
 * gradient of E with respect to a, b and c (3 x 3, row-major), as functions on R^3. */
double au_dec_sphere_area(const double *a, const double *b, const double *c, double *grad);

/* The least area the chord triangle (a, b, c), corners on the unit sphere, can have while its longest
 * edge stays as it is and its third corner stays on the sphere above the same point of that edge:
 * half the edge's length times the depth of that point below the sphere. A long edge's chord runs
 * deep under the sphere (about l^2/8 at its middle), so a long, thin triangle keeps a chord area near
 * l^3/16 however flat it gets on the sphere (a Schwarz lantern): its area share cannot be met with
 * that edge. 0 for a degenerate edge. */
double au_dec_sphere_chord_floor(const double *a, const double *b, const double *c);

/* The chord floor's excess of a sphere map P (au_metrics.chord_floor_excess): the area by which the
 * faces' least chord areas (au_dec_sphere_chord_floor) exceed their shares As[f] / sAs x sAd, as a
 * fraction of sAd, the chord triangles' total. *nfaces (may be NULL): how many faces exceed it. */
double au_dec_sphere_floor_excess(size_t nf, const int *F, const double *P, const double *As, double sAs, double sAd,
                                  int *nfaces);

/* au_dec_sphere_area of every face: area [0..nf-1]. */
void au_dec_sphere_face_areas(int nf, const int *F, const double *V, double *area);

/* The tube starts' triangle reshaping (sphere/au_sphere_init.c, torus/au_torus_init.c), on one triangle
 * x (its three corners, changed in place), g the gradient of the log scale across it (|g| = gn > 0).
 * au_dec_tri_compress scales each corner's component along g by beta: a protrusion shortened along its
 * length, so the harmonic map squeezes it less. */
void au_dec_tri_compress(double x[3][3], const double *g, double gn, double beta);

/* Shears x along the girth n x g (n the surface triangle's normal, |n| = nn > 0) until the corner off the
 * edge most across g stands over an end of that edge: the triangles of an antiprism band of a tube become
 * a prism band's, a turn of each ring against the next that the flow, a gradient, cannot make. Corner
 * above the edge: to its right end; below: to its left end (the same shear for both kinds of triangle of
 * a band). Returns 1 if x was sheared, 0 if its corner stood over the edge already. */
int au_dec_tri_twist(double x[3][3], const double *n, double nn, const double *g, double gn);

/* The cotans of triangle x's corners: c[k] at corner k, the weight of the opposite edge; 0 for a
 * degenerate triangle. */
void au_dec_tri_cotans(const double x[3][3], double c[3]);

#ifdef __cplusplus
}
#endif
#endif
