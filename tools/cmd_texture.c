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

#include "au_sphere.h"
#include "au_texture.h"
#include "cli.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define HELP_TEX "authalic texture --help"
#define HELP_SAMPLE "authalic sample --help"
#define MAX_ATTR 16

static void print_texture_help(void) {
  printf("usage: authalic texture IN [--map SPHERE_MAP] OUT.obj [options]\n\n"
         "Writes the closed genus-0 mesh IN as OUT.obj with texture coordinates (`vt`) in an equal-area\n"
         "projection of its sphere map, so every texel of a texture stands for the same surface area.\n"
         "The sphere map is read from SPHERE_MAP (the output of `authalic sphere IN SPHERE_MAP`) or\n"
         "computed on the fly. Faces across the projection's seam get their own copies of `vt`; with\n"
         "cea, the faces holding a pole are split there (the pole vertices are appended after IN's).\n\n"
         "options of texture:\n"
         "  --map SPHERE_MAP    the sphere map of IN (same vertices and faces, positions on a sphere\n"
         "                      about the origin of any radius)\n"
         "  --projection P      cea: Lambert cylindrical equal-area, u = (lon + pi)/(2 pi),\n"
         "                      v = (sin lat + 1)/2; sample with u wrapped (repeat) (default)\n"
         "                      laea: Lambert azimuthal equal-area, northern hemisphere in the left half,\n"
         "                      southern in the right half (no wrapping needed)\n"
         "  --lonlat FILE       write longitude and latitude in degrees of every vertex of OUT.obj\n"
         "  --bake ATTR         bake a per-vertex attribute into --image: `normal` (unit normals as\n"
         "                      colours (n + 1)/2), `position` (the bounding box as RGB), or a file with\n"
         "                      one number per vertex of IN (text, FreeSurfer curv, GIfTI .shape.gii or\n"
         "                      .func.gii), drawn with the viridis colour map\n"
         "  --image OUT.png     the baked texture; OUT.mtl is written beside OUT.obj and names it\n"
         "  --size WxH          texture size in texels (default 1024x512; laea needs an even W)\n"
         "  --preview P.png     the sphere map from +z and -z coloured by Upsilon = ln(surface/sphere\n"
         "                      area) from -0.5 (blue) to +0.5 (red), with the Upsilon (dark red) and\n"
         "                      Lambda (blue) histograms\n"
         "  --render R.png      IN drawn with the baked texture through OUT.obj's coordinates, from the\n"
         "                      side of the seam and from the opposite side (needs --bake)\n"
         "  --mark-seam         tint the faces across the cea seam red in --render\n"
         "  --distortion FILE   per-vertex areal distortion log2(sphere area share / surface area share)\n"
         "                      of the sphere map (HCP's convention): a FreeSurfer curv file, or GIfTI\n"
         "                      when FILE ends in .gii (e.g. .shape.gii)\n"
         "  --quiet             no progress and no summary on stderr (errors and warnings remain)\n"
         "  --help              this text\n");
}

static void print_sample_help(void) {
  printf("usage: authalic sample IN --grid WxH OUT [--map SPHERE_MAP] [options]\n\n"
         "Samples the closed genus-0 mesh IN on an equal-area grid of its sphere map: cell (row r,\n"
         "column c) spans longitudes -180 + 360 [c, c+1]/W degrees and sin(latitude) in\n"
         "1 - 2 [r, r+1]/H (row 0 at the north pole), so every cell covers 4 pi/(W H) of the sphere and,\n"
         "through an authalic map, the same share of the surface. The cell centre's preimage on IN gives\n"
         "the cell's values: x, y, z, then the attributes asked for.\n"
         "OUT.npy: NumPy float64 array of shape (H, W, 3 + attributes): numpy.load(OUT).\n"
         "OUT.csv: one line per cell: row,col,lon,lat,x,y,z,attributes (after a header line).\n\n"
         "options of sample:\n"
         "  --grid WxH          grid size, W and H from 1 to 16384 (required)\n"
         "  --map SPHERE_MAP    the sphere map of IN (computed on the fly when absent)\n"
         "  --normals           add the surface normal (3 columns)\n"
         "  --attr FILE         add a per-vertex scalar (one number per vertex: a text file, a FreeSurfer\n"
         "                      curv file such as lh.sulc, or GIfTI .shape.gii / .func.gii); repeatable\n"
         "  --report R.json     the surface area of every cell's preimage (mean, std/mean, min, max) and\n"
         "                      the map's distortion\n"
         "  --preview P.png     the preview picture of the sphere map (see `authalic texture --help`)\n"
         "  --quiet             no progress and no summary on stderr\n"
         "  --help              this text\n");
}

