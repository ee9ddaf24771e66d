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

/* ---------------------------------------------------------------- layouts */

typedef enum au_tex_proj {
  AU_TEX_CEA = 0,  /* Lambert cylindrical equal-area: u = (lon + pi)/(2 pi), v = (sin lat + 1)/2; the
                      seam is the meridian lon = +-pi, the poles are the top and bottom rows */
  AU_TEX_LAEA = 1  /* two Lambert azimuthal equal-area charts: the northern hemisphere centred in the
                      left half of the image, the southern in the right half; each chart is a square
                      of half side `half` (projection units) around its pole, so the ring between the
                      equator (radius sqrt 2) and the square holds the continuation of the other
                      hemisphere, which faces across the equator use */
} au_tex_proj;

typedef struct au_tex_layout {
  au_tex_proj proj;
  double half; /* laea: half side of each chart, in [sqrt 2, 2]; set by au_tex_coords so that every
                  face fits in its chart. cea: ignored. */
} au_tex_layout;

/* The layout's default: cea; laea with half = 1.5. */
au_tex_layout au_tex_layout_default(au_tex_proj proj);

/* Texture coordinates -> points on the unit sphere, n points.
 * uv: [0..2n-1] (u, v) pairs. p: out [0..3n-1] unit vectors. valid: out [0..n-1] (may be NULL):
 * 1 where (u, v) is the image of a point of the sphere (cea: 0 <= v <= 1, u taken modulo 1;
 * laea: inside the chart of radius 2), else 0 and p = (0, 0, 0).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_tex_to_sphere(const au_tex_layout *lay, int n, const double *uv, double *p, unsigned char *valid,
                           au_msg *msg);

/* Points on the sphere -> texture coordinates in the layout's primary chart (cea: u in [0, 1);
 * laea: the chart of the point's own hemisphere, z >= 0 north). p: [0..3n-1], need not be unit
 * (normalized here; a zero vector is AU_E_ARG). uv: out [0..2n-1].
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_tex_from_sphere(const au_tex_layout *lay, int n, const double *p, double *uv, au_msg *msg);

/* Longitude and latitude in degrees of n points p [0..3n-1] into lonlat [0..2n-1] (lon, lat).
 * At the poles lon is 0. Returns AU_OK, AU_E_ARG. */
au_status au_tex_lonlat(int n, const double *p, double *lonlat);

/* ---------------------------------------------------------------- exact location on the sphere */

/* Exact sign of det[a b c] = a . (b x c) for double vectors: +1, 0 or -1. A floating-point filter
 * decides almost always; otherwise the determinant is expanded exactly (error-free products and
 * sums). On the sphere, +1 says c lies left of the great circle from a to b. */
int au_sph_orient(const double a[3], const double b[3], const double c[3]);

/* A point-location structure over the triangles of a sphere map (a cube-map grid of buckets; each
 * bucket lists the triangles whose gnomonic image meets it). Read-only after building. */
typedef struct au_locator au_locator;

/* Build the locator of P (nv x 3, unit vectors) with faces F (nf x 3), a fold-free map: the
 * triangles share one orientation, det[a b c] > 0, or all < 0 (a mesh oriented inwards, or a
 * mirrored map; the locator then works on the reversed triangles and says so in no other way).
 * Triangles against the majority (folds) are still indexed.
 * On success *out owns the locator (free with au_locator_free).
 * Returns AU_OK, AU_E_ARG (NULL arrays, nv < 3, nf < 1, bad index), AU_E_NOMEM. */
au_status au_locator_build(int nv, const double *P, int nf, const int *F, au_locator **out, au_msg *msg);
/* Free the locator and set *loc to NULL; NULL-safe. */
void au_locator_free(au_locator **loc);

/* The triangle that contains the point p (any nonzero vector; its ray from the centre is what
 * counts), decided with exact predicates: p is in triangle (a, b, c) when det[a b p], det[b c p] and
 * det[c a p] are all >= 0 (the same test as in a gnomonic chart, where the triangle is flat).
 * Points on shared edges or vertices belong to the first triangle found. bary: out (may be NULL),
 * the barycentric coordinates of the ray's crossing of the flat triangle (a, b, c), >= 0, sum 1;
 * they are the coordinates of the piecewise linear map, so sum(bary_k X[F[f,k]]) is p's preimage.
 * hint: in/out (may be NULL): a face to try first; set to the answer. Returns the face index, or -1
 * when no triangle contains p (only possible when the map does not cover the sphere). */
