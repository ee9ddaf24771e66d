/* cli.c - the pieces every command of the `authalic` program shares (see cli.h). */
#define _POSIX_C_SOURCE 200809L

#include "cli.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

double cli_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int cli_vusage_error(const char *help, const char *fmt, va_list ap) {
  fputs("authalic: error: ", stderr);
  vfprintf(stderr, fmt, ap);
  fprintf(stderr, " (see `%s`)\n", help);
  return EXIT_USAGE;
}

int cli_usage_error(const char *help, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  int rc = cli_vusage_error(help, fmt, ap);
  va_end(ap);
  return rc;
}

/* The readers already start their messages with "PATH:" (or "PATH:LINE:"); those are printed as
 * they are, so the path is not said twice. */
void cli_say(const char *kind, const char *path, au_status st, const au_msg *msg) {
  const char *text = msg && msg->text[0] ? msg->text : au_status_str(st);
  size_t n = strlen(path);
  if (strncmp(text, path, n) == 0 && text[n] == ':')
    fprintf(stderr, "authalic: %s: %s\n", kind, text);
  else
    fprintf(stderr, "authalic: %s: %s: %s\n", kind, path, text);
}

int cli_fail(const char *path, au_status st, const au_msg *msg) {
  cli_say("error", path, st, msg);
  return au_status_is_input_error(st) ? EXIT_USAGE : EXIT_INTERNAL;
}

int cli_parse_int(const char *s, long lo, long hi, int *out) {
  char *end = NULL;
  errno = 0;
  long v = strtol(s, &end, 10);
  if (!*s || *end || errno == ERANGE || v < lo || v > hi) return -1;
  *out = (int)v;
  return 0;
}

int cli_parse_nonneg(const char *s, double *out) {
  char *end = NULL;
  errno = 0;
  double v = strtod(s, &end);
  if (!*s || *end || errno == ERANGE || !isfinite(v) || v < 0) return -1;
  *out = v;
  return 0;
}

int cli_same_file(const char *a, const char *b) {
  struct stat sa, sb;
  if (strcmp(a, b) == 0) return 1;
  return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

int cli_check_writable_path(const char *help, const char *path, const char *what) {
  struct stat st;
  if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) return cli_usage_error(help, "%s '%s' is a directory", what, path);
  const char *slash = strrchr(path, '/');
  if (!slash) return 0;
  size_t n = slash == path ? 1 : (size_t)(slash - path);
  char *dir = malloc(n + 1);
  if (!dir) return cli_usage_error(help, "out of memory");
  memcpy(dir, path, n);
  dir[n] = '\0';
  int ok = stat(dir, &st) == 0 && S_ISDIR(st.st_mode);
  int rc = ok ? 0 : cli_usage_error(help, "%s '%s': directory '%s' does not exist", what, path, dir);
  free(dir);
  return rc;
}

int cli_check_outputs(const char *help, const char *in, const char *out, const char *report) {
  if (cli_same_file(in, out)) return cli_usage_error(help, "output '%s' is the input file; refusing to overwrite it", out);
  if (report && cli_same_file(report, in)) return cli_usage_error(help, "report '%s' is the input file", report);
  if (report && cli_same_file(report, out)) return cli_usage_error(help, "report '%s' is the output file", report);
  if (au_io_format_of_name(out) == AU_IO_FORMAT_STL)
    return cli_usage_error(help, "cannot write '%s' files (output '%s'; use .obj, .off, .ply, .gii or --format)",
                           strrchr(out, '.'), out);
  int rc = cli_check_writable_path(help, out, "output");
  if (rc == 0 && report) rc = cli_check_writable_path(help, report, "report");
  return rc;
}

void cli_progress_init(cli_progress_state *p, int quiet) {
  p->t_start = p->t_last = cli_now();
  p->tty = isatty(STDERR_FILENO) && !quiet;
  p->drawn = 0;
}

void cli_progress(void *user, int step, int max_steps, double err) {
  cli_progress_state *p = user;
  double t = cli_now();
  if (t - p->t_start <= 1.0 && !p->tty) return;
  if (p->tty) {
    fprintf(stderr, "\rauthalic: step %d/%d  err %.3e ", step, max_steps, err);
    p->drawn = 1;
  } else if (t - p->t_last >= 1.0) {
    fprintf(stderr, "authalic: step %d/%d  err %.3e\n", step, max_steps, err);
    p->t_last = t;
  }
  fflush(stderr);
}

