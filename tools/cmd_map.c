/* cmd_map.c - `authalic sphere | disk | annulus | square | torus IN OUT`: a mesh onto the unit sphere,
 * the unit disk, an annulus with outer radius 1, the unit square or a flat torus (argv[0] says which),
 * through the public entry point au_map. Parses, reads, maps, writes; no numerics. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

static const char *const usage_sphere =
    "usage: authalic sphere IN OUT [options]\n\n"
    "Maps the closed genus-0 triangle mesh IN onto the unit sphere so that every vertex cell keeps\n"
    "its share of the surface area, and writes the map to OUT (.obj .off .ply .gii, or FreeSurfer).\n"
    "Progress and a summary line go to stderr; OUT and the report are written only when the whole run\n"
    "succeeded.\n\n";
static const char *const usage_disk =
    "usage: authalic disk IN OUT [options]\n\n"
    "Maps the triangle mesh IN, which must have one boundary loop (a topological disk), onto the\n"
    "unit disk so that every vertex cell keeps its share of the surface area. The boundary stays on\n"
    "the unit circle and slides along it during the flow.\n\n";
static const char *const usage_annulus =
    "usage: authalic annulus IN OUT [options]\n\n"
    "Maps the triangle mesh IN, which must have two boundary loops (a topological annulus), onto\n"
    "an annulus centred at the origin with outer radius 1 so that every vertex cell keeps its share\n"
    "of the surface area. Both loops slide along their circles during the flow.\n\n";
static const char *const usage_square =
    "usage: authalic square IN OUT [options]\n\n"
    "Maps the triangle mesh IN, which must have one boundary loop, onto the unit square [0,1]^2 so\n"
    "that every vertex cell keeps its share of the surface area (Zou et al. 2011, sec. 4.1). Four\n"
    "boundary vertices go to the corners and stay there; the others slide along their sides.\n"
    "Triangles whose three vertices would land on one side are split first: the new vertices\n"
    "(edge midpoints) come after the input's vertices in OUT, the new faces after its faces.\n\n";
static const char *const usage_torus =
    "usage: authalic torus IN OUT.obj [options]\n\n"
    "Maps the closed genus-1 triangle mesh IN onto a flat torus: the plane modulo a lattice of\n"
    "area 1, with no cut (tree-cotree homology basis, harmonic 1-forms, their conjugate; the period\n"
    "lattice is the conformal modulus), then made equal-area by the least-shear Lie advection in\n"
    "the plane, each face's corners keeping their lattice translations (the lattice, so the total\n"
    "area 1, is kept). --angles works as elsewhere; --init-only stops at the conformal start.\n\n"
    "OUT.obj has the input's vertices (surface positions, in order) and faces, with `vt` in the\n"
    "plane: each vertex once in the fundamental domain, and where a face crosses the domain's edge\n"
    "its corners get their own `vt` copies shifted by exact lattice vectors (seamless: the texture\n"
    "repeats by the lattice). The report gives \"lattice\": [[a1x, a1y], [a2x, a2y]].\n\n";
static const char *const usage_circles =
    "usage: authalic circles IN OUT [options]\n\n"
    "Maps the genus-0 triangle mesh IN with k >= 1 boundary loops onto the unit disk with k - 1 round\n"
    "holes (a circle domain) so that every vertex cell keeps its share of the surface area. Every\n"
    "boundary vertex slides along its circle and each hole's centre moves with the flow; a hole's\n"
    "area is that of the flat cap over its loop, scaled with the surface. k = 1 is the disk map.\n"
    "The report lists each loop's circle: a vertex on it, centre and radius (docs/circles.md).\n\n";
static const char *const usage_planar_out =
    "OUT (.obj .off .ply .gii, or FreeSurfer) has the input's vertices in the input's order and its\n"
    "faces, with positions (u, v, 0); an .obj also gets `vt` texture coordinates in [0,1]^2. Progress\n"
    "and a summary line go to stderr; OUT and the report are written only when the whole run succeeded.\n\n";

/* Four comma-separated whole numbers >= 0; 0 on success. */
static int parse_corners(const char *s, int c[4]) {
  const char *p = s;
  for (int q = 0; q < 4; q++) {
    char buf[32];
    const char *e = strchr(p, ',');
    size_t n = e ? (size_t)(e - p) : strlen(p);
    if ((q < 3) != (e != NULL) || n == 0 || n >= sizeof buf) return -1;
    memcpy(buf, p, n);
    buf[n] = '\0';
    if (cli_parse_int(buf, 0, 2147483647L, &c[q])) return -1;
    p = e ? e + 1 : p + n;
  }
  return 0;
}

