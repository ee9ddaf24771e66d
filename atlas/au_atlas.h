/* au_atlas.h - the atlas of a surface of any genus: a flat metric with cone singularities, cut into charts,
 * made equal area by a flow that moves both sides of every seam together.
 *
 * A surface of genus g (closed, or with boundary loops) has no flat metric conformal to its own
 * unless the curvature goes somewhere: to a few cone vertices, whose curvatures kappa_v = 2*pi -
 * Theta_v (Theta_v the cone's angle) sum to 2*pi*chi on a closed surface (Gauss-Bonnet), or to the
 * boundary. This part computes that metric:
 * 1. cone placement (au_atlas_place_cones), greedy at the extremes of the conformal factor (Ben-Chen,
 *    Gotsman & Bunin 2008): with the cones so far held at u = 0 (and the boundary, which takes the
 *    rest of the curvature), the linearized flattening L u = -K (L the cotan Laplacian, K the angle
 *    defects) is solved and the vertex of largest |u| becomes the next cone; the cones' curvatures are
 *    what the linear solve leaves at them, so they sum to 2*pi*chi exactly (closed surfaces). With
 *    quarter set they are rounded to multiples of pi/2 with the sum kept: the nearest rounding where it
 *    leaves the flattening's range within u_range, else each cone down or up, chosen greedily (one up and
 *    one down at a time) to narrow the range (u is linear in the curvatures: one solve per cone); while
 *    the range stays above u_range a cone is added at the vertex of most extreme u (past max_cones, up to
 *    twice it, only when the range at max_cones is above u_range + 0.5), until a new cone comes out flat.
 * 2. the metric (au_atlas_cetm): the convex energy of Springborn, Schroeder & Pinkall 2008 (conformal
 *    equivalence of triangle meshes) in the log scale factors u, new length l_ij exp((u_i + u_j) / 2),
 *    minimized by Newton: the gradient is Theta_i minus the angle sum at i, the Hessian the cotan
 *    Laplacian of the new metric (CHOLMOD through au_solver.h). Interior vertices get Theta = 2*pi
 *    unless they are cones; boundary vertices keep u = 0 (their lengths); a closed surface holds one
 *    vertex at 0 (the scale). A triangle that violates the triangle inequality has the extended
 *    angles (0, 0, pi) and no cotan weight, as the paper's extension of the energy prescribes.
 * 3. the cut and the charts (au_atlas_layout_make), see below;
 * 4. the equal-area flow with per-corner rigid motions (au_atlas_flow), then the charts separated where
 *    they overlap and packed again (au_atlas_separate). docs/atlas.md. */
#ifndef AU_ATLAS_H
#define AU_ATLAS_H

#include "au_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Options of the cone metric. */
typedef struct au_atlas_opts {
  int max_cones;  /* the most cones placed automatically (default 24; with quarter up to twice as many where
                     the rounding leaves the flattening's range above u_range + 0.5) */
  double u_range; /* place cones until max u - min u of the linearized flattening is below this (default 1.5:
                     lengths within a factor e^1.5 of the surface's, areas e^3) */
  int quarter;    /* 1: cone curvatures in multiples of pi/2 (seam rotations in multiples of 90 degrees);
                     default 0 */
  int max_newton; /* Newton steps of the metric (default 50) */
  double tol;     /* stop when every interior vertex's angle sum is within tol of its target (default 1e-10) */
} au_atlas_opts;

/* The defaults above. */
au_atlas_opts au_atlas_opts_default(void);
/* AU_OK when every field of o is usable (max_cones >= 0, u_range and tol finite and > 0, quarter 0 or 1,
 * max_newton >= 1), else AU_E_ARG naming the first that is not. au_atlas_place_cones and au_atlas_cetm check
 * their options so. */
au_status au_atlas_opts_check(const au_atlas_opts *o, au_msg *msg);

/* Cones: vertex indices and angles (Theta, radians; 2*pi is no cone). */
typedef struct au_atlas_cones {
  int n;
  int *v;        /* v [0..n-1] */
  double *angle; /* angle [0..n-1] */
} au_atlas_cones;

/* Free the arrays of c (not c itself) and zero it; NULL-safe. */
void au_atlas_cones_clear(au_atlas_cones *c);

/* Place cones on the validated mesh m (topology t) as described above. On success c owns its arrays
 * (au_atlas_cones_clear); a disk or annulus may get no cone (n = 0) when the boundary alone flattens
 * it within u_range. With quarter, a closed mesh whose every vertex is a cone (the flow then moves nothing) and
 * one of whose angle sums is not a multiple of pi/2 has no equal-area atlas: AU_E_TOO_COARSE, msg names the
 * vertex (docs/atlas-quarter-limits.md). Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_TOO_COARSE. */
