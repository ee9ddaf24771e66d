/* au_io.h - reading and writing meshes (OBJ, OFF, PLY, STL); STL goes through the OpenMesh bridge.
 *
 * The reader keeps the file's vertex order and face order exactly. OBJ, OFF and PLY are parsed
 * by au_io.c itself, because OpenMesh repairs what it cannot represent (it splits non-manifold
 * faces, drops faces with repeated corners) and reads PLY coordinates as float; a broken mesh must
 * reach au_mesh_validate unrepaired. STL (float positions, no shared vertices) is read by OpenMesh,
 * which merges equal positions in order of first appearance; its facet count is checked against the
 * file's (AU_E_FORMAT if OpenMesh dropped any). Writers go to a temporary file beside the target
 * and rename it into place, so a failed run never leaves a partial or clobbered file.
 *
 * Neuroimaging surfaces (issue 19): FreeSurfer binary triangle surfaces (`lh.white`, found by their
 * magic number 0xFFFFFE whatever the name; au_io_freesurfer.c) and GIfTI surfaces (.gii, .surf.gii,
 * gzip-compressed .gii.gz, or a file that starts as XML; read and written through Debian's GIfTI
 * library, au_io_gifti.c). What those formats carry besides the mesh (FreeSurfer's created-by line
 * and volume-geometry footer, GIfTI's metadata and coordinate systems) is kept in an au_io_meta that
 * au_io_read_meta returns and au_io_write takes, so an output keeps what its input said. Per-vertex
 * values (curvature, thickness, sulcal depth, the areal distortion of a map) are read and written by
 * au_io_read_scalars / au_io_write_scalars: text, FreeSurfer curv, GIfTI .shape.gii / .func.gii. */
#ifndef AU_IO_H
#define AU_IO_H

#include "au_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* au_io_format, au_io_meta and their functions are public (include/authalic.h). */

/* Read a triangle mesh from path. A FreeSurfer surface is recognized by its magic number and a GIfTI
 * file by its name (.gii, .gii.gz) or its first bytes (XML, or gzip under a .gii.gz name); anything
 * else by the extension (.obj .off .ply .stl, any case).
 * Polygons with more than three corners are rejected (AU_E_FACE), not silently triangulated.
 * On success *out owns the mesh (free with au_mesh_free).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO (missing, unreadable, a directory),
 * AU_E_FORMAT (unknown extension, malformed or truncated file, vertices dropped by the reader),
 * AU_E_EMPTY, AU_E_INDEX, AU_E_FACE. */
au_status au_io_read(const char *path, au_mesh **out, au_msg *msg);


/* Options for writing. */
typedef struct au_io_write_opts {
  const double *uv; /* uv [0..2*nv-1]: per-vertex texture coordinates written as OBJ `vt`; may be NULL (default) */
  int precision;    /* significant digits for coordinates, 1..17 (default 17: exact round trip); text formats
                       only: FreeSurfer and GIfTI store float32 coordinates */
  au_io_format format;        /* AU_IO_FORMAT_AUTO (default): by the extension of path; otherwise this format
                                 whatever the name (STL cannot be written) */
  const au_io_meta *meta;     /* the input's metadata, carried into FreeSurfer and GIfTI outputs: the
                                 FreeSurfer footer byte for byte, the GIfTI metadata (AnatomicalStructure*,
                                 coordinate systems); NULL (default): none. A FreeSurfer footer goes only
                                 into a FreeSurfer output, GIfTI metadata only into a GIfTI one. */
  const char *geometric_type; /* GIfTI GeometricType of the output's pointset ("Spherical", "Flat", ...);
                                 NULL (default): the input's, if it had one */
  int nvt;          /* per-corner texture coordinates instead of uv: nvt rows of vt (OBJ only) */
  const double *vt; /* vt [0..2*nvt-1]; NULL (default): none */
  const int *Ft;    /* Ft [0..3*nf-1]: the vt row of each corner, written as `f v/vt` */
} au_io_write_opts;

au_io_write_opts au_io_write_opts_default(void);

/* Write vertices P (nv x 3, row-major) with the faces of m to path; the format is opts->format, or
 * follows the extension (.obj .off .ply .gii .gii.gz). OBJ, OFF and PLY are ASCII; FreeSurfer is
 * big-endian binary with a created-by line (and the footer of opts->meta if it came from a
 * FreeSurfer file); GIfTI has a float32 POINTSET and an int32 TRIANGLE array, base64 of gzip data.
 * Input vertex order and faces. Written to a temporary file in the target's directory and renamed
 * over path only when complete.
 * opts may be NULL for defaults; uv and vt are exclusive (AU_E_ARG), and Ft must lie in 0..nvt-1. Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO, AU_E_FORMAT (unknown
 * extension and no format given, or a format that cannot be written, or a coordinate beyond float32
 * for FreeSurfer and GIfTI). */
au_status au_io_write(const char *path, const au_mesh *m, const double *P, const au_io_write_opts *opts,
                      au_msg *msg);

/* Write a text file atomically: the whole of buf (len bytes) to a temporary file beside path,
 * then rename. Used by the JSON report writer. Returns AU_OK, AU_E_ARG, AU_E_IO. */
au_status au_io_write_text(const char *path, const char *buf, size_t len, au_msg *msg);

/* A growable text buffer, for writers that build their text first (au_io_write_text takes it).
 * Zero-initialize; au_textbuf_printf appends (a failed allocation or format sets bad and stops it);
 * au_textbuf_free releases. */
typedef struct au_textbuf {
  char *s;
  size_t len, cap;
  int bad;
} au_textbuf;
void au_textbuf_printf(au_textbuf *b, const char *fmt, ...)
#ifdef __GNUC__
    __attribute__((format(printf, 2, 3)))
#endif
    ;
void au_textbuf_free(au_textbuf *b);


/* 1 if the extension of path is one au_io_write can produce, else 0. */
int au_io_can_write(const char *path);

/* au_io_read_scalars and au_io_write_scalars are public (include/authalic.h). */

#ifdef __cplusplus
}
#endif
#endif
