/* cmd_texture.c - `authalic texture` (equal-area texture coordinates, baking, previews) and
 * `authalic sample` (the surface sampled on an equal-area grid of the sphere). Numerics live in
 * sphere/au_texture.h; this file parses, calls the library and writes the results. */
#define _XOPEN_SOURCE 700

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "cli.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define MAX_ATTR CLI_MAX_REPEAT

static const char *const usage_texture =
    "usage: authalic texture IN [--map SPHERE_MAP] OUT.obj [options]\n\n"
    "Writes the closed genus-0 mesh IN as OUT.obj with texture coordinates (`vt`) in an equal-area\n"
    "projection of its sphere map, so every texel of a texture stands for the same surface area.\n"
    "The sphere map is read from SPHERE_MAP (the output of `authalic sphere IN SPHERE_MAP`) or\n"
    "computed on the fly, then with equal spherical triangle areas (no chord polish: closer\n"
    "texture areas). Faces across the projection's seam get their own copies of `vt`; with\n"
    "cea, the faces holding a pole are split there (the pole vertices are appended after IN's).\n\n";

static const char *const usage_sample =
    "usage: authalic sample IN --grid WxH OUT [--map SPHERE_MAP] [options]\n\n"
    "Samples the closed genus-0 mesh IN on an equal-area grid of its sphere map: cell (row r,\n"
    "column c) spans longitudes -180 + 360 [c, c+1]/W degrees and sin(latitude) in\n"
    "1 - 2 [r, r+1]/H (row 0 at the north pole), so every cell covers 4 pi/(W H) of the sphere and,\n"
    "through an authalic map, the same share of the surface. The cell centre's preimage on IN gives\n"
    "the cell's values: x, y, z, then the attributes asked for.\n"
    "OUT.npy: NumPy float64 array of shape (H, W, 3 + attributes): numpy.load(OUT).\n"
    "OUT.csv: one line per cell: row,col,lon,lat,x,y,z,attributes (after a header line).\n\n";

/* Everything either command was asked to do. */
typedef struct tex_args {
  const char *in, *out, *map, *lonlat, *bake, *image, *preview, *render, *report, *distortion;
  const char *attr[MAX_ATTR];
  int nattr;
  au_tex_proj proj;
  au_tex_opts topts;
  int has_proj, W, H, has_size, normals, quiet, sample, mark_seam;
} tex_args;

/* The .mtl path beside an .obj path (malloc'ed). */
static char *mtl_path(const char *obj) {
  size_t n = strlen(obj);
  char *s = malloc(n + 1);
  if (!s) return NULL;
  memcpy(s, obj, n + 1);
  memcpy(s + n - 4, ".mtl", 4);
  return s;
}