void cli_progress_end(cli_progress_state *p) {
  if (p->drawn) fputc('\n', stderr);
  p->drawn = 0;
}

void cli_warn(cli_warnings *w, const char *path, const char *fmt, ...) {
  char line[sizeof w->buf[0]];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  fprintf(stderr, "authalic: warning: %s: %s\n", path, line);
  if (w->n < CLI_MAX_WARNINGS) {
    memcpy(w->buf[w->n], line, sizeof line);
    w->list[w->n] = w->buf[w->n];
    w->n++;
  }
}

int cli_parse_neuro(const char *help, int argc, char **argv, int *i, int allow_radius, cli_neuro_args *n) {
  const char *s = argv[*i];
  if (strcmp(s, "--format") && strcmp(s, "--distortion") && (!allow_radius || strcmp(s, "--radius"))) return 0;
  if (*i + 1 >= argc) return cli_usage_error(help, "option '%s' needs a value", s), -1;
  const char *v = argv[++*i];
  if (strcmp(s, "--format") == 0) {
    if (n->format != AU_IO_FORMAT_AUTO) return cli_usage_error(help, "option '%s' given twice", s), -1;
    if ((n->format = au_io_format_parse(v)) == AU_IO_FORMAT_AUTO)
      return cli_usage_error(help, "--format '%s': expected obj, off, ply, freesurfer or gifti", v), -1;
  } else if (strcmp(s, "--distortion") == 0) {
    if (n->distortion) return cli_usage_error(help, "option '%s' given twice", s), -1;
    if (!*v) return cli_usage_error(help, "option '--distortion' needs a file name"), -1;
    n->distortion = v;
  } else {
    if (n->has_radius++) return cli_usage_error(help, "option '%s' given twice", s), -1;
    if (cli_parse_nonneg(v, &n->radius) || !(n->radius > 0) || n->radius > 1e30)
      return cli_usage_error(help, "--radius '%s': expected a positive number", v), -1;
  }
  return 1;
}

void cli_print_neuro_options(int radius) {
  printf("  --format F       write OUT as obj, off, ply, freesurfer (binary triangle surface, big-endian,\n"
         "                   float32) or gifti (.gii; gzip-compressed for a .gii.gz name); default: by OUT's\n"
         "                   extension, and an OUT with none (lh.sphere.authalic) gets the input's format\n"
         "  --distortion FILE  per-vertex areal distortion log2(map area share / surface area share) of\n"
         "                   the barycentric vertex cells (HCP's convention): a FreeSurfer curv file, or\n"
         "                   GIfTI when FILE ends in .gii (e.g. .shape.gii)\n");
  if (radius)
    printf("  --radius R       write the sphere with radius R > 0 (FreeSurfer and HCP spheres: 100); the\n"
           "                   metrics and the report are those of the unit sphere (default 1)\n");
}

int cli_output_format(const char *help, const char *out, au_io_format forced, const au_io_meta *in_meta,
                      au_io_format *fmt) {
  au_io_format f = forced != AU_IO_FORMAT_AUTO ? forced : au_io_format_of_name(out);
  if (f == AU_IO_FORMAT_AUTO) f = au_io_meta_format(in_meta);
  if (f == AU_IO_FORMAT_AUTO || f == AU_IO_FORMAT_STL)
    return cli_usage_error(help, "output '%s' has no extension of a format that can be written and the input is %s "
                           "(use .obj, .off, .ply, .gii or --format)", out, au_io_format_name(f));
  *fmt = f;
  return 0;
}

int cli_write_distortion(const char *path, const au_mesh *m, const double *P, au_domain domain,
                         const au_io_meta *meta) {
  au_msg msg = {{0}};
  double *d = malloc((size_t)m->nv * sizeof *d);
  if (!d) return cli_fail(path, AU_E_NOMEM, NULL);
  au_status st = au_metrics_vertex_distortion(m->nv, m->nf, m->X, P, m->F, domain, d, NULL);
  if (st == AU_OK) st = au_io_write_scalars(path, m->nv, d, m->nf, meta, &msg);
  free(d);
  return st == AU_OK ? -1 : cli_fail(path, st, &msg);
}

int cli_load(const char *in, const au_mesh_expect *ex, au_mesh **m, au_topo **t, cli_warnings *w,
             au_report_stage *stages, int *nst) {
  return cli_load_meta(in, ex, m, t, NULL, w, stages, nst);
}