au_status au_atlas_place_cones(const au_mesh *m, const au_topo *t, const au_atlas_opts *o, au_atlas_cones *c,
                               au_msg *msg);

/* What the metric's solve did. */
typedef struct au_atlas_cetm_info {
  int steps;        /* Newton steps taken */
  double err;       /* largest |Theta_i - angle sum at i| over the interior vertices at the end */
  int degenerate;   /* triangles violating the triangle inequality in the final metric */
} au_atlas_cetm_info;

/* The flat cone metric of m (topology t) with the cones c (interior vertices; a cone on the boundary is
 * refused): u [0..nv-1] out, the log scale factors (0 on the boundary, at unreferenced vertices and, on a
 * closed surface, at the first referenced vertex). On a closed surface the cones' curvatures must sum to
 * 2*pi*chi (to 1e-9), or AU_E_ARG says by how much they miss.
 * Returns AU_OK; AU_W_NOT_CONVERGED (max_newton steps without reaching tol: u is the last iterate);
 * AU_E_ARG; AU_E_NOMEM; AU_E_NOT_SPD; AU_E_NUMERIC. */
au_status au_atlas_cetm(const au_mesh *m, const au_topo *t, const au_atlas_cones *c, const au_atlas_opts *o, double *u,
                        au_atlas_cetm_info *info, au_msg *msg);

/* The angles of every corner of m in the metric of u: ang [0..3*nf-1] out, corner k of face f at
 * ang[3f+k]; returns the number of triangles that violate the triangle inequality (their angles are
 * 0, 0 and pi). u may be NULL (the mesh's own metric). */
int au_atlas_corner_angles(const au_mesh *m, const double *u, double *ang);

/* The cut and the laid-out charts of a cone metric. */
typedef struct au_atlas_layout {
  int nvt;              /* per-corner coordinates: vt [0..2*nvt-1], in [0, 1]^2 */
  double *vt;
  int *Ft;              /* Ft [0..3*nf-1]: the row of vt of corner k of face f */
  unsigned char *cut;   /* cut [0..ne-1]: 1 for an interior edge cut open (a seam edge) */
  int ncut;             /* interior edges cut */
  int ncharts;          /* connected pieces of the cut surface */
  int *chart;           /* chart [0..nf-1]: the chart of each face */
  int nseams;           /* seams: chains of cut edges between branch points, cones and the boundary */
  double *seam_rot;     /* seam_rot [0..nseams-1]: the rotation (radians, in (-pi, pi]) taking one side's
                           edges onto the other's */
  int *seam_edge;       /* seam_edge [0..ne-1]: the seam of a cut edge, -1 elsewhere */
  double seam_rot_dev;  /* the largest difference between a cut edge's rotation and its seam's */
  double seam_len_dev;  /* the largest difference between the two sides' lengths of a cut edge (atlas units) */
  int folds;            /* faces with a non-positive signed area in vt */
  double coverage;      /* share of the unit square the charts cover */
  double scale;         /* atlas units per unit of length of the cone metric */
} au_atlas_layout;

/* The lengths elen [0..ne-1] of the edges of m (topology t) in the metric of the log scale factors u
 * (l_ij exp((u_i + u_j) / 2)); u may be NULL (the mesh's own lengths). */
void au_atlas_edge_lengths(const au_mesh *m, const au_topo *t, const double *u, double *elen);

/* What the holonomy fix did. */
typedef struct au_atlas_holonomy_info {
  int loops;         /* generator loops: 2 genus + boundary loops - 1 (0 on a sphere, disk) */
  int fixed;         /* loops whose holonomy is now a multiple of pi/2: all of them, or 0 on a fallback */
  int steps;         /* Newton steps */
  double hol_dev;    /* before: the largest |holonomy - nearest multiple of pi/2| of a loop, radians */
  double err;        /* after: the largest residual of an angle sum or a loop's holonomy, radians */
  double max_change; /* the largest relative change |l / l0 - 1| of an edge length */
} au_atlas_holonomy_info;

