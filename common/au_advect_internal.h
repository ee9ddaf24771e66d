/* au_advect_internal.h - cross-file internals of the advection: the exact Gauss-Newton step. */
#ifndef AU_ADVECT_INTERNAL_H
#define AU_ADVECT_INTERNAL_H

#include "au_advect.h"

#include <stddef.h>

/* Corner k of face f at positions P under per-corner shifts (au_advect_domain.shift): P's own row when
 * shift is NULL, so that the arithmetic of every unshifted domain stays exactly as it was; else buf,
 * filled with P[F[3f+k]] + shift. */
static inline const double *au__corner(const double *P, const int *F, const double *shift, int f, int k, double *buf) {
  const double *p = P + 3 * F[3 * f + k];
  if (!shift) return p;
  const double *s = shift + 9 * (size_t)f + 3 * k;
  buf[0] = p[0] + s[0], buf[1] = p[1] + s[1], buf[2] = p[2] + s[2];
  return buf;
}

typedef struct au_gn au_gn;

/* Prepare the Gauss-Newton step for the mesh's connectivity (pattern analysis done once).
 * Returns AU_OK, AU_E_NOMEM, AU_E_NUMERIC. */
/* faces: 0 for the vertex cells, 1 for the triangles as cells. */
au_status au__gn_create(const au_mesh *m, const au_topo *t, int faces, au_gn **out, au_msg *msg);

/* The displacement D [0..3nv-1] of least kinetic energy sum_j W_j^-1 |u_j|^2 whose first-order change of
 * the barycentric vertex areas at P is dA [0..nv-1]: u = W D^T g with (D W D^T + reg) g = dA, D the exact
 * derivative of the cell areas with respect to the (constrained) vertex positions.
 * W [0..nv-1] > 0. Returns AU_OK, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_NUMERIC. */
au_status au__gn_step(au_gn *gn, const au_advect_domain *dom, const double *P, const double *W, const double *dA,
                      double damping, double *D, au_msg *msg);

void au__gn_free(au_gn **gn);

/* The least-shear area step (au_lm.c). */
typedef struct au_lm au_lm;

/* Prepare for the mesh's connectivity (the 2nv x 2nv pattern is analyzed once).
 * Returns AU_OK, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au__lm_create(const au_mesh *m, const au_topo *t, au_lm **out, au_msg *msg);

/* The displacement D [0..3nv-1] (in the directions the domain allows at each vertex) whose first-order
 * change of the face areas at P is closest to dAf [0..nf-1] in sum_f w_f ((change_f - dAf_f) / A_f)^2,
 * plus alpha times the w-weighted shear energy of the motion and eps times its kinetic energy (see
 * au_lm.c). wf [0..nf-1] > 0: face weights (e.g. the target areas); NULL: the current areas A_f.
 * alpha >= 0, eps > 0. sphere_areas (spherical domains only): A_f and its change are the spherical
 * triangle's (au_dec_sphere_area) and the shear is measured in the tangent plane at the centroid
 * direction; 0: the chord triangle's. restore in [0, 1]: the shear term aims at that fraction of the
 * linear motion taking each triangle to the similar copy of its surface triangle closest to it (0:
 * at no shear). lantern >= 0 raises a face's restoring fraction to min(1, restore (1 + lantern rho)),
 * rho = l^3 / (16 w_f) with l its longest chord edge (needs wf; 0: off). Returns AU_OK, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_NUMERIC. */
au_status au__lm_step(au_lm *lm, const au_advect_domain *dom, const double *P, const double *dAf, const double *wf,
                      double alpha, double eps, int sphere_areas, double restore, double lantern, double *D,
                      au_msg *msg);

void au__lm_free(au_lm **lm);

/* The allowed directions of vertex i at p under the domain's constraint: B [0..5], two orthonormal
 * vectors, or fewer (zero rows) where the domain allows fewer (au_lm.c). */
void au__allowed_basis(const au_advect_domain *dom, int i, const double *p, double *B);

/* The angle step (au_ang.c): after the flow, towards the map of least Dirichlet energy whose vertex
 * cells have their target areas, with the triangles' areas held softly. */
typedef struct au_ang au_ang;

/* Prepare for the mesh's connectivity (the 2-ring pattern of the 2nv x 2nv system, analyzed once).
 * Returns AU_OK, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au__ang_create(const au_mesh *m, au_ang **out, au_msg *msg);

/* The displacement D [0..3nv-1] (allowed directions) of one Gauss-Newton step at P for
 * E_D + beta * faces + gamma * cells + mu * trust region (see au_ang.c), with the chord (flat) triangle
 * areas measured against the target areas T [0..nf-1] and the vertex cells against TV [0..nv-1], both
 * in the domain's units. beta, gamma >= 0, mu > 0. Returns AU_OK, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_NUMERIC. */
au_status au__ang_step(au_ang *a, const au_advect_domain *dom, const double *P, const double *T, const double *TV,
                       double beta, double gamma, double mu, double *D, au_msg *msg);

void au__ang_free(au_ang **a);

#endif