int au_locator_find(const au_locator *loc, const double p[3], int *hint, double bary[3]);

/* ---------------------------------------------------------------- texture coordinates */

/* A mesh with per-corner texture coordinates: the input's vertices first, in order, then the
 * vertices added at the poles (cea only); the input's faces in order, a face split at a pole keeps
 * its index for its first part and appends the other two. */
typedef struct au_tex_mesh {
  int nv, nf;         /* vertices and faces after the pole and edge splits */
  int nv_in, nf_in;   /* the input's counts (vertices [0, nv_in) and faces [0, nf_in) are the input's) */
  double *X;          /* X [0..3*nv-1]: positions on the surface (added vertices interpolated) */
  double *P;          /* P [0..3*nv-1]: positions on the sphere */
  int *F;             /* F [0..3*nf-1]: faces */
  int *src_face;      /* src_face [0..nf-1]: the input face each face comes from */
  int nvt;            /* number of distinct texture coordinates */
  double *vt;         /* vt [0..2*nvt-1]: (u, v); cea: u may leave [0, 1] by less than a face's width
                         on faces across the seam (sample with u wrapped, "repeat") */
  int *Ft;            /* Ft [0..3*nf-1]: texture coordinate of each corner */
  double *lonlat;     /* lonlat [0..2*nv-1]: longitude, latitude in degrees of P */
  au_tex_layout layout; /* the layout the coordinates refer to (laea: half as fitted) */
  int seam_faces;     /* faces whose corners were shifted across the seam (cea) */
  int pole_splits;    /* faces split at a pole (cea, 0..2) */
  int pole_vertices;  /* input vertices lying on a pole (their corners get one vt per face) */
  int edge_splits;    /* cea: edges split because a face on them came out flipped in (u, v) with
                         straight edges (slivers, faces near a pole); their midpoints are added */
} au_tex_mesh;

/* Compute texture coordinates of the map P of m in the projection proj.
 * m: the surface (nv, nf, X, F). P: nv x 3 unit vectors, the map, fold-free.
 * On success *out owns the result (free with au_tex_mesh_free).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC, AU_E_FOLD (a pole fell in no triangle). */
au_status au_tex_coords(const au_mesh *m, const double *P, au_tex_proj proj, au_tex_mesh **out, au_msg *msg);
void au_tex_mesh_free(au_tex_mesh **t);

/* Write t as OBJ: `v` surface positions, `vt`, `f v/vt ...`, after a comment header naming the
 * layout. Written to a temporary file beside path and renamed into place.
 * mtl_name: when not NULL, a `mtllib` line naming it and `usemtl authalic` are written (the caller
 * writes the .mtl file). Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO. */
au_status au_tex_write_obj(const char *path, const au_tex_mesh *t, const char *mtl_name, au_msg *msg);

/* ---------------------------------------------------------------- baking and sampling */

/* For every texel of a W x H image in layout lay, the face of the map containing the texel
 * centre's point on the sphere and its barycentric coordinates. face: out [0..W*H-1] (-1 where the
 * texel has no point: laea outside radius 2, or no triangle found); bary: out [0..3*W*H-1] (may be
 * NULL). Rows top to bottom. Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_tex_locate_texels(const au_tex_layout *lay, const au_locator *loc, int W, int H, int *face,
                               double *bary, au_msg *msg);

/* Interpolate a per-vertex attribute at located points: out[i*k + j] = sum_c bary[3i+c] *
 * A[F[3 face[i] + c]*k + j], NaN where face[i] < 0. n points, k components.
 * Returns AU_OK, AU_E_ARG. */
au_status au_tex_interpolate(int n, const int *face, const double *bary, const int *F, int k, const double *A,
                             double *out);

/* Area-weighted vertex normals of the surface: N out [0..3*nv-1], unit (0 for unreferenced).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM. */
au_status au_tex_vertex_normals(const au_mesh *m, double *N);