/* "W:H", two positive finite numbers, into W / H; 0 on success. */
static int parse_aspect(const char *s, double *aspect) {
  const char *c = strchr(s, ':');
  char buf[64];
  double w, h;
  if (!c || (size_t)(c - s) >= sizeof buf) return -1;
  memcpy(buf, s, (size_t)(c - s));
  buf[c - s] = '\0';
  if (cli_parse_nonneg(buf, &w) || cli_parse_nonneg(c + 1, &h) || !(w > 0) || !(h > 0) || !isfinite(w / h) || !(w / h > 0))
    return -1;
  *aspect = w / h;
  return 0;
}

/* The options' values into o; -1 to go on, else the exit code (a usage error printed). */
static int map_options(const cli_args *a, au_options *o) {
  const char *h = a->help;
  const char *v;
  if (cli_opt_int(a, OPT_STEPS, 1, AU_MAX_STEPS, &o->max_steps)) return EXIT_USAGE;
  if (cli_opt_nonneg(a, OPT_TOL, &o->tol)) return EXIT_USAGE;
  if (cli_opt_int(a, OPT_ANGLES, 1, AU_MAX_ANGLE_STEPS, &o->angle_steps)) return EXIT_USAGE;
  if ((v = a->val[OPT_RESTORE]) && (cli_parse_nonneg(v, &o->restore_shapes) || o->restore_shapes > 1))
    return cli_usage_error(h, "--restore-shapes '%s': expected a number from 0 to 1", v);
  o->refine_faces = a->val[OPT_REFINE_FACES] != NULL;
  o->refine_mesh = a->val[OPT_REFINE_MESH] != NULL;
  if ((v = a->val[OPT_REFINE_BUDGET]) && strcmp(v, "auto") == 0)
    o->refine_max_faces = AU_REFINE_AUTO;
  else if (v && (cli_parse_nonneg(v, &o->refine_max_faces) ||
                 !(o->refine_max_faces > 1 && o->refine_max_faces <= AU_REFINE_MAX_FACES)))
    return cli_usage_error(h, "--refine-budget '%s': expected auto or a number above 1 and at most %d", v, AU_REFINE_MAX_FACES);
  o->init_only = a->val[OPT_INIT_ONLY] != NULL;
  o->balance = a->val[OPT_NO_BALANCE] == NULL;
  if ((v = a->val[OPT_START])) {
    if (strcmp(v, "conformal") == 0) o->start = AU_START_CONFORMAL;
    else if (strcmp(v, "multilevel") == 0) o->start = AU_START_MULTILEVEL;
    else return cli_usage_error(h, "--start '%s': expected conformal or multilevel", v);
  }
  if ((v = a->val[OPT_BOUNDARY])) {
    if (strcmp(v, "slide") == 0) o->boundary = AU_BOUNDARY_SLIDE;
    else if (strcmp(v, "fixed") == 0) o->boundary = AU_BOUNDARY_FIXED;
    else return cli_usage_error(h, "--boundary '%s': expected slide or fixed", v);
  }
  if ((v = a->val[OPT_INNER_RADIUS]) && (cli_parse_nonneg(v, &o->inner_radius) || !(o->inner_radius > 0 && o->inner_radius < 1)))
    return cli_usage_error(h, "--inner-radius '%s': expected a number between 0 and 1 (exclusive)", v);
  if ((v = a->val[OPT_OUTER_LOOP])) {
    if (strcmp(v, "longer") == 0) o->outer_loop = AU_OUTER_LONGER;
    else if (strcmp(v, "shorter") == 0) o->outer_loop = AU_OUTER_SHORTER;
    else if (cli_parse_int(v, 0, 2147483647L, &o->outer_loop))
      return cli_usage_error(h, "--outer-loop '%s': expected longer, shorter or a vertex index", v);
  }
  if ((v = a->val[OPT_OUTER]) && cli_parse_int(v, 0, 2147483647L, &o->outer_loop))
    return cli_usage_error(h, "--outer '%s': expected a vertex index", v);
  if ((v = a->val[OPT_ASPECT]) && parse_aspect(v, &o->aspect))
    return cli_usage_error(h, "--aspect '%s': expected W:H with two positive numbers", v);
  if ((v = a->val[OPT_CORNERS]) && parse_corners(v, o->corners))
    return cli_usage_error(h, "--corners '%s': expected four vertex indices I,J,K,L", v);
  if ((v = a->val[OPT_LATTICE])) {
    if (strcmp(v, "conformal") == 0) o->lattice = AU_LATTICE_CONFORMAL;
    else if (strcmp(v, "square") == 0) o->lattice = AU_LATTICE_SQUARE;
    else return cli_usage_error(h, "--lattice '%s': expected conformal or square", v);
  }
  return -1;
}

