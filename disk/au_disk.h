/* au_disk.h - equal-area (authalic) maps of open surfaces onto planar domains: the unit disk, an
 * annulus centred at the origin with outer radius 1, and the unit square [0,1]^2.
 *
 * Pipeline (Zou et al. 2011, sec. 4.1 and 4.5.1): a fold-free near-conformal initial map with the
 * boundary on the domain's boundary, then the shared Lie-advection loop (common/au_advect.h) with a
 * planar domain in which interior vertices move freely and boundary vertices slide along their
 * circle or side (tangential component of the velocity, then projection back onto the circle or
 * side); square corners stay fixed. `AU_DISK_FIXED` keeps the whole initial boundary instead.
 * Positions are nv x 3 with z = 0; faces keep the input's counter-clockwise orientation. */
#ifndef AU_DISK_H
#define AU_DISK_H

#include "au_advect.h"
#include "au_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------- boundary constraints */

/* What a vertex may do during the flow. */
typedef enum au_disk_kind {
  AU_BC_FREE = 0,   /* interior vertex: moves freely in the plane */
  AU_BC_CIRCLE = 1, /* slides on the circle |p| = value (tangential velocity, radial projection) */
  AU_BC_XSIDE = 2,  /* slides on the vertical line x = value, y clamped to [lo, hi] */
  AU_BC_YSIDE = 3,  /* slides on the horizontal line y = value, x clamped to [lo, hi] */
  AU_BC_FIXED = 4   /* does not move */
} au_disk_kind;

/* Per-vertex constraints of a planar domain. Arrays are owned by the struct (au_disk_bc_free). */
typedef struct au_disk_bc {
  int nv;
  unsigned char *kind; /* kind [0..nv-1]: an au_disk_kind */
  double *value;       /* value [0..nv-1]: circle radius (> 0), or the fixed coordinate of a side */
  double lo, hi;       /* the clamp interval of side vertices (square: 0 and 1) */
} au_disk_bc;

/* Allocate constraints for nv vertices, all AU_BC_FREE. On success *out owns them.
 * Returns AU_OK, AU_E_ARG (nv <= 0), AU_E_NOMEM. */
au_status au_disk_bc_alloc(int nv, au_disk_bc **out);
/* Free and set *bc to NULL; NULL-safe. */
void au_disk_bc_free(au_disk_bc **bc);

/* The advection domain that applies bc (planar: spherical = 0, ctx = bc, which must outlive it).
 * constrain: zeroes z; circle vertices keep the tangential component of d; side vertices keep the
 * component along their side; fixed vertices get d = 0. retract: z = 0; circle vertices are scaled
 * radially onto their circle (| |p| - r | within rounding, ~1e-16 r); side vertices are put on their
 * line and clamped to [lo, hi]. */
au_advect_domain au_disk_bc_domain(const au_disk_bc *bc);

/* ---------------------------------------------------------------- initial maps */

/* How an initial map's interior was computed. */
typedef enum au_disk_init_method {
  AU_INIT_COTAN = 0,     /* harmonic with cotan weights (discrete conformal for this boundary) */
  AU_INIT_MEANVALUE = 1  /* harmonic with symmetrized mean-value weights: positive, so the map is a
                            bijection onto a convex domain (Tutte, Floater); used when cotan folds */
} au_disk_init_method;

/* Disk: the single boundary loop onto the unit circle by arc length (counter-clockwise, loop vertex 0
 * at angle 0), the interior harmonic (cotan; mean-value weights if cotan folds).
 * m, t: a mesh validated with loops 1 and its topology. P: out, nv x 3 (caller-allocated), z = 0;
 * unreferenced vertices get the origin. method: out, may be NULL.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_NUMERIC, AU_E_FOLD (even the positive
 * weights folded in floating point: msg says how many triangles). */
au_status au_disk_init(const au_mesh *m, const au_topo *t, double *P, au_disk_init_method *method, au_msg *msg);

