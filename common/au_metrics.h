/* au_metrics.h - distortion of a parameterization (paper eq. 23) and area-ratio statistics.
 *
 * Definitions follow ../shared/tools/param-eval exactly, so the two agree to 1e-9:
 * per face, J is the affine map from the domain triangle (the chordal triangle on the sphere) to the
 * surface triangle, the surface scaled so its total area equals the domain triangles' total;
 * gmax >= gmin its singular values; Upsilon = ln(gmax*gmin) (area), Lambda = ln(gmax/gmin) (angle).
 * r = (domain area share)/(surface area share) per face. Faces whose domain or surface area is
 * <= 1e-14 of the total are excluded from the statistics (counted in `excluded`). */
#ifndef AU_METRICS_H
#define AU_METRICS_H

#include "au_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* au_domain, au_metrics and au_metrics_compute are public (include/authalic.h). */

/* au_metrics_vertex_distortion is public (include/authalic.h). */

/* au_metrics_compute of a map given by per-corner plane coordinates (a torus map's vt, Ft): the
 * mesh (X, F, nv vertices) cut along the seams, one vertex per vt row (row i < nv is vertex i's, the
 * others copies), so every face is measured by its own lifted triangle, as param-eval measures a
 * map given by vt. ups, lam: as au_metrics_compute (may be NULL). Returns AU_OK, AU_E_ARG,
 * AU_E_NOMEM. */
au_status au__metrics_vt(int nv, int nf, const double *X, const int *F, int nvt, const double *vt, const int *Ft,
                         au_metrics *out, double *ups, double *lam);

/* The share of the surface whose barycentric vertex cells have under 1/e of their share in the map P
 * (its straight triangles: chord triangles on the sphere, plane triangles with z 0), and how many
 * vertices those are (*count): the squeezed protrusions a map leaves (tpose; docs/sphere.md).
 * Unlike au_metrics_vertex_distortion it counts cells of any size, the degenerate ones too: those are
 * the most squeezed. Returns -1 out of memory. */
double au__metrics_squeezed(int nv, int nf, const double *X, const double *P, const int *F, int *count);

#ifdef __cplusplus
}
#endif
#endif
