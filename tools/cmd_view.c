/* cmd_view.c - `authalic view IN MAP OUT.html`: the page of au_view_html for a surface and a map of it
 * written earlier (by this program or another): MAP has IN's faces, with positions on a sphere or in
 * the plane z = 0, or OBJ `vt` texture coordinates (a torus map, a texture's coordinates). Also the
 * page of a map command's result (--html, cli_write_view). Parses, reads, writes; no numerics. */
#define _POSIX_C_SOURCE 200809L

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static const char usage_text[] =
    "usage: authalic view IN MAP OUT.html [--attr FILE] [--report R.json] [--title TEXT] [--quiet]\n"
    "One self-contained HTML page (nothing fetched when it opens) showing the surface IN and its map MAP\n"
    "side by side: the sphere as a globe, a planar map flat, a map by OBJ `vt` coordinates flat (tiled\n"
    "3 x 3 when they tile the plane, as a torus map's do); coloured by per-face area distortion log r,\n"
    "angle distortion, a checkerboard through the map or --attr; linked cursors, the headline figures and\n"
    "the histograms. MAP has IN's faces (the output of `authalic sphere|disk|annulus|square|torus`).\n"
    "options:\n"
    "  --attr FILE         a per-vertex value of IN to colour by (text, FreeSurfer curv such as lh.sulc,\n"
    "                      GIfTI .shape.gii / .func.gii)\n"
    "  --report R.json     the map's report: its steps and time are shown with the figures\n"
    "  --title TEXT        the page's title (default: IN's file name)\n"
    "  --quiet             no summary on stderr\n"
    "  --help              this text\n";

static const char *const help = "authalic view --help";

/* The last part of a path. */
static const char *base_name(const char *p) {
  const char *s = strrchr(p, '/');
  return s ? s + 1 : p;
}

/* An OBJ's `vt` rows and each face corner's row (f v/vt ...), when it has them: 1 with *vt, *Ft (nf
 * faces expected) and *nvt set, 0 when the file has no `vt` (or is not OBJ) or its faces name none
 * (per-vertex coordinates: a texture, the map is in `v`), else an exit code with the error printed.
 * Faces are triangles, as the program writes them. */
static int read_obj_vt(const char *path, int nf, double **vt, int **Ft, int *nvt) {
  if (!cli_has_ext(path, ".obj")) return 0;
  FILE *fp = fopen(path, "r");
  if (!fp) return fprintf(stderr, "authalic: error: %s: cannot open: %s\n", path, strerror(errno)), EXIT_USAGE;
  size_t cap = 1024, n = 0;
  double *t = malloc(2 * cap * sizeof *t);
  int *C = malloc(3 * (size_t)nf * sizeof *C), f = 0, rc = 1, line = 0, plain = 0;
  char buf[4096];
  while (t && C && rc == 1 && fgets(buf, sizeof buf, fp)) {
    line++;
    if (buf[0] == 'v' && buf[1] == 't' && (buf[2] == ' ' || buf[2] == '\t')) {
      if (n == cap) {
        double *g = realloc(t, 4 * cap * sizeof *t);
        if (!g) break;
        t = g, cap *= 2;
      }
      if (sscanf(buf + 3, "%lf %lf", &t[2 * n], &t[2 * n + 1]) != 2) {
        fprintf(stderr, "authalic: error: %s:%d: a vt line without two numbers\n", path, line);
        rc = EXIT_USAGE;
      }
      n++;
    } else if (buf[0] == 'f' && (buf[1] == ' ' || buf[1] == '\t') && n > 0 && !plain) {
      char *p = buf + 2;
      for (int k = 0; k < 4 && rc == 1; k++) {
        while (*p == ' ' || *p == '\t') p++;
        if (*p == '\n' || *p == '\r' || !*p) {
          if (k < 3) rc = -1;
          break;
        }
        char *slash = p;
        while (*slash && *slash != '/' && *slash != ' ' && *slash != '\t' && *slash != '\n') slash++;
        long r = *slash == '/' && slash[1] != '/' ? strtol(slash + 1, NULL, 10) : 0;
        if (r == 0 && k == 0 && f == 0) { /* per-vertex vt (a texture of the map), not a map by corners */
          plain = 1;
          break;
        }
        if (k == 3 || f >= nf || r == 0) rc = -1;
        else C[3 * (size_t)f + k] = (int)(r < 0 ? (long)n + r : r - 1);
        while (*p && *p != ' ' && *p != '\t' && *p != '\n') p++;
      }
      if (rc == -1) {
        fprintf(stderr, "authalic: error: %s:%d: with `vt`, every face needs three v/vt corners (and IN's %d faces)\n",
                path, line, nf);
        rc = EXIT_USAGE;
      }
      if (!plain) f++;
    }
  }
  fclose(fp);
  if (rc == 1 && (!t || !C)) fprintf(stderr, "authalic: error: %s: out of memory\n", path), rc = EXIT_INTERNAL;
  if (rc == 1 && (n == 0 || plain)) rc = 0;
  if (rc == 1 && f != nf)
    fprintf(stderr, "authalic: error: %s: %d faces; IN has %d\n", path, f, nf), rc = EXIT_USAGE;
  for (size_t c = 0; rc == 1 && c < 3 * (size_t)nf; c++)
    if (C[c] < 0 || C[c] >= (int)n)
      fprintf(stderr, "authalic: error: %s: face %zu names vt %d of %zu\n", path, c / 3 + 1, C[c] + 1, n), rc = EXIT_USAGE;
  if (rc != 1) return free(t), free(C), rc;
  *vt = t, *Ft = C, *nvt = (int)n;
  return 1;
}