static int parse_args(int argc, char **argv, tex_args *a) {
  cli_args c;
  int rc = cli_parse(argc, argv, a->sample ? CLI_SAMPLE : CLI_TEXTURE, 2, a->sample ? usage_sample : usage_texture, &c);
  if (rc >= 0) return rc;
  const char *help = c.help;
  if (c.npos < 2) return cli_usage_error(help, c.npos == 0 ? "missing input and output files" : "missing output file");
  a->in = c.pos[0], a->out = c.pos[1];
  if (!*a->in || !*a->out) return cli_usage_error(help, "empty file name");
  a->map = c.val[OPT_MAP], a->lonlat = c.val[OPT_LONLAT], a->bake = c.val[OPT_BAKE], a->image = c.val[OPT_IMAGE];
  a->preview = c.val[OPT_PREVIEW], a->render = c.val[OPT_RENDER], a->report = c.val[OPT_REPORT];
  a->distortion = c.val[OPT_DISTORTION];
  a->normals = c.val[OPT_NORMALS] != NULL, a->mark_seam = c.val[OPT_MARK_SEAM] != NULL, a->quiet = c.val[OPT_QUIET] != NULL;
  for (int k = 0; k < c.nrep; k++) a->attr[a->nattr++] = c.rep[k];
  const char *v = c.val[OPT_PROJECTION];
  if (v && strcmp(v, "cea") == 0) a->proj = AU_TEX_CEA;
  else if (v && strcmp(v, "laea") == 0) a->proj = AU_TEX_LAEA;
  else if (v && strcmp(v, "oct") == 0) a->proj = AU_TEX_OCT;
  else if (v) return cli_usage_error(help, "--projection '%s': expected cea, laea or oct", v);
  a->topts = au_tex_opts_default();
  a->topts.proj = a->proj;
  if ((v = c.val[OPT_AXIS]) != NULL) {
    double *d = a->topts.axis_dir;
    char tail;
    a->topts.axis = AU_TEX_AXIS_VECTOR;
    d[0] = d[1] = d[2] = 0;
    if (strcmp(v, "auto") == 0) a->topts.axis = AU_TEX_AXIS_AUTO;
    else if (strcmp(v, "z") == 0) a->topts.axis = AU_TEX_AXIS_Z, d[2] = 1;
    else if (strcmp(v, "x") == 0) d[0] = 1;
    else if (strcmp(v, "y") == 0) d[1] = 1;
    else if (sscanf(v, "%lf,%lf,%lf%c", &d[0], &d[1], &d[2], &tail) != 3 || !isfinite(d[0] + d[1] + d[2]) ||
             d[0] * d[0] + d[1] * d[1] + d[2] * d[2] == 0)
      return cli_usage_error(help, "--axis '%s': expected auto, x, y, z or a nonzero vector X,Y,Z", v);
  }
  if ((v = c.val[OPT_AREA_TOL]) != NULL) {
    char *end;
    a->topts.area_tol = strcmp(v, "auto") == 0 ? -1 : strtod(v, &end);
    if (strcmp(v, "auto") && (end == v || *end || !(a->topts.area_tol >= 0 && a->topts.area_tol < 1e3)))
      return cli_usage_error(help, "--area-tol '%s': expected a number >= 0 or auto", v);
  }
  if ((v = c.val[OPT_AREA_TARGET]) != NULL) {
    char *end;
    a->topts.area_target = strcmp(v, "auto") == 0 ? -1 : strtod(v, &end);
    if (strcmp(v, "auto") && (end == v || *end || !(a->topts.area_target >= 0 && a->topts.area_target < 1e3)))
      return cli_usage_error(help, "--area-target '%s': expected a number >= 0 or auto", v);
    if (a->topts.area_tol == 0) return cli_usage_error(help, "--area-target: needs --area-tol");
  }
  cli_opt_id size = a->sample ? OPT_GRID : OPT_SIZE;
  a->has_size = c.val[size] != NULL;
  if (cli_opt_size(&c, size, &a->W, &a->H)) return EXIT_USAGE;

  /* Combinations and output names. */
  if (a->sample) {
    if (!a->has_size) return cli_usage_error(help, "missing --grid WxH");
    if ((long)a->W * a->H > 16L * 1024 * 1024) return cli_usage_error(help, "--grid %dx%d: more than 16M cells", a->W, a->H);
    if (!cli_has_ext(a->out, ".npy") && !cli_has_ext(a->out, ".csv"))
      return cli_usage_error(help, "output '%s': use .npy or .csv", a->out);
    if (a->report && !cli_has_ext(a->report, ".json")) return cli_usage_error(help, "report '%s': use .json", a->report);
  } else {
    if (!cli_has_ext(a->out, ".obj")) return cli_usage_error(help, "output '%s': texture coordinates are written as .obj", a->out);
    if (a->bake && !a->image) return cli_usage_error(help, "--bake needs --image OUT.png");
    if (a->image && !a->bake) return cli_usage_error(help, "--image needs --bake ATTR");
    if (a->render && !a->bake) return cli_usage_error(help, "--render needs --bake ATTR and --image");
    if (a->mark_seam && !a->render) return cli_usage_error(help, "--mark-seam applies to --render only");
    if (a->has_size && !a->bake) return cli_usage_error(help, "--size applies to --bake only");
    if (!a->has_size) a->W = 1024, a->H = 512;
    if (a->proj == AU_TEX_LAEA && a->W % 2) return cli_usage_error(help, "--size %dx%d: laea needs an even width", a->W, a->H);
    if ((long)a->W * a->H > 64L * 1024 * 1024) return cli_usage_error(help, "--size %dx%d: more than 64M texels", a->W, a->H);
    if (a->image && !cli_has_ext(a->image, ".png")) return cli_usage_error(help, "image '%s': use .png", a->image);
    if (a->render && !cli_has_ext(a->render, ".png")) return cli_usage_error(help, "render '%s': use .png", a->render);
  }
  if (a->preview && !cli_has_ext(a->preview, ".png")) return cli_usage_error(help, "preview '%s': use .png", a->preview);

  /* Every output distinct from the inputs and from each other, in an existing directory. */
  char *mtl = (!a->sample && a->bake) ? mtl_path(a->out) : NULL;
  const char *outs[8] = {a->out, a->lonlat, a->image, a->preview, a->render, a->report, mtl, a->distortion};
  const char *names[8] = {"output", "--lonlat", "--image", "--preview", "--render", "--report", "material file",
                          "--distortion"};
  const char *ins[2 + MAX_ATTR] = {a->in, a->map};
  int nin = 2;
  for (int k = 0; k < a->nattr; k++) ins[nin++] = a->attr[k];
  if (!a->sample && a->bake && strcmp(a->bake, "normal") && strcmp(a->bake, "position")) ins[nin++] = a->bake;
  rc = -1;
  for (int k = 0; k < 8 && rc < 0; k++) {
    cli_expect_output(outs[k]);
    if (!outs[k]) continue;
    for (int j = 0; j < nin && rc < 0; j++)
      if (ins[j] && cli_same_file(outs[k], ins[j]))
        rc = cli_usage_error(help, "%s '%s' is an input file; refusing to overwrite it", names[k], outs[k]);
    for (int j = 0; j < k && rc < 0; j++)
      if (outs[j] && cli_same_file(outs[k], outs[j]))
        rc = cli_usage_error(help, "%s '%s' is also the %s", names[k], outs[k], names[j]);
    if (rc < 0 && cli_check_writable_path(help, outs[k], names[k])) rc = EXIT_USAGE;
  }
  free(mtl);
  return rc;
}

/* The sphere map of m: read from a->map (checked against m) or computed. P: out, nv x 3.
 * Returns -1 on success, else the exit code (the error printed). */