/* The parents file of --refine-mesh SURF, SURF.parents.txt, into buf ("" without SURF). */
static void parents_name(const char *surf, char *buf, size_t n) {
  snprintf(buf, n, "%s%s", surf ? surf : "", surf ? ".parents.txt" : "");
}

/* Parse `authalic CMD ...`; -1 to go on, else the exit code. */
static int parse_map(int argc, char **argv, int cmd, cli_args *a, au_options *o) {
  char usage[2048];
  const char *u = cmd == CLI_SPHERE ? usage_sphere : cmd == CLI_DISK ? usage_disk : cmd == CLI_ANNULUS ? usage_annulus
                : cmd == CLI_TORUS ? usage_torus : cmd == CLI_CIRCLES ? usage_circles : usage_square;
  snprintf(usage, sizeof usage, "%s%s", u, cmd == CLI_SPHERE || cmd == CLI_TORUS ? "" : usage_planar_out);
  int rc = cli_parse(argc, argv, cmd, 2, usage, a);
  if (rc >= 0) return rc;
  if (a->npos < 2) return cli_usage_error(a->help, a->npos == 0 ? "missing input and output files" : "missing output file");
  if (!*a->pos[0] || !*a->pos[1]) return cli_usage_error(a->help, "empty file name");
  *o = au_options_default();
  if ((rc = map_options(a, o)) >= 0) return rc;
  if (o->init_only) {
    static const cli_opt_id flow_only[] = {OPT_STEPS,   OPT_TOL,    OPT_DENSITY,         OPT_REFINE_FACES, OPT_REFINE_MESH,
                                           OPT_RESTORE, OPT_ANGLES, OPT_SPHERICAL_AREAS, OPT_BOUNDARY,     OPT_REFINE_BUDGET};
    for (size_t k = 0; k < sizeof flow_only / sizeof flow_only[0]; k++)
      if (a->val[flow_only[k]])
        return cli_usage_error(a->help, "--init-only runs no advection: --%s does not apply", cli_option_name(flow_only[k]));
  }
  if (a->val[OPT_REFINE_BUDGET] && !a->val[OPT_REFINE_MESH])
    return cli_usage_error(a->help, "--refine-budget applies to --refine-mesh, which is not given");
  if (a->val[OPT_REFINE_MESH] && a->val[OPT_DENSITY])
    return cli_usage_error(a->help, "--refine-mesh does not take --density (the new vertices and faces would have none)");
  if (a->val[OPT_REFINE_MESH] && a->val[OPT_SPHERICAL_AREAS])
    return cli_usage_error(a->help, "--refine-mesh does not take --spherical-areas (spherical triangles have no chord floor "
                                    "to refine)");
  const char *v = a->val[OPT_FORMAT];
  if (v && au_io_format_parse(v) == AU_IO_FORMAT_AUTO)
    return cli_usage_error(a->help, "--format '%s': expected obj, off, ply, freesurfer or gifti", v);
  double radius;
  /* Written as float32 by FreeSurfer and GIfTI: beyond these the coordinates overflow or vanish. */
  if ((v = a->val[OPT_RADIUS]) && (cli_parse_nonneg(v, &radius) || !(radius >= 1e-30) || radius > 1e30))
    return cli_usage_error(a->help, "--radius '%s': expected a number from 1e-30 to 1e30", v);
  rc = cli_check_outputs(a->help, a->pos[0], a->pos[1], a->val[OPT_REPORT]);
  const char *dens = a->val[OPT_DENSITY];
  if (!rc && dens && (cli_same_file(dens, a->pos[1]) || (a->val[OPT_REPORT] && cli_same_file(dens, a->val[OPT_REPORT]))))
    rc = cli_usage_error(a->help, "--density '%s' is also an output file; refusing to overwrite it", dens);
  const char *d = a->val[OPT_DISTORTION];
  if (!rc && d && (cli_same_file(d, a->pos[0]) || cli_same_file(d, a->pos[1]) ||
                   (a->val[OPT_REPORT] && cli_same_file(d, a->val[OPT_REPORT])) ||
                   (a->val[OPT_DENSITY] && cli_same_file(d, a->val[OPT_DENSITY]))))
    rc = cli_usage_error(a->help, "--distortion '%s' is also another input or output file", d);
  if (!rc && d) rc = cli_check_writable_path(a->help, d, "--distortion");
  /* --refine-mesh SURF is checked like OUT before the run: it was written over the input, or lost under
   * OUT, or refused only after the whole map was made. Its parents file too. */
  const char *sf = a->val[OPT_REFINE_MESH];
  char parents[4200];
  parents_name(sf, parents, sizeof parents);
  for (int k = 0; !rc && sf && k < 2; k++) {
    const char *f = k ? parents : sf;
    if (cli_same_file(f, a->pos[0]) || cli_same_file(f, a->pos[1]) || (a->val[OPT_REPORT] && cli_same_file(f, a->val[OPT_REPORT])) ||
        (d && cli_same_file(f, d)) || (a->val[OPT_DENSITY] && cli_same_file(f, a->val[OPT_DENSITY])))
      rc = cli_usage_error(a->help, "--refine-mesh '%s': %s is also another input or output file", sf, k ? parents : "it");
  }
  if (!rc && sf && au_io_format_of_name(sf) == AU_IO_FORMAT_STL)
    rc = cli_usage_error(a->help, "--refine-mesh '%s': cannot write that extension (use .obj, .off, .ply or .gii)", sf);
  if (!rc && sf) rc = cli_check_writable_path(a->help, sf, "--refine-mesh");
  if (!rc && sf) rc = cli_check_writable_path(a->help, parents, "--refine-mesh's parents file");
  if (!rc && cmd == CLI_TORUS && !cli_has_ext(a->pos[1], ".obj"))
    return cli_usage_error(a->help, "%s: the torus map is written as .obj (its seamless `vt` need OBJ)", a->pos[1]);
  const char *pv = a->val[OPT_PREVIEW];
  if (!rc && pv && !cli_has_ext(pv, ".png")) return cli_usage_error(a->help, "--preview '%s': use .png", pv);
  if (!rc && pv && (cli_same_file(pv, a->pos[0]) || cli_same_file(pv, a->pos[1]) ||
                    (a->val[OPT_REPORT] && cli_same_file(pv, a->val[OPT_REPORT])) || (d && cli_same_file(pv, d))))
    return cli_usage_error(a->help, "--preview '%s' is also another input or output file", pv);
  if (!rc && pv) rc = cli_check_writable_path(a->help, pv, "--preview");
  const char *hv = a->val[OPT_HTML];
  if (!rc && hv && (cli_same_file(hv, a->pos[0]) || cli_same_file(hv, a->pos[1]) || (a->val[OPT_REPORT] && cli_same_file(hv, a->val[OPT_REPORT])) ||
                    (d && cli_same_file(hv, d)) || (pv && cli_same_file(hv, pv)) || (sf && cli_same_file(hv, sf)) ||
                    (dens && cli_same_file(hv, dens))))
    return cli_usage_error(a->help, "--html '%s' is also another input or output file", hv);
  if (!rc && hv) rc = cli_check_writable_path(a->help, hv, "--html");
  return rc ? rc : -1;
}