/* steps and time.total of a report written by a map command. */
static int read_report(const char *path, int *steps, double *seconds) {
  au_msg msg = {{0}};
  FILE *fp = fopen(path, "rb");
  if (!fp) return fprintf(stderr, "authalic: error: %s: cannot open the report: %s\n", path, strerror(errno)), EXIT_USAGE;
  fseek(fp, 0, SEEK_END);
  long n = ftell(fp);
  fseek(fp, 0, SEEK_SET);
  char *s = n >= 0 ? malloc((size_t)n + 1) : NULL;
  size_t got = s ? fread(s, 1, (size_t)n, fp) : 0;
  fclose(fp);
  if (!s) return cli_fail(path, AU_E_NOMEM, &msg);
  s[got] = '\0';
  cJSON *root = cJSON_Parse(s);
  free(s);
  if (!cJSON_IsObject(root)) {
    cJSON_Delete(root);
    return fprintf(stderr, "authalic: error: %s: not a JSON report\n", path), EXIT_USAGE;
  }
  const cJSON *k = cJSON_GetObjectItemCaseSensitive(root, "steps");
  const cJSON *t = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(root, "time"), "total");
  if (cJSON_IsNumber(k)) *steps = k->valueint;
  if (cJSON_IsNumber(t)) *seconds = t->valuedouble;
  cJSON_Delete(root);
  return -1;
}

int cli_write_view(const char *path, const char *name, const au_view_input *in, int quiet) {
  au_msg msg = {{0}};
  double t0 = cli_now();
  au_status st = au_view_write(path, in, &msg);
  if (st != AU_OK) return cli_fail(name, st, &msg);
  if (!quiet) fprintf(stderr, "authalic: view: %s (%d faces) in %.2fs\n", name, in->nf, cli_now() - t0);
  return -1;
}