/* Make the flat cone metric elen [0..ne-1] (edge lengths of m, topology t, with the cones c: every interior
 * vertex's angle sum is 2 pi or its cone's angle, as au_atlas_cetm leaves them) one whose holonomy around every
 * homology loop (2 genus loops, and one around each boundary loop but one) is a multiple of pi/2, so that with
 * quarter cones every seam's rotation is a multiple of 90 degrees: Newton's method on the log edge lengths, each
 * step the least change that satisfies the linearized angle sums and holonomies (one sparse SPD solve), halved
 * until every angle keeps a quarter of the smallest angle of the start and the residual falls; to 1e-11 rad.
 * The lengths are no longer conformal to the mesh's. elen is changed only on success. Returns AU_OK (also when
 * there is no loop); AU_W_NOT_CONVERGED (a degenerate triangle, or no step that keeps the triangles valid:
 * elen unchanged, msg says so); AU_E_ARG (a length not finite and > 0, a cone not at an interior vertex or
 * with an angle not finite and > 0, two cones at one vertex, loops that do not fit t's genus and boundary
 * loops); AU_E_NOMEM; AU_E_NOT_SPD. */
au_status au_atlas_holonomy_fix(const au_mesh *m, const au_topo *t, const au_atlas_cones *c, double *elen,
                                au_atlas_holonomy_info *info, au_msg *msg);

/* Before au_atlas_holonomy_fix, with quarter cones c chosen automatically: bring the loops' holonomies nearer to
 * multiples of pi/2, as predicted by the linearized response of the conformal metric elen [0..ne-1] (the
 * holonomy's derivative in the cone angles, d H_k / d Theta_v = -zeta_k(v), one Laplacian solve per loop), so
 * that the lengths need less change to reach them. With turns, first a few cones' angles change by a quarter turn
 * (one up and one down, so Gauss-Bonnet still holds; on an open surface also one alone), each at most once,
 * every angle kept at least pi/2 and none flat, greedily while the sum of the squared distances falls by a fifth;
 * then (always) cones move to a neighbouring vertex (none next to another cone, the boundary or the held vertex;
 * at most three edges a cone), greedily while it falls by 2%. *nchanged (may be NULL): the turns and moves made;
 * the caller solves the metric again when it is > 0. Returns AU_OK, AU_E_ARG (the inputs refused as by
 * au_atlas_holonomy_fix), AU_E_NOMEM, AU_E_NOT_SPD. */
au_status au_atlas_holonomy_balance(const au_mesh *m, const au_topo *t, au_atlas_cones *c, const double *elen,
                                    int turns, int *nchanged, au_msg *msg);

/* Cut m through the cones c and, for genus >= 1 or several boundary loops, a homology basis (the
 * complement of a dual spanning tree that avoids a shortest-path tree from the cones, or from the boundary,
 * with the branches that end at an ordinary interior vertex pruned; a cone of angle > 2 pi that is left
 * at the end of a branch gets a second cut, to another cut vertex or the boundary, which splits its chart
 * in two), lay out each chart by integrating the metric (len [0..ne-1], the edges' lengths) face by face, every chart starting in one
 * common frame (the surface developed along a dual tree), turn each chart to its smallest bounding box
 * (with quarter: by a multiple of 90 degrees only, so that seam rotations stay the holonomy's), split a
 * chart that covers a texel of a 1024 x 1024 raster twice (a race from the two faces by centroid distance), and
 * pack the charts into [0, 1]^2 at one scale with a gap of gap (atlas units) around each: by their shapes
 * when shapes is 1 (au_atlas_pack), on shelves only when 0 (for a layout that the flow moves and
 * au_atlas_separate packs again). On success *L owns its arrays (au_atlas_layout_free).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_INTERNAL (a dual tree that does not span). */
au_status au_atlas_layout_make(const au_mesh *m, const au_topo *t, const au_atlas_cones *c, const double *len,
                               double gap, int quarter, int shapes, au_atlas_layout *L, au_msg *msg);
/* Free the arrays of L and zero it; NULL-safe. */
void au_atlas_layout_free(au_atlas_layout *L);

/* Pack L and, while a chart covers a texel of the 1024 x 1024 raster twice, split it between two faces
 * found there (up to 8 pairs per chart and round; new cut edges; the separated corners keep their
 * coordinates in new rows of vt; a split is a race from both faces by centroid distance, so the two pieces
 * meet near their bisector). Long charts are cut only as far as the packing needs: with none cut, then
 * every chart whose longer side exceeds 1.0, 0.8, 0.65 and finally 0.5 sqrt(atlas area) (at most 32 cuts
 * in all) is split between the faces at the two ends of that side, until one packing by the charts'
 * shapes at the scale that covers 0.55 of the square fits. Rounds on shelves (at most 40 per step), then
 * by the charts' shapes (au_atlas_pack). *nsplit (may be NULL): the splits made. Returns AU_OK,
 * AU_E_NOMEM. */
au_status au_atlas_separate(const au_mesh *m, const au_topo *t, au_atlas_layout *L, int quarter, double gap, int *nsplit,
                            au_msg *msg);