/* Annulus: u harmonic with u = 0 on the inner loop and 1 on the outer one gives the conformal
 * modulus (Dirichlet energy E: ln(1/r) = 2 pi / E); its conjugate theta (harmonic, period 1 around
 * the annulus, computed with a jump across a dual path from loop to loop) gives the angle. The map
 * is p = rho(u) (cos 2 pi theta, sin 2 pi theta) with rho = r^(1-u); cotan weights first, symmetrized
 * mean-value weights if that folds.
 * outer: index of the loop in t that goes to the unit circle (0 or 1).
 * inner_radius: the inner circle's radius in (0, 1), or 0 for the conformal modulus's.
 * P: out, nv x 3. radius_out: out, the inner radius used; modulus_radius: out, the conformal
 * modulus's inner radius exp(-2 pi / E); method: out. The last three may be NULL.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_NUMERIC, AU_E_FOLD. */
au_status au_annulus_init(const au_mesh *m, const au_topo *t, int outer, double inner_radius, double *P,
                          double *radius_out, double *modulus_radius, au_disk_init_method *method, au_msg *msg);

/* Square corners chosen automatically: the most corner-like boundary vertex (smallest sum of surface
 * angles) goes to (0,0); the other three are the most corner-like vertices within an eighth of the
 * perimeter of the arc-length quarter points (a vertex whose angle sum is below 135 degrees), else
 * the vertex nearest the quarter point. corners: out [0..3], vertex indices in the loop's order
 * (counter-clockwise in the domain). Returns AU_OK, AU_E_ARG (fewer than 4 boundary vertices). */
au_status au_square_corners(const au_mesh *m, const au_topo *t, int corners[4], au_msg *msg);

/* Put four user-given corner vertices in the order they follow corners[0] along the boundary
 * (the first stays first). Returns AU_OK or AU_E_ARG (msg names a vertex that is not on the
 * boundary, or a repeated one). */
au_status au_square_order_corners(const au_topo *t, int corners[4], au_msg *msg);

/* Split the interior edges whose two endpoints lie on the same side of the square (a corner lies
 * on two sides): such an edge would be laid along the side and its triangles would degenerate or
 * fold (paper 4.1: triangles with three vertices on one side). Each split adds the edge's midpoint
 * as a new vertex after the original ones and replaces the edge's two faces by four: the first
 * keeps the face's index, the others are appended. Repeats until no such edge is left.
 * corners: [0..3] in loop order. *out: a new mesh (a plain copy if nothing was split; free with
 * au_mesh_free). nsplit: out, number of vertices added (may be NULL).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, or a topology error of the new mesh. */
au_status au_square_split(const au_mesh *m, const au_topo *t, const int corners[4], au_mesh **out, int *nsplit,
                          au_msg *msg);

/* Square: the boundary onto the unit square's sides by arc length between the corners (corners[0]
 * at (0,0), then (1,0), (1,1), (0,1)), the interior harmonic (cotan; mean-value if cotan folds).
 * The mesh must have no interior edge with both ends on one side (au_square_split).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_NUMERIC, AU_E_FOLD. */
au_status au_square_init(const au_mesh *m, const au_topo *t, const int corners[4], double *P,
                         au_disk_init_method *method, au_msg *msg);

/* ---------------------------------------------------------------- the maps */

typedef enum au_disk_boundary {
  AU_DISK_SLIDE = 0, /* boundary vertices slide along their circle or side (default) */
  AU_DISK_FIXED = 1  /* the initial boundary is kept (the paper's fixed boundary) */
} au_disk_boundary;

typedef struct au_disk_opts {
  au_advect_opts flow;       /* the advection's options; defaults: au_advect_opts_default() except
                                tol 3e-3 (vertex mean |log ratio|) and face_tol 1e-2 (face mean |r-1|) */
  au_disk_boundary boundary; /* default AU_DISK_SLIDE */
  double inner_radius;       /* annulus: inner radius in (0, 1), 0 for the conformal modulus's (default 0) */
  int outer_loop;            /* annulus: loop index in the topology for the outer circle, -1: the longer
                                loop (default -1) */
  int corners[4];            /* square: corner vertices, corners[0] at (0,0), then counter-clockwise in
                                loop order (au_square_order_corners); -1: chosen by au_square_corners
                                (default -1) */
} au_disk_opts;

