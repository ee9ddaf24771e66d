/* au_texture.h - equal-area spherical textures and equal-area sampling of a sphere map.
 *
 * Given a surface M (positions X) and a fold-free map P of it onto the unit sphere with the same
 * faces (au_sphere_map), this module
 *   - lays the sphere out in an equal-area projection (GeographicLib, au_geo.h): Lambert
 *     cylindrical (cea) or two Lambert azimuthal hemispheres side by side (laea), so every texel of
 *     an image stands for the same area of the sphere, and so, through an authalic map, of M;
 *   - gives the mesh per-corner texture coordinates in that layout (faces across the seam get their
 *     own copies, faces around a pole are split at the pole) and writes them as OBJ;
 *   - locates points on the sphere exactly in the map's triangles (exact orientation predicates;
 *     the test is the point-in-triangle test of the gnomonic chart) and interpolates per-vertex
 *     attributes of M with the barycentric coordinates of the piecewise linear map;
 *   - bakes attributes into texel grids, samples M on equal-area grids, measures the surface area of
 *     each grid cell's preimage, and draws pictures (PNG through libpng): a preview of the map
 *     coloured by area distortion with the paper's histograms, and a render of M with its texture.
 *
 * Conventions: texture coordinates (u, v) as in OBJ, v = 0 at the bottom of the image; images are
 * stored row-major with row 0 at the top, so texel (row r, column c) has its centre at
 * u = (c + 0.5)/W, v = 1 - (r + 0.5)/H. Longitude/latitude: lon = atan2(y, x), lat = asin(z). */
#ifndef AU_TEXTURE_H
#define AU_TEXTURE_H

#include "au_mesh.h"
#include "au_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The texture, location, sampling and picture functions are public: include/authalic.h declares them. */

#ifdef __cplusplus
}
#endif
#endif