/* Read a density file (au_io_read_scalars: text, FreeSurfer curv or GIfTI values): nv values (per
 * vertex) or nf (per face), each positive and finite. On success *out (malloc'ed) and *count are set
 * and -1 is returned; otherwise the error is printed and the exit code returned. */
static int read_density(const char *path, int nv, int nf, double **out, int *count) {
  au_msg msg = {{0}};
  double *v = NULL;
  int n = 0;
  FILE *fp = fopen(path, "r");
  if (!fp) {
    fprintf(stderr, "authalic: error: %s: cannot open the density file: %s\n", path, strerror(errno));
    return EXIT_USAGE;
  }
  fclose(fp);
  au_status st = au_io_read_scalars(path, 0, &v, &n, &msg);
  if (st != AU_OK) return cli_fail(path, st, &msg);
  for (int i = 0; i < n; i++)
    if (!(v[i] > 0)) {
      fprintf(stderr, "authalic: error: %s: value %d ('%g') is not a positive finite number\n", path, i + 1, v[i]);
      free(v);
      return EXIT_USAGE;
    }
  if (n != nv && n != nf) {
    fprintf(stderr, "authalic: error: %s: %d values; the mesh has %d vertices and %d faces\n", path, n, nv, nf);
    free(v);
    return EXIT_USAGE;
  }
  *out = v, *count = n;
  return -1;
}