au_disk_opts au_disk_opts_default(void);

typedef struct au_disk_report {
  double t_init;                  /* seconds in the initial map */
  double t_flow;                  /* seconds in the advection */
  au_disk_init_method init;       /* how the initial map was made */
  double inner_radius;            /* annulus: inner radius used */
  double modulus_radius;          /* annulus: inner radius of the conformal modulus */
  int outer_loop;                 /* annulus: loop index mapped to the unit circle */
  int corners[4];                 /* square: the corners used */
  au_advect_report flow;          /* steps, errors, step fractions */
} au_disk_report;

/* The disk map: initial map, then the flow with sliding (or fixed) boundary. The first vertex of the
 * boundary loop stays where the initial map put it (at (1, 0)): that removes the rotation, which
 * changes nothing else, from the flow's step system.
 * m, t: validated with loops 1. opts, rep may be NULL. P: out, nv x 3, z = 0, boundary on the unit
 * circle. P0: out, the initial map (nv x 3), may be NULL.
 * Returns AU_OK, AU_W_NOT_CONVERGED (valid, fold-free, tolerance not met), or an error of
 * au_disk_init / au_advect_run. */
au_status au_disk_map(const au_mesh *m, const au_topo *t, const au_disk_opts *opts, double *P, double *P0,
                      au_disk_report *rep, au_msg *msg);

/* The annulus map (m, t validated with loops 2): outer loop on the unit circle, inner loop on the
 * circle of radius rep->inner_radius, both sliding (the outer loop's first vertex held, as for the
 * disk). As au_disk_map otherwise. */
au_status au_annulus_map(const au_mesh *m, const au_topo *t, const au_disk_opts *opts, double *P, double *P0,
                         au_disk_report *rep, au_msg *msg);

/* The square map: m must already be split (au_square_split) for the corners in opts (or, with
 * corners -1, for the ones au_square_corners picks on m). Boundary vertices slide on their sides,
 * the corners stay at the square's corners. As au_disk_map otherwise. */
au_status au_square_map(const au_mesh *m, const au_topo *t, const au_disk_opts *opts, double *P, double *P0,
                        au_disk_report *rep, au_msg *msg);

/* ---------------------------------------------------------------- circle domains (au_circles.c) */

/* A circle of the circle domain: centre (cx, cy), radius r. */
typedef struct au_circle {
  double cx, cy, r;
} au_circle;

/* The circle-domain map of a genus-0 mesh with k >= 1 boundary loops: loop `outer` onto the unit
 * circle, every other loop onto a circle inside it (the unit disk with k - 1 round holes), equal area.
 * Boundary vertices slide along their circles; each hole's centre moves with its loop in the flow's
 * first moves (the translation that best fits the loop's tangential motion). A hole's radius is set
 * in the start from its prescribed area (au_circles_radii), as far as the start has room for it.
 * k = 1 is au_disk_map. outer: the loop index for the unit circle, -1 for the longest loop
 * (opts->outer_loop is ignored). circles: out [0..nloops-1], each loop's circle (may be NULL).
 * The rest as au_disk_map; rep->outer_loop is the outer loop. Returns AU_OK, AU_W_NOT_CONVERGED,
 * AU_E_ARG, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_NUMERIC, AU_E_FOLD (the start folded). */
au_status au_circles_map(const au_mesh *m, const au_topo *t, const au_disk_opts *opts, int outer, double *P, double *P0,
                         au_circle *circles, au_disk_report *rep, au_msg *msg);

/* The prescribed radii: hole l gets the area fraction cap_l / (surface area + sum of the holes' caps),
 * radius sqrt of it; the outer loop gets 1. radius: out [0..nloops-1]. */
void au_circles_radii(const au_mesh *m, const au_topo *t, int outer, double *radius);

#ifdef __cplusplus
}
#endif
#endif
