/* authalic.h - equal-area (authalic) maps of triangle meshes: the one public header of libauthalic.
 *
 * This header is the manual. authalic maps a triangle mesh onto a canonical domain - the unit
 * sphere (closed genus-0 meshes), the unit disk or the unit square (one boundary loop), an annulus
 * (two boundary loops), a flat torus (closed genus-1 meshes) - so that every part of the surface gets its fair share of the domain's
 * area, and no triangle is ever folded. The method is Lie advection (Zou, Hu, Gu & Hua, "Authalic
 * parameterization of general surfaces using Lie advection", IEEE TVCG 2011): a conformal start,
 * then a flow of the domain until the areas match.
 *
 *     #include <authalic.h>
 *
 *     au_mesh *m = NULL;
 *     au_result *r = NULL;
 *     au_msg msg = {{0}};
 *     if (au_mesh_read("bunny.obj", &m, &msg) < 0) { fprintf(stderr, "%s\n", msg.text); return 2; }
 *     au_options o = au_options_default();
 *     au_status st = au_map(m->X, m->nv, m->F, m->nf, AU_TARGET_SPHERE, &o, &r, &msg);
 *     if (st >= 0) au_mesh_write("bunny_sphere.obj", r->nv, r->P, r->nf, r->F, NULL, &msg);
 *     au_result_free(&r);
 *     au_mesh_free(&m);
 *
 * Build with `pkg-config --cflags --libs authalic` or CMake's `find_package(authalic)` and the
 * target `authalic::authalic`.
 *
 * Conventions:
 * - Every fallible function returns an au_status: 0 success, > 0 a warning (the result is usable),
 *   < 0 an error. Errors at or below -100 are faults of the input (a bad file, a mesh of the wrong
 *   topology); the others are internal or numerical. Functions that take an `au_msg *msg` fill it
 *   with one line naming the problem ("edge (12, 40) is shared by 3 faces"); msg may be NULL.
 * - Arrays are row-major and 0-based: V or X is nv x 3 doubles (x, y, z of vertex i at 3i..3i+2),
 *   F is nf x 3 ints, counter-clockwise seen from outside. The caller's arrays are never modified
 *   and need not outlive the call.
 * - What the library allocates, the caller frees with the function named beside it; every free
 *   function takes the address of the pointer, is NULL-safe, and sets the pointer to NULL.
 * - The library keeps no mutable global state, installs no signal handler, sets no thread counts
 *   and prints nothing: two maps may run at once in two threads of one process. A map uses up to
 *   two threads of its own (the target machine has two cores). CHOLMOD's OpenMP regions and
 *   OpenBLAS's threads follow the process's settings: on a two-core machine, OMP_THREAD_LIMIT=1 and
 *   OPENBLAS_NUM_THREADS=1 in the environment before the process starts are faster (the `authalic`
 *   program sets both for itself).
 * - Thread safety: distinct calls on distinct results are independent; a result may be read from
 *   several threads at once.
 */
#ifndef AUTHALIC_H
#define AUTHALIC_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define AU_VERSION_MAJOR 1
#define AU_VERSION_MINOR 0
#define AU_VERSION_PATCH 0

/* Marks what the shared library exports; everything else is hidden. */
#if defined(AU_BUILDING_LIBRARY) && defined(__GNUC__)
#define AU_API __attribute__((visibility("default")))
#else
#define AU_API
#endif

/* ================================================================ status and messages */

/* One list generates the enum and the strings, so they cannot drift. X(name, value, description).
 * 0 success; > 0 warnings; -1..-99 internal or numerical errors; <= -100 faults of the input. */
#define AU_STATUS_MAP(X)                                                          \
  X(AU_OK, 0, "ok")                                                               \
  X(AU_W_UNREFERENCED, 1, "unreferenced vertices")                                \
  X(AU_W_NOT_CONVERGED, 2, "tolerance not reached")                               \
  X(AU_W_REORIENTED, 3, "faces re-oriented")                                      \
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
  X(AU_E_DENSITY, -114, "bad density values")                                     \
  X(AU_E_TOO_COARSE, -115, "mesh too coarse for the options")

typedef enum au_status {
#define AU_STATUS_ENUM(name, value, text) name = value,
  AU_STATUS_MAP(AU_STATUS_ENUM)
#undef AU_STATUS_ENUM
} au_status;

/* The short description of a status ("non-manifold edge"); never NULL. */
AU_API const char *au_status_str(au_status s);
/* The enum name of a status ("AU_E_NONMANIFOLD_EDGE"); never NULL. */
AU_API const char *au_status_name(au_status s);
/* 1 if s is an error caused by the input (a bad file or mesh, s <= -100), else 0. */
AU_API int au_status_is_input_error(au_status s);

/* One line naming a problem, filled by fallible functions; empty when nothing was said. */
typedef struct au_msg {
  char text[512]; /* NUL-terminated */
} au_msg;