int cli_load_meta(const char *in, const au_mesh_expect *ex, au_mesh **m, au_topo **t, au_io_meta **meta,
                  cli_warnings *w, au_report_stage *stages, int *nst) {
  au_msg msg = {{0}};
  double t0 = cli_now();
  au_status st = au_io_read_meta(in, m, meta, &msg);
  if (st != AU_OK) return cli_fail(in, st, &msg);
  stages[(*nst)++] = (au_report_stage){"read", cli_now() - t0};
  t0 = cli_now();
  st = au_mesh_validate(*m, ex, t, &msg);
  if (st < 0) {
    au_mesh_free(m);
    if (meta) au_io_meta_free(meta);
    return cli_fail(in, st, &msg);
  }
  if (st > 0) cli_warn(w, in, "%s", msg.text[0] ? msg.text : au_status_str(st));
  stages[(*nst)++] = (au_report_stage){"validate", cli_now() - t0};
  return -1;
}

int cli_refuse_folds(const char *in, const au_metrics *fin, int not_converged) {
  if (fin->folds <= 0) return -1;
  au_msg msg = {{0}};
  /* Folded here means a sign the output's reader would see: triangles the start squeezed below a
   * double's resolution that the flow had no steps left to grow (a 4x subdivided cow: 286 at 60
   * steps, none at 120). */
  au_msg_set(&msg, AU_E_FOLD, "the map has %d folded triangle%s; nothing written%s", fin->folds,
             fin->folds == 1 ? "" : "s",
             not_converged ? " (the flow had not converged: more --steps may grow them back)" : "");
  return cli_fail(in, AU_E_FOLD, &msg);
}

/* The temporary name OUT is first written under: a hidden sibling with the same extension (the
 * writer picks the format by it). */
static char *temp_name(const char *out) {
  const char *slash = strrchr(out, '/');
  size_t dirlen = slash ? (size_t)(slash - out + 1) : 0, n = strlen(out) + 64;
  char *t = malloc(n);
  if (t) snprintf(t, n, "%.*s.authalic-%ld-%s", (int)dirlen, out, (long)getpid(), out + dirlen);
  return t;
}

/* The finished output waiting under its temporary name, for the signal handler. */
static char *volatile publishing;

static void on_fatal_signal(int sig) {
  au_io_remove_pending();
  char *tmp = publishing;
  if (tmp) unlink(tmp);
  signal(sig, SIG_DFL);
  raise(sig);
}

void cli_install_signal_cleanup(void) {
  static const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_fatal_signal;
  sigemptyset(&sa.sa_mask);
  for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++) {
    struct sigaction old;
    /* A signal ignored by whoever started us (nohup) stays ignored. */
    if (sigaction(sigs[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    sigaction(sigs[i], &sa, NULL);
  }
}

int cli_publish(const char *out, const au_mesh *m, const double *P, const au_io_write_opts *wopts,
                const char *report, const au_report_info *info, au_report_stage *write_stage) {
  au_msg msg = {{0}};
  double t0 = cli_now();
  int rc = EXIT_INTERNAL;
  char *tmp = temp_name(out);
  if (!tmp) return cli_fail(out, AU_E_NOMEM, NULL);
  publishing = tmp;
  au_status st = au_io_write(tmp, m, P, wopts, &msg);
  if (st != AU_OK) {
    rc = cli_fail(out, st, &msg);
    goto done;
  }
  /* A result that replaces an earlier one keeps its permissions, as au_io_write's own would. */
  struct stat old;
  if (stat(out, &old) == 0 && S_ISREG(old.st_mode)) chmod(tmp, old.st_mode & 07777);
  if (write_stage) write_stage->seconds = cli_now() - t0;
  if (report && info) {
    st = au_report_write(report, info, &msg);
    if (st != AU_OK) {
      rc = cli_fail(report, st, &msg);
      goto done;
    }
  }
  if (rename(tmp, out) != 0) {
    fprintf(stderr, "authalic: error: %s: cannot rename the finished output into place: %s\n", out, strerror(errno));
    rc = EXIT_USAGE;
    goto done;
  }
  rc = EXIT_OK;
done:
  if (rc != EXIT_OK) unlink(tmp); /* the temporary may not exist; then there is nothing to remove */
  publishing = NULL;
  free(tmp);
  return rc;
}
