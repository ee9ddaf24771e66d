/* au_geo.h - the C face of the GeographicLib bridge (au_geographiclib.cpp): equal-area and gnomonic
 * projections of the unit sphere, and exact areas of spherical polygons.
 *
 * Every function works on the unit sphere (radius 1, flattening 0), takes and returns angles in
 * degrees as GeographicLib does, processes n points per call so the C++ objects are built once per
 * batch, and turns every C++ exception into a status (std::bad_alloc into AU_E_NOMEM, any other into
 * AU_E_NUMERIC). Nothing here keeps state between calls. */
#ifndef AU_GEO_H
#define AU_GEO_H

#include "au_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The equal-area projections, all from GeographicLib::AlbersEqualArea on the unit sphere with
 * k0 = 1 and central meridian 0:
 *   AU_GEO_CEA:        stdlat 0, Lambert cylindrical equal-area: x = lon (radians), y = sin(lat);
 *                      the sphere fills [-pi, pi] x [-1, 1].
 *   AU_GEO_LAEA_NORTH: stdlat 90, Lambert azimuthal equal-area centred on the north pole: the
 *                      northern hemisphere fills the disk of radius sqrt(2), the whole sphere but
 *                      the south pole the open disk of radius 2.
 *   AU_GEO_LAEA_SOUTH: the same centred on the south pole: the AU_GEO_LAEA_NORTH chart of the
 *                      point turned half a turn about the x axis, (lat, lon) -> (-lat, -lon), so
 *                      both charts keep the orientation seen from outside the sphere. */
typedef enum au_geo_aea { AU_GEO_CEA = 0, AU_GEO_LAEA_NORTH = 1, AU_GEO_LAEA_SOUTH = 2 } au_geo_aea;

/* Forward projection of n points. lat, lon: [0..n-1] degrees (lat in [-90, 90]). x, y: out
 * [0..n-1], projection units of the unit sphere (area is preserved: the image of a region has the
 * region's area in steradians). Returns AU_OK, AU_E_ARG (NULL array, n < 0, unknown kind, a
 * latitude outside [-90, 90] or non-finite input), AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_geo_aea_forward(au_geo_aea kind, int n, const double *lat, const double *lon, double *x, double *y,
                             au_msg *msg);

/* Inverse projection of n points. x, y: [0..n-1]. lat, lon: out [0..n-1] degrees, lon in
 * [-180, 180]. Points outside the projection's image (|y| > 1 for CEA, radius > 2 for LAEA) are not
 * valid input: GeographicLib returns the nearest pole for them; callers test the range first.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_geo_aea_inverse(au_geo_aea kind, int n, const double *x, const double *y, double *lat, double *lon,
                             au_msg *msg);

/* Gnomonic (central) projection centred at (lat0, lon0): great circles become straight lines, so a
 * spherical triangle within 90 degrees of the centre becomes a planar triangle. lat, lon: [0..n-1]
 * degrees; x, y: out [0..n-1]; points 90 degrees or more from the centre get NaN.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_geo_gnomonic_forward(double lat0, double lon0, int n, const double *lat, const double *lon, double *x,
                                  double *y, au_msg *msg);

/* Inverse gnomonic projection centred at (lat0, lon0). Returns AU_OK, AU_E_ARG, AU_E_NOMEM,
 * AU_E_NUMERIC. */
au_status au_geo_gnomonic_inverse(double lat0, double lon0, int n, const double *x, const double *y, double *lat,
                                  double *lon, au_msg *msg);

/* Area of the spherical polygon with n >= 3 vertices lat, lon (degrees) joined by great-circle arcs
 * (GeographicLib::PolygonArea on the unit sphere). *area: out, steradians, positive for
 * counter-clockwise traversal seen from outside the sphere, in (-2 pi, 2 pi]. Returns AU_OK,
 * AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_geo_polygon_area(int n, const double *lat, const double *lon, double *area, au_msg *msg);

#ifdef __cplusplus
}
#endif
#endif
