/* cli_options.h - every option of every command of the `authalic` program, in one table that
 * generates the parser and the --help texts (cli_parse, cli_print_options in cli.c). A command
 * reads the parsed values by id and converts them with the cli_opt_* helpers (cli.h). */
#ifndef AU_CLI_OPTIONS_H
#define AU_CLI_OPTIONS_H

/* The commands, as bits: an option lists the commands that take it. */
enum {
  CLI_SPHERE = 1,
  CLI_DISK = 2,
  CLI_ANNULUS = 4,
  CLI_SQUARE = 8,
  CLI_TEXTURE = 16,
  CLI_SAMPLE = 32,
  CLI_TORUS = 64,
  CLI_CIRCLES = 128,
  CLI_ATLAS = 256,
  CLI_PLANAR = CLI_DISK | CLI_ANNULUS | CLI_SQUARE | CLI_CIRCLES,
  CLI_MAPS = CLI_SPHERE | CLI_PLANAR,
  CLI_ALL = CLI_MAPS | CLI_TEXTURE | CLI_SAMPLE | CLI_TORUS | CLI_ATLAS
};

/* How an option takes its value. */
enum {
  CLI_FLAG = 0,   /* no value; at most once */
  CLI_VALUE = 1,  /* one value; at most once */
  CLI_FILE = 2,   /* one file name, not empty; at most once */
  CLI_REPEAT = 3  /* a file name, repeatable (up to CLI_MAX_REPEAT times) */
};
#define CLI_MAX_REPEAT 16

/* X(id, name, metavar, kind, commands, help). An id may appear in several rows, one per wording of
 * its help (the rows' commands must not overlap). In the help, "%D" is replaced by the option's
 * default for the command (cli.c, option_default), "%M" by its largest value. Rows are printed in
 * this order. */