/* The one summary line on stderr; a map of spherical areas (--spherical-areas) also gives its own
 * measure, the spherical triangles' (the chord figures of such a map stay far off on long edges). */
static void summary(int cmd, const au_result *r, int spherical, double seconds) {
  const au_metrics *f = &r->metrics;
  if (cmd == CLI_SPHERE) {
    /* The retries that ran: " (lantern retry discarded; twisted start kept)". */
    const char *part[5] = {
        r->conv.lantern_retry == 3   ? "lantern retry skipped: it would repeat the first flow"
        : r->conv.lantern_retry == 2 ? "lantern retry kept"
        : r->conv.lantern_retry == 1 ? "lantern retry discarded"
                                     : "",
        r->conv.twist_retry == 3   ? "twisted start: the conformal one folded"
        : r->conv.twist_retry == 2 ? "twisted start kept"
        : r->conv.twist_retry == 1 ? "twisted start discarded"
                                   : "",
        r->conv.staged_retry == 2 ? "staged retry kept" : r->conv.staged_retry == 1 ? "staged retry discarded" : "",
        r->conv.vertex_polish == 2 ? "vertex polish kept" : r->conv.vertex_polish == 1 ? "vertex polish discarded" : "",
        r->conv.global_polish == 2 ? "global polish kept" : r->conv.global_polish == 1 ? "global polish discarded" : ""};
    char tail[200] = "";
    size_t len = 0;
    for (int k = 0; k < 5; k++)
      if (*part[k]) len += (size_t)snprintf(tail + len, sizeof tail - len, "%s%s", len ? "; " : " (", part[k]);
    if (len) snprintf(tail + len, sizeof tail - len, ")");
    char sph[96] = "";
    if (spherical)
      snprintf(sph, sizeof sph, " sph|r-1|=%.3g sph vertex|log r|=%.3g", f->sph_r_mean_abs_dev, f->sph_vertex_logr_mean_abs);
    fprintf(stderr, "authalic: sphere: V=%d F=%d steps=%d folds=%d mean|r-1|=%.3g vertex|log r|=%.3g%s time=%.2fs%s\n", r->nv,
            r->nf, r->conv.steps, f->folds, f->r_mean_abs_dev, f->vertex_logr_mean_abs, sph, seconds, tail);
    return;
  }
  char extra[160] = "";
  if (cmd == CLI_TORUS) {
    const double(*L)[2] = r->lattice;
    fprintf(stderr, "authalic: torus: V=%d F=%d steps=%d folds=%d mean|r-1|=%.3g vertex|log r|=%.3g lattice=(%.6g,%.6g),(%.6g,%.6g) "
            "vt=%d start=%s time=%.2fs\n", r->nv, r->nf, r->conv.steps, f->folds, f->r_mean_abs_dev, f->vertex_logr_mean_abs,
            L[0][0], L[0][1], L[1][0], L[1][1], r->nvt, r->init_method ? r->init_method : "?", seconds);
    return;
  }
  if (cmd == CLI_ANNULUS)
    snprintf(extra, sizeof extra, " inner_radius=%.6g modulus_radius=%.6g", r->inner_radius, r->modulus_radius);
  else if (cmd == CLI_SQUARE)
    snprintf(extra, sizeof extra, " corners=%d,%d,%d,%d split=%d", r->corners[0], r->corners[1], r->corners[2],
             r->corners[3], r->nsplit);
  else if (cmd == CLI_CIRCLES)
    snprintf(extra, sizeof extra, " circles=%d outer_vertex=%d", r->ncircles, r->circle_vertex[r->circle_outer]);
  fprintf(stderr,
          "authalic: %s: V=%d F=%d steps=%d folds=%d mean|r-1|=%.3g vertex|log r|=%.3g boundary_dev=%.2g%s start=%s "
          "time=%.2fs\n",
          cli_cmd_name(cmd), r->nv, r->nf, r->conv.steps, f->folds, f->r_mean_abs_dev, f->vertex_logr_mean_abs,
          r->boundary_dev, extra, r->init_method ? r->init_method : "?", seconds);
}

/* --refine-mesh SURF: the refined surface and SURF.parents.txt, written to their temporaries surf and
 * parents (each an atomic write of the library's), renamed into place once OUT is. -1 to go on, else
 * the exit code (neither temporary left behind). */
