/* au_io_internal.h - the C interface of the OpenMesh bridge (au_io_openmesh.cpp), used only by au_io.c. */
#ifndef AU_IO_INTERNAL_H
#define AU_IO_INTERNAL_H

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

#ifdef __cplusplus
}
#endif
#endif
