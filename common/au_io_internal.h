/* au_io_internal.h - what the readers and writers of au_io share across files: the OpenMesh bridge
 * (au_io_openmesh.cpp), the FreeSurfer files (au_io_freesurfer.c), the GIfTI files (au_io_gifti.c)
 * and the helpers of au_io.c they use (reading a whole file, atomic writes). Used only by common/au_io*. */
#ifndef AU_IO_INTERNAL_H
#define AU_IO_INTERNAL_H

#include <stddef.h>
#include <stdio.h>

#include "au_io.h"
#include "au_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Read path with OpenMesh (the reader follows the extension) into plain arrays, in the order
 * OpenMesh produced them. On success *X (3 * *nv doubles) and *F (3 * *nf ints) are allocated
 * with malloc and owned by the caller (free with free); on failure both are NULL.
 * Faces with more than three corners are rejected, not triangulated. No exception escapes.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_FORMAT (OpenMesh could not read the file),
 * AU_E_FACE (a face is not a triangle; msg names it), AU_E_INTERNAL (any other exception). */
au_status au_io__openmesh_read(const char *path, int *nv, int *nf, double **X, int **F, au_msg *msg);

#ifndef __cplusplus
/* What a file carried besides its mesh (au_io.h describes the public side). */
struct au_io_meta {
  au_io_format format;
  char *fs_stamp;              /* FreeSurfer: the created-by line, without its line end; NULL if none */
  unsigned char *fs_footer;    /* FreeSurfer: the bytes after the faces, as they were; NULL if none */
  size_t fs_footer_len;
  void *gii;                   /* GIfTI: a gifti_image holding the metadata (its arrays without data); NULL if none */
};

/* Read path whole into a NUL-terminated buffer (*out, *len bytes before the NUL); the caller frees
 * *out. Returns AU_OK, AU_E_IO (missing, unreadable, a directory), AU_E_NOMEM. */
au_status au_io__slurp(const char *path, char **out, size_t *len, au_msg *msg);

/* Write through emit (which returns nonzero on failure, with errno set) into a temporary file beside
 * path, then rename it over path; on failure nothing is left. Returns AU_OK, AU_E_NOMEM, AU_E_IO. */
typedef int (*au_io__emit_fn)(FILE *fp, const void *ctx);
au_status au_io__write_atomic(const char *path, au_io__emit_fn emit, const void *ctx, au_msg *msg);

/* A new mesh of nv vertices and nf faces into *out, or AU_E_EMPTY / AU_E_FORMAT / AU_E_NOMEM naming path. */
au_status au_io__mesh_new(const char *path, long long nv, long long nf, au_mesh **out, au_msg *msg);

/* FreeSurfer (au_io_freesurfer.c). buf holds the whole file (len bytes). */
au_status au_io__fs_read_surface(const char *path, const unsigned char *buf, size_t len, au_mesh **out,
                                 au_io_meta *meta, au_msg *msg);
au_status au_io__fs_write_surface(const char *path, const au_mesh *m, const double *P, const au_io_meta *meta,
                                  au_msg *msg);
au_status au_io__fs_read_curv(const char *path, const unsigned char *buf, size_t len, int n, double **out, int *count,
                              au_msg *msg);
au_status au_io__fs_write_curv(const char *path, int n, const double *values, int nfaces, au_msg *msg);
/* 1 if x fits a float32 (finite, |x| <= FLT_MAX), else 0. */
int au_io__fits_float(double x);
/* AU_OK if every coordinate of P (nv x 3) fits a float32, else AU_E_FORMAT naming the vertex and the
 * container that cannot hold it ("a FreeSurfer surface", "a GIfTI pointset"). */
au_status au_io__check_float32(const char *path, int nv, const double *P, const char *container, au_msg *msg);

/* GIfTI through giftiio (au_io_gifti.c). buf holds the whole file (len bytes, gzip or XML). */
au_status au_io__gii_read_surface(const char *path, const unsigned char *buf, size_t len, au_mesh **out,
                                  au_io_meta *meta, au_msg *msg);
au_status au_io__gii_write_surface(const char *path, const au_mesh *m, const double *P, const au_io_write_opts *opts,
                                   au_msg *msg);
au_status au_io__gii_read_scalars(const char *path, const unsigned char *buf, size_t len, int n, double **out,
                                  int *count, au_msg *msg);
au_status au_io__gii_write_scalars(const char *path, int n, const double *values, const au_io_meta *meta,
                                   au_msg *msg);
/* A value of the file's or the pointset's metadata of a kept gifti_image; NULL if absent. */
const char *au_io__gii_meta_get(const void *gii, const char *name);
void au_io__gii_free(void *gii);
/* 1 if the name ends in .gii or .gii.gz (any case). */
int au_io__gii_name(const char *path);
#endif

#ifdef __cplusplus
}
#endif
#endif