/* Everything either command was asked to do. */
typedef struct tex_args {
  const char *in, *out, *map, *lonlat, *bake, *image, *preview, *render, *report, *distortion;
  const char *attr[MAX_ATTR];
  int nattr;
  au_tex_proj proj;
  int has_proj, W, H, has_size, normals, quiet, sample, mark_seam;
} tex_args;

/* "WxH" with both in [1, 16384]. */
static int parse_size(const char *s, int *W, int *H) {
  const char *x = strchr(s, 'x');
  if (!x || x == s || !x[1] || strchr(x + 1, 'x')) return -1;
  char a[32];
  size_t n = (size_t)(x - s);
  if (n >= sizeof a) return -1;
  memcpy(a, s, n);
  a[n] = '\0';
  return cli_parse_int(a, 1, 16384, W) || cli_parse_int(x + 1, 1, 16384, H) ? -1 : 0;
}

static int has_ext(const char *path, const char *ext) {
  const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
  return dot && (!slash || dot > slash) && strcasecmp(dot, ext) == 0;
}

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
  const char *help = a->sample ? HELP_SAMPLE : HELP_TEX;
  int npos = 0, dashdash = 0;
  const char *pos[2] = {NULL, NULL};
  for (int i = 1; i < argc; i++) {
    const char *s = argv[i];
    if (dashdash || s[0] != '-' || s[1] == '\0') {
      if (npos >= 2) return cli_usage_error(help, "unexpected extra argument '%s'", s);
      pos[npos++] = s;
      continue;
    }
    if (strcmp(s, "--") == 0) {
      dashdash = 1;
    } else if (strcmp(s, "--help") == 0 || strcmp(s, "-h") == 0) {
      if (a->sample) print_sample_help();
      else print_texture_help();
      return EXIT_OK;
    } else if (strcmp(s, "--quiet") == 0) {
      if (a->quiet++) return cli_usage_error(help, "option '%s' given twice", s);
    } else if (a->sample && strcmp(s, "--normals") == 0) {
      if (a->normals++) return cli_usage_error(help, "option '%s' given twice", s);
    } else if (!a->sample && strcmp(s, "--mark-seam") == 0) {
      if (a->mark_seam++) return cli_usage_error(help, "option '%s' given twice", s);
    } else {
      /* Options with a value. */
      const char **slot = NULL;
      int is_known = 1;
      if (strcmp(s, "--map") == 0) slot = &a->map;
      else if (strcmp(s, "--preview") == 0) slot = &a->preview;
      else if (!a->sample && strcmp(s, "--lonlat") == 0) slot = &a->lonlat;
      else if (!a->sample && strcmp(s, "--bake") == 0) slot = &a->bake;
      else if (!a->sample && strcmp(s, "--image") == 0) slot = &a->image;
      else if (!a->sample && strcmp(s, "--render") == 0) slot = &a->render;
      else if (!a->sample && strcmp(s, "--distortion") == 0) slot = &a->distortion;
      else if (a->sample && strcmp(s, "--report") == 0) slot = &a->report;
      else if (!a->sample && strcmp(s, "--projection") == 0) ;
      else if (!a->sample && strcmp(s, "--size") == 0) ;
      else if (a->sample && strcmp(s, "--grid") == 0) ;
      else if (a->sample && strcmp(s, "--attr") == 0) ;
      else is_known = 0;
      if (!is_known) return cli_usage_error(help, "unknown option '%s'", s);
      if (i + 1 >= argc) return cli_usage_error(help, "option '%s' needs a value", s);
      const char *v = argv[++i];
      if (slot) {
        if (*slot) return cli_usage_error(help, "option '%s' given twice", s);
        if (!*v) return cli_usage_error(help, "option '%s' needs a file name", s);
        *slot = v;
      } else if (strcmp(s, "--projection") == 0) {
        if (a->has_proj++) return cli_usage_error(help, "option '%s' given twice", s);
        if (strcmp(v, "cea") == 0) a->proj = AU_TEX_CEA;
        else if (strcmp(v, "laea") == 0) a->proj = AU_TEX_LAEA;
        else return cli_usage_error(help, "--projection '%s': expected cea or laea", v);
      } else if (strcmp(s, "--size") == 0 || strcmp(s, "--grid") == 0) {
        if (a->has_size++) return cli_usage_error(help, "option '%s' given twice", s);
        if (parse_size(v, &a->W, &a->H))
          return cli_usage_error(help, "%s '%s': expected WxH with W and H whole numbers from 1 to 16384", s, v);
      } else {
        if (a->nattr >= MAX_ATTR) return cli_usage_error(help, "at most %d --attr files", MAX_ATTR);
        if (!*v) return cli_usage_error(help, "option '--attr' needs a file name");
        a->attr[a->nattr++] = v;
      }
    }
  }
  if (npos < 2) return cli_usage_error(help, npos == 0 ? "missing input and output files" : "missing output file");
  a->in = pos[0], a->out = pos[1];
  if (!*a->in || !*a->out) return cli_usage_error(help, "empty file name");

  /* Combinations and output names. */
  if (a->sample) {
    if (!a->has_size) return cli_usage_error(help, "missing --grid WxH");
    if ((long)a->W * a->H > 16L * 1024 * 1024) return cli_usage_error(help, "--grid %dx%d: more than 16M cells", a->W, a->H);
    if (!has_ext(a->out, ".npy") && !has_ext(a->out, ".csv"))
      return cli_usage_error(help, "output '%s': use .npy or .csv", a->out);
    if (a->report && !has_ext(a->report, ".json")) return cli_usage_error(help, "report '%s': use .json", a->report);
  } else {
    if (!has_ext(a->out, ".obj")) return cli_usage_error(help, "output '%s': texture coordinates are written as .obj", a->out);
    if (a->bake && !a->image) return cli_usage_error(help, "--bake needs --image OUT.png");
    if (a->image && !a->bake) return cli_usage_error(help, "--image needs --bake ATTR");
    if (a->render && !a->bake) return cli_usage_error(help, "--render needs --bake ATTR and --image");
    if (a->mark_seam && !a->render) return cli_usage_error(help, "--mark-seam applies to --render only");
    if (a->has_size && !a->bake) return cli_usage_error(help, "--size applies to --bake only");
    if (!a->has_size) a->W = 1024, a->H = 512;
    if (a->proj == AU_TEX_LAEA && a->W % 2) return cli_usage_error(help, "--size %dx%d: laea needs an even width", a->W, a->H);
    if ((long)a->W * a->H > 64L * 1024 * 1024) return cli_usage_error(help, "--size %dx%d: more than 64M texels", a->W, a->H);
    if (a->image && !has_ext(a->image, ".png")) return cli_usage_error(help, "image '%s': use .png", a->image);
    if (a->render && !has_ext(a->render, ".png")) return cli_usage_error(help, "render '%s': use .png", a->render);
  }
  if (a->preview && !has_ext(a->preview, ".png")) return cli_usage_error(help, "preview '%s': use .png", a->preview);

  /* Every output distinct from the inputs and from each other, in an existing directory. */
  char *mtl = (!a->sample && a->bake) ? mtl_path(a->out) : NULL;
  const char *outs[8] = {a->out, a->lonlat, a->image, a->preview, a->render, a->report, mtl, a->distortion};
  const char *names[8] = {"output", "--lonlat", "--image", "--preview", "--render", "--report", "material file",
                          "--distortion"};
  const char *ins[2 + MAX_ATTR] = {a->in, a->map};
  int nin = 2;
  for (int k = 0; k < a->nattr; k++) ins[nin++] = a->attr[k];
  if (!a->sample && a->bake && strcmp(a->bake, "normal") && strcmp(a->bake, "position")) ins[nin++] = a->bake;
  int rc = -1;
  for (int k = 0; k < 8 && rc < 0; k++) {
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
static int get_map(const tex_args *a, const au_mesh *m, const au_topo *topo, double *P, cli_warnings *warn,
                   au_metrics *met) {
  au_msg msg = {{0}};
  au_status st;
  if (a->map) {
    au_mesh *s = NULL;
    st = au_io_read(a->map, &s, &msg);
    if (st != AU_OK) return cli_fail(a->map, st, &msg);
    int bad = s->nv != m->nv || s->nf != m->nf;
    for (long i = 0; !bad && i < 3L * m->nf; i++) bad = s->F[i] != m->F[i];
    if (bad) {
      au_msg_set(&msg, AU_E_FORMAT, "not a map of '%s': %d vertices and %d faces (the input has %d and %d) or other faces",
                 a->in, s->nv, s->nf, m->nv, m->nf);
      au_mesh_free(&s);
      return cli_fail(a->map, AU_E_FORMAT, &msg);
    }
    /* The sphere's radius is that of the first vertex used: FreeSurfer's and HCP's have 100. Their
     * vertices are within 1e-4 of it (FreeSurfer's fsaverage5 sphere: 99.9929 .. 100.0078), and are
     * projected onto it. */
    double R = 0;
    for (int i = 0; i < m->nv && !(R > 0); i++)
      if (topo->vused[i]) R = sqrt(s->X[3 * i] * s->X[3 * i] + s->X[3 * i + 1] * s->X[3 * i + 1] + s->X[3 * i + 2] * s->X[3 * i + 2]);
    for (int i = 0; i < m->nv; i++) {
      const double *q = s->X + 3 * (size_t)i;
      double r = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
      if (topo->vused[i] && !(fabs(r / R - 1) <= 1e-3)) {
        au_msg_set(&msg, AU_E_FORMAT, "vertex %d is not on the sphere of the first vertex's radius %.9g (|p| = %.9g)", i, R, r);
        au_mesh_free(&s);
        return cli_fail(a->map, AU_E_FORMAT, &msg);
      }
      for (int j = 0; j < 3; j++) P[3 * i + j] = r > 0 ? q[j] / r : (j == 2);
    }
    au_mesh_free(&s);
  } else {
    cli_progress_state prog;
    cli_progress_init(&prog, a->quiet);
    au_sphere_opts opts = au_sphere_opts_default();
    if (!a->quiet) opts.flow.progress = cli_progress, opts.flow.user = &prog;
    au_sphere_report rep;
    memset(&rep, 0, sizeof rep);
    st = au_sphere_map(m, topo, &opts, P, NULL, &rep, &msg);
    cli_progress_end(&prog);
    if (st < 0) return cli_fail(a->in, st, &msg);
    if (st == AU_W_NOT_CONVERGED)
      cli_warn(warn, a->in, "sphere map: tolerance %g not reached in %d steps", opts.flow.tol, rep.flow.steps);
  }
  st = au_metrics_compute(m->nv, m->nf, m->X, P, m->F, AU_DOMAIN_SPHERE, met, NULL, NULL);
  if (st != AU_OK) return cli_fail(a->in, st, NULL);
  if (met->folds > 0) {
    if (!a->map) return cli_refuse_folds(a->in, met, 0);
    au_msg_set(&msg, AU_E_FORMAT, "the sphere map has %d folded triangle%s; nothing written", met->folds,
               met->folds == 1 ? "" : "s");
    return cli_fail(a->map, AU_E_FORMAT, &msg);
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
  for (int k = 0; k < w->n; k++) unlink(w->path[k]);
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

static int run_texture(const tex_args *a) {
  double t_start = cli_now();
  au_report_stage stages[4];
  int nst = 0, rc;
  cli_warnings warn;
  warn.n = 0;
  au_mesh *m = NULL;
  au_topo *topo = NULL;
  au_tex_mesh *t = NULL;
  au_locator *loc = NULL;
  double *P = NULL;
  unsigned char *rgb = NULL;
  char *mtl = NULL, *mtlbuf = NULL, *ref = NULL, *ll = NULL;
  au_msg msg = {{0}};
  au_status st;
  au_metrics met;
  au_io_meta *meta = NULL;
  written w = {{0}, 0};
  double range[2] = {0, 0};

  au_mesh_expect ex = au_mesh_expect_default();
  ex.loops = 0, ex.genus = 0, ex.command = "texture";
  rc = cli_load_meta(a->in, &ex, &m, &topo, &meta, &warn, stages, &nst);
  if (rc >= 0) goto done;
  P = malloc(3 * (size_t)m->nv * sizeof *P);
  if (!P) {
    rc = cli_fail(a->in, AU_E_NOMEM, NULL);
    goto done;
  }
  rc = get_map(a, m, topo, P, &warn, &met);
  if (rc >= 0) goto done;
  st = au_tex_coords(m, P, a->proj, &t, &msg);
  if (st != AU_OK) {
    rc = cli_fail(a->map ? a->map : a->in, st, &msg);
    goto done;
  }
  if (a->bake) {
    rgb = malloc(3 * (size_t)a->W * a->H);
    st = rgb ? au_locator_build(m->nv, P, m->nf, m->F, &loc, &msg) : AU_E_NOMEM;
    if (st != AU_OK) {
      rc = cli_fail(a->in, st, &msg);
      goto done;
    }
    rc = bake(a, m, &t->layout, loc, rgb, range);
    if (rc >= 0) goto done;
  }

  /* Writing: the image and its material first, the OBJ that names them, then the extras. */
  if (a->bake) {
    rc = write_done(&w, a->image, au_png_write(a->image, a->W, a->H, rgb, &msg), &msg);
    if (rc >= 0) goto done;
    mtl = mtl_path(a->out);
    ref = image_ref(a->out, a->image);
    size_t len = ref ? strlen(ref) + 256 : 0;
    mtlbuf = ref ? malloc(len) : NULL;
    if (!mtl || !mtlbuf) {
      rc = write_done(&w, a->out, AU_E_NOMEM, NULL);
      goto done;
    }
    int k = snprintf(mtlbuf, len, "# authalic texture: material of the baked attribute '%s'\nnewmtl authalic\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nmap_Kd %s\n",
                     a->bake, ref);
    rc = write_done(&w, mtl, au_io_write_text(mtl, mtlbuf, (size_t)k, &msg), &msg);
    if (rc >= 0) goto done;
  }
  const char *mtl_base = NULL;
  if (mtl) mtl_base = strrchr(mtl, '/') ? strrchr(mtl, '/') + 1 : mtl;
  rc = write_done(&w, a->out, au_tex_write_obj(a->out, t, mtl_base, &msg), &msg);
  if (rc >= 0) goto done;
  if (a->lonlat) {
    size_t cap = 64 + 48 * (size_t)t->nv, len = 0;
    ll = malloc(cap);
    if (!ll) {
      rc = write_done(&w, a->lonlat, AU_E_NOMEM, NULL);
      goto done;
    }
    len += (size_t)snprintf(ll, cap, "# longitude latitude (degrees) of each vertex of %s\n", a->out);
    for (int i = 0; i < t->nv && len < cap; i++)
      len += (size_t)snprintf(ll + len, cap - len, "%.12g %.12g\n", t->lonlat[2 * i], t->lonlat[2 * i + 1]);
    rc = write_done(&w, a->lonlat, au_io_write_text(a->lonlat, ll, len, &msg), &msg);
    if (rc >= 0) goto done;
  }
  if (a->preview) {
    rc = write_done(&w, a->preview, au_tex_preview(a->preview, m, P, 1024, 0, &msg), &msg);
    if (rc >= 0) goto done;
  }
  if (a->distortion) {
    rc = cli_write_distortion(a->distortion, m, P, AU_DOMAIN_SPHERE, meta);
    if (rc >= 0) {
      for (int k = 0; k < w.n; k++) unlink(w.path[k]);
      goto done;
    }
    w.path[w.n++] = a->distortion;
  }
  if (a->render) {
    double view[3];
    au_tex_seam_view(t, view);
    rc = write_done(&w, a->render, au_tex_render(a->render, t, rgb, a->W, a->H, view, 512, a->mark_seam, &msg), &msg);
    if (rc >= 0) goto done;
  }
  if (!a->quiet) {
    fprintf(stderr, "authalic: texture: V=%d F=%d projection=%s vt=%d seam faces=%d pole splits=%d edge splits=%d mean|r-1|=%.3g",
            m->nv, m->nf, a->proj == AU_TEX_CEA ? "cea" : "laea", t->nvt, t->seam_faces, t->pole_splits, t->edge_splits,
            met.r_mean_abs_dev);
    if (a->bake) fprintf(stderr, " baked=%s %dx%d", a->bake, a->W, a->H);
    if (range[1] > range[0]) fprintf(stderr, " range=[%g, %g]", range[0], range[1]);
    fprintf(stderr, " time=%.2fs\n", cli_now() - t_start);
  }
  rc = EXIT_OK;
done:
  au_tex_mesh_free(&t);
  au_locator_free(&loc);
  au_io_meta_free(&meta);
  au_topo_free(&topo);
  au_mesh_free(&m);
  free(P), free(rgb), free(mtl), free(mtlbuf), free(ref), free(ll);
  return rc;
}

/* A JSON number (null when not finite). */
static void json_num(char *s, size_t n, double v) {
  if (isfinite(v)) snprintf(s, n, "%.9g", v);
  else snprintf(s, n, "null");
}

static int run_sample(const tex_args *a) {
  double t_start = cli_now();
  au_report_stage stages[4];
  int nst = 0, rc;
  cli_warnings warn;
  warn.n = 0;
  au_mesh *m = NULL;
  au_topo *topo = NULL;
  au_locator *loc = NULL;
  double *P = NULL, *bary = NULL, *out = NULL, *A = NULL, *tmp = NULL, *area = NULL;
  int *face = NULL;
  char *text = NULL;
  au_msg msg = {{0}};
  au_status st;
  au_metrics met;
  written w = {{0}, 0};

  au_mesh_expect ex = au_mesh_expect_default();
  ex.loops = 0, ex.genus = 0, ex.command = "sample";
  rc = cli_load(a->in, &ex, &m, &topo, &warn, stages, &nst);
  if (rc >= 0) goto done;
  size_t n = (size_t)a->W * a->H;
  int K = 3 + (a->normals ? 3 : 0) + a->nattr;
  P = malloc(3 * (size_t)m->nv * sizeof *P);
  A = malloc(3 * (size_t)m->nv * sizeof *A);
  face = malloc(n * sizeof *face);
  bary = malloc(3 * n * sizeof *bary);
  out = malloc(n * K * sizeof *out);
  tmp = malloc(3 * n * sizeof *tmp);
  if (!P || !A || !face || !bary || !out || !tmp) {
    rc = cli_fail(a->in, AU_E_NOMEM, NULL);
    goto done;
  }
  /* The attribute files are read before the (possibly long) map computation. */
  double *attrs = NULL;
  if (a->nattr) {
    attrs = malloc((size_t)a->nattr * m->nv * sizeof *attrs);
    if (!attrs) {
      rc = cli_fail(a->in, AU_E_NOMEM, NULL);
      goto done;
    }
    for (int k = 0; k < a->nattr; k++) {
      st = au_read_scalars(a->attr[k], m->nv, attrs + (size_t)k * m->nv, &msg);
      if (st != AU_OK) {
        free(attrs);
        rc = cli_fail(a->attr[k], st, &msg);
        goto done;
      }
    }
  }
  rc = get_map(a, m, topo, P, &warn, &met);
  if (rc < 0) {
    st = au_locator_build(m->nv, P, m->nf, m->F, &loc, &msg);
    au_tex_layout lay = au_tex_layout_default(AU_TEX_CEA);
    if (st == AU_OK) st = au_tex_locate_texels(&lay, loc, a->W, a->H, face, bary, &msg);
    size_t miss = 0;
    for (size_t i = 0; st == AU_OK && i < n; i++) miss += face[i] < 0;
    if (st == AU_OK && miss)
      st = au_msg_set(&msg, AU_E_FOLD, "%zu grid cells have no preimage (the map does not cover the sphere)", miss);
    /* Columns: x y z, then normals, then the scalars. */
    int col = 0;
    if (st == AU_OK) st = au_tex_interpolate((int)n, face, bary, m->F, 3, m->X, tmp);
    for (size_t i = 0; st == AU_OK && i < n; i++) memcpy(out + i * K, tmp + 3 * i, 3 * sizeof *tmp);
    col = 3;
    if (st == AU_OK && a->normals) {
      au_tex_vertex_normals(m, A);
      st = au_tex_interpolate((int)n, face, bary, m->F, 3, A, tmp);
      for (size_t i = 0; st == AU_OK && i < n; i++) {
        double *v = tmp + 3 * i, r = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        for (int j = 0; j < 3; j++) out[i * K + col + j] = r > 0 ? v[j] / r : 0;
      }
      col += 3;
    }
    for (int k = 0; st == AU_OK && k < a->nattr; k++, col++) {
      st = au_tex_interpolate((int)n, face, bary, m->F, 1, attrs + (size_t)k * m->nv, tmp);
      for (size_t i = 0; st == AU_OK && i < n; i++) out[i * K + col] = tmp[i];
    }
    if (st != AU_OK) rc = cli_fail(a->in, st, &msg);
  }
  free(attrs);
  if (rc >= 0) goto done;

  double amean = 0, astd = 0, amin = INFINITY, amax = 0;
  if (a->report) {
    area = malloc(n * sizeof *area);
    st = area ? au_tex_cell_areas(m, P, loc, a->W, a->H, 4, area, &msg) : AU_E_NOMEM;
    if (st != AU_OK) {
      rc = cli_fail(a->in, st, &msg);
      goto done;
    }
    for (size_t i = 0; i < n; i++) amean += area[i] / n, amin = fmin(amin, area[i]), amax = fmax(amax, area[i]);
    for (size_t i = 0; i < n; i++) astd += (area[i] - amean) * (area[i] - amean) / n;
    astd = sqrt(astd);
  }

  /* Writing: the samples, then the extras. */
  if (has_ext(a->out, ".npy")) {
    long shape[3] = {a->H, a->W, K};
    rc = write_done(&w, a->out, au_npy_write(a->out, 3, shape, out, &msg), &msg);
  } else {
    size_t cap = 256 + n * (size_t)(40 + 26 * K), len = 0;
    text = malloc(cap);
    if (!text) {
      rc = write_done(&w, a->out, AU_E_NOMEM, NULL);
      goto done;
    }
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
    rc = write_done(&w, a->out, len < cap ? au_io_write_text(a->out, text, len, &msg) : AU_E_INTERNAL, &msg);
  }
  if (rc >= 0) goto done;
  if (a->report) {
    char b[6][32];
    json_num(b[0], 32, amean), json_num(b[1], 32, amean > 0 ? astd / amean : NAN);
    json_num(b[2], 32, amean > 0 ? amin / amean : NAN), json_num(b[3], 32, amean > 0 ? amax / amean : NAN);
    json_num(b[4], 32, met.r_cv), json_num(b[5], 32, met.upsilon_mean_abs);
    char rep[2048];
    int k = snprintf(rep, sizeof rep,
                     "{\n  \"tool_version\": \"%s\",\n  \"command\": \"sample\",\n  \"nv\": %d,\n  \"nf\": %d,\n"
                     "  \"grid\": [%d, %d],\n  \"columns\": %d,\n  \"cell_sphere_area\": %.17g,\n"
                     "  \"cell_area_subsamples\": 16,\n  \"cell_area_mean\": %s,\n  \"cell_area_cv\": %s,\n"
                     "  \"cell_area_min_rel\": %s,\n  \"cell_area_max_rel\": %s,\n  \"map_r_cv\": %s,\n"
                     "  \"map_upsilon_mean_abs\": %s,\n  \"map_folds\": %d,\n  \"seconds\": %.3f\n}\n",
                     AU_VERSION, m->nv, m->nf, a->W, a->H, K, 4 * M_PI / n, b[0], b[1], b[2], b[3], b[4], b[5],
                     met.folds, cli_now() - t_start);
    rc = write_done(&w, a->report, au_io_write_text(a->report, rep, (size_t)k, &msg), &msg);
    if (rc >= 0) goto done;
  }
  if (a->preview) {
    rc = write_done(&w, a->preview, au_tex_preview(a->preview, m, P, 1024, 0, &msg), &msg);
    if (rc >= 0) goto done;
  }
  if (!a->quiet) {
    fprintf(stderr, "authalic: sample: V=%d F=%d grid=%dx%d columns=%d", m->nv, m->nf, a->W, a->H, K);
    if (a->report) fprintf(stderr, " cell area std/mean=%.4f min/mean=%.3f max/mean=%.3f", astd / amean, amin / amean, amax / amean);
    fprintf(stderr, " time=%.2fs\n", cli_now() - t_start);
  }
  rc = EXIT_OK;
done:
  au_locator_free(&loc);
  au_topo_free(&topo);
  au_mesh_free(&m);
  free(P), free(A), free(face), free(bary), free(out), free(tmp), free(area), free(text);
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