static int get_map(const tex_args *a, const au_mesh *m, double *P, cli_warnings *warn, au_metrics *met) {
  au_msg msg = {{0}};
  au_status st;
  if (a->map) {
    au_mesh *s = NULL;
    st = au_mesh_read(a->map, &s, &msg);
    if (st != AU_OK) return cli_fail(a->map, st, &msg);
    int bad = s->nv != m->nv || s->nf != m->nf;
    for (long i = 0; !bad && i < 3L * m->nf; i++) bad = s->F[i] != m->F[i];
    if (bad) {
      au_msg_set(&msg, AU_E_FORMAT, "not a map of '%s': %d vertices and %d faces (the input has %d and %d) or other faces",
                 a->in, s->nv, s->nf, m->nv, m->nf);
      au_mesh_free(&s);
      return cli_fail(a->map, AU_E_FORMAT, &msg);
    }
    /* Vertices no face uses may lie anywhere. The sphere's radius is that of the first vertex used:
     * FreeSurfer's and HCP's have 100, their vertices within 1e-4 of it (FreeSurfer's fsaverage5
     * sphere: 99.9929 .. 100.0078), and they are projected onto it. */
    unsigned char *used = calloc((size_t)m->nv, 1);
    if (!used) {
      au_mesh_free(&s);
      return cli_fail(a->map, AU_E_NOMEM, NULL);
    }
    for (long i = 0; i < 3L * m->nf; i++) used[m->F[i]] = 1;
    double R = 0;
    for (int i = 0; i < m->nv && !(R > 0); i++)
      if (used[i]) R = sqrt(s->X[3 * i] * s->X[3 * i] + s->X[3 * i + 1] * s->X[3 * i + 1] + s->X[3 * i + 2] * s->X[3 * i + 2]);
    int rc = -1;
    for (int i = 0; i < m->nv && rc < 0; i++) {
      const double *q = s->X + 3 * (size_t)i;
      double r = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
      if (used[i] && !(fabs(r / R - 1) <= 1e-3)) {
        au_msg_set(&msg, AU_E_FORMAT, "vertex %d is not on the sphere of the first vertex's radius %.9g (|p| = %.9g)", i, R, r);
        rc = cli_fail(a->map, AU_E_FORMAT, &msg);
      }
      for (int j = 0; j < 3; j++) P[3 * i + j] = r > 0 ? q[j] / r : (j == 2);
    }
    free(used);
    au_mesh_free(&s);
    if (rc >= 0) return rc;
  } else {
    cli_progress_state prog;
    cli_progress_init(&prog, a->quiet);
    au_options opts = au_options_default();
    /* The map's spherical triangles, not its chord triangles, are what this command uses: texels and
     * grid cells are located on the sphere, and a straight texture triangle's area tends to its
     * spherical triangle's. So the flow drives the spherical areas only and skips the chord polish,
     * which trades spherical error for chordal (spot_lowres: spherical per-face 0.0401 with the
     * polish, 0.0089 without; docs/textures.md). `authalic sphere`'s maps are unchanged. */
    opts.spherical_areas = 1;
    if (!a->quiet) opts.progress = cli_progress, opts.user = &prog;
    au_result *r = NULL;
    st = au_map(m->X, m->nv, m->F, m->nf, AU_TARGET_SPHERE, &opts, &r, &msg);
    cli_progress_end(&prog);
    if (st < 0) return cli_fail(a->in, st, &msg);
    memcpy(P, r->P, 3 * (size_t)m->nv * sizeof *P);
    if (st == AU_W_NOT_CONVERGED) {
      int steps;
      double tol;
      au_target_defaults(AU_TARGET_SPHERE, &steps, &tol);
      cli_warn(warn, a->in, "sphere map: tolerance %g not reached in %d steps", tol, r->conv.steps);
    }
    au_result_free(&r);
  }
  st = au_metrics_compute(m->nv, m->nf, m->X, P, m->F, AU_DOMAIN_SPHERE, met, NULL, NULL);
  if (st != AU_OK) return cli_fail(a->in, st, NULL);
  if (met->folds > 0) {
    au_msg_set(&msg, AU_E_FORMAT, "the sphere map has %d folded triangle%s; nothing written", met->folds,
               met->folds == 1 ? "" : "s");
    return cli_fail(a->map ? a->map : a->in, a->map ? AU_E_FORMAT : AU_E_FOLD, &msg);
  }
  return -1;
}

/* Outputs written so far by this run, removed again if a later one fails. */
typedef struct written {
  const char *path[8];
  int n;
} written;

static int write_done(written *w, const char *path, au_status st, const au_msg *msg) {
  if (st == AU_OK) {
    w->path[w->n++] = path;
    return -1;
  }
  for (int k = 0; k < w->n; k++) cli_remove_output(w->path[k]);
  w->n = 0;
  return cli_fail(path, st, msg);
}