/* The surface area of the preimage of every cell of the W x H cea grid (the grid of `authalic
 * sample`; every cell covers 4 pi/(W H) of the sphere), the surface scaled to total area 4 pi so
 * an exact authalic map gives every cell the same value. Each cell is integrated with sub x sub
 * equal-area sub-cells; inside a face the density is exact (the flat triangle's area over its
 * central projection's). m: the surface; P: its map. area: out [0..W*H-1], rows top to bottom.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_tex_cell_areas(const au_mesh *m, const double *P, const au_locator *loc, int W, int H, int sub,
                            double *area, au_msg *msg);

/* ---------------------------------------------------------------- pictures */

/* Write an 8-bit RGB image (W x H, rgb [0..3*W*H-1], rows top to bottom) as PNG, atomically.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO. */
au_status au_png_write(const char *path, int W, int H, const unsigned char *rgb, au_msg *msg);
/* Read an 8-bit RGB or RGBA PNG (alpha dropped, grey expanded). On success *rgb is malloc'ed
 * (3*W*H bytes) and the caller frees it. Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO, AU_E_FORMAT. */
au_status au_png_read(const char *path, int *W, int *H, unsigned char **rgb, au_msg *msg);

/* Colour maps: t in [0, 1] (clamped; NaN gives grey) to RGB. */
void au_cmap_viridis(double t, unsigned char rgb[3]);
/* Diverging blue - white - dark red, t = 0.5 white. */
void au_cmap_diverging(double t, unsigned char rgb[3]);

/* The preview picture of a sphere map: the sphere seen from +z and from -z (orthographic, the
 * hemispheres side by side), faces coloured by Upsilon = ln(surface share / sphere share) (red:
 * the surface is squeezed on the sphere, blue: stretched) over [-range, range], and below them the
 * histograms of Upsilon (dark red) and Lambda (blue) as in the paper's figures, each over its
 * data's 99th percentile (|Upsilon|: symmetric), the ends marked. m: the surface; P: its map;
 * size: width in pixels (>= 200), the height size/2 + 40 + size/4. range: the colour scale's end,
 * fixed so pictures of different maps compare; <= 0 gives 0.5 (a factor e^0.5 = 1.65 in area).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO, AU_E_NUMERIC. */
au_status au_tex_preview(const char *path, const au_mesh *m, const double *P, int size, double range, au_msg *msg);

/* Render the surface of t with the texture image img (tw x th RGB) through t's texture
 * coordinates (u wrapped, bilinear), orthographic and Lambert-shaded, from two opposite viewpoints
 * side by side: from direction view (a 3-vector, need not be unit) and from -view. size: height of
 * the picture in pixels (>= 64); width 2*size. mark_seam: 1 tints the cea faces whose coordinates
 * cross the seam red (to show the texture runs on through them), 0 plain.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO. */
au_status au_tex_render(const char *path, const au_tex_mesh *t, const unsigned char *img, int tw, int th,
                        const double view[3], int size, int mark_seam, au_msg *msg);

/* A direction from the surface's centroid towards the middle of the cea seam (the preimage of the
 * meridian lon = +-pi), for a render that shows the seam. view: out 3-vector, unit. Returns AU_OK,
 * AU_E_ARG. */
au_status au_tex_seam_view(const au_tex_mesh *t, double view[3]);

/* ---------------------------------------------------------------- small files */

/* Write a NumPy .npy file (format version 1.0, little-endian float64 '<f8', C order) holding
 * data [0..prod(shape)-1] with the given shape (ndim 1..4), atomically.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO. */
au_status au_npy_write(const char *path, int ndim, const long *shape, const double *data, au_msg *msg);

/* Read a per-vertex scalar file (au_io_read_scalars): text (whitespace- or comma-separated numbers,
 * lines starting with '#' skipped), a FreeSurfer curv file (lh.sulc, lh.thickness) or GIfTI values
 * (.shape.gii, .func.gii); exactly n values, all finite. vals: out [0..n-1]. Returns AU_OK, AU_E_ARG,
 * AU_E_NOMEM, AU_E_IO, AU_E_FORMAT (msg names the line and what is wrong, or how many values were found). */
au_status au_read_scalars(const char *path, int n, double *vals, au_msg *msg);

#ifdef __cplusplus
}
#endif
#endif
