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

typedef enum au_domain { AU_DOMAIN_SPHERE = 0, AU_DOMAIN_PLANE = 1 } au_domain;

typedef struct au_metrics {
  int nv, nf;
  au_domain domain;                         /* the domain the map was measured on */
  double upsilon_mean_abs, upsilon_std, upsilon_max_abs, upsilon_p95_abs, upsilon_p99_abs;
  double upsilon_wmean_abs;                 /* |Upsilon| weighted by surface area */
  double lambda_mean, lambda_std, lambda_max, lambda_p95;
  double logr_mean_abs;                     /* mean |ln r| per face */
  double r_std, r_mean_abs_dev, r_cv;       /* std of r, mean |r-1|, std/mean of r */
  double authalic_energy;                   /* sum |domain share - surface share| */
  double vertex_logr_mean_abs, vertex_logr_max_abs; /* barycentric vertex cells, |ln ratio| */
  double angle_diff_mean_deg;               /* mean |domain angle - surface angle| over corners, degrees */
  /* sphere only (zero otherwise): same statistics with exact spherical triangle areas */
  double sph_r_mean_abs_dev, sph_r_cv, sph_vertex_logr_mean_abs;
  double sphere_radius_max_dev;             /* max | |p| - 1 | over referenced vertices */
  /* Faces whose chord area cannot come down to their share with their longest edge as it is
   * (au_dec_sphere_chord_floor above the share), and the sum of those floors' excess over the shares
   * as a fraction of the domain's total: the part of the area error the map's long, thin triangles
   * fix (a finer mesh there, or shorter edges, lowers it). */
  int chord_floor_faces;
  double chord_floor_excess;
  int folds;                                /* faces with orientation <= 0 (sphere: triple product) */
  int excluded;                             /* faces left out as degenerate */
  double surface_area, domain_area;         /* totals (domain: sum of chordal/planar triangles) */
} au_metrics;

/* Compute the metrics of the map X -> P.
 * X: surface positions, nv x 3 row-major. P: domain positions, nv x 3 (planar domains: z ignored).
 * F: nf x 3 faces. ups, lam: optional per-face outputs [0..nf-1] (NaN for excluded faces); may be NULL.
 * Returns AU_OK, AU_E_ARG (NULL arrays, nf <= 0, zero total area), AU_E_NOMEM. */
au_status au_metrics_compute(int nv, int nf, const double *X, const double *P, const int *F, au_domain domain,
                             au_metrics *out, double *ups, double *lam);

/* Per-vertex areal distortion of the map X -> P, as HCP's convention (and param-eval's vertex cells):
 * out[i] = log2((vd_i / sum vd) / (vs_i / sum vs)), where vd_i and vs_i are the barycentric vertex
 * areas (a third of each incident triangle's area) on the domain and on the surface. On the sphere
 * the domain triangles are the chord triangles (what param-eval measures), so the values do not
 * depend on the sphere's radius; planar domains drop z. Positive where the map gives a vertex more
 * than its share. A vertex whose cell is degenerate on either side (at most 1e-14 of the total, e.g.
 * a vertex no face uses) gets 0 and is counted in *ndegenerate.
 * X, P: nv x 3 row-major; F: nf x 3. out: caller-allocated, nv doubles. ndegenerate may be NULL.
 * Returns AU_OK, AU_E_ARG (NULL arrays, nv or nf <= 0, an index out of range, zero total area),
 * AU_E_NOMEM. */
au_status au_metrics_vertex_distortion(int nv, int nf, const double *X, const double *P, const int *F, au_domain domain,
                                       double *out, int *ndegenerate);

#ifdef __cplusplus
}
#endif
#endif
