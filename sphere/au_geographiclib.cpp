// au_geographiclib.cpp - the GeographicLib bridge: projections and polygon areas on the unit sphere
// behind the extern "C" API of au_geo.h. Every exception is caught and becomes a status.
#include <GeographicLib/AlbersEqualArea.hpp>
#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/Gnomonic.hpp>
#include <GeographicLib/PolygonArea.hpp>

#include <cmath>
#include <exception>
#include <new>

#include "au_geo.h"

using GeographicLib::AlbersEqualArea;
using GeographicLib::Geodesic;
using GeographicLib::Gnomonic;
using GeographicLib::PolygonArea;

namespace {

// The status of an exception caught at the C boundary, with its text in msg.
au_status from_exception(au_msg *msg, const char *where) {
  try {
    throw;
  } catch (const std::bad_alloc &) {
    return au_msg_set(msg, AU_E_NOMEM, "%s: out of memory", where);
  } catch (const std::exception &e) {
    return au_msg_set(msg, AU_E_NUMERIC, "%s: GeographicLib: %s", where, e.what());
  } catch (...) {
    return au_msg_set(msg, AU_E_NUMERIC, "%s: unknown C++ exception", where);
  }
}

// The southern chart is the northern one of the point turned half a turn about the x axis,
// (lat, lon) -> (-lat, -lon): a rotation, so orientation is kept. (On the sphere,
// AlbersEqualArea(1, 0, -90, 1) measured here still puts the north pole at the origin, with y
// mirrored, so it is not the chart centred on the south pole.)
double stdlat_of(au_geo_aea kind) { return kind == AU_GEO_CEA ? 0.0 : 90.0; }
double flip_of(au_geo_aea kind) { return kind == AU_GEO_LAEA_SOUTH ? -1.0 : 1.0; }

bool kind_ok(au_geo_aea kind) {
  return kind == AU_GEO_CEA || kind == AU_GEO_LAEA_NORTH || kind == AU_GEO_LAEA_SOUTH;
}

}  // namespace

extern "C" au_status au_geo_aea_forward(au_geo_aea kind, int n, const double *lat, const double *lon, double *x,
                                        double *y, au_msg *msg) {
  if (n < 0 || (n > 0 && (!lat || !lon || !x || !y)) || !kind_ok(kind))
    return au_msg_set(msg, AU_E_ARG, "au_geo_aea_forward: bad arguments");
  try {
    const AlbersEqualArea p(1.0, 0.0, stdlat_of(kind), 1.0);
    for (int i = 0; i < n; i++) {
      if (!std::isfinite(lat[i]) || !std::isfinite(lon[i]) || std::fabs(lat[i]) > 90.0)
        return au_msg_set(msg, AU_E_ARG, "au_geo_aea_forward: point %d (lat %g, lon %g) is not a valid position", i,
                          lat[i], lon[i]);
      const double sg = flip_of(kind);
      p.Forward(0.0, sg * lat[i], sg * lon[i], x[i], y[i]);
    }
  } catch (...) {
    return from_exception(msg, "au_geo_aea_forward");
  }
  return AU_OK;
}

extern "C" au_status au_geo_aea_inverse(au_geo_aea kind, int n, const double *x, const double *y, double *lat,
                                        double *lon, au_msg *msg) {
  if (n < 0 || (n > 0 && (!lat || !lon || !x || !y)) || !kind_ok(kind))
    return au_msg_set(msg, AU_E_ARG, "au_geo_aea_inverse: bad arguments");
  try {
    const AlbersEqualArea p(1.0, 0.0, stdlat_of(kind), 1.0);
    for (int i = 0; i < n; i++) {
      if (!std::isfinite(x[i]) || !std::isfinite(y[i]))
        return au_msg_set(msg, AU_E_ARG, "au_geo_aea_inverse: point %d is not finite", i);
      p.Reverse(0.0, x[i], y[i], lat[i], lon[i]);
      if (kind == AU_GEO_LAEA_SOUTH) {
        lat[i] = -lat[i];
        lon[i] = lon[i] == 180.0 ? 180.0 : -lon[i];
      }
    }
  } catch (...) {
    return from_exception(msg, "au_geo_aea_inverse");
  }
  return AU_OK;
}

extern "C" au_status au_geo_gnomonic_forward(double lat0, double lon0, int n, const double *lat, const double *lon,
                                             double *x, double *y, au_msg *msg) {
  if (n < 0 || (n > 0 && (!lat || !lon || !x || !y)) || !(std::fabs(lat0) <= 90.0) || !std::isfinite(lon0))
    return au_msg_set(msg, AU_E_ARG, "au_geo_gnomonic_forward: bad arguments");
  try {
    const Geodesic g(1.0, 0.0);
    const Gnomonic p(g);
    for (int i = 0; i < n; i++) p.Forward(lat0, lon0, lat[i], lon[i], x[i], y[i]);
  } catch (...) {
    return from_exception(msg, "au_geo_gnomonic_forward");
  }
  return AU_OK;
}

extern "C" au_status au_geo_gnomonic_inverse(double lat0, double lon0, int n, const double *x, const double *y,
                                             double *lat, double *lon, au_msg *msg) {
  if (n < 0 || (n > 0 && (!lat || !lon || !x || !y)) || !(std::fabs(lat0) <= 90.0) || !std::isfinite(lon0))
    return au_msg_set(msg, AU_E_ARG, "au_geo_gnomonic_inverse: bad arguments");
  try {
    const Geodesic g(1.0, 0.0);
    const Gnomonic p(g);
    for (int i = 0; i < n; i++) p.Reverse(lat0, lon0, x[i], y[i], lat[i], lon[i]);
  } catch (...) {
    return from_exception(msg, "au_geo_gnomonic_inverse");
  }
  return AU_OK;
}

extern "C" au_status au_geo_polygon_area(int n, const double *lat, const double *lon, double *area, au_msg *msg) {
  if (n < 3 || !lat || !lon || !area) return au_msg_set(msg, AU_E_ARG, "au_geo_polygon_area: bad arguments");
  try {
    const Geodesic g(1.0, 0.0);
    PolygonArea poly(g);
    for (int i = 0; i < n; i++) {
      if (!std::isfinite(lat[i]) || !std::isfinite(lon[i]) || std::fabs(lat[i]) > 90.0)
        return au_msg_set(msg, AU_E_ARG, "au_geo_polygon_area: vertex %d is not a valid position", i);
      poly.AddPoint(lat[i], lon[i]);
    }
    double perimeter = 0, a = 0;
    poly.Compute(false, true, perimeter, a);
    *area = a;
  } catch (...) {
    return from_exception(msg, "au_geo_polygon_area");
  }
  return AU_OK;
}