#define CLI_OPTIONS(X)                                                                                                 \
  X(OPT_MAP, "map", "SPHERE_MAP", CLI_FILE, CLI_TEXTURE | CLI_SAMPLE,                                                 \
    "the sphere map of IN (same vertices and faces, positions on a sphere about the origin of any radius); "       \
    "computed on the fly when absent, then driving the spherical triangles' areas only (no chord polish)")          \
  X(OPT_GRID, "grid", "WxH", CLI_VALUE, CLI_SAMPLE, "grid size, W and H from 1 to 16384 (required)")                \
  X(OPT_REPORT, "report", "R.json", CLI_FILE, CLI_MAPS | CLI_TORUS,                                                  \
    "write a JSON report: metrics of the result and of the initial map, per-step errors, stage times, warnings")    \
  X(OPT_STEPS, "steps", "K", CLI_VALUE, CLI_MAPS | CLI_TORUS, "most advection steps, 1..%M (default %D)")           \
  X(OPT_STEPS, "steps", "K", CLI_VALUE, CLI_ATLAS, "most steps of the equal-area flow, 1..10000 (default 200)")    \
  X(OPT_TOL, "tol", "T", CLI_VALUE, CLI_MAPS | CLI_TORUS, "stop when the vertex mean |log area ratio| is below T, T >= 0 (default %D)") \
  X(OPT_DENSITY, "density", "FILE", CLI_FILE, CLI_MAPS | CLI_TORUS,                                                  \
    "prescribed density: one positive number per vertex (or per face) of IN, in order: text (whitespace-"          \
    "separated), a FreeSurfer curv or a GIfTI .shape.gii/.func.gii file; domain area is proportional to density "  \
    "x surface area")                                                        \
  X(OPT_BOUNDARY, "boundary", "MODE", CLI_VALUE, CLI_PLANAR,                                                         \
    "slide (default): boundary vertices slide along the domain's boundary (square: corners fixed); fixed: the "     \
    "initial map's boundary is kept")                                                                                \
  X(OPT_INNER_RADIUS, "inner-radius", "R", CLI_VALUE, CLI_ANNULUS,                                                   \
    "radius of the inner circle, 0 < R < 1 (default: the conformal modulus's)")                                      \
  X(OPT_OUTER_LOOP, "outer-loop", "WHICH", CLI_VALUE, CLI_ANNULUS,                                                   \
    "the loop mapped to the unit circle: longer (default), shorter, or the index of a vertex on it")                 \
  X(OPT_CORNERS, "corners", "I,J,K,L", CLI_VALUE, CLI_SQUARE,                                                        \
    "boundary vertices (0-based) for the corners: I goes to (0,0), the others to (1,0), (1,1), (0,1) in the "       \
    "order they follow I along the boundary (default: the most corner-like vertices near the arc-length quarters)") \
  X(OPT_OUTER, "outer", "V", CLI_VALUE, CLI_CIRCLES,                                                                 \
    "a vertex on the loop mapped to the unit circle (default: a vertex of the longest loop)")                         \
  X(OPT_ASPECT, "aspect", "W:H", CLI_VALUE, CLI_SQUARE,                                                              \
    "map onto the rectangle of width to height W:H (the longer side 1; default 1:1): the square's equal-area map "  \
    "stretched, which keeps it equal area")                                                                          \
  X(OPT_RESTORE, "restore-shapes", "F", CLI_VALUE, CLI_SPHERE,                                                       \
    "while the spherical areas are driven, aim each step's shear a fraction F (0..1, default %D; 0: off) back at "  \
    "the surface's triangle shapes: fewer long, thin triangles")                                                     \
  X(OPT_REFINE_FACES, "refine-faces", NULL, CLI_FLAG, CLI_MAPS,                                                      \
    "once the vertex cells meet the tolerance, go on refining the triangles' areas as long as it helps at all "     \
    "(default: while it gains 10% in 4 steps), on the flow's ordinary schedule")                                     \
  X(OPT_ANGLES, "angles", "N", CLI_VALUE, CLI_MAPS | CLI_TORUS,                                                      \
    "N steps (1..%M) towards the map of least Dirichlet energy with the vertex cells held at their areas: less "     \
    "angle distortion, vertex cells within about 1e-4, the triangles' areas held near theirs (on the sphere from "  \
    "a vertex error of 0.01 on, elsewhere after the flow)")                                                          \
  X(OPT_REFINE_MESH, "refine-mesh", "SURF", CLI_FILE, CLI_SPHERE,                                                    \
    "split the map's long edges where a chord triangle cannot shrink to its share, with new vertices on the "     \
    "input's edges, and flow again (at most twice the faces, see --refine-budget); OUT gets the refined mesh's map, SURF its surface, "  \
    "SURF.parents.txt one line per new vertex: its number, its parents' numbers (0-based) and t, the vertex being " \
    "(1 - t) parent1 + t parent2")                                                                                   \
  X(OPT_REFINE_BUDGET, "refine-budget", "K", CLI_VALUE, CLI_SPHERE,                                                  \
    "with --refine-mesh: at most K times the input's faces instead of twice (K above 1, at most 16), or auto: 2x, "  \
    "then 3x and 4x while the refined map's per-face mean |r-1| is over 0.02 or its vertex error over 0.005 (the "   \
    "first that meets both is kept, else the lowest per-face); long, thin limbs meet those at 2x (limbs4, coil) or " \
    "3x (limbs8, tpose; "                                                                                             \
    "docs/sphere.md)")                                                                                          \
  X(OPT_START, "start", "S", CLI_VALUE, CLI_SPHERE,                                                                 \
    "conformal (default): the balanced conformal map, which squeezes protrusions exponentially; multilevel: "     \
    "coarse-to-fine, the mesh simplified to a few hundred vertices, mapped, and its vertices brought back level by " \
    "level inside their rings (docs/coarse-to-fine.md); the report's \"start\" says which ran")                    \
  X(OPT_NO_BALANCE, "no-balance", NULL, CLI_FLAG, CLI_SPHERE, "skip the Moebius balancing of the conformal start")  \
  X(OPT_SPHERICAL_AREAS, "spherical-areas", NULL, CLI_FLAG, CLI_SPHERE,                                              \
    "equalize the spherical triangles' areas and skip the chord polish: the map `texture` and `sample` make "      \
    "for themselves (closer texture areas; param-eval's chord figures are higher)")                                 \
  X(OPT_INIT_ONLY, "init-only", NULL, CLI_FLAG, CLI_MAPS | CLI_TORUS,                                                \
    "stop after the initial (conformal or harmonic) map, for comparison")                                            \
  X(OPT_INIT_ONLY, "init-only", NULL, CLI_FLAG, CLI_ATLAS,                                                           \
    "stop at the conformal cone atlas (no equal-area flow), for comparison")                                         \
  X(OPT_LATTICE, "lattice", "SHAPE", CLI_VALUE, CLI_TORUS,                                                           \
    "conformal (default): the conformal modulus's lattice, scaled to area 1; square: the unit square (the linear "   \
    "map from the conformal lattice, no longer conformal)")                                                          \
  X(OPT_FORMAT, "format", "F", CLI_VALUE, CLI_MAPS,                                                                 \
    "write OUT as obj, off, ply, freesurfer (binary triangle surface, big-endian, float32) or gifti (.gii; "         \
    "gzip-compressed for a .gii.gz name); default: by OUT's extension, and an OUT with none "                        \
    "(lh.sphere.authalic) gets the input's format")                                                                  \
  X(OPT_RADIUS, "radius", "R", CLI_VALUE, CLI_SPHERE,                                                                \
    "write the sphere with radius R, 1e-30 <= R <= 1e30 (FreeSurfer and HCP spheres: 100); the metrics and the report are those "   \
    "of the unit sphere (default 1)")                                                                                \
  X(OPT_DISTORTION, "distortion", "FILE", CLI_FILE, CLI_SPHERE | CLI_PLANAR | CLI_TEXTURE | CLI_TORUS,               \
    "per-vertex areal distortion log2(map area share / surface area share) of the barycentric vertex cells "         \
    "(HCP's convention): a FreeSurfer curv file, or GIfTI when FILE ends in .gii (e.g. .shape.gii)")                \
  X(OPT_PROJECTION, "projection", "P", CLI_VALUE, CLI_TEXTURE,                                                       \
    "cea (default): Lambert cylindrical equal-area, u = (lon + pi)/(2 pi), v = (sin lat + 1)/2; sample with u "     \
    "wrapped (repeat). laea: Lambert azimuthal equal-area, northern hemisphere in the left half, southern in the "  \
    "right half (no wrapping needed). oct: equal-area octahedral square, no poles, a thin gutter around it")        \
  X(OPT_AXIS, "axis", "A", CLI_VALUE, CLI_TEXTURE,                                                                   \
    "the texture's north pole: z (default, the map's own axes), x, y, a vector X,Y,Z, or auto (the poles where the " \
    "map's triangles are smallest, the seam across the fewest faces; the rotation is printed)")                    \
  X(OPT_AREA_TOL, "area-tol", "T", CLI_VALUE, CLI_TEXTURE,                                                           \
    "also split faces whose straight texture triangle misses its spherical area by more than T (e.g. 0.01; auto: a " \
    "quarter of the map's per-face error), until the texture is as exact as the map (--area-target): closer "    \
    "per-face areas at more faces (default 0: off)")                                                                 \
  X(OPT_AREA_TARGET, "area-target", "E", CLI_VALUE, CLI_TEXTURE,                                                     \
    "with --area-tol: stop splitting once the texture's per-face mean |r-1| is at most E (default auto: the map's "  \
    "own, 1.25 x its per-face mean |r-1| + 0.002, at most 32x the faces; 0: no target, at most 8x the faces)")       \
  X(OPT_LONLAT, "lonlat", "FILE", CLI_FILE, CLI_TEXTURE,                                                             \
    "write longitude and latitude in degrees of every vertex of OUT.obj")                                            \
  X(OPT_BAKE, "bake", "ATTR", CLI_FILE, CLI_TEXTURE,                                                                 \
    "bake a per-vertex attribute into --image: `normal` (unit normals as colours (n + 1)/2), `position` (the "      \
    "bounding box as RGB), or a file with one number per vertex of IN (text, FreeSurfer curv, GIfTI .shape.gii or " \
    ".func.gii), drawn with the viridis colour map")                                                                 \
  X(OPT_IMAGE, "image", "OUT.png", CLI_FILE, CLI_TEXTURE,                                                            \
    "the baked texture; OUT.mtl is written beside OUT.obj and names it")                                             \
  X(OPT_SIZE, "size", "WxH", CLI_VALUE, CLI_TEXTURE, "texture size in texels (default 1024x512; laea needs an even W)") \
  X(OPT_NORMALS, "normals", NULL, CLI_FLAG, CLI_SAMPLE, "add the surface normal (3 columns)")                       \
  X(OPT_ATTR, "attr", "FILE", CLI_REPEAT, CLI_SAMPLE,                                                                \
    "add a per-vertex scalar (one number per vertex: a text file, a FreeSurfer curv file such as lh.sulc, or "     \
    "GIfTI .shape.gii / .func.gii); repeatable")                                                                     \
  X(OPT_REPORT, "report", "R.json", CLI_FILE, CLI_SAMPLE,                                                            \
    "the surface area of every cell's preimage (mean, std/mean, min, max) and the map's distortion")                \
  X(OPT_PREVIEW, "preview", "P.png", CLI_FILE, CLI_TEXTURE | CLI_SAMPLE,                                             \
    "the sphere map from +z and -z coloured by Upsilon = ln(surface/sphere area) from -0.5 (blue) to +0.5 (red), " \
    "with the Upsilon (dark red) and Lambda (blue) histograms")                                                      \
  X(OPT_PREVIEW, "preview", "P.png", CLI_FILE, CLI_TORUS,                                                            \
    "the map's vt triangles tiled 3 x 3 by the lattice, coloured by Upsilon = ln(surface/domain area) from -0.5 "   \
    "(blue) to +0.5 (red), the fundamental domain outlined, with the Upsilon and Lambda histograms")                 \
  X(OPT_RENDER, "render", "R.png", CLI_FILE, CLI_TEXTURE,                                                            \
    "IN drawn with the baked texture through OUT.obj's coordinates, from the side of the seam and from the "       \
    "opposite side (needs --bake)")                                                                                  \
  X(OPT_MARK_SEAM, "mark-seam", NULL, CLI_FLAG, CLI_TEXTURE, "tint the faces across the cea seam red in --render")  \
  X(OPT_HTML, "html", "OUT.html", CLI_FILE, CLI_MAPS | CLI_TORUS | CLI_ATLAS,                                                  \
    "the map as one self-contained interactive page (authalic view; docs/view.md)")                                  \
  X(OPT_CONES, "cones", "FILE", CLI_FILE, CLI_ATLAS,                                                                 \
    "the cones instead of automatic ones: one line per cone, a vertex (0-based) and its angle in degrees; on a "    \
    "closed surface the curvatures 360 - angle must sum to 360 x Euler characteristic")                            \
  X(OPT_QUARTER, "quarter", NULL, CLI_FLAG, CLI_ATLAS,                                                              \
    "cone angles and every loop's holonomy in multiples of 90 degrees: every seam turns by a quarter turn")          \
  X(OPT_MAX_CONES, "max-cones", "N", CLI_VALUE, CLI_ATLAS,                                                           \
    "at most N automatic cones, 1..1000 (default 24; with --quarter up to 2N where needed)")                         \
  X(OPT_REPORT, "report", "R.json", CLI_FILE, CLI_ATLAS,                                                             \
    "write a JSON report: cones, charts, seams and their rotations, coverage, folds, overlapping texels, times")    \
  X(OPT_QUIET, "quiet", NULL, CLI_FLAG, CLI_ALL, "no progress and no summary on stderr (errors and warnings remain)") \
  X(OPT_HELP, "help", NULL, CLI_FLAG, CLI_ALL, "this text")

