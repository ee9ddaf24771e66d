/* cmd_atlas.c - `authalic atlas IN OUT.obj`: the atlas of a surface of any genus (au_atlas), written as
 * the input's vertices and faces with per-corner texture coordinates. Parses, reads, maps, writes. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char usage[] =
    "usage: authalic atlas IN OUT.obj [options]\n"
    "A seamless atlas of a connected orientable manifold mesh of any genus, closed or open: per-corner texture\n"
    "coordinates (vt) in [0,1]^2, charts cut through cones and a homology basis, laid out in a flat cone metric\n"
    "conformal to the surface, then made equal area by a flow that moves both sides of every seam together\n"
    "(one rotation and translation per seam), packed at one scale (docs/atlas.md).\n";

/* Read the cones file: lines "VERTEX ANGLE_DEG" ('#' comments and blank lines skipped). Returns -1 with
 * the arrays set, or prints the error and returns the exit code. */
static int read_cones(const char *path, int nv, int **v, double **ang, int *n) {
  FILE *fp = fopen(path, "r");
  if (!fp) {
    fprintf(stderr, "authalic: error: %s: cannot open the cones file: %s\n", path, strerror(errno));
    return EXIT_USAGE;
  }
  char line[512];
  int cap = 0, lineno = 0, rc = -1;
  *n = 0, *v = NULL, *ang = NULL;
  while (fgets(line, sizeof line, fp)) {
    lineno++;
    char *p = line;
    while (*p == ' ' || *p == '\t') p++;
    if (*p == '#' || *p == '\n' || *p == '\r' || *p == 0) continue;
    long vi;
    double deg;
    char tail[2];
    if (sscanf(p, "%ld %lf %1s", &vi, &deg, tail) != 2 || vi < 0 || vi >= nv || !isfinite(deg) || !(deg > 0)) {
      fprintf(stderr, "authalic: error: %s:%d: expected a vertex 0..%d and a positive angle in degrees\n", path, lineno,
              nv - 1);
      rc = EXIT_USAGE;
      break;
    }
    if (*n == cap) {
      cap = cap ? 2 * cap : 16;
      int *nvv = realloc(*v, (size_t)cap * sizeof **v);
      if (nvv) *v = nvv;
      double *na = realloc(*ang, (size_t)cap * sizeof **ang);
      if (na) *ang = na;
      if (!nvv || !na) {
        rc = cli_fail(path, AU_E_NOMEM, NULL);
        break;
      }
    }
    (*v)[*n] = (int)vi, (*ang)[*n] = deg * 3.14159265358979323846 / 180, (*n)++;
  }
  fclose(fp);
  if (rc < 0 && *n == 0) {
    fprintf(stderr, "authalic: error: %s: no cones in the file\n", path);
    rc = EXIT_USAGE;
  }
  return rc;
}