/* printf into m (NULL-safe); returns s. */
AU_API au_status au_msg_set(au_msg *m, au_status s, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* The library's version as "MAJOR.MINOR.PATCH"; never NULL. */
AU_API const char *au_version(void);

/* sizeof the public struct named name ("au_options", "au_expert", "au_result", "au_metrics",
 * "au_convergence", "au_mesh", "au_msg", "au_write_opts", "au_report_extra", "au_tex_layout",
 * "au_tex_mesh"), or 0 for another name: for bindings that lay the structs out themselves (Python's
 * ctypes) to check their layout against the library they loaded. */
AU_API size_t au_struct_size(const char *name);

/* Free memory the library handed out as a plain pointer (the JSON of au_result_json). NULL-safe. */
AU_API void au_free(void *p);

/* ================================================================ meshes */

/* A triangle mesh as two arrays. Meshes made by the library are freed with au_mesh_free. */
typedef struct au_mesh {
  int nv;    /* number of vertices, >= 0 */
  int nf;    /* number of triangles, >= 0 */
  double *X; /* X [0..3*nv-1]: x, y, z of vertex i at X[3i..3i+2] */
  int *F;    /* F [0..3*nf-1]: the corners of face f at F[3f..3f+2], counter-clockwise from outside */
} au_mesh;

/* Allocate a mesh with room for nv vertices and nf faces (contents zeroed); *out owns it.
 * Returns AU_OK, AU_E_ARG (negative counts, out NULL), AU_E_NOMEM. */
AU_API au_status au_mesh_alloc(int nv, int nf, au_mesh **out);
/* Deep copy. Returns AU_OK, AU_E_ARG, AU_E_NOMEM. */
AU_API au_status au_mesh_copy(const au_mesh *m, au_mesh **out);
/* Free a mesh and set *m to NULL; NULL-safe. */
AU_API void au_mesh_free(au_mesh **m);
/* Make the faces' orientation consistent in place: a breadth-first walk over the faces of each
 * component flips every face that traverses an edge in the same direction as its neighbour, and of the
 * two consistent orientations the one that keeps the most faces as they were is kept. au_map and
 * every command do this first. nflipped (may be NULL) receives how many faces were reversed.
 * Returns AU_OK (nothing to do), AU_W_REORIENTED (msg says how many faces and the first), AU_E_ARG,
 * AU_E_NOMEM, AU_E_INDEX, AU_E_FACE, AU_E_NONMANIFOLD_EDGE (names the edge), AU_E_ORIENTATION (the
 * surface is not orientable, a Moebius strip: msg names the edge where the walk met itself reversed);
 * on an error m is unchanged. */
AU_API au_status au_mesh_orient(au_mesh *m, int *nflipped, au_msg *msg);

/* Read a triangle mesh; the format follows the extension: .obj .off .ply (ASCII or binary) .stl.
 * The file's vertex and face order is kept exactly; polygons with more than three corners are
 * rejected (AU_E_FACE), not triangulated; nothing is repaired (au_mesh_check says what is wrong).
 * On success *out owns the mesh. Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO (missing, unreadable,
 * a directory), AU_E_FORMAT (unknown extension, malformed or truncated), AU_E_EMPTY, AU_E_INDEX,
 * AU_E_FACE. */
AU_API au_status au_mesh_read(const char *path, au_mesh **out, au_msg *msg);

/* ---- neuroimaging files and per-vertex values
 * FreeSurfer binary triangle surfaces (`lh.white`: found by their magic number 0xFFFFFE whatever the
 * name) and GIfTI surfaces (.gii, .surf.gii, gzip-compressed .gii.gz) are read by au_mesh_read too.
 * What those formats carry besides the mesh (FreeSurfer's created-by line and volume-geometry footer,
 * GIfTI's metadata and coordinate systems) is kept in an au_io_meta (au_io_read_meta) that
 * au_write_opts.meta carries into an output of the same format. Per-vertex values (curvature,
 * thickness, sulcal depth, a map's areal distortion): text, FreeSurfer curv, GIfTI .shape.gii /
 * .func.gii. Reading GIfTI redirects the process's stderr for the length of giftiio's parse (giftiio
 * reports damage only there); programs that print from other threads meanwhile lose that output. */

/* The file formats. AU_IO_FORMAT_AUTO means "not given": the output's extension decides. */
typedef enum au_io_format {
  AU_IO_FORMAT_AUTO = 0,
  AU_IO_FORMAT_OBJ,
  AU_IO_FORMAT_OFF,
  AU_IO_FORMAT_PLY,
  AU_IO_FORMAT_STL,        /* read only */
  AU_IO_FORMAT_FREESURFER, /* binary triangle surface, big-endian */
  AU_IO_FORMAT_GIFTI       /* .gii; .gii.gz is written gzip-compressed */
} au_io_format;

/* The format a path's name asks for: .obj .off .ply .stl (any case), .gii or .gii.gz (also
 * .surf.gii, .shape.gii, ...); AU_IO_FORMAT_AUTO for any other name (FreeSurfer's names, such as
 * `lh.white` or `rh.sphere.reg`, say nothing about the format). NULL gives AU_IO_FORMAT_AUTO. */
AU_API au_io_format au_io_format_of_name(const char *path);

/* The format named by a word as `--format` takes it: obj, off, ply, freesurfer, gifti (lower case);
 * AU_IO_FORMAT_AUTO for anything else (or NULL). */
AU_API au_io_format au_io_format_parse(const char *word);

/* The lower-case name of a format ("obj", ..., "freesurfer", "gifti"; "auto"). Never NULL. */
AU_API const char *au_io_format_name(au_io_format f);

/* What a neuroimaging file carries besides its mesh, kept so that an output can say it again:
 * the format read; for FreeSurfer the created-by line and the bytes after the faces (the volume
 * geometry footer and any tags, kept as they are); for GIfTI the file's metadata and the pointset's
 * metadata and coordinate systems. Opaque; free with au_io_meta_free. */
typedef struct au_io_meta au_io_meta;

/* The format of the file the metadata was read from (AU_IO_FORMAT_AUTO for NULL). */
AU_API au_io_format au_io_meta_format(const au_io_meta *meta);

/* A value of the metadata: for GIfTI a name of the file's or the pointset's metadata
 * ("AnatomicalStructurePrimary", "GeometricType", ...), for FreeSurfer "created_by" (the created-by
 * line); NULL if absent. The string belongs to meta. */
AU_API const char *au_io_meta_get(const au_io_meta *meta, const char *name);

/* Free *meta and set it to NULL; NULL-safe. */
AU_API void au_io_meta_free(au_io_meta **meta);

/* au_io_read, and also what the file carries besides the mesh: on success *meta (if meta is not
 * NULL) owns the file's metadata (free with au_io_meta_free; for OBJ, OFF, PLY and STL it records
 * only the format). On failure *meta is NULL. Returns what au_io_read returns. */
AU_API au_status au_io_read_meta(const char *path, au_mesh **out, au_io_meta **meta, au_msg *msg);

/* Read n per-vertex values from path into *out (malloc'ed, n doubles, owned by the caller; NULL on
 * failure). The format: a FreeSurfer curv file (found by its magic number 0xFFFFFF, float32 values),
 * GIfTI (.gii or .gii.gz, e.g. .shape.gii or .func.gii, or XML content: the one data array that is
 * neither a POINTSET nor a TRIANGLE, one value per vertex), or text: numbers separated by blanks,
 * commas or line ends, with `#` starting a comment line. n > 0: exactly n values are expected;
 * n == 0: any positive count is taken. *count (may be NULL) gets the count read. Every value must
 * be finite. Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO (missing, unreadable), AU_E_FORMAT
 * (malformed, truncated, a non-finite value, another count than n; msg says which). */
AU_API au_status au_io_read_scalars(const char *path, int n, double **out, int *count, au_msg *msg);

/* Write n per-vertex values: GIfTI (a float32 NIFTI_INTENT_SHAPE array; gzip-compressed for .gii.gz)
 * when path ends in .gii or .gii.gz (.shape.gii, .func.gii), otherwise a FreeSurfer curv file
 * (magic 0xFFFFFF, n, nfaces, 1 value per vertex, big-endian float32). nfaces: the mesh's face count,
 * which a curv header records (0 if unknown). meta (may be NULL): the input's metadata; a GIfTI
 * output carries its AnatomicalStructurePrimary and AnatomicalStructureSecondary. Written
 * atomically as au_io_write. Returns AU_OK, AU_E_ARG (n <= 0, NULL values), AU_E_NOMEM, AU_E_IO,
 * AU_E_FORMAT (a value that is not finite or beyond float32). */
AU_API au_status au_io_write_scalars(const char *path, int n, const double *values, int nfaces, const au_io_meta *meta,
                              au_msg *msg);

/* How au_mesh_write writes. Start from au_write_opts_default(). */
typedef struct au_write_opts {
  const double *uv; /* uv [0..2*nv-1]: per-vertex texture coordinates written as OBJ `vt` lines;
                       NULL (default): none. Ignored by formats other than OBJ. */
  int precision;    /* significant digits of coordinates, 1..17 (default 17: exact round trip) */
  int nvt;          /* per-corner texture coordinates instead (a torus result's vt, Ft): nvt rows */
  const double *vt; /* vt [0..2*nvt-1], written as OBJ `vt` lines; NULL (default): none. Not with uv */
  const int *Ft;    /* Ft [0..3*nf-1]: the vt row of each corner, 0 <= Ft < nvt, written as `f v/vt` */
  au_io_format format; /* AU_IO_FORMAT_AUTO (default): by path's extension; otherwise this format whatever
                          the name (STL cannot be written) */
  const au_io_meta *meta; /* the input's metadata (au_io_read_meta), carried into a FreeSurfer or GIfTI
                             output of the same format: the footer byte for byte, the GIfTI
                             AnatomicalStructure and coordinate systems; NULL (default): none */
  const char *geometric_type; /* GIfTI GeometricType of the output ("Spherical", "Flat"); NULL (default):
                                 the input's, if it had one */
  double radius;    /* scale positions by this before writing (a sphere of radius 100 for FreeSurfer and
                       HCP); 0 (default) or 1: as given */
} au_write_opts;

AU_API au_write_opts au_write_opts_default(void);

/* Write nv vertices V (nv x 3) with nf faces F (nf x 3) to path; the format follows the extension
 * (.obj .off .ply, ASCII). The file is written beside path under a temporary name
 * (au_temp_path) and renamed over path only when complete, so a failed write leaves neither a
 * partial file nor a clobbered old one; a symbolic link stays and the file it names is replaced, and
 * a path that exists but is not a regular file (a device such as /dev/null, a FIFO) is refused with
 * AU_E_IO, since a rename would put a plain file in its place. opts may be NULL.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO, AU_E_FORMAT (unknown extension). */
AU_API au_status au_mesh_write(const char *path, int nv, const double *V, int nf, const int *F,
                               const au_write_opts *opts, au_msg *msg);

/* 1 if au_mesh_write can write path's extension, else 0. */
AU_API int au_mesh_can_write(const char *path);

/* The temporary name a write to path uses in this process ("<path>.tmp<pid>"; for a symbolic link to
 * a file, beside that file, which the write replaces, keeping the link), into buf (len bytes). A program that wants an interrupted run to leave nothing behind computes these names
 * before it writes and removes them in its signal handler (unlink is async-signal-safe).
 * Returns AU_OK, AU_E_ARG (buf too short). */
AU_API au_status au_temp_path(const char *path, char *buf, size_t len);

/* The file a write to path replaces (au_mesh_write, au_write_text and every writer of the library):
 * path itself, or for a symbolic link the file it names (through further links, also when that file
 * does not exist yet), so that the link stays. Freed with au_free; NULL when out of memory or path is
 * NULL. For programs that put their own temporaries in place, as the library does. */
AU_API char *au_output_target(const char *path);

/* Write len bytes of text to path atomically (as au_mesh_write does). Returns AU_OK, AU_E_ARG, AU_E_IO. */
AU_API au_status au_write_text(const char *path, const char *text, size_t len, au_msg *msg);

/* Read a per-vertex scalar file: whitespace-separated numbers (lines starting with '#' skipped),
 * exactly n of them, all finite. vals: out [0..n-1]. Returns AU_OK, AU_E_ARG, AU_E_IO, AU_E_FORMAT
 * (msg names the line and what is wrong, or how many values were found). */
AU_API au_status au_read_scalars(const char *path, int n, double *vals, au_msg *msg);

/* ================================================================ maps */

/* The domain a mesh is mapped onto. */
typedef enum au_target {
  AU_TARGET_SPHERE = 0,  /* closed genus-0 mesh onto the unit sphere */
  AU_TARGET_DISK = 1,    /* one boundary loop onto the unit disk */
  AU_TARGET_ANNULUS = 2, /* two boundary loops onto the annulus of outer radius 1 (inner radius from
                            the conformal modulus, or au_options.inner_radius) */
  AU_TARGET_SQUARE = 3,  /* one boundary loop onto [0,1]^2, four boundary vertices at the corners */
  AU_TARGET_TORUS = 4,   /* closed genus-1 mesh onto a flat torus R^2 / Lambda, Lambda of determinant 1
                            (the conformal modulus's shape, or the unit square: au_options.lattice),
                            with no cut: the result's seamless per-corner texture coordinates (vt, Ft)
                            repeat by the lattice. For now the conformal start only (see au_map) */
  AU_TARGET_CIRCLES = 5  /* genus-0 mesh with k >= 1 boundary loops onto the unit disk with k - 1 round
                            holes, every circle sliding (docs/circles.md); outer_loop names the loop
                            on the unit circle (default: the longest) */
} au_target;

/* The name of a target ("sphere", "disk", "annulus", "square", "torus", "circles"); NULL for an unknown value. */
AU_API const char *au_target_name(au_target t);

/* Check that a mesh can be mapped onto target t, and name the first problem: empty, non-finite
 * coordinates, index out of range, repeated corner, non-manifold edge or vertex, non-orientable
 * surface, several components, wrong number of boundary loops, wrong genus, zero-area faces.
 * Inconsistently oriented faces of an orientable surface are not a problem: au_map re-orients them
 * (au_mesh_orient) with a warning. au_map makes the same check. Returns AU_OK, AU_W_UNREFERENCED
 * (usable; msg says how many vertices no face uses), AU_W_REORIENTED (usable once re-oriented; msg
 * says how many faces, and the unreferenced vertices too if any), AU_E_ARG, AU_E_NOMEM, or one of the
 * input errors (<= -100). */
AU_API au_status au_mesh_check(const double *V, int nv, const int *F, int nf, au_target t, au_msg *msg);

#define AU_MAX_STEPS 512      /* the most advection steps a map may take (au_options.max_steps) */
#define AU_MAX_ANGLE_STEPS 50 /* the most angle steps (au_options.angle_steps) */
#define AU_REFINE_MAX_FACES 16 /* the largest face budget of refine_mesh (au_options.refine_max_faces) */
#define AU_REFINE_AUTO (-1.0) /* au_options.refine_max_faces: the budget raised until the map meets bounds */

/* The defaults au_map uses for target t when au_options leaves them open: the most steps, and the
 * tolerance (vertex mean |ln ratio|). Either pointer may be NULL. */
AU_API void au_target_defaults(au_target t, int *max_steps, double *tol);

/* Named starting points for au_options (au_options_preset). */
typedef enum au_preset {
  AU_PRESET_DEFAULT = 0,      /* fast: stop once the vertex cells are within the tolerance */
  AU_PRESET_REFINE_FACES = 1, /* then go on refining the triangles' areas as long as it helps at all
                                 (several times the default's time for about half its per-face error) */
  AU_PRESET_ANGLES = 2        /* then 5 angle steps: less angle distortion, vertex cells to ~1e-4, at a
                                 higher per-face error */
} au_preset;

/* Boundary handling of the planar targets. */
typedef enum au_boundary {
  AU_BOUNDARY_SLIDE = 0, /* boundary vertices slide along their circle or side (default) */
  AU_BOUNDARY_FIXED = 1  /* the initial map's boundary is kept */
} au_boundary;

/* The torus's lattice (au_options.lattice). */
typedef enum au_lattice {
  AU_LATTICE_CONFORMAL = 0, /* the conformal modulus's lattice scaled to determinant 1, reduced (|a1| <= |a2|,
                               |a1 . a2| <= |a1|^2 / 2), a1 along +x (default) */
  AU_LATTICE_SQUARE = 1     /* the unit square's, a1 = (1, 0), a2 = (0, 1): the linear map taking the
                               conformal lattice's reduced basis to it, so no longer conformal */
} au_lattice;

/* au_options.outer_loop: which loop of an annulus goes to the unit circle. */
#define AU_OUTER_LONGER (-1)  /* the longer loop (default) */
#define AU_OUTER_SHORTER (-2) /* the shorter loop */

/* A step-by-step report to a progress callback: step k of at most max_steps, with the current area
 * error (per-face mean |r - 1|). Return 0 to go on, nonzero to cancel the map (au_map then returns
 * AU_E_CANCELLED). */
typedef int (*au_progress_fn)(void *user, int step, int max_steps, double err);

typedef struct au_expert au_expert;

/* The sphere map's start (au_options.start). */
typedef enum au_start {
  AU_START_CONFORMAL = 0, /* the conformal map, Moebius-balanced: squeezes protrusions exponentially */
  AU_START_MULTILEVEL = 1 /* coarse-to-fine: the mesh simplified to a few hundred vertices, mapped, and
                             its vertices brought back level by level, each inside its ring's kernel,
                             with a few flow steps per level (docs/coarse-to-fine.md); where it cannot
                             be made, the conformal start is used and au_result.init_method says so */
} au_start;

/* What au_map is asked to do. Start from au_options_default() or au_options_preset(); fields that
 * do not apply to the target are ignored. */
typedef struct au_options {
  int max_steps;          /* most advection steps, 1..512; 0 (default): 60 */
  double tol;             /* stop when the vertex-level mean |ln(area ratio)| is at most tol, >= 0;
                             negative (default -1): the target's default, 2e-3 on the sphere and 3e-3
                             on planar targets */
  int refine_faces;       /* 1: after the vertex cells meet tol, refine the triangles' areas while it
                             helps at all (AU_PRESET_REFINE_FACES); 0 (default): while it gains 10% in
                             4 steps */
  int angle_steps;        /* 0..50 angle steps after the flow (AU_PRESET_ANGLES: 5): steps towards the
                             map of least Dirichlet energy with the vertex cells held at their areas.
                             On the sphere they begin as soon as the vertex error is 0.01 (unless
                             refine_faces). 0 (default): none */
  const double *vertex_density; /* [0..nv-1], each > 0 and finite: the domain area of a vertex's
                                   cell is proportional to density x its surface area; NULL (default):
                                   equal area. At most one of vertex_density and face_density. */
  const double *face_density;   /* [0..nf-1], the same per face; NULL (default) */
  double restore_shapes;  /* sphere: while the spherical areas are driven, each step's shear aims this
                             fraction (0..1) back at the surface's triangle shapes (fewer long, thin
                             triangles); negative (default -1): 0.1. With spherical_areas it goes off for
                             the rest of a run once a restoring step was undone */
  int balance;            /* sphere: 1 (default) Moebius-balance the conformal start; 0 skip */
  int init_only;          /* 1: stop after the initial (conformal / harmonic) map; 0 (default) */
  au_boundary boundary;   /* planar targets: default AU_BOUNDARY_SLIDE */
  double inner_radius;    /* annulus: inner radius in (0, 1); 0 (default): the conformal modulus's */
  int outer_loop;         /* annulus: AU_OUTER_LONGER (default), AU_OUTER_SHORTER, or the index of a
                             vertex on the loop that goes to the unit circle */
  int corners[4];         /* square: boundary vertices for (0,0), (1,0), (1,1), (0,1), the last three
                             taken in the order they follow corners[0] along the boundary; all -1
                             (default): the most corner-like vertices near the arc-length quarters */
  au_progress_fn progress; /* called once per step from the calling thread; NULL (default) */
  void *user;             /* passed to progress */
  const int *cancel;      /* when *cancel becomes nonzero (set from any thread; read atomically
                             before the flow and at each of its steps, so a cancel during the initial
                             map takes effect when that ends), the map stops, frees what it holds and
                             au_map returns AU_E_CANCELLED; NULL (default) */
  const au_expert *expert; /* the flow's tuning (au_expert_default); NULL (default): the target's
                              defaults with refine_faces applied. When given, it replaces them all. */
  au_lattice lattice;     /* torus: AU_LATTICE_CONFORMAL (default) or AU_LATTICE_SQUARE */
  int refine_mesh;        /* sphere: 1: after the flow, split the map's long edges where a chord
                             triangle cannot shrink to its share (the chord floor), with new vertices on
                             the input surface, and flow again, within refine_max_faces (four
                             candidate refinements, the best kept: sphere/au_sphere_refine.c). The result's mesh is then the refined one (nv > nv_in) and
                             au_result.parent tells where each new vertex lies; when no refinement
                             lowers the vertex error without raising the per-face one, the input's
                             mesh and map (nrefined 0, a warning says so). 0 (default): the input's mesh */
  int measure_start;      /* 1 (default): also measure the initial map (au_result.init_metrics);
                             0: skip it, a tenth of a second on 100k faces (au_result_json then
                             measures it itself) */
  double refine_max_faces; /* sphere with refine_mesh: the refined mesh has at most this many times the
                              input's faces, 1 < x <= AU_REFINE_MAX_FACES; 0 (default): 2. Long thin limbs gain from
                              more (docs/sphere.md). AU_REFINE_AUTO: 2, then 3 and 4 while the refined
                              map's per-face mean |r - 1| is over 0.02 or its vertex mean |log r| over 0.005;
                              the first budget that meets both is kept, else the one with the lowest per-face
                              error; it stops at 2 where no face is held by the chord floor. A warning lists
                              what was tried (each budget is a whole refinement) */
  int spherical_areas;    /* sphere: 1: equalize the spherical triangles' areas only, with no chord polish
                             (the map `authalic texture` and `sample` make for themselves: texels and
                             grid cells lie on the sphere; au_metrics' sph_ figures measure it, its chord
                             figures stay higher on long edges); overrides expert->sphere_areas. Not
                             with refine_mesh (AU_E_ARG: spherical triangles have no chord floor to
                             refine). With angle_steps, the angle steps hold the chord cells. 0
                             (default): expert->sphere_areas, by default 1: the chord triangles'
                             areas, param-eval's headline figures */
  double aspect;          /* square: the rectangle's width / height, > 0: the equal-area map onto the unit
                             square stretched to [0, w] x [0, h], max(w, h) = 1 (a linear stretch scales every
                             area alike, so the map stays equal area); 0 (default): the unit square */
  au_start start;         /* sphere: the start (default AU_START_CONFORMAL); other targets ignore it */
} au_options;

AU_API au_options au_options_default(void);
/* au_options_default() with the preset applied. */
AU_API au_options au_options_preset(au_preset p);

/* The flow's tuning, for experiments: most users never need it. Get the values au_map would use
 * from au_expert_default, change some, and point au_options.expert at the struct. The meaning of
 * each rule is in docs/flow.md and the flow's source (common/au_advect.h). */
struct au_expert {
  int method;             /* 0 least-shear steps (default), 1 the paper's Poisson steps */
  double shear;           /* shear weight against the area residual while the schedule runs, >= 0 (1) */
  double shear_tail;      /* the same after the schedule, >= 0 (0.01; on the sphere's resolved schedule 0.007 until
                           * a step is undone, unless set: docs/flow-tail.md) */
  double face_shear_tail; /* the shear weight's floor in the per-face refinement; 0: shear_tail (0;
                             planar refine_faces: 3e-4) */
  int schedule_steps;     /* K of the paper's eq. 19: the excess spread over K-k+1 steps (4; on the sphere's
                           * resolved schedule 3 until a step is undone, unless set) */
  double max_log_step;    /* a cell's area changes by at most this factor's log in one step (1.2) */
  double newton_below;    /* Poisson method: exact Gauss-Newton steps below this error (0.7) */
  int face_steps;         /* Poisson method: at most this many per-face steps (30) */
  double face_tol;        /* stop refining at this per-face mean |r - 1| (1e-3; planar 1e-2, planar
                             refine_faces 1e-3) */
  double face_damping;    /* Poisson method: damping of the face steps, relative (0.1) */
  double max_move;        /* Poisson method: a vertex moves at most this fraction of its triangles'
                             inradius per step, 0 < x < 0.5 (0.3) */
  double face_gain;       /* refinement goes on while it gains this fraction in 4 steps (0.1;
                             refine_faces 0.02) */
  int sphere_areas;       /* sphere: 1 drive the spherical triangles' areas first, then polish the
                             chord triangles' (1); 2 the spherical ones only (no chord polish; the
                             vertex polish is then of the spherical triangles); 0 chord triangles'
                             throughout */
  double polish_gap;      /* sphere: polish only if the chord error exceeds the spherical one by more
                             than this fraction (0.1; refine_faces 0) */
  double restore;         /* sphere: shape restoring (0.1), as au_options.restore_shapes */
  double lantern;         /* sphere: shape restoring raised on faces near the chord floor (0) */
  double lantern_retry;   /* sphere: a map missing tol by more than retry_above x is mapped again with
                             lantern = this, the better map kept (2; 0 off) */
  double retry_above;     /* see lantern_retry (2) */
  double twist_retry;     /* sphere: a map still missing tol by more than retry_above x, with a chord
                             floor excess above this, is mapped again from the twisted start, the better
                             map kept (0.02; 0 off; docs/sphere.md) */
  int vertex_polish;      /* sphere: a map still missing tol gets at most this many sweeps of the vertex
                             polish (each vertex alone steps on its own triangles' chord areas, or the
                             spherical ones' with sphere_areas 2), kept if its vertex error falls and its
                             per-face error does not rise, in that measure (200; 0 off) */
  double polish_cells;    /* sphere: the vertex polish's weight of the vertex cells against the faces (1) */
  double resolved_jump;   /* a start whose mean jump of log r across edges is at most this runs the
                             resolved schedule (0.1; refine_faces 0: never) */
  double resolved_shear;  /* resolved schedule: first shear weight (0.1) */
  double resolved_decay;  /* resolved schedule: shear weight factor per accepted step (0.25) */
  double resolved_log_step; /* resolved schedule: per-step area change bound, log (2; on the sphere, 2.5
                              * until a step is undone, unless set) */
  double angle_faces;     /* angle steps: weight of the triangles' areas (300) */
  double angle_cells;     /* angle steps: weight of the vertex cells' areas (1e6) */
  double angle_trust;     /* angle steps: Levenberg-Marquardt term (1) */
  double angle_switch;    /* sphere: the angle steps begin at this vertex error (0.01; planar and
                             refine_faces 0: after the flow) */
  int staged_retry;       /* sphere: a map still missing tol with at least 1% of the surface in vertex
                             cells under 1/e of their share (squeezed limbs) is mapped again from its
                             start in at most this many stages, each towards part of the way, the better
                             map kept (8; 0 off; docs/sphere.md) */
  int global_polish;      /* sphere: a chord map still missing tol after the vertex polish gets at most
                             this many steps of the global polish (every vertex at once, on the chord
                             triangles' and the vertex cells' areas and, in a small weight, their
                             conformal distortion), kept on the vertex polish's terms (200; 0 off: the
                             vertex polish's map; not on meshes of more than 100000 vertices, for its
                             memory; docs/sphere.md) */
};

/* The tuning au_map uses for target t, with or without refine_faces. */
AU_API au_expert au_expert_default(au_target t, int refine_faces);


/* Distortion of a map, with the names and definitions of ../shared/tools/param-eval (they agree to
 * 1e-9). Per face, J is the affine map from the domain triangle (the chord triangle on the sphere)
 * to the surface triangle, the surface scaled to the domain's total area; gmax >= gmin its singular
 * values; Upsilon = ln(gmax gmin) (area), Lambda = ln(gmax / gmin) (angle); r = domain share /
 * surface share. Faces whose domain or surface area is <= 1e-14 of the total are left out (counted
 * in excluded). */
typedef enum au_domain { AU_DOMAIN_SPHERE = 0, AU_DOMAIN_PLANE = 1 } au_domain;

typedef struct au_metrics {
  int nv, nf;
  au_domain domain;
  double upsilon_mean_abs, upsilon_std, upsilon_max_abs, upsilon_p95_abs, upsilon_p99_abs;
  double upsilon_wmean_abs;                 /* |Upsilon| weighted by surface area */
  double lambda_mean, lambda_std, lambda_max, lambda_p95;
  double logr_mean_abs;                     /* mean |ln r| per face */
  double r_std, r_mean_abs_dev, r_cv;       /* std of r, mean |r - 1|, std/mean of r */
  double authalic_energy;                   /* sum |domain share - surface share| */
  double vertex_logr_mean_abs, vertex_logr_max_abs; /* barycentric vertex cells, |ln ratio| */
  double angle_diff_mean_deg;               /* mean |domain angle - surface angle| over corners */
  double sph_r_mean_abs_dev, sph_r_cv, sph_vertex_logr_mean_abs; /* sphere: with spherical areas */
  double sphere_radius_max_dev;             /* sphere: max | |p| - 1 | */
  int chord_floor_faces;                    /* sphere: faces whose longest chord edge keeps their chord
                                               area above their share */
  double chord_floor_excess;                /* and that excess, as a fraction of the total */
  int folds;                                /* faces with orientation <= 0 */
  int excluded;                             /* faces left out as degenerate */
  double surface_area, domain_area;         /* totals (domain: chord or planar triangles) */
} au_metrics;

/* The metrics of the map X -> P. X, P: nv x 3 (planar domains: z ignored); F: nf x 3. ups, lam:
 * optional per-face Upsilon and Lambda [0..nf-1] (NaN for excluded faces), may be NULL.
 * Returns AU_OK, AU_E_ARG (NULL arrays, nf <= 0, zero total area), AU_E_NOMEM. */
AU_API au_status au_metrics_compute(int nv, int nf, const double *X, const double *P, const int *F, au_domain domain,
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
AU_API au_status au_metrics_vertex_distortion(int nv, int nf, const double *X, const double *P, const int *F, au_domain domain,
                                       double *out, int *ndegenerate);
/* The same for a map given by per-corner texture coordinates (a torus result's vt, Ft): face f's
 * domain triangle has corners vt[Ft[3f+k]]; the cells are still the nv vertices of F (a vertex on
 * the fundamental domain's edge gathers the areas of all its copies), so out has nv values.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM. */
AU_API au_status au_metrics_vertex_distortion_vt(int nv, int nf, const double *X, const int *F, int nvt, const double *vt,
                                                 const int *Ft, double *out, int *ndegenerate);

/* The per-step log of a map's flow. */
typedef struct au_convergence {
  int steps;         /* advection steps taken */
  int converged;     /* 1 if the tolerance was met */
  int undone;        /* steps solved and then undone for making the areas worse (not in steps) */
  double *err;       /* err [0..steps]: vertex mean |ln ratio| before each step and at the end */
  double *face_err;  /* face_err [0..steps]: per-face mean |r - 1| likewise */
  double *frac;      /* frac [0..steps-1]: mean fraction of the wanted displacement taken */
  int polish_from;   /* sphere: the step from which err and face_err measure chord triangles
                        (spherical ones before it); 0: one measure throughout */
  int angle_from;    /* the step at which the angle steps began; 0: none */
  int resolved;      /* 1 if the flow ran its resolved schedule (a start the mesh resolves well) */
  double start_jump; /* the start's mean jump of log r across interior edges */
  int lantern_retry; /* sphere: 0 none; 1 the retry ran and was discarded; 2 its map was kept; 3 it was due
                        but skipped: its flow would have repeated the first one step for step */
  double retry_err[2]; /* the first map's and the retry's vertex error: the mean |log r| of the vertex cells
                          of the chord triangles, or of the spherical ones for a map of spherical areas
                          only (sphere_areas 2, --spherical-areas): the retries compare maps by the areas
                          the map is made for */
  int twist_retry;   /* sphere: 0 none; 1 the twisted retry ran and was discarded; 2 its map was kept;
                        3 the conformal start folded and the map comes from the strong twisted start */
  int twist_faces;   /* with a twisted retry: the faces its start sheared */
  double twist_err;  /* with a twisted retry: its map's vertex error (as retry_err) */
  int vertex_polish; /* sphere: 0 none; 1 the vertex polish ran and was discarded; 2 it was kept */
  int polish_sweeps; /* with a vertex polish: its sweeps */
  double polish_err[4]; /* with a vertex polish: vertex error before and after it, per-face mean |r - 1|
                           before and after (of the spherical triangles for a map of spherical areas
                           only, au_options.spherical_areas or au_expert.sphere_areas 2; else of the
                           chord ones) */
  int staged_retry;  /* sphere: 0 none; 1 the staged retry (squeezed protrusions: the flow again from the
                        start, in stages) ran and was discarded; 2 its map was kept */
  int staged_stages; /* with a staged retry: its stages (the last run, to the shares, not counted) */
  double staged_err[2]; /* with a staged retry: the vertex error (as retry_err) before it and of its map */
  int global_polish; /* sphere: 0 none; 1 the global polish (every vertex at once, after the vertex polish;
                        of the refined map with refine_mesh) ran and was discarded; 2 it was kept */
  int global_polish_steps; /* with a global polish: its steps */
  double global_polish_err[4]; /* with a global polish: as polish_err (chord triangles) */
  double global_polish_robust; /* with a global polish: the pseudo-Huber d its area residuals ran with, 0 for
                                  squares (docs/sphere-polish-speed.md says where each is used) */
} au_convergence;

#define AU_MAX_WARNINGS 8

/* What au_map returns: the mapped mesh, its metrics and the log. Free with au_result_free. */
typedef struct au_result {
  au_target target;
  au_status status;   /* AU_OK, or AU_W_NOT_CONVERGED: valid and fold-free, tolerance not met */
  int nv, nf;         /* the mapped mesh: the input's counts, or more for the square, which splits
                         edges whose two ends would lie on one side */
  int nv_in, nf_in;   /* the input's counts: vertices [0, nv_in) and faces [0, nf_in) are the
                         input's, in order; split midpoints and their faces come after */
  double *P;          /* P [0..3*nv-1]: the map (unit vectors on the sphere; (u, v, 0) in the plane) */
  double *P0;         /* P0 [0..3*nv-1]: the initial (conformal or harmonic) map */
  double *X;          /* X [0..3*nv-1]: surface positions (the input's, then split midpoints) */
  int *F;             /* F [0..3*nf-1]: faces (the input's, then the split faces) */
  double *uv;         /* planar targets: uv [0..2*nv-1] texture coordinates in [0,1]^2 ((u+1)/2,
                         (v+1)/2 for disk and annulus; (u, v) for the square); NULL on the sphere */
  au_metrics metrics;      /* of P */
  au_metrics init_metrics; /* of P0, when init_measured */
  au_convergence conv;     /* the flow's log (zero with init_only) */
  int init_only;           /* 1 if the flow was not run */
  double t_check, t_init, t_flow, t_metrics; /* seconds in the mesh check, the initial map, the flow,
                                                the metrics */
  long factorizations;     /* sparse numeric factorizations (CHOLMOD) the map made, every stage counted;
                              counted process-wide, so maps made at the same time in other threads add
                              theirs */
  double boundary_dev;     /* planar: the boundary's largest distance from the domain's boundary */
  const char *init_method; /* planar and torus: "cotan" or "meanvalue" (how the harmonic start was made),
                              torus also "compressed" (docs/torus-hard-shapes.md);
                              sphere: "conformal" or "multilevel" (the start that made the map) */
  double inner_radius, modulus_radius; /* annulus: the inner radius used, the conformal modulus's */
  int outer_loop_vertex;   /* annulus: a vertex on the loop mapped to the unit circle */
  int corners[4];          /* square: the corner vertices, in the order (0,0), (1,0), (1,1), (0,1) */
  int nsplit;              /* square: vertices added by splitting */
  int nwarnings;
  char warnings[AU_MAX_WARNINGS][600]; /* one line each, e.g. "tolerance 0.002 not reached in 60
                                          steps (error 3.1e-03)" */
  /* The torus (other targets: zero and NULL). P holds each vertex's position in the fundamental
     domain {s a1 + t a2 : 0 <= s, t <= 1}; a face that crosses the domain's edge has corners outside
     it, so a face is drawn from vt and Ft, not from P (uv is NULL). */
  double lattice[2][2];   /* the lattice's basis: a1 = lattice[0], a2 = lattice[1]; determinant 1 */
  double conformal_lattice[2][2]; /* the conformal modulus's lattice (= lattice unless AU_LATTICE_SQUARE) */
  int nvt;                /* number of texture coordinates, >= nv */
  double *vt;             /* vt [0..2*nvt-1]: row i < nv is P[i]'s (x, y); the rows after it are copies of
                             vertices shifted by exact lattice vectors, for faces across the domain's edge */
  int *Ft;                /* Ft [0..3*nf-1]: the vt row of each corner. Seamless: the two faces of an edge
                             place its two ends at positions that differ by one lattice vector; the faces'
                             vt triangles tile the plane periodically and cover area 1 per period */
  int nrefined;            /* sphere with refine_mesh: vertices added, nv - nv_in; else 0 */
  int *parent;             /* parent [0..2*nrefined-1]: new vertex nv_in + k lies on the segment from
                              vertex parent[2k] to vertex parent[2k+1] (a parent may be a new vertex with
                              a smaller number), at parent_t[k]; NULL without refinement */
  double *parent_t;        /* parent_t [0..nrefined-1]: X[nv_in + k] = (1 - t) X[parent[2k]] +
                              t X[parent[2k+1]] (0.5: the midpoint); NULL without refinement */
  int init_measured;       /* 1 if init_metrics hold the initial map's metrics (au_options.measure_start) */
  /* AU_TARGET_CIRCLES (other targets: 0 and NULL). */
  int ncircles;            /* the boundary loops' circles, one per loop */
  double *circles;         /* circles [0..3*ncircles-1]: centre x, centre y, radius of each */
  int *circle_vertex;      /* circle_vertex [0..ncircles-1]: a vertex of each loop (its first in the loop's order) */
  int circle_outer;        /* the index of the unit circle among them */
} au_result;

/* Map the mesh (V, F) onto target t.
 * V: nv x 3, F: nf x 3 (see the conventions above); not modified, and not needed after the call.
 * opts: may be NULL for au_options_default(). out: on success (status >= 0) *out owns the result;
 * on failure *out is NULL.
 * The mesh is checked first (au_mesh_check). A map is never folded: a map that would be returns
 * AU_E_FOLD and no result.
 * Returns AU_OK; AU_W_NOT_CONVERGED (the map is valid and fold-free, the tolerance was not met:
 * more steps may help); AU_W_UNREFERENCED (unreferenced vertices: they keep P = (0,0,1) or the
 * origin); AU_W_REORIENTED (faces that disagreed with their neighbours were reversed: the result's F
 * holds the re-oriented faces); AU_E_ARG (a bad option: msg names it); AU_E_CANCELLED; AU_E_NOMEM; AU_E_NOT_SPD,
 * AU_E_NUMERIC, AU_E_FOLD, AU_E_INTERNAL; or an input error (<= -100) of the check, AU_E_DENSITY
 * (a density value not positive and finite). The warnings of the result say more than the status.
 * AU_TARGET_TORUS: the conformal start (tree-cotree homology basis, harmonic 1-forms, the conjugate,
 * the period lattice; positive weights if cotan folds), then the least-shear flow in the plane with
 * every face's corners keeping their lattice translations (docs/torus.md); init_only = 1 stops at the
 * start. The Poisson method (expert) is refused with AU_E_ARG. A mesh that is not closed genus 1 gets
 * AU_E_GENUS or AU_E_BOUNDARY naming its genus. */
AU_API au_status au_map(const double *V, int nv, const int *F, int nf, au_target t, const au_options *opts,
                        au_result **out, au_msg *msg);

/* Free a result and set *r to NULL; NULL-safe. */
AU_API void au_result_free(au_result **r);

/* What the report names besides the result (all optional). */
typedef struct au_report_extra {
  const char *input, *output;  /* file names to record; NULL: none */
  const char *tool;            /* the program's name and version; NULL: "libauthalic <version>" */
  double t_read, t_validate, t_write; /* seconds the caller spent; < 0: not reported (t_validate:
                                         the result's own check is reported) */
  const char *const *warnings; int nwarnings; /* the caller's own warnings, after the result's */
} au_report_extra;

/* The JSON report of a result (the `authalic` program's --report): sizes, steps, stage times,
 * warnings, the metrics of the final and initial maps under param-eval's key names, the per-step
 * errors. extra may be NULL. On success *json is a NUL-terminated string the caller frees with
 * au_free. Returns AU_OK, AU_E_ARG, AU_E_NOMEM. */
AU_API au_status au_result_json(const au_result *r, const au_report_extra *extra, char **json, au_msg *msg);

/* ================================================================ equal-area textures and sampling
 * Given a surface (X, F) and its fold-free sphere map P (au_map onto AU_TARGET_SPHERE), lay the
 * sphere out in an equal-area projection (texture coordinates), locate points exactly in the map's
 * triangles, bake and sample attributes, and draw pictures. Texture coordinates (u, v) as in OBJ,
 * v = 0 at the bottom; images row-major with row 0 at the top, so texel (row r, column c) has its
 * centre at u = (c + 0.5)/W, v = 1 - (r + 0.5)/H. lon = atan2(y, x), lat = asin(z). */

typedef enum au_tex_proj {
  AU_TEX_CEA = 0,  /* Lambert cylindrical equal-area: u = (lon + pi)/(2 pi), v = (sin lat + 1)/2; the
                      seam is the meridian lon = +-pi, the poles are the top and bottom rows */
  AU_TEX_LAEA = 1, /* two Lambert azimuthal equal-area charts: the northern hemisphere in the left
                      half of the image, the southern in the right half; each chart is a square of
                      half side `half` around its pole, its ring outside the equator (radius sqrt 2)
                      holding the continuation used by faces across the equator */
  AU_TEX_OCT = 2   /* equal-area octahedral map (Praun & Hoppe 2003, Clarberg 2008): the northern
                      hemisphere fills the diamond |s| + |t| <= 1 of the square [-1, 1]^2, the
                      southern the four corners (the south pole); no poles, the seams are the four
                      southern half meridians (the square's edges, folded at their midpoints); the
                      image is [-half, half]^2, a gutter around the square holding the continuation
                      across its edges (s = (2u - 1) half, t = (2v - 1) half) */
} au_tex_proj;

typedef struct au_tex_layout {
  au_tex_proj proj;
  double half; /* laea: half side of each chart, in [sqrt 2, 2]; oct: half side of the image in the
                  square's units, in [1, 2] (both set by au_tex_coords so that every face fits);
                  cea: ignored */
  double R[9]; /* rotation from the map's frame to the texture's (row-major; the texture's x, y, z
                  axes in the map's frame as rows): (lon, lat) are those of R p. Identity by default */
} au_tex_layout;

/* The layout's default: cea; laea with half = 1.5; oct with half = 1.03; R the identity. */
AU_API au_tex_layout au_tex_layout_default(au_tex_proj proj);

/* Texture coordinates uv [0..2n-1] -> points p [0..3n-1] on the unit sphere, in the map's frame.
 * valid: out [0..n-1] (may be NULL): 1 where (u, v) is the image of a point (cea: 0 <= v <= 1, u
 * modulo 1; laea: inside the chart of radius 2; oct: inside [0, 1]^2), else 0 and p = 0. Returns
 * AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
AU_API au_status au_tex_to_sphere(const au_tex_layout *lay, int n, const double *uv, double *p, unsigned char *valid,
                                  au_msg *msg);
/* Points p [0..3n-1] (map's frame; nonzero, normalized here) -> uv [0..2n-1] in the layout's primary
 * chart (oct: inside the square). Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
AU_API au_status au_tex_from_sphere(const au_tex_layout *lay, int n, const double *p, double *uv, au_msg *msg);
/* Longitude, latitude in degrees of points p [0..3n-1] into lonlat [0..2n-1] (lon 0 at the poles).
 * Returns AU_OK, AU_E_ARG. */
AU_API au_status au_tex_lonlat(int n, const double *p, double *lonlat);

/* Exact sign of det[a b c] = a . (b x c): +1, 0 or -1 (a floating-point filter, then an exact
 * expansion). On the sphere, +1 says c lies left of the great circle from a to b. */
AU_API int au_sph_orient(const double a[3], const double b[3], const double c[3]);

/* Exact point location in the triangles of a sphere map (read-only after building; may be shared
 * by threads). */
typedef struct au_locator au_locator;

/* Build the locator of the map P (nv x 3, unit vectors) with faces F (nf x 3), fold-free (all
 * triangles of one orientation). On success *out owns it. Returns AU_OK, AU_E_ARG, AU_E_NOMEM. */
AU_API au_status au_locator_build(int nv, const double *P, int nf, const int *F, au_locator **out, au_msg *msg);
AU_API void au_locator_free(au_locator **loc);

/* The face whose spherical triangle contains the ray of p (any nonzero vector), by exact
 * predicates; points on shared edges go to the first face found. bary: out (may be NULL), the
 * barycentric coordinates of the piecewise linear map (sum bary_k X[F[f,k]] is p's preimage).
 * hint: in/out (may be NULL), a face to try first. Returns the face, or -1 if none contains p. */
AU_API int au_locator_find(const au_locator *loc, const double p[3], int *hint, double bary[3]);

/* A mesh with per-corner texture coordinates (au_tex_coords): the input's vertices first, then
 * vertices added at the poles or on split edges (each on an input triangle: the midpoint of an
 * edge, so the surface is unchanged), the input's faces first (a split face keeps its index for its
 * first part), then the added ones. */
typedef struct au_tex_mesh {
  int nv, nf;         /* after the splits */
  int nv_in, nf_in;   /* the input's counts */
  double *X;          /* X [0..3*nv-1]: positions on the surface */
  double *P;          /* P [0..3*nv-1]: positions on the sphere (the map's frame) */
  int *F;             /* F [0..3*nf-1] */
  int *src_face;      /* src_face [0..nf-1]: the input face each face comes from */
  int nvt;            /* number of texture coordinates */
  double *vt;         /* vt [0..2*nvt-1]; cea: u may leave [0, 1] on faces across the seam (repeat) */
  int *Ft;            /* Ft [0..3*nf-1]: the texture coordinate of each corner */
  double *lonlat;     /* lonlat [0..2*nv-1]: longitude, latitude in degrees of R P (texture frame) */
  au_tex_layout layout; /* the layout the coordinates refer to */
  int seam_faces;     /* faces whose corners were shifted across the seam (cea), straddle the
                         equator (laea), or were unfolded across the square's edge (oct) */
  int pole_splits;    /* faces split at a pole (cea, 0..2) */
  int pole_vertices;  /* input vertices on a pole */
  int edge_splits;    /* edges split: fold_splits + area_splits */
  int fold_splits;    /* edges split because a face came out turned over in its chart */
  int area_splits;    /* edges split because a face's straight texture area missed its spherical area
                         by more than the tolerance */
  double area_tol;    /* the tolerance used (au_tex_opts.area_tol, or the automatic one; 0: off) */
  double area_err_mean, area_err_max; /* |straight texture area / spherical area - 1| over the final
                         faces (cea: faces with a pole corner left out) */
  int folds_left;     /* faces turned over in the texture: 0 on success */
  int area_worst_first; /* with area splitting: 1 if the kept coordinates split the worst faces first
                           by longest-edge propagation, 0 if every face above the tolerance each
                           round (both are made and the better kept: see au_tex_opts.area_rule) */
  double vt_err_mean;   /* per-face mean |vt share / surface share - 1| of the result (what param-eval
                           measures with --coords vt --domain plane) */
  int area_dropped;     /* with area_rule 0: 1 if the coordinates without area splits were kept
                           (area_splits 0, area_tol the tolerance tried): because they met the target
                           (area_target_met), or had the lowest error of all tries, or every try with
                           area splits left a face turned over (area_tries_failed == area_tries) */
  double area_target;   /* the per-face texture error the area splitting aimed at and the result is
                           judged by (the option, or the automatic one); 0: none */
  int area_target_met;  /* 1 if vt_err_mean <= area_target */
  int area_tries;       /* with area_rule 0: the tries with area splits made (2; 4 when those with
                           the target missed it and both rules were also made without it) */
  int area_tries_failed; /* of those, the ones that left a face turned over (refused) */
} au_tex_mesh;

/* Options of au_tex_coords_opts. */
typedef enum au_tex_axis {
  AU_TEX_AXIS_Z = 0,     /* the map's own axes: poles on its z axis, cea's seam at its -x */
  AU_TEX_AXIS_AUTO = 1,  /* poles where the map's triangles are smallest (least mean spherical area of
                            the faces within 10 degrees of either pole, over 500 directions), then
                            turned about that axis so the seam crosses the fewest faces (cea: the
                            meridian at 180 degrees; oct: the four southern half meridians) */
  AU_TEX_AXIS_VECTOR = 2 /* the north pole at axis_dir */
} au_tex_axis;

typedef struct au_tex_opts {
  au_tex_proj proj;    /* projection (AU_TEX_CEA) */
  au_tex_axis axis;    /* where the texture's poles go (AU_TEX_AXIS_Z) */
  double axis_dir[3];  /* AU_TEX_AXIS_VECTOR: the north pole in the map's frame, nonzero, any length
                          ((0, 0, 1)) */
  double area_tol;     /* 0 (default): no splitting for area (only faces that would turn over are
                          split); > 0: also split a face while |straight texture area / spherical
                          area - 1| exceeds this, until area_target is met (with auto on the
                          shared meshes: 1-15x the faces, docs/textures.md);
                          < 0: that with an automatic tolerance, a quarter of the map's per-face
                          mean |r - 1| (spherical areas), at least 0.001 */
  int max_rounds;      /* rounds of splitting for area, 0..64 (16; with a target, rounds that split
                          for area); splitting for folds goes on until none is left, or gives up
                          (AU_E_NUMERIC) when the folds have not come down to a new low for 1024
                          rounds, after 4096 rounds (with a target: after the last area split), at
                          64x the faces, or when the folds rise 8 rounds in a row */
  int area_rule;       /* with area splitting: 0 (default) both rules below and no area splits at all,
                          the best kept (au_tex_mesh.vt_err_mean, area_dropped): with a target, the
                          fewest faces among those that meet it, else the lowest per-face texture
                          error; 1 every face above the tolerance each round; 2 the worst faces
                          first, by longest-edge propagation (docs/textures.md) */
  double area_target;  /* with area splitting: stop splitting for area once the texture's per-face mean
                          |vt share / surface share - 1| is at most this (> 0); < 0 (default): the
                          sphere map's own error, 1.25 x its per-face mean |r - 1| (chord triangles,
                          what param-eval IN MAP measures) + 0.002; 0: no target */
  int area_growth;     /* area splitting stops once the faces have grown this many times, 1..64;
                          0 (default): 8, or 32 with a target */
} au_tex_opts;

/* The defaults above. */
AU_API au_tex_opts au_tex_opts_default(void);

/* Texture coordinates of the sphere map P (nv x 3, fold-free) of m with the options opts (NULL: the
 * defaults). Every face comes out the map's way round in the texture (faces are split until it
 * does: au_tex_mesh.fold_splits), and, when area_tol is not 0, faces whose straight-edged texture
 * triangle misses its spherical area by more than area_tol are split too (area_splits). On success *out owns the
 * result. Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC, AU_E_FOLD. */
AU_API au_status au_tex_coords_opts(const au_mesh *m, const double *P, const au_tex_opts *opts, au_tex_mesh **out,
                                    au_msg *msg);
/* au_tex_coords_opts with the default options but the projection. */
AU_API au_status au_tex_coords(const au_mesh *m, const double *P, au_tex_proj proj, au_tex_mesh **out, au_msg *msg);
AU_API void au_tex_mesh_free(au_tex_mesh **t);

/* Write t as OBJ (v, vt, f v/vt), atomically. mtl_name: NULL, or a material library to name
 * (`mtllib`, `usemtl authalic`). Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO. */
AU_API au_status au_tex_write_obj(const char *path, const au_tex_mesh *t, const char *mtl_name, au_msg *msg);

/* For each texel of a W x H image in layout lay, the face holding the texel centre's point and its
 * barycentric coordinates. face: out [0..W*H-1] (-1: no point); bary: out [0..3*W*H-1] (may be
 * NULL). Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
AU_API au_status au_tex_locate_texels(const au_tex_layout *lay, const au_locator *loc, int W, int H, int *face,
                                      double *bary, au_msg *msg);
/* out[i*k + j] = sum_c bary[3i+c] A[F[3 face[i] + c]*k + j] for n located points with k components;
 * NaN where face[i] < 0. Returns AU_OK, AU_E_ARG. */
AU_API au_status au_tex_interpolate(int n, const int *face, const double *bary, const int *F, int k, const double *A,
                                    double *out);
/* Area-weighted unit vertex normals N [0..3*nv-1] (0 for unreferenced). Returns AU_OK, AU_E_ARG,
 * AU_E_NOMEM. */
AU_API au_status au_tex_vertex_normals(const au_mesh *m, double *N);
/* The surface area of the preimage of every cell of the W x H equal-area (cea) grid, the surface
 * scaled to total area 4 pi (an exact authalic map gives every cell 4 pi / (W H)); sub x sub
 * sub-cells each. area: out [0..W*H-1], rows top to bottom. Returns AU_OK, AU_E_ARG, AU_E_NOMEM,
 * AU_E_NUMERIC. */
AU_API au_status au_tex_cell_areas(const au_mesh *m, const double *P, const au_locator *loc, int W, int H, int sub,
                                   double *area, au_msg *msg);

/* Write an 8-bit RGB image (rgb [0..3*W*H-1], rows top to bottom) as PNG, atomically.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO. */
AU_API au_status au_png_write(const char *path, int W, int H, const unsigned char *rgb, au_msg *msg);
/* Read an 8-bit RGB(A) or grey PNG as RGB; *rgb (3*W*H bytes) is freed with au_free.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO, AU_E_FORMAT. */
AU_API au_status au_png_read(const char *path, int *W, int *H, unsigned char **rgb, au_msg *msg);
/* Colour maps, t in [0, 1] (clamped; NaN grey): viridis, and blue - white - dark red. */
AU_API void au_cmap_viridis(double t, unsigned char rgb[3]);
AU_API void au_cmap_diverging(double t, unsigned char rgb[3]);

/* The preview picture of a sphere map: the sphere from +z and -z side by side, faces coloured by
 * Upsilon over [-range, range] (range <= 0: 0.5), and the Upsilon and Lambda histograms below.
 * size: width in pixels (>= 200). Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO, AU_E_NUMERIC. */
AU_API au_status au_tex_preview(const char *path, const au_mesh *m, const double *P, int size, double range,
                                au_msg *msg);
/* The preview picture of a torus result (AU_TARGET_TORUS, from au_map): its vt triangles tiled 3 x 3
 * by the lattice (seamless maps tile without gaps or overlaps), faces coloured by Upsilon over
 * [-range, range] (range <= 0: 0.5), the tiles' edges grey and the fundamental domain black, the
 * Upsilon and Lambda histograms below. size: width in pixels (>= 200). Returns AU_OK, AU_E_ARG,
 * AU_E_NOMEM, AU_E_IO, AU_E_NUMERIC. */
AU_API au_status au_torus_preview(const char *path, const au_result *r, int size, double range, au_msg *msg);
/* Render the surface of t with the texture img (tw x th RGB) from direction view and from -view,
 * side by side; size: height in pixels (>= 64); mark_seam: 1 tints the cea seam's faces red.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO. */
AU_API au_status au_tex_render(const char *path, const au_tex_mesh *t, const unsigned char *img, int tw, int th,
                               const double view[3], int size, int mark_seam, au_msg *msg);
/* A unit direction from the surface's centroid towards the middle of the cea seam. Returns AU_OK,
 * AU_E_ARG. */
AU_API au_status au_tex_seam_view(const au_tex_mesh *t, double view[3]);

/* Write a NumPy .npy file (version 1.0, '<f8', C order) of the given shape (ndim 1..4), atomically.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO. */
AU_API au_status au_npy_write(const char *path, int ndim, const long *shape, const double *data, au_msg *msg);

/* ---- the view page (docs/view.md) */

/* What au_view_html shows: a surface and its map. The map is either P at the vertices (on a sphere
 * about the origin of any radius, drawn as a globe; or in the plane z = 0, drawn flat) or per-corner
 * plane coordinates (vt, Ft: drawn flat, tiled 3 x 3 when the copies of the vertices differ by a
 * lattice, as a torus map's do). */
typedef struct au_view_input {
  int nv, nf;            /* the surface's vertices and faces (> 0) */
  const double *X;       /* X [0..3*nv-1] */
  const int *F;          /* F [0..3*nf-1], 0 <= F < nv */
  const double *P;       /* P [0..3*nv-1]: the map at the vertices; NULL (default) when vt is given */
  int nvt;               /* the map by corners instead: nvt rows of vt (0, default: none) */
  const double *vt;      /* vt [0..2*nvt-1] */
  const int *Ft;         /* Ft [0..3*nf-1], 0 <= Ft < nvt: the vt row of each corner */
  const double *attr;    /* attr [0..nv-1]: a per-vertex value to colour by (curv, sulc, ...); NULL (default) */
  const char *attr_name; /* its name on the page; NULL (default): "attribute" */
  const char *title;     /* the page's title; NULL (default): none */
  int steps;             /* the flow's steps, shown with the figures; -1 (default): not known */
  double seconds;        /* the run's seconds, likewise; < 0 (default): not known */
} au_view_input;

/* An au_view_input with the defaults above and everything else 0 or NULL. */
AU_API au_view_input au_view_input_default(void);

/* One self-contained HTML page (nothing is fetched when it opens; three.js is inlined) with the
 * surface and its map side by side, both coloured by the per-face area distortion log r on a
 * diverging scale (switchable to the angle distortion Lambda, a checkerboard through the map and the
 * attribute), linked cursors, the headline figures (folds, per-face mean |r - 1|, vertex mean |log r|
 * as au_metrics_compute gives them, steps, time) and the distortion histograms. On success *html is
 * the page (free with au_free) and *len its length (len may be NULL). Returns AU_OK, AU_E_ARG (a
 * missing array, both or neither of P and vt, an index out of range), AU_E_NOMEM, or the status of
 * the metrics (a zero total area). */
AU_API au_status au_view_html(const au_view_input *in, char **html, size_t *len, au_msg *msg);
/* au_view_html written to path atomically (au_write_text). Returns its statuses and AU_E_IO. */
AU_API au_status au_view_write(const char *path, const au_view_input *in, au_msg *msg);

/* ================================================================ atlas (any genus)
 * An atlas of any connected orientable manifold mesh, closed or open, of any genus: cones placed where
 * the conformal factor is extreme (or given), a flat cone metric by a convex conformal solve, a cut
 * through the cones and a homology basis into disk-like charts laid out in that metric (the conformal
 * start), then the equal-area flow with a rigid motion per corner (both sides of every seam move
 * together), charts split where they would overlap, packed into [0,1]^2 at one scale. Seams match by a
 * rigid motion. equal_area says whether the flow reached a per-face mean |r - 1| of 0.02. docs/atlas.md. */

/* Options of au_atlas; start from au_atlas_options_default(). */
typedef struct au_atlas_options {
  int max_cones;            /* automatic cones: at most this many (default 24); with quarter, up to twice
                               as many where the rounded cones leave the conformal factor's range wide
                               (docs/atlas-quarter.md) */
  int quarter;              /* 1: cone angles in multiples of pi/2 and every loop's holonomy a multiple
                               of pi/2, so every seam turns by a quarter turn (default 0) */
  int ncones;               /* > 0: these cones instead of automatic ones (default 0) */
  const int *cone_v;        /* cone_v [0..ncones-1]: interior vertices */
  const double *cone_angle; /* cone_angle [0..ncones-1]: angles in radians; on a closed surface the
                               curvatures 2 pi - angle must sum to 2 pi chi */
  int raster;               /* the raster the overlap check uses, in pixels a side (default 1024) */
  int conformal_only;       /* 1: stop at the conformal start, no equal-area flow (default 0) */
  int max_steps;            /* most steps of the equal-area flow, 1..10000 (default 200) */
} au_atlas_options;
AU_API au_atlas_options au_atlas_options_default(void);

/* An atlas. All arrays are owned by the result (au_atlas_result_free). */
typedef struct au_atlas_result {
  int nv, nf;
  int *F;             /* F [0..3*nf-1]: the faces (the input's, re-oriented where they disagreed) */
  int nvt;
  double *vt;         /* vt [0..2*nvt-1]: per-corner texture coordinates in [0,1]^2 */
  int *Ft;            /* Ft [0..3*nf-1]: the row of vt of corner k of face f */
  int ncones;
  int *cone_v;        /* cone vertices and their angles (radians) */
  double *cone_angle;
  int ncharts, nseams, ncut; /* charts, seams (chains of cut edges), cut edges */
  double *seam_rot;   /* seam_rot [0..nseams-1]: each seam's rotation, radians */
  double seam_rot_dev;  /* largest deviation of a seam edge's rotation from its seam's */
  double seam_len_dev;  /* largest difference of a seam edge's two lengths, atlas units */
  double coverage;      /* share of the unit square the charts cover */
  int folds;            /* faces turned over in vt (0 on success) */
  long overlap_texels;  /* pixel centres of the raster covered twice (0 on success) */
  int equal_area;       /* 1: the flow brought the per-face mean |r - 1| to 0.02 or below */
  int flow_steps;       /* steps of the equal-area flow (0: not run) */
  double face_err_start, face_err; /* per-face mean |r - 1| of the conformal start and of the result */
  int genus, nloops;
  int newton_steps;     /* of the cone metric */
  double metric_err;    /* the metric's largest angle-sum error, radians */
  int holonomy_loops;   /* with quarter cones: the homology loops (2 genus + boundary loops - 1) */
  int holonomy_cones;   /* quarter turns and one-edge moves of automatic cones that brought the loops' holonomy nearer */
  int holonomy_fixed;   /* the homology loops whose holonomy was made a multiple of pi/2 (all, or 0 with a warning) */
  double holonomy_dev;  /* the conformal metric's largest |holonomy - nearest multiple of pi/2|, radians */
  double holonomy_len_change; /* the largest relative change of an edge length that fixing it took */
  double t_check, t_cones, t_metric, t_layout, t_flow; /* seconds */
  au_status status;
  int nwarnings;
  char warnings[4][512];
} au_atlas_result;

/* The atlas of (V, F). Returns AU_OK, AU_W_REORIENTED, AU_W_UNREFERENCED (the status of the mesh's
 * check; warnings say more), AU_W_NOT_CONVERGED (the metric missed its tolerance: the atlas is still
 * fold-free and overlap-free but its seams match less exactly), AU_E_ARG (bad options or cones: msg
 * says which), AU_E_NOMEM, AU_E_NOT_SPD, AU_E_NUMERIC, AU_E_FOLD (the layout folded or overlapped),
 * AU_E_TOO_COARSE (with quarter: a closed mesh whose every vertex is a cone, one of whose angle sums is
 * not a multiple of pi/2: msg names the vertex), or an input error of the check (several components,
 * non-manifold, non-orientable...). */
AU_API au_status au_atlas(const double *V, int nv, const int *F, int nf, const au_atlas_options *o,
                          au_atlas_result **out, au_msg *msg);
AU_API void au_atlas_result_free(au_atlas_result **r);
/* The result as JSON (free with au_free). t_read, t_write: seconds to report, or < 0 to leave out. */
AU_API au_status au_atlas_result_json(const au_atlas_result *r, double t_read, double t_write, char **json,
                                      au_msg *msg);

#ifdef __cplusplus
}
#endif
#endif