/* The baked texture: texel colours of the attribute a->bake. rgb: out, 3*W*H. */
static int bake(const tex_args *a, const au_mesh *m, const au_tex_layout *lay, const au_locator *loc, unsigned char *rgb,
                double *range) {
  au_msg msg = {{0}};
  au_status st;
  size_t n = (size_t)a->W * a->H;
  int kind = strcmp(a->bake, "normal") == 0 ? 0 : strcmp(a->bake, "position") == 0 ? 1 : 2;
  int k = kind == 2 ? 1 : 3;
  double *A = malloc((size_t)m->nv * k * sizeof *A);
  int *face = malloc(n * sizeof *face);
  double *bary = malloc(3 * n * sizeof *bary), *val = malloc(n * k * sizeof *val);
  int rc = -1;
  if (!A || !face || !bary || !val) {
    rc = cli_fail(a->in, AU_E_NOMEM, NULL);
    goto done;
  }
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  if (kind == 0) {
    au_tex_vertex_normals(m, A);
  } else if (kind == 1) {
    memcpy(A, m->X, 3 * (size_t)m->nv * sizeof *A);
    for (int i = 0; i < m->nv; i++)
      for (int j = 0; j < 3; j++) lo[j] = fmin(lo[j], A[3 * i + j]), hi[j] = fmax(hi[j], A[3 * i + j]);
  } else {
    st = au_read_scalars(a->bake, m->nv, A, &msg);
    if (st != AU_OK) {
      rc = cli_fail(a->bake, st, &msg);
      goto done;
    }
    for (int i = 0; i < m->nv; i++) lo[0] = fmin(lo[0], A[i]), hi[0] = fmax(hi[0], A[i]);
    range[0] = lo[0], range[1] = hi[0];
  }
  st = au_tex_locate_texels(lay, loc, a->W, a->H, face, bary, &msg);
  if (st == AU_OK) st = au_tex_interpolate((int)n, face, bary, m->F, k, A, val);
  if (st != AU_OK) {
    rc = cli_fail(a->in, st, &msg);
    goto done;
  }
  for (size_t i = 0; i < n; i++) {
    unsigned char *c = rgb + 3 * i;
    const double *v = val + i * k;
    if (face[i] < 0) {
      c[0] = c[1] = c[2] = 128;
    } else if (kind == 0) {
      double r = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      for (int j = 0; j < 3; j++) c[j] = (unsigned char)lround(255 * (r > 0 ? (v[j] / r + 1) / 2 : 0.5));
    } else if (kind == 1) {
      for (int j = 0; j < 3; j++) c[j] = (unsigned char)lround(255 * (hi[j] > lo[j] ? (v[j] - lo[j]) / (hi[j] - lo[j]) : 0.5));
    } else {
      au_cmap_viridis(hi[0] > lo[0] ? (v[0] - lo[0]) / (hi[0] - lo[0]) : 0.5, c);
    }
  }
done:
  free(A), free(face), free(bary), free(val);
  return rc;
}

/* The path of the image as the material file beside out should name it: its base name when both
 * are in the same directory (as written), else an absolute path. malloc'ed; NULL when out of memory. */
static char *image_ref(const char *out, const char *image) {
  const char *so = strrchr(out, '/'), *si = strrchr(image, '/');
  size_t lo = so ? (size_t)(so - out) : 0, li = si ? (size_t)(si - image) : 0;
  const char *base = si ? si + 1 : image;
  if ((!so && !si) || (so && si && lo == li && strncmp(out, image, lo) == 0)) return strdup(base);
  if (image[0] == '/') return strdup(image);
  char *dir = si ? strndup(image, li) : strdup(".");
  char abs[PATH_MAX];
  const char *res = dir && realpath(dir, abs) ? abs : NULL;
  free(dir);
  if (!res) return strdup(image);
  size_t n = strlen(res) + strlen(base) + 2;
  char *s = malloc(n);
  if (s) snprintf(s, n, "%s/%s", res, base);
  return s;
}

/* What a texture run makes and frees, handed from step to step. */
typedef struct tex_run {
  au_mesh *m;
  au_io_meta *meta;
  double *P;           /* the sphere map, nv x 3 */
  au_metrics met;      /* the sphere map's metrics */
  au_tex_mesh *t;      /* the texture coordinates */
  au_locator *loc;     /* NULL without --bake */
  unsigned char *rgb;  /* the baked texture, 3 x W x H; NULL without --bake */
  double range[2];     /* the baked scalar file's range; {0, 0} otherwise */
  char *mtl;           /* the material file beside OUT; NULL without --bake */
  cli_warnings warn;
  written w;
} tex_run;

/* Reads IN and gets its sphere map before anything is made of it. -1 to go on, else the exit code. */
static int texture_load(const tex_args *a, tex_run *s) {
  double t_read = 0, t_check = 0;
  int rc = cli_load(a->in, AU_TARGET_SPHERE, &s->m, &s->meta, &s->warn, &t_read, &t_check);
  if (rc >= 0) return rc;
  s->P = malloc(3 * (size_t)s->m->nv * sizeof *s->P);
  if (!s->P) return cli_fail(a->in, AU_E_NOMEM, NULL);
  return get_map(a, s->m, s->P, &s->warn, &s->met);
}

/* Makes the texture coordinates and warns when --area-target could not be met. -1 to go on, else the
 * exit code. */