int cli_cmd_atlas(int argc, char **argv) {
  cli_args c;
  int rc = cli_parse(argc, argv, CLI_ATLAS, 2, usage, &c);
  if (rc >= 0) return rc;
  const char *help = c.help;
  if (c.npos < 2) return cli_usage_error(help, c.npos == 0 ? "missing input and output files" : "missing output file");
  const char *in = c.pos[0], *out = c.pos[1], *report = c.val[OPT_REPORT], *cones = c.val[OPT_CONES];
  if (!*in || !*out) return cli_usage_error(help, "empty file name");
  if (!cli_has_ext(out, ".obj")) return cli_usage_error(help, "output '%s': the atlas is written as OBJ (per-corner vt): use .obj", out);
  if ((rc = cli_check_outputs(help, in, out, report))) return rc;
  const char *html = c.val[OPT_HTML];
  if (html && (cli_same_file(html, in) || cli_same_file(html, out) || (report && cli_same_file(html, report)) ||
               (cones && cli_same_file(html, cones))))
    return cli_usage_error(help, "--html '%s' is also another input or output file", html);
  if (html && (rc = cli_check_writable_path(help, html, "--html"))) return rc;
  au_atlas_options o = au_atlas_options_default();
  if (cli_opt_int(&c, OPT_MAX_CONES, 1, 1000, &o.max_cones)) return EXIT_USAGE;
  o.quarter = c.val[OPT_QUARTER] != NULL;
  o.conformal_only = c.val[OPT_INIT_ONLY] != NULL;
  if (cli_opt_int(&c, OPT_STEPS, 1, 10000, &o.max_steps)) return EXIT_USAGE;
  if (cones && (o.quarter || c.val[OPT_MAX_CONES]))
    return cli_usage_error(help, "--cones gives the cones: --quarter and --max-cones apply to automatic ones");
  const int quiet = c.val[OPT_QUIET] != NULL;
  double t_start = cli_now(), t_read = 0, t_check = 0;
  au_mesh *m = NULL;
  au_atlas_result *r = NULL;
  int *cv = NULL;
  double *ca = NULL;
  char *json = NULL;
  au_msg msg = {{0}};
  rc = cli_load(in, (au_target)-1, &m, NULL, NULL, &t_read, &t_check);
  if (rc >= 0) return rc;
  if (cones) {
    if ((rc = read_cones(cones, m->nv, &cv, &ca, &o.ncones)) >= 0) goto done;
    o.cone_v = cv, o.cone_angle = ca;
  }
  au_status st = au_atlas(m->X, m->nv, m->F, m->nf, &o, &r, &msg);
  if (st < 0) {
    if (st == AU_E_ARG && cones) {
      fprintf(stderr, "authalic: error: %s: %s\n", cones, msg.text);
      rc = EXIT_USAGE;
    } else {
      rc = cli_fail(in, st, &msg);
    }
    goto done;
  }
  for (int k = 0; k < r->nwarnings; k++) fprintf(stderr, "authalic: warning: %s: %s\n", in, r->warnings[k]);
  if (report) {
    cli_expect_output(report);
    st = au_atlas_result_json(r, t_read, -1, &json, &msg);
    if (st == AU_OK) st = au_write_text(report, json, strlen(json), &msg);
    if (st != AU_OK) {
      rc = cli_fail(report, st, &msg);
      goto done;
    }
  }
  if (html) {
    /* The page is written whole under its own name (au_write_text renames a temporary into place) and
     * removed again, as the report is, if OUT cannot be published. */
    au_view_input v = au_view_input_default();
    v.nv = m->nv, v.nf = m->nf, v.X = m->X, v.F = r->F;
    v.nvt = r->nvt, v.vt = r->vt, v.Ft = r->Ft;
    v.steps = r->flow_steps, v.seconds = cli_now() - t_start;
    const char *slash = strrchr(in, '/');
    v.title = slash ? slash + 1 : in;
    cli_expect_output(html);
    if ((rc = cli_write_view(html, html, &v, quiet)) >= 0) {
      if (report) cli_remove_output(report);
      goto done;
    }
  }
  au_write_opts w = au_write_opts_default();
  w.nvt = r->nvt, w.vt = r->vt, w.Ft = r->Ft;
  rc = cli_publish(out, m->nv, m->X, m->nf, r->F, &w, NULL, NULL, NULL);
  if (rc != EXIT_OK) {
    if (report) cli_remove_output(report);
    if (html) cli_remove_output(html);
    goto done;
  }
  if (!quiet) {
    /* With quarter cones on a surface with homology loops: how many loops' holonomy is a quarter turn. */
    char hol[48] = "";
    if (r->holonomy_loops > 0) snprintf(hol, sizeof hol, " quarter_loops=%d/%d", r->holonomy_fixed, r->holonomy_loops);
    fprintf(stderr,
            "authalic: atlas: V=%d F=%d genus=%d loops=%d cones=%d charts=%d seams=%d coverage=%.3f folds=%d "
            "overlap_texels=%ld face_error=%.4f (start %.4f) equal_area=%s%s time=%.2fs\n",
            r->nv, r->nf, r->genus, r->nloops, r->ncones, r->ncharts, r->nseams, r->coverage, r->folds,
            r->overlap_texels, r->face_err, r->face_err_start, r->equal_area ? "yes" : "no", hol, cli_now() - t_start);
  }
done:
  au_free(json);
  au_atlas_result_free(&r);
  au_mesh_free(&m);
  free(cv), free(ca);
  return rc;
}