/* Measure L again after its vt changed: folds, coverage, cut edges, and the seams (chains of cut edges
 * between branch points, the cones c and the boundary) with their rotations and the deviations of their
 * edges' rotations and lengths. Returns AU_OK, AU_E_NOMEM. */
au_status au_atlas_measure(const au_mesh *m, const au_topo *t, const au_atlas_cones *c, au_atlas_layout *L,
                           au_msg *msg);

/* Turn each of the nch charts (chart [0..nf-1] of each face; faces Ft into vt [0..2*nvt-1], every row of vt
 * used by faces of one chart only) to its smallest bounding box (quarter: by quarter turns only), lay it
 * flat and pack all into [0, 1]^2 at the largest common scale with gap around each, in place: on shelves, and
 * by their rasterized footprints (grid cells of side gap, bottom-left fill, quarter turns, the charts in
 * three orders: by area, longer side, bounding box), whichever packs at the larger scale; *scale (may be
 * NULL) receives the scale. Returns AU_OK, AU_E_NOMEM. */
au_status au_atlas_pack(int nf, const int *Ft, const int *chart, int nch, int nvt, double *vt, int quarter, double gap,
                        double *scale, au_msg *msg);

/* Options of the equal-area flow. */
typedef struct au_atlas_flow_opts {
  int max_steps;   /* (200) */
  double face_tol; /* stop when the per-face mean |r - 1| is below this (0.005) */
  double shear;    /* the first step's weight of the displacement's Dirichlet energy (1) */
  double angles;   /* the first weight mu of the faces' mean squared shear (the anti-conformal part of the map
                      from the surface, per face 2 sinh(Lambda / 2) at its share of the area) against the mean
                      squared logs of the area ratios; 0: no shear term, the flow ends at face_tol (0.064) */
  double angles_face_tol;   /* with angles: stop at the first step with the per-face mean |r - 1| at most
                               this (0.012) ... */
  double angles_vertex_tol; /* ... and the vertex cells' mean |log r| (cells cut along the seams, as
                               param-eval --coords vt) at most this (0.003) */
  double settle;   /* with angles: mu is quartered where a step lowers the objective by less than this share
                      of it (1e-3) */
} au_atlas_flow_opts;
au_atlas_flow_opts au_atlas_flow_opts_default(void);
/* AU_OK when every field of o is usable (max_steps >= 0; face_tol, angles, angles_face_tol, angles_vertex_tol
 * finite and >= 0; shear finite and > 0; settle in [0, 1)), else AU_E_ARG naming the first that is not.
 * au_atlas_flow checks its options so. */
au_status au_atlas_flow_opts_check(const au_atlas_flow_opts *o, au_msg *msg);
typedef struct au_atlas_flow_info {
  int steps;
  double err0, err; /* per-face mean |r - 1| before and after */
} au_atlas_flow_info;

/* The equal-area flow of the layout L of m (cones c pinned where their angle is not 2 pi), in place on
 * L->vt: every vertex has a home position p and every corner of it lies at R p + t, R and t the corner's
 * fixed rigid motion (the seams' rotations met round the vertex), so both sides of every seam move
 * together. Damped Gauss-Newton steps on the logs of the faces' area shares (a squeezed face is pulled as
 * hard as a stretched one is pushed) and, with o->angles, the faces' shear against the surface (weighted
 * by mu, lowered by continuation until the areas are within angles_face_tol and angles_vertex_tol:
 * docs/atlas-angles.md), with a Dirichlet term on the corners' displacements, each step shortened until
 * no face turns over and the objective falls. Where no step lowers them any more (a
 * stationary point, as a symmetric map of a symmetric mesh can be), every free home position moves once
 * by a fixed pseudo-random 1% of its faces' size and the flow goes on. The charts are not
 * packed again. Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_FOLD. */
au_status au_atlas_flow(const au_mesh *m, const au_topo *t, const au_atlas_cones *c, au_atlas_layout *L,
                        const au_atlas_flow_opts *o, au_atlas_flow_info *info, au_msg *msg);

/* The per-face mean |r - 1| of L (r: a face's share of the atlas over its share of the surface); -1 when
 * out of memory. */
double au_atlas_face_error(const au_mesh *m, const au_atlas_layout *L);

/* Rasterize the faces (vt, Ft) at the pixel centres of an R x R raster of [0, 1]^2 (a centre on an edge
 * belongs to one face only, by the top-left rule) and count the pixels covered more than once; *covered
 * (may be NULL) receives the pixels covered at all. Returns the count, or -1 when out of memory. */
long au_atlas_overlap_texels(int nf, const double *vt, const int *Ft, int R, long *covered);

#ifdef __cplusplus
}
#endif
#endif