static int write_refined(const char *surf, const char *parents, const char *surf_name, const char *parents_name,
                         const au_result *r, au_io_format fmt, const au_io_meta *meta) {
  au_msg msg = {{0}};
  /* The refined surface is the input's surface, finer: its format (when SURF's name has no extension)
   * and its metadata, GeometricType included. */
  au_write_opts w = au_write_opts_default();
  w.format = fmt, w.meta = meta;
  au_status st = au_mesh_write(surf, r->nv, r->X, r->nf, r->F, &w, &msg);
  if (st < 0) return cli_fail(surf_name, st, &msg);
  /* A line is at most 3 ints and a %.17g: 80 bytes with room. */
  size_t cap = 80 * (size_t)(r->nrefined > 0 ? r->nrefined : 1), len = 0;
  char *text = malloc(cap);
  for (int k = 0; text && k < r->nrefined; k++)
    len += (size_t)snprintf(text + len, cap - len, "%d %d %d %.17g\n", r->nv_in + k, r->parent[2 * k], r->parent[2 * k + 1],
                            r->parent_t[k]);
  st = text ? au_write_text(parents, text, len, &msg) : AU_E_NOMEM;
  free(text);
  if (st < 0) {
    unlink(surf);
    return cli_fail(parents_name, st, &msg);
  }
  return -1;
}

/* The outputs besides OUT and the report (the refined surface and its parents, the distortion, the
 * preview, the page) wait under temporary names beside the files they replace until OUT is published:
 * a run that fails later leaves a user's earlier files, and the links to them, as they were. */
enum { P_SURF, P_PARENTS, P_DISTORTION, P_PREVIEW, P_HTML, NPENDING };
typedef struct pending {
  const char *name[NPENDING]; /* as given; NULL where not asked for */
  char *dest[NPENDING], *tmp[NPENDING];
  int written[NPENDING]; /* the temporary holds the output, to be renamed or removed */
} pending;

/* The formats of OUT (torus: OBJ) and of --refine-mesh's SURF, settled only once the input is read: a
 * name without an extension takes the input's format. -1 to go on, else the exit code. */
static int output_formats(const cli_args *a, au_target t, const au_io_meta *meta, au_io_format *ofmt,
                          au_io_format *sfmt) {
  const char *surf = a->val[OPT_REFINE_MESH];
  int rc;
  *ofmt = AU_IO_FORMAT_OBJ;
  if (t != AU_TARGET_TORUS && (rc = cli_output_format(a->help, a->pos[1], au_io_format_parse(a->val[OPT_FORMAT]), meta, ofmt)))
    return rc;
  *sfmt = surf ? au_io_format_of_name(surf) : AU_IO_FORMAT_OBJ;
  if (*sfmt == AU_IO_FORMAT_AUTO) *sfmt = au_io_meta_format(meta);
  if (*sfmt == AU_IO_FORMAT_AUTO || *sfmt == AU_IO_FORMAT_STL)
    return cli_usage_error(a->help, "--refine-mesh '%s': no extension of a format that can be written and the input is %s "
                                    "(use .obj, .off, .ply or .gii)", surf, au_io_format_name(*sfmt));
  return -1;
}

/* Names every pending output's temporary up front, so that a fatal signal can remove it. -1 to go on,
 * else the exit code. */
static int pending_open(pending *p) {
  for (int k = 0; k < NPENDING; k++) {
    if (!p->name[k]) continue;
    if (!(p->dest[k] = au_output_target(p->name[k])) || !(p->tmp[k] = cli_temp_name(p->dest[k])))
      return cli_fail(p->name[k], AU_E_NOMEM, NULL);
    cli_expect_output(p->tmp[k]), cli_expect_temp(p->tmp[k]);
  }
  return -1;
}

/* Renames the written temporaries into place once OUT is published; EXIT_OK, else EXIT_INTERNAL. */
static int pending_publish(pending *p) {
  int rc = EXIT_OK;
  for (int k = 0; rc == EXIT_OK && k < NPENDING; k++)
    if (p->written[k]) {
      if (rename(p->tmp[k], p->dest[k]) != 0) {
        fprintf(stderr, "authalic: error: %s: cannot rename it into place: %s\n", p->name[k], strerror(errno));
        rc = EXIT_INTERNAL; /* its temporary stays written: pending_close removes it */
      } else {
        p->written[k] = 0;
      }
    }
  return rc;
}