static int texture_coords(const tex_args *a, tex_run *s) {
  au_msg msg = {{0}};
  au_status st = au_tex_coords_opts(s->m, s->P, &a->topts, &s->t, &msg);
  if (st != AU_OK) return cli_fail(a->map ? a->map : a->in, st, &msg);
  const au_tex_mesh *t = s->t;
  if (t->area_target > 0 && !t->area_target_met)
    cli_warn(&s->warn, a->in,
             "the texture's per-face error %.4g misses the target %.4g; the map's spherical per-face error %.4g "
             "is a floor%s",
             t->vt_err_mean, t->area_target, s->met.sph_r_mean_abs_dev,
             a->map && s->met.sph_r_mean_abs_dev > s->met.r_mean_abs_dev ? " (`authalic sphere --spherical-areas`, or texture without --map, makes a map with a lower one)" : "");
  return -1;
}

/* --bake: locates the texels on the sphere map and colours them. -1 to go on, else the exit code. */
static int texture_bake(const tex_args *a, tex_run *s) {
  au_msg msg = {{0}};
  s->rgb = malloc(3 * (size_t)a->W * a->H);
  au_status st = s->rgb ? au_locator_build(s->m->nv, s->P, s->m->nf, s->m->F, &s->loc, &msg) : AU_E_NOMEM;
  if (st != AU_OK) return cli_fail(a->in, st, &msg);
  return bake(a, s->m, &s->t->layout, s->loc, s->rgb, s->range);
}

/* --bake: the image, then the material file naming it, both before the OBJ that names the material.
 * -1 to go on, else the exit code (the outputs written so far removed). */
static int write_material(const tex_args *a, tex_run *s) {
  au_msg msg = {{0}};
  int rc = write_done(&s->w, a->image, au_png_write(a->image, a->W, a->H, s->rgb, &msg), &msg);
  if (rc >= 0) return rc;
  s->mtl = mtl_path(a->out);
  char *ref = image_ref(a->out, a->image);
  size_t len = ref ? strlen(ref) + strlen(a->bake) + 256 : 0; /* both names, any length */
  char *mtlbuf = ref ? malloc(len) : NULL;
  if (!s->mtl || !mtlbuf) {
    rc = write_done(&s->w, a->out, AU_E_NOMEM, NULL);
  } else {
    int k = snprintf(mtlbuf, len, "# authalic texture: material of the baked attribute '%s'\nnewmtl authalic\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nmap_Kd %s\n",
                     a->bake, ref);
    rc = write_done(&s->w, s->mtl, k >= 0 && (size_t)k < len ? au_write_text(s->mtl, mtlbuf, (size_t)k, &msg) : AU_E_INTERNAL, &msg);
  }
  free(mtlbuf), free(ref);
  return rc;
}

/* --lonlat: each vertex's longitude and latitude as text. -1 to go on, else the exit code. */
static int write_lonlat(const tex_args *a, tex_run *s) {
  au_msg msg = {{0}};
  const au_tex_mesh *t = s->t;
  /* The header names OUT (any length); a vertex's line is at most 2 x 19 + 2 characters. */
  size_t cap = 64 + strlen(a->out) + 48 * (size_t)t->nv, len = 0;
  char *ll = malloc(cap);
  if (!ll) return write_done(&s->w, a->lonlat, AU_E_NOMEM, NULL);
  len += (size_t)snprintf(ll, cap, "# longitude latitude (degrees) of each vertex of %s\n", a->out);
  for (int i = 0; i < t->nv && len < cap; i++)
    len += (size_t)snprintf(ll + len, cap - len, "%.12g %.12g\n", t->lonlat[2 * i], t->lonlat[2 * i + 1]);
  int rc = write_done(&s->w, a->lonlat, len < cap ? au_write_text(a->lonlat, ll, len, &msg) : AU_E_INTERNAL, &msg);
  free(ll);
  return rc;
}

/* Writing: the image and its material first, the OBJ that names them, then the extras. -1 when all
 * are written, else the exit code (the outputs written so far removed). */
static int texture_write(const tex_args *a, tex_run *s) {
  au_msg msg = {{0}};
  int rc;
  if (a->bake && (rc = write_material(a, s)) >= 0) return rc;
  const char *mtl_base = NULL;
  if (s->mtl) mtl_base = strrchr(s->mtl, '/') ? strrchr(s->mtl, '/') + 1 : s->mtl;
  if ((rc = write_done(&s->w, a->out, au_tex_write_obj(a->out, s->t, mtl_base, &msg), &msg)) >= 0) return rc;
  if (a->lonlat && (rc = write_lonlat(a, s)) >= 0) return rc;
  if (a->preview && (rc = write_done(&s->w, a->preview, au_tex_preview(a->preview, s->m, s->P, 1024, 0, &msg), &msg)) >= 0)
    return rc;
  if (a->distortion) {
    rc = cli_write_distortion(a->distortion, a->distortion, s->m, s->P, AU_DOMAIN_SPHERE, 0, NULL, NULL, s->meta);
    if (rc >= 0) {
      for (int k = 0; k < s->w.n; k++) cli_remove_output(s->w.path[k]);
      return rc;
    }
    s->w.path[s->w.n++] = a->distortion;
  }
  if (a->render) {
    double view[3];
    au_tex_seam_view(s->t, view);
    rc = write_done(&s->w, a->render, au_tex_render(a->render, s->t, s->rgb, a->W, a->H, view, 512, a->mark_seam, &msg), &msg);
    if (rc >= 0) return rc;
  }
  return -1;
}

