/* au_status.h - status codes and the message buffer shared by every authalic module. */
#ifndef AU_STATUS_H
#define AU_STATUS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* One list generates the enum and the strings (libuv style), so they cannot drift.
 * X(name, value, short description). 0 is success, negative values are errors, positive
 * values are warnings (the result is usable). Errors below -100 are faults of the input
 * (the CLI exits 2); errors in -1..-99 are internal or numerical (the CLI exits 1). */
#define AU_STATUS_MAP(X)                                                          \
  X(AU_OK, 0, "ok")                                                               \
  X(AU_W_UNREFERENCED, 1, "unreferenced vertices")                                \
  X(AU_W_NOT_CONVERGED, 2, "tolerance not reached")                               \
  X(AU_E_NOMEM, -1, "out of memory")                                              \
  X(AU_E_ARG, -2, "invalid argument")                                             \
  X(AU_E_NOT_SPD, -3, "matrix not positive definite")                             \
  X(AU_E_NUMERIC, -4, "numerical failure")                                        \
  X(AU_E_FOLD, -5, "map has folded triangles")                                    \
  X(AU_E_INTERNAL, -6, "internal error")                                          \
  X(AU_E_CANCELLED, -7, "cancelled")                                              \
  X(AU_E_IO, -101, "cannot read or write file")                                   \
  X(AU_E_FORMAT, -102, "unknown or malformed file format")                        \
  X(AU_E_EMPTY, -103, "empty mesh")                                               \
  X(AU_E_NONFINITE, -104, "non-finite coordinates")                               \
  X(AU_E_INDEX, -105, "face index out of range")                                  \
  X(AU_E_FACE, -106, "bad face")                                                  \
  X(AU_E_NONMANIFOLD_EDGE, -107, "non-manifold edge")                             \
  X(AU_E_NONMANIFOLD_VERTEX, -108, "non-manifold vertex")                         \
  X(AU_E_ORIENTATION, -109, "inconsistent orientation")                           \
  X(AU_E_COMPONENTS, -110, "several connected components")                        \
  X(AU_E_BOUNDARY, -111, "wrong number of boundary loops")                        \
  X(AU_E_GENUS, -112, "wrong genus")                                              \
  X(AU_E_DEGENERATE, -113, "zero-area face")                                      \
  X(AU_E_DENSITY, -114, "bad density values")

typedef enum au_status {
#define AU_STATUS_ENUM(name, value, text) name = value,
  AU_STATUS_MAP(AU_STATUS_ENUM)
#undef AU_STATUS_ENUM
} au_status;

/* The short description of a status ("non-manifold edge"); never NULL. */
const char *au_status_str(au_status s);
/* The enum name of a status ("AU_E_NONMANIFOLD_EDGE"); never NULL. */
const char *au_status_name(au_status s);
/* 1 if s is an error caused by the input (bad file, bad mesh): the CLI exits 2. */
int au_status_is_input_error(au_status s);

/* Optional message buffer filled by fallible functions with one line naming the problem
 * (e.g. "edge (12, 40) is shared by 3 faces"). Pass NULL when the message is not wanted. */
typedef struct au_msg {
  char text[512]; /* NUL-terminated; empty when nothing was said */
} au_msg;

/* printf into m (NULL-safe); returns s, so `return au_msg_set(m, AU_E_ARG, "...")` reads well. */
au_status au_msg_set(au_msg *m, au_status s, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#ifdef __cplusplus
}
#endif
#endif