/* Removes the temporaries not renamed (a failure anywhere after they were written) and frees the names. */
static void pending_close(pending *p) {
  for (int k = 0; k < NPENDING; k++) {
    if (p->written[k]) unlink(p->tmp[k]);
    free(p->tmp[k]), au_free(p->dest[k]);
  }
}

/* Gives --density's values to the options as per-vertex or per-face by their count; *density (the
 * caller frees it) holds them. -1 to go on, else the exit code. */
static int apply_density(const cli_args *a, const au_mesh *m, au_options *o, double **density) {
  int nval = 0, rc;
  if (!a->val[OPT_DENSITY]) return -1;
  if ((rc = read_density(a->val[OPT_DENSITY], m->nv, m->nf, density, &nval)) >= 0) return rc;
  if (nval == m->nv) o->vertex_density = *density;
  else o->face_density = *density;
  return -1;
}

/* Runs the map with the options the command line set (the density already given to them) and reports
 * its warnings, or its failure, the program's way. -1 to go on (*r set), else the exit code. */
static int map_mesh(const cli_args *a, const au_mesh *m, au_target t, au_options *o, cli_progress_state *prog,
                    au_result **r) {
  const char *in = a->pos[0];
  au_msg msg = {{0}};
  /* --spherical-areas: the map the texture command computes for itself (cmd_texture.c, get_map). */
  o->spherical_areas = a->val[OPT_SPHERICAL_AREAS] != NULL;
  if (a->val[OPT_QUIET] == NULL) o->progress = cli_progress, o->user = prog;
  o->measure_start = a->val[OPT_REPORT] != NULL; /* only the report shows the start's metrics */
  au_status st = au_map(m->X, m->nv, m->F, m->nf, t, o, r, &msg);
  cli_progress_end(prog);
  if (st >= 0) {
    for (int k = 0; k < (*r)->nwarnings; k++) fprintf(stderr, "authalic: warning: %s: %s\n", in, (*r)->warnings[k]);
    return -1;
  }
  /* A bad corner or outer-loop vertex is the user's to fix, like bad input; the library names the
   * option by its field (outer_loop), the program by its flag (--outer-loop). */
  if (st == AU_E_ARG) {
    char *colon = strchr(msg.text, ':');
    for (char *c = msg.text; colon && c < colon; c++)
      if (*c == '_') *c = '-';
    fprintf(stderr, "authalic: error: %s: --%s\n", in, msg.text);
    return EXIT_USAGE;
  }
  return cli_fail(in, st, &msg);
}

/* Writes the outputs besides OUT and the report to their temporaries, each marked written in p. -1 to
 * go on, else the exit code. */
static int write_pending(const cli_args *a, const au_result *r, au_target t, au_io_format sfmt, const au_io_meta *meta,
                         double t_start, pending *p) {
  const char *in = a->pos[0];
  int rc;
  if (p->name[P_SURF]) {
    if ((rc = write_refined(p->tmp[P_SURF], p->tmp[P_PARENTS], p->name[P_SURF], p->name[P_PARENTS], r, sfmt, meta)) >= 0)
      return rc;
    p->written[P_SURF] = p->written[P_PARENTS] = 1;
  }
  if (p->name[P_DISTORTION]) {
    au_mesh mm = {r->nv, r->nf, r->X, r->F};
    rc = cli_write_distortion(p->tmp[P_DISTORTION], p->name[P_DISTORTION], &mm, r->P,
                              t == AU_TARGET_SPHERE ? AU_DOMAIN_SPHERE : AU_DOMAIN_PLANE, r->nvt,
                              t == AU_TARGET_TORUS ? r->vt : NULL, r->Ft, meta);
    if (rc >= 0) return rc;
    p->written[P_DISTORTION] = 1;
  }
  if (p->name[P_PREVIEW]) {
    au_msg msg = {{0}};
    au_status st = au_torus_preview(p->tmp[P_PREVIEW], r, 1024, 0, &msg);
    if (st < 0) return cli_fail(p->name[P_PREVIEW], st, &msg);
    p->written[P_PREVIEW] = 1;
  }
  if (p->name[P_HTML]) {
    au_view_input v = au_view_input_default();
    v.nv = r->nv, v.nf = r->nf, v.X = r->X, v.F = r->F;
    if (t == AU_TARGET_TORUS) v.nvt = r->nvt, v.vt = r->vt, v.Ft = r->Ft;
    else v.P = r->P;
    v.steps = r->conv.steps, v.seconds = cli_now() - t_start;
    const char *slash = strrchr(in, '/');
    v.title = slash ? slash + 1 : in;
    if ((rc = cli_write_view(p->tmp[P_HTML], p->name[P_HTML], &v, 1)) >= 0) return rc;
    p->written[P_HTML] = 1;
  }
  return -1;
}