/* The one summary line on stderr. */
static void texture_summary(const tex_args *a, const tex_run *s, double seconds) {
  const au_tex_mesh *t = s->t;
  const double *R = t->layout.R;
  char target[64] = "";
  if (t->area_target > 0)
    snprintf(target, sizeof target, ", target %.4g %s", t->area_target, t->area_target_met ? "met" : "missed");
  fprintf(stderr, "authalic: texture: V=%d F=%d projection=%s vt=%d seam faces=%d pole splits=%d edge splits=%d "
          "(split for folding=%d for area=%d%s, tol %.3g%s%s) out V=%d F=%d mean|r-1|=%.3g sph|r-1|=%.4g vt|r-1|=%.4g "
          "axis=%.6f,%.6f,%.6f",
          s->m->nv, s->m->nf, a->proj == AU_TEX_CEA ? "cea" : a->proj == AU_TEX_LAEA ? "laea" : "oct", t->nvt, t->seam_faces,
          t->pole_splits, t->edge_splits, t->fold_splits, t->area_splits, t->area_worst_first ? " worst first" : "",
          t->area_tol, target, !t->area_dropped ? "" : t->area_target_met ? ", none needed" : t->area_tries_failed == t->area_tries ? ", dropped: splits left folds" : ", dropped: no lower error",
          t->nv, t->nf, s->met.r_mean_abs_dev, s->met.sph_r_mean_abs_dev, t->vt_err_mean, R[6], R[7], R[8]);
  if (a->bake) fprintf(stderr, " baked=%s %dx%d", a->bake, a->W, a->H);
  if (s->range[1] > s->range[0]) fprintf(stderr, " range=[%g, %g]", s->range[0], s->range[1]);
  fprintf(stderr, " time=%.2fs\n", seconds);
}

/* The texture command after parsing: read and map, texture coordinates, bake, write, summarize. */
static int run_texture(const tex_args *a) {
  double t_start = cli_now();
  tex_run s;
  memset(&s, 0, sizeof s);
  int rc = texture_load(a, &s);
  if (rc < 0) rc = texture_coords(a, &s);
  if (rc < 0 && a->bake) rc = texture_bake(a, &s);
  if (rc < 0) rc = texture_write(a, &s);
  if (rc < 0) {
    if (!a->quiet) texture_summary(a, &s, cli_now() - t_start);
    rc = EXIT_OK;
  }
  au_tex_mesh_free(&s.t);
  au_locator_free(&s.loc);
  au_io_meta_free(&s.meta);
  au_mesh_free(&s.m);
  free(s.P), free(s.rgb), free(s.mtl);
  return rc;
}

/* A JSON number (null when not finite). */
static void json_num(char *s, size_t n, double v) {
  if (isfinite(v)) snprintf(s, n, "%.9g", v);
  else snprintf(s, n, "null");
}

/* The samples as CSV: a header, then one row per grid cell (its row, column, the longitude and latitude of
 * its centre, then its K columns). */
static au_status write_samples_csv(const tex_args *a, int K, const double *out, au_msg *msg) {
  size_t n = (size_t)a->W * a->H, cap = 256 + n * (size_t)(40 + 26 * K), len = 0;
  char *text = malloc(cap);
  if (!text) return au_msg_set(msg, AU_E_NOMEM, "out of memory for the samples");
  len += (size_t)snprintf(text, cap, "row,col,lon,lat,x,y,z");
  if (a->normals) len += (size_t)snprintf(text + len, cap - len, ",nx,ny,nz");
  for (int k = 0; k < a->nattr; k++) len += (size_t)snprintf(text + len, cap - len, ",attr%d", k);
  len += (size_t)snprintf(text + len, cap - len, "\n");
  for (int r = 0; r < a->H; r++)
    for (int c = 0; c < a->W; c++) {
      double lon = -180 + 360 * (c + 0.5) / a->W, lat = asin(1 - 2 * (r + 0.5) / a->H) * 180 / M_PI;
      len += (size_t)snprintf(text + len, cap - len, "%d,%d,%.12g,%.12g", r, c, lon, lat);
      const double *v = out + ((size_t)r * a->W + c) * K;
      for (int k = 0; k < K; k++) len += (size_t)snprintf(text + len, cap - len, ",%.17g", v[k]);
      len += (size_t)snprintf(text + len, cap - len, "\n");
    }
  au_status st = len < cap ? au_write_text(a->out, text, len, msg)
                           : au_msg_set(msg, AU_E_INTERNAL, "samples: the CSV text outgrew its buffer");
  free(text);
  return st;
}

/* What a sample run makes and frees, handed from step to step. */
typedef struct sample_run {
  au_mesh *m;
  double *P;       /* the sphere map, nv x 3 */
  au_metrics met;  /* the sphere map's metrics */
  au_locator *loc;
  size_t n;        /* grid cells, W x H */
  int K;           /* columns a cell: x y z, the normal, the attributes */
  int *face;       /* each cell centre's face, n */
  double *bary;    /* and its barycentric coordinates there, 3 n */
  double *A;       /* the vertex normals, 3 nv */
  double *tmp;     /* one interpolated quantity, 3 n */
  double *out;     /* the samples, n x K */
  double *attrs;   /* the attributes, nattr x nv; NULL without --attr */
  double amean, astd, amin, amax; /* the cells' preimage areas (--report) */
  cli_warnings warn;
  written w;
} sample_run;