/* The ids, each once. */
typedef enum cli_opt_id {
  OPT_MAP, OPT_GRID, OPT_REPORT, OPT_STEPS, OPT_TOL, OPT_DENSITY, OPT_BOUNDARY, OPT_INNER_RADIUS, OPT_OUTER_LOOP,
  OPT_CORNERS, OPT_RESTORE, OPT_REFINE_FACES, OPT_ANGLES, OPT_REFINE_MESH, OPT_REFINE_BUDGET, OPT_START, OPT_NO_BALANCE, OPT_SPHERICAL_AREAS, OPT_INIT_ONLY, OPT_LATTICE,
  OPT_FORMAT, OPT_RADIUS, OPT_DISTORTION, OPT_PROJECTION, OPT_AXIS, OPT_AREA_TOL, OPT_AREA_TARGET, OPT_LONLAT,
  OPT_BAKE, OPT_IMAGE, OPT_SIZE, OPT_NORMALS, OPT_ATTR, OPT_PREVIEW, OPT_RENDER, OPT_MARK_SEAM, OPT_HTML, OPT_QUIET, OPT_HELP,
  OPT_OUTER, OPT_ASPECT, OPT_CONES, OPT_QUARTER, OPT_MAX_CONES,
  OPT_COUNT
} cli_opt_id;

/* What cli_parse found. */
typedef struct cli_args {
  int cmd;                 /* the command's bit */
  const char *help;        /* "authalic CMD --help", for error messages */
  const char *pos[3];      /* positional arguments in order */
  int npos;
  const char *val[OPT_COUNT]; /* the value of each option given (flags: "" ), NULL if absent */
  const char *rep[CLI_MAX_REPEAT]; /* the values of the repeatable option, in order */
  int nrep;
} cli_args;

#endif