int cli_cmd_view(int argc, char **argv) {
  const char *pos[3] = {NULL}, *attr = NULL, *report = NULL, *title = NULL;
  int npos = 0, quiet = 0;
  for (int i = 1; i < argc; i++) {
    const char *s = argv[i];
    const char **val = strcmp(s, "--attr") == 0 ? &attr : strcmp(s, "--report") == 0 ? &report
                     : strcmp(s, "--title") == 0 ? &title : NULL;
    if (strcmp(s, "--help") == 0 || strcmp(s, "-h") == 0) return fputs(usage_text, stdout), EXIT_OK;
    if (strcmp(s, "--quiet") == 0) quiet = 1;
    else if (val) {
      if (*val) return cli_usage_error(help, "option '%s' given twice", s);
      if (i + 1 >= argc || !*argv[i + 1]) return cli_usage_error(help, "option '%s' needs a value", s);
      *val = argv[++i];
    } else if (s[0] == '-' && s[1]) {
      return cli_usage_error(help, "unknown option '%s'", s);
    } else if (npos < 3) {
      pos[npos++] = s;
    } else {
      return cli_usage_error(help, "unexpected extra argument '%s'", s);
    }
  }
  if (npos < 3) return cli_usage_error(help, "expected IN MAP OUT.html");
  const char *in = pos[0], *map = pos[1], *out = pos[2];
  for (int k = 0; k < 2; k++)
    if (cli_same_file(out, pos[k]) || (attr && cli_same_file(out, attr)) || (report && cli_same_file(out, report)))
      return cli_usage_error(help, "output '%s' is also an input file; refusing to overwrite it", out);
  int rc = cli_check_writable_path(help, out, "output");
  if (rc) return rc;
  cli_expect_output(out);

  au_mesh *m = NULL, *mm = NULL;
  double t_read, t_check, *vt = NULL, *a = NULL;
  int *Ft = NULL, nvt = 0, na = 0;
  au_view_input v = au_view_input_default();
  if ((rc = cli_load(in, (au_target)-1, &m, NULL, NULL, &t_read, &t_check)) >= 0) goto done;
  if ((rc = cli_load(map, (au_target)-1, &mm, NULL, NULL, &t_read, &t_check)) >= 0) goto done;
  rc = -1;
  if (mm->nf != m->nf || memcmp(mm->F, m->F, 3 * (size_t)m->nf * sizeof *m->F) != 0) {
    fprintf(stderr, "authalic: error: %s: its faces are not those of %s (%d and %d faces): a map keeps the input's "
            "vertices and faces\n", map, in, mm->nf, m->nf);
    rc = EXIT_USAGE;
    goto done;
  }
  /* The map is MAP's positions, unless those are IN's surface (a torus map, a texture): then its vt. */
  int surface = mm->nv == m->nv;
  double ext = 0;
  for (size_t i = 0; surface && i < 3 * (size_t)m->nv; i++) ext = fmax(ext, fabs(m->X[i]));
  for (size_t i = 0; surface && i < 3 * (size_t)m->nv; i++) surface = fabs(mm->X[i] - m->X[i]) <= 1e-6 * ext;
  int got = surface ? read_obj_vt(map, m->nf, &vt, &Ft, &nvt) : 0;
  if (got != 0 && got != 1) {
    rc = got;
    goto done;
  }
  if (surface && !got) {
    fprintf(stderr, "authalic: error: %s: its vertices are those of %s and it has no per-corner `vt`: not a map of it\n", map, in);
    rc = EXIT_USAGE;
    goto done;
  }
  if (!got && mm->nv != m->nv) {
    fprintf(stderr, "authalic: error: %s: %d vertices; %s has %d\n", map, mm->nv, in, m->nv);
    rc = EXIT_USAGE;
    goto done;
  }
  if (attr) {
    au_msg msg = {{0}};
    au_status st = au_io_read_scalars(attr, m->nv, &a, &na, &msg);
    if (st != AU_OK) {
      rc = cli_fail(attr, st, &msg);
      goto done;
    }
  }
  if (report && (rc = read_report(report, &v.steps, &v.seconds)) >= 0) goto done;
  v.nv = m->nv, v.nf = m->nf, v.X = m->X, v.F = m->F;
  if (got) v.nvt = nvt, v.vt = vt, v.Ft = Ft;
  else v.P = mm->X;
  v.attr = a, v.attr_name = attr ? base_name(attr) : NULL;
  v.title = title ? title : base_name(in);
  rc = cli_write_view(out, out, &v, quiet);
  if (rc < 0) rc = EXIT_OK;
done:
  au_mesh_free(&m), au_mesh_free(&mm);
  free(vt), free(Ft), free(a);
  return rc;
}