/* Reads IN and takes all of the grid's memory before the (possibly long) map computation, so that a
 * grid too large fails at once. -1 to go on, else the exit code. */
static int sample_load(const tex_args *a, sample_run *s) {
  double t_read = 0, t_check = 0;
  int rc = cli_load(a->in, AU_TARGET_SPHERE, &s->m, NULL, &s->warn, &t_read, &t_check);
  if (rc >= 0) return rc;
  size_t n = s->n = (size_t)a->W * a->H;
  int K = s->K = 3 + (a->normals ? 3 : 0) + a->nattr;
  s->P = malloc(3 * (size_t)s->m->nv * sizeof *s->P);
  s->A = malloc(3 * (size_t)s->m->nv * sizeof *s->A);
  s->face = malloc(n * sizeof *s->face);
  s->bary = malloc(3 * n * sizeof *s->bary);
  s->out = malloc(n * K * sizeof *s->out);
  s->tmp = malloc(3 * n * sizeof *s->tmp);
  if (!s->P || !s->A || !s->face || !s->bary || !s->out || !s->tmp) return cli_fail(a->in, AU_E_NOMEM, NULL);
  return -1;
}

/* The attribute files are read before the (possibly long) map computation, so that a bad one fails at
 * once. -1 to go on, else the exit code. */
static int sample_read_attrs(const tex_args *a, sample_run *s) {
  au_msg msg = {{0}};
  if (!a->nattr) return -1;
  const int nv = s->m->nv;
  s->attrs = malloc((size_t)a->nattr * nv * sizeof *s->attrs);
  if (!s->attrs) return cli_fail(a->in, AU_E_NOMEM, NULL);
  for (int k = 0; k < a->nattr; k++) {
    au_status st = au_read_scalars(a->attr[k], nv, s->attrs + (size_t)k * nv, &msg);
    if (st != AU_OK) return cli_fail(a->attr[k], st, &msg);
  }
  return -1;
}

/* Finds every cell centre's preimage and interpolates the columns there: x y z, then normals, then the
 * scalars. -1 to go on, else the exit code. */
static int sample_grid(const tex_args *a, sample_run *s) {
  au_msg msg = {{0}};
  const au_mesh *m = s->m;
  const size_t n = s->n;
  const int K = s->K;
  au_status st = au_locator_build(m->nv, s->P, m->nf, m->F, &s->loc, &msg);
  au_tex_layout lay = au_tex_layout_default(AU_TEX_CEA);
  if (st == AU_OK) st = au_tex_locate_texels(&lay, s->loc, a->W, a->H, s->face, s->bary, &msg);
  size_t miss = 0;
  for (size_t i = 0; st == AU_OK && i < n; i++) miss += s->face[i] < 0;
  if (st == AU_OK && miss)
    st = au_msg_set(&msg, AU_E_FOLD, "%zu grid cells have no preimage (the map does not cover the sphere)", miss);
  int col = 0;
  if (st == AU_OK) st = au_tex_interpolate((int)n, s->face, s->bary, m->F, 3, m->X, s->tmp);
  for (size_t i = 0; st == AU_OK && i < n; i++) memcpy(s->out + i * K, s->tmp + 3 * i, 3 * sizeof *s->tmp);
  col = 3;
  if (st == AU_OK && a->normals) {
    au_tex_vertex_normals(m, s->A);
    st = au_tex_interpolate((int)n, s->face, s->bary, m->F, 3, s->A, s->tmp);
    for (size_t i = 0; st == AU_OK && i < n; i++) {
      double *v = s->tmp + 3 * i, r = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      for (int j = 0; j < 3; j++) s->out[i * K + col + j] = r > 0 ? v[j] / r : 0;
    }
    col += 3;
  }
  for (int k = 0; st == AU_OK && k < a->nattr; k++, col++) {
    st = au_tex_interpolate((int)n, s->face, s->bary, m->F, 1, s->attrs + (size_t)k * m->nv, s->tmp);
    for (size_t i = 0; st == AU_OK && i < n; i++) s->out[i * K + col] = s->tmp[i];
  }
  return st != AU_OK ? cli_fail(a->in, st, &msg) : -1;
}

/* --report: the surface area of every cell's preimage, as mean, std, min and max. -1 to go on, else
 * the exit code. */
static int sample_cell_areas(const tex_args *a, sample_run *s) {
  au_msg msg = {{0}};
  const size_t n = s->n;
  double *area = malloc(n * sizeof *area);
  au_status st = area ? au_tex_cell_areas(s->m, s->P, s->loc, a->W, a->H, 4, area, &msg) : AU_E_NOMEM;
  if (st != AU_OK) {
    free(area);
    return cli_fail(a->in, st, &msg);
  }
  for (size_t i = 0; i < n; i++) s->amean += area[i] / n, s->amin = fmin(s->amin, area[i]), s->amax = fmax(s->amax, area[i]);
  for (size_t i = 0; i < n; i++) s->astd += (area[i] - s->amean) * (area[i] - s->amean) / n;
  s->astd = sqrt(s->astd);
  free(area);
  return -1;
}

