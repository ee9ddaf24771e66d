/* au_octahedral.c - the equal-area octahedral map of the unit sphere onto the square [-1, 1]^2.
 *
 * Praun & Hoppe, "Spherical parametrization and remeshing" (SIGGRAPH 2003), and Clarberg, "Fast
 * equal-area mapping of the (hemi)sphere using SIMD" (J. Graphics Tools 13(3), 2008). Written here
 * from the formulas, derived as follows. In the octant x, y, z >= 0, take the square's triangle
 * u, v >= 0, u + v <= 1, with d = u + v and t = v / d. Sending the segment u + v = d to the circle of
 * latitude z = 1 - d^2 and t linearly to the longitude phi = (pi/2) t makes the map equal-area: the
 * square's element du dv = d dd dt, the sphere's dz dphi = 2d dd (pi/2) dt = pi d dd dt, a constant
 * factor pi (the square's area 4 is the sphere's 4 pi). The other northern octants follow by the
 * signs of u and v; the southern hemisphere fills the square's four corner triangles
 * |u| + |v| >= 1, each the mirror image of its northern neighbour across the line |u| + |v| = 1
 * (z negated), so the map is continuous across the equator and keeps its orientation everywhere
 * (two reflections). The square's edges are folded at their midpoints: (1, v) and (1, -v) are the
 * same point (on the meridian y = 0, x > 0, z < 0), and likewise on the other three edges; the
 * four corners are the south pole. The map therefore continues past the square by the half turns
 * about the edge midpoints, (u, v) -> (2 - u, -v) across u = 1 and so on: au__oct_wrap brings a
 * point of that continuation back into the square, which is how the texture's gutter and
 * neighbouring texels across an edge find their sphere points (mip-map friendly).
 * No poles: the map is smooth inside every octant; its only creases are the octant boundaries. */
#include <math.h>

#include "au_texture_internal.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

void au__oct_forward(const double p[3], double uv[2]) {
  double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  double x = p[0] / r, y = p[1] / r, z = p[2] / r;
  /* 1 - |z| loses all digits near the poles; x^2 + y^2 = (1 - |z|)(1 + |z|) keeps them. */
  double h2 = x * x + y * y;
  double d = sqrt(h2 / (1 + fabs(z)));
  double t = (x == 0 && y == 0) ? 0.0 : atan2(fabs(y), fabs(x)) / (M_PI / 2);
  double a = d * (1 - t), b = d * t;
  if (z < 0) {
    double a2 = 1 - b, b2 = 1 - a;
    a = a2, b = b2;
  }
  uv[0] = x < 0 ? -a : a;
  uv[1] = y < 0 ? -b : b;
}

void au__oct_wrap(double uv[2]) {
  /* Each half turn about an edge midpoint brings the point closer to the square; a point within one
   * square's width of it needs at most two (one per axis). */
  for (int k = 0; k < 4; k++) {
    if (uv[0] > 1) uv[0] = 2 - uv[0], uv[1] = -uv[1];
    else if (uv[0] < -1) uv[0] = -2 - uv[0], uv[1] = -uv[1];
    else if (uv[1] > 1) uv[1] = 2 - uv[1], uv[0] = -uv[0];
    else if (uv[1] < -1) uv[1] = -2 - uv[1], uv[0] = -uv[0];
    else break;
  }
}

void au__oct_inverse(const double uv_in[2], double p[3]) {
  double uv[2] = {uv_in[0], uv_in[1]};
  au__oct_wrap(uv);
  double a = fabs(uv[0]), b = fabs(uv[1]);
  int south = a + b > 1;
  if (south) {
    double a2 = 1 - b, b2 = 1 - a;
    a = a2, b = b2;
  }
  double d = a + b;
  double t = d > 0 ? b / d : 0.0, phi = (M_PI / 2) * t;
  /* |z| = 1 - d^2 and the radius of the circle of latitude sqrt(1 - z^2) = d sqrt(2 - d^2). */
  double z = 1 - d * d, h = d * sqrt(fmax(0.0, 2 - d * d));
  double x = h * cos(phi), y = h * sin(phi);
  p[0] = uv[0] < 0 ? -x : x;
  p[1] = uv[1] < 0 ? -y : y;
  p[2] = south ? -z : z;
}

/* The continuation copies of a square point near the edges: the identity, the half turns about the
 * four edge midpoints and the translations by (+-2, +-2) (two half turns). */
void au__oct_copy(const double uv[2], int k, double out[2]) {
  static const double T[9][4] = {/* sign of u, sign of v, offset of u, offset of v */
                                  {1, 1, 0, 0},   {-1, -1, 2, 0}, {-1, -1, -2, 0}, {-1, -1, 0, 2}, {-1, -1, 0, -2},
                                  {1, 1, 2, 2},   {1, 1, 2, -2},  {1, 1, -2, 2},   {1, 1, -2, -2}};
  out[0] = T[k][0] * uv[0] + T[k][2];
  out[1] = T[k][1] * uv[1] + T[k][3];
}