/* Publishes OUT (and the report), then the pending outputs; the exit code. */
static int publish(const cli_args *a, const au_result *r, au_target t, au_io_format ofmt, const au_io_meta *meta,
                   au_report_extra *extra, pending *p) {
  au_write_opts w = au_write_opts_default();
  w.uv = r->uv;
  /* The torus keeps the surface in `v` and puts the map in the per-corner `vt`. */
  if (t == AU_TARGET_TORUS) w.nvt = r->nvt, w.vt = r->vt, w.Ft = r->Ft;
  w.format = ofmt, w.meta = meta, w.geometric_type = t == AU_TARGET_SPHERE ? "Spherical" : "Flat";
  if (a->val[OPT_RADIUS]) cli_parse_nonneg(a->val[OPT_RADIUS], &w.radius); /* checked when parsed */
  int rc = cli_publish(a->pos[1], r->nv, t == AU_TARGET_TORUS ? r->X : r->P, r->nf, r->F, &w, a->val[OPT_REPORT], r, extra);
  return rc == EXIT_OK ? pending_publish(p) : rc;
}

/* The command after parsing: read, map, write the pending outputs, publish, summarize. */
static int run_map(const cli_args *a, au_options *o) {
  double t_start = cli_now();
  const char *in = a->pos[0], *out = a->pos[1], *report = a->val[OPT_REPORT], *surf = a->val[OPT_REFINE_MESH];
  const int quiet = a->val[OPT_QUIET] != NULL;
  au_target t = cli_cmd_target(a->cmd);
  au_report_extra extra = {NULL, NULL, NULL, -1, -1, -1, NULL, 0};
  extra.input = in, extra.output = out, extra.tool = "authalic " AU_VERSION;
  au_mesh *m = NULL;
  au_result *r = NULL;
  au_io_meta *meta = NULL;
  double *density = NULL;
  char parents[4200];
  parents_name(surf, parents, sizeof parents);
  pending p = {{surf, surf ? parents : NULL, a->val[OPT_DISTORTION], a->val[OPT_PREVIEW], a->val[OPT_HTML]}, {NULL}, {NULL}, {0}};
  au_io_format ofmt = AU_IO_FORMAT_OBJ, sfmt = AU_IO_FORMAT_OBJ;
  cli_progress_state prog;
  cli_progress_init(&prog, quiet);
  cli_expect_output(out);
  cli_expect_output(report);

  /* The check's warning (unreferenced vertices) is the result's too: not kept twice. */
  int rc = cli_load(in, (au_target)-1, &m, &meta, NULL, &extra.t_read, &extra.t_validate);
  if (rc < 0) rc = output_formats(a, t, meta, &ofmt, &sfmt);
  if (rc < 0) rc = pending_open(&p);
  if (rc < 0) rc = apply_density(a, m, o, &density);
  if (rc < 0) rc = map_mesh(a, m, t, o, &prog, &r);
  if (rc < 0) rc = write_pending(a, r, t, sfmt, meta, t_start, &p);
  if (rc < 0 && (rc = publish(a, r, t, ofmt, meta, &extra, &p)) == EXIT_OK && !quiet)
    summary(a->cmd, r, a->val[OPT_SPHERICAL_AREAS] != NULL, cli_now() - t_start);
  pending_close(&p);
  cli_progress_end(&prog);
  au_result_free(&r);
  au_io_meta_free(&meta);
  au_mesh_free(&m);
  free(density);
  return rc;
}

int cli_cmd_map(int argc, char **argv) {
  int cmd = strcmp(argv[0], "disk") == 0 ? CLI_DISK : strcmp(argv[0], "annulus") == 0 ? CLI_ANNULUS
          : strcmp(argv[0], "square") == 0 ? CLI_SQUARE : strcmp(argv[0], "torus") == 0 ? CLI_TORUS
          : strcmp(argv[0], "circles") == 0 ? CLI_CIRCLES : CLI_SPHERE;
  cli_args a;
  au_options o;
  int rc = parse_map(argc, argv, cmd, &a, &o);
  return rc >= 0 ? rc : run_map(&a, &o);
}