/* --report as JSON: the grid, the cells' preimage areas relative to their mean, the map's distortion.
 * -1 to go on, else the exit code. */
static int write_sample_report(const tex_args *a, sample_run *s, double seconds) {
  au_msg msg = {{0}};
  const double amean = s->amean;
  char b[6][32];
  json_num(b[0], 32, amean), json_num(b[1], 32, amean > 0 ? s->astd / amean : NAN);
  json_num(b[2], 32, amean > 0 ? s->amin / amean : NAN), json_num(b[3], 32, amean > 0 ? s->amax / amean : NAN);
  json_num(b[4], 32, s->met.r_cv), json_num(b[5], 32, s->met.upsilon_mean_abs);
  char rep[2048];
  int k = snprintf(rep, sizeof rep,
                   "{\n  \"tool_version\": \"%s\",\n  \"command\": \"sample\",\n  \"nv\": %d,\n  \"nf\": %d,\n"
                   "  \"grid\": [%d, %d],\n  \"columns\": %d,\n  \"cell_sphere_area\": %.17g,\n"
                   "  \"cell_area_subsamples\": 16,\n  \"cell_area_mean\": %s,\n  \"cell_area_cv\": %s,\n"
                   "  \"cell_area_min_rel\": %s,\n  \"cell_area_max_rel\": %s,\n  \"map_r_cv\": %s,\n"
                   "  \"map_upsilon_mean_abs\": %s,\n  \"map_folds\": %d,\n  \"seconds\": %.3f\n}\n",
                   AU_VERSION, s->m->nv, s->m->nf, a->W, a->H, s->K, 4 * M_PI / s->n, b[0], b[1], b[2], b[3], b[4], b[5],
                   s->met.folds, seconds);
  return write_done(&s->w, a->report, au_write_text(a->report, rep, (size_t)k, &msg), &msg);
}

/* Writing: the samples, then the extras. -1 when all are written, else the exit code (the outputs
 * written so far removed). */
static int sample_write(const tex_args *a, sample_run *s, double t_start) {
  au_msg msg = {{0}};
  int rc;
  if (cli_has_ext(a->out, ".npy")) {
    long shape[3] = {a->H, a->W, s->K};
    rc = write_done(&s->w, a->out, au_npy_write(a->out, 3, shape, s->out, &msg), &msg);
  } else {
    rc = write_done(&s->w, a->out, write_samples_csv(a, s->K, s->out, &msg), &msg);
  }
  if (rc >= 0) return rc;
  if (a->report && (rc = write_sample_report(a, s, cli_now() - t_start)) >= 0) return rc;
  if (a->preview && (rc = write_done(&s->w, a->preview, au_tex_preview(a->preview, s->m, s->P, 1024, 0, &msg), &msg)) >= 0)
    return rc;
  return -1;
}

/* The one summary line on stderr. */
static void sample_summary(const tex_args *a, const sample_run *s, double t_start) {
  fprintf(stderr, "authalic: sample: V=%d F=%d grid=%dx%d columns=%d", s->m->nv, s->m->nf, a->W, a->H, s->K);
  if (a->report)
    fprintf(stderr, " cell area std/mean=%.4f min/mean=%.3f max/mean=%.3f", s->astd / s->amean, s->amin / s->amean,
            s->amax / s->amean);
  fprintf(stderr, " time=%.2fs\n", cli_now() - t_start);
}

/* The sample command after parsing: read, attributes, map, grid, cell areas, write, summarize. */
static int run_sample(const tex_args *a) {
  double t_start = cli_now();
  sample_run s;
  memset(&s, 0, sizeof s);
  s.amin = INFINITY;
  int rc = sample_load(a, &s);
  if (rc < 0) rc = sample_read_attrs(a, &s);
  if (rc < 0) rc = get_map(a, s.m, s.P, &s.warn, &s.met);
  if (rc < 0) rc = sample_grid(a, &s);
  free(s.attrs), s.attrs = NULL; /* interpolated into the samples: not kept through the writing */
  if (rc < 0 && a->report) rc = sample_cell_areas(a, &s);
  if (rc < 0) rc = sample_write(a, &s, t_start);
  if (rc < 0) {
    if (!a->quiet) sample_summary(a, &s, t_start);
    rc = EXIT_OK;
  }
  au_locator_free(&s.loc);
  au_mesh_free(&s.m);
  free(s.P), free(s.A), free(s.face), free(s.bary), free(s.out), free(s.tmp);
  return rc;
}

int cli_cmd_texture(int argc, char **argv) {
  tex_args a;
  memset(&a, 0, sizeof a);
  a.proj = AU_TEX_CEA;
  int rc = parse_args(argc, argv, &a);
  return rc >= 0 ? rc : run_texture(&a);
}

int cli_cmd_sample(int argc, char **argv) {
  tex_args a;
  memset(&a, 0, sizeof a);
  a.sample = 1;
  int rc = parse_args(argc, argv, &a);
  return rc >= 0 ? rc : run_sample(&a);
}
