/* cli.c - the pieces every command of the `authalic` program shares (see cli.h). */
#define _POSIX_C_SOURCE 200809L

#include "cli.h"

#include <strings.h>

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

/* The directory path names its file in (stat into st) and the name's last part (*base). 0 if the
 * directory cannot be stat'ed. */
static int parent_dir(const char *path, struct stat *st, const char **base) {
  const char *slash = strrchr(path, '/');
  *base = slash ? slash + 1 : path;
  if (!slash) return stat(".", st) == 0;
  size_t n = slash == path ? 1 : (size_t)(slash - path);
  char *dir = malloc(n + 1);
  if (!dir) return 0;
  memcpy(dir, path, n);
  dir[n] = '\0';
  int ok = stat(dir, st) == 0;
  free(dir);
  return ok;
}

/* cli_same_file for names that are not links to follow. */
static int same_name(const char *a, const char *b) {
  struct stat sa, sb;
  const char *na, *nb;
  if (strcmp(a, b) == 0) return 1;
  int ea = stat(a, &sa) == 0, eb = stat(b, &sb) == 0;
  if (ea && eb) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  return parent_dir(a, &sa, &na) && parent_dir(b, &sb, &nb) && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino &&
         *na && strcmp(na, nb) == 0;
}

int cli_same_file(const char *a, const char *b) {
  /* Two links to one file that is not there yet are one output too (au_output_target). */
  char *ra = au_output_target(a), *rb = au_output_target(b);
  int same = ra && rb ? same_name(ra, rb) : same_name(a, b);
  au_free(ra), au_free(rb);
  return same;
}

int cli_check_writable_path(const char *help, const char *path, const char *what) {
  struct stat st;
  const int exists = stat(path, &st) == 0;
  if (!exists && errno == ELOOP) return cli_usage_error(help, "%s '%s': too many levels of symbolic links", what, path);
  if (exists && S_ISDIR(st.st_mode)) return cli_usage_error(help, "%s '%s' is a directory", what, path);
  /* Every output is written whole under a temporary name and renamed into place: over a device, a FIFO
   * or a socket that would put a plain file in its stead (as root, /dev/null itself). */
  if (exists && !S_ISREG(st.st_mode))
    return cli_usage_error(help, "%s '%s' is not a regular file (a device, FIFO or socket); give a file name", what,
                           path);
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

int cli_has_ext(const char *path, const char *ext) {
  const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
  return dot && (!slash || dot > slash) && strcasecmp(dot, ext) == 0;
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

/* ---------------------------------------------------------------- the option table */

typedef struct cli_option {
  cli_opt_id id;
  const char *name, *metavar;
  int kind, cmds;
  const char *help;
} cli_option;

static const cli_option options[] = {
#define CLI_OPTION_ROW(id, name, metavar, kind, cmds, help) {id, name, metavar, kind, cmds, help},
    CLI_OPTIONS(CLI_OPTION_ROW)
#undef CLI_OPTION_ROW
};
#define NOPTIONS (int)(sizeof options / sizeof options[0])

static const char *const cmd_names[] = {"sphere", "disk", "annulus", "square", "texture", "sample", "torus", "circles",
                                        "atlas"};

const char *cli_option_name(cli_opt_id id) {
  for (int k = 0; k < NOPTIONS; k++)
    if (options[k].id == id) return options[k].name;
  return "?";
}

const char *cli_cmd_name(int cmd) {
  for (int k = 0; k < (int)(sizeof cmd_names / sizeof cmd_names[0]); k++)
    if (cmd == 1 << k) return cmd_names[k];
  return "?";
}

au_target cli_cmd_target(int cmd) {
  return cmd == CLI_DISK ? AU_TARGET_DISK : cmd == CLI_ANNULUS ? AU_TARGET_ANNULUS : cmd == CLI_SQUARE ? AU_TARGET_SQUARE
         : cmd == CLI_TORUS ? AU_TARGET_TORUS : cmd == CLI_CIRCLES ? AU_TARGET_CIRCLES : AU_TARGET_SPHERE;
}

/* An option's default and largest value as the help shows them ("%D", "%M"). */
static void option_values(cli_opt_id id, int cmd, char *dflt, char *max, size_t n) {
  int steps;
  double tol;
  au_target_defaults(cli_cmd_target(cmd), &steps, &tol);
  dflt[0] = max[0] = '\0';
  if (id == OPT_STEPS) snprintf(dflt, n, "%d", steps), snprintf(max, n, "%d", AU_MAX_STEPS);
  if (id == OPT_TOL) snprintf(dflt, n, "%g", tol);
  if (id == OPT_ANGLES) snprintf(max, n, "%d", AU_MAX_ANGLE_STEPS);
  if (id == OPT_RESTORE) snprintf(dflt, n, "%g", au_expert_default(AU_TARGET_SPHERE, 0).restore);
}

/* Print text from column col, wrapped at the words to lines of at most width columns. */
static void print_wrapped(const char *text, int col, int width) {
  int x = col;
  const char *p = text;
  while (*p) {
    const char *e = p;
    while (*e && *e != ' ') e++;
    int w = (int)(e - p);
    if (x > col && x + 1 + w > width) printf("\n%*s", col, ""), x = col;
    else if (x > col) putchar(' '), x++;
    printf("%.*s", w, p);
    x += w;
    p = *e ? e + 1 : e;
  }
  putchar('\n');
}

void cli_print_options(int cmd) {
  printf("options of %s:\n", cli_cmd_name(cmd));
  for (int k = 0; k < NOPTIONS; k++) {
    const cli_option *o = &options[k];
    if (!(o->cmds & cmd)) continue;
    char head[64], dflt[32], max[32], text[1024];
    snprintf(head, sizeof head, "  --%s%s%s", o->name, o->metavar ? " " : "", o->metavar ? o->metavar : "");
    option_values(o->id, cmd, dflt, max, sizeof dflt);
    size_t n = 0;
    for (const char *s = o->help; *s && n < sizeof text - 40; s++) {
      if (s[0] == '%' && (s[1] == 'D' || s[1] == 'M')) n += (size_t)snprintf(text + n, sizeof text - n, "%s", s[1] == 'D' ? dflt : max), s++;
      else text[n++] = *s;
    }
    text[n] = '\0';
    int col = 22;
    printf("%-*s", col, head);
    if ((int)strlen(head) >= col) printf("\n%*s", col, "");
    print_wrapped(text, col, 104);
  }
}

static const cli_option *find_option(const char *name, int cmd) {
  for (int k = 0; k < NOPTIONS; k++)
    if ((options[k].cmds & cmd) && strcmp(options[k].name, name) == 0) return &options[k];
  return NULL;
}

int cli_parse(int argc, char **argv, int cmd, int maxpos, const char *usage_text, cli_args *a) {
  enum { NCMD = (int)(sizeof cmd_names / sizeof cmd_names[0]) };
  static char helps[NCMD][40];
  memset(a, 0, sizeof *a);
  a->cmd = cmd;
  const char *name = cli_cmd_name(cmd);
  for (int k = 0; k < NCMD; k++)
    if (cmd == 1 << k) snprintf(helps[k], sizeof helps[k], "authalic %s --help", name), a->help = helps[k];
  int dashdash = 0;
  for (int i = 1; i < argc; i++) {
    const char *s = argv[i];
    if (dashdash || s[0] != '-' || s[1] == '\0') {
      if (a->npos >= maxpos) return cli_usage_error(a->help, "unexpected extra argument '%s'", s);
      a->pos[a->npos++] = s;
      continue;
    }
    if (strcmp(s, "--") == 0) {
      dashdash = 1;
      continue;
    }
    const cli_option *o = strncmp(s, "--", 2) == 0 ? find_option(s + 2, cmd) : strcmp(s, "-h") == 0 ? find_option("help", cmd) : NULL;
    if (!o) return cli_usage_error(a->help, "unknown option '%s'", s);
    if (o->id == OPT_HELP) {
      fputs(usage_text, stdout);
      cli_print_options(cmd);
      return EXIT_OK;
    }
    const char *v = "";
    if (o->kind != CLI_FLAG) {
      if (i + 1 >= argc) return cli_usage_error(a->help, "option '%s' needs a value", s);
      v = argv[++i];
      if ((o->kind == CLI_FILE || o->kind == CLI_REPEAT) && !*v)
        return cli_usage_error(a->help, "option '%s' needs a file name", s);
    }
    if (o->kind == CLI_REPEAT) {
      if (a->nrep >= CLI_MAX_REPEAT) return cli_usage_error(a->help, "at most %d %s files", CLI_MAX_REPEAT, s);
      a->rep[a->nrep++] = v;
    } else if (a->val[o->id]) {
      return cli_usage_error(a->help, "option '%s' given twice", s);
    }
    a->val[o->id] = v;
  }
  return -1;
}

static const char *opt_name(cli_opt_id id) {
  for (int k = 0; k < NOPTIONS; k++)
    if (options[k].id == id) return options[k].name;
  return "?";
}

int cli_opt_int(const cli_args *a, cli_opt_id id, long lo, long hi, int *out) {
  const char *v = a->val[id];
  if (!v || cli_parse_int(v, lo, hi, out) == 0) return 0;
  return cli_usage_error(a->help, "--%s '%s': expected a whole number from %ld to %ld", opt_name(id), v, lo, hi);
}

int cli_opt_nonneg(const cli_args *a, cli_opt_id id, double *out) {
  const char *v = a->val[id];
  if (!v || cli_parse_nonneg(v, out) == 0) return 0;
  return cli_usage_error(a->help, "--%s '%s': expected a finite number >= 0", opt_name(id), v);
}

int cli_opt_size(const cli_args *a, cli_opt_id id, int *W, int *H) {
  const char *s = a->val[id];
  if (!s) return 0;
  const char *x = strchr(s, 'x');
  char w[32];
  size_t n = x ? (size_t)(x - s) : 0;
  int ok = x && x != s && x[1] && !strchr(x + 1, 'x') && n < sizeof w;
  if (ok) {
    memcpy(w, s, n);
    w[n] = '\0';
    ok = cli_parse_int(w, 1, 16384, W) == 0 && cli_parse_int(x + 1, 1, 16384, H) == 0;
  }
  if (ok) return 0;
  return cli_usage_error(a->help, "--%s '%s': expected WxH with W and H whole numbers from 1 to 16384", opt_name(id), s);
}

/* ---------------------------------------------------------------- progress and warnings */

void cli_progress_init(cli_progress_state *p, int quiet) {
  p->t_start = p->t_last = cli_now();
  p->tty = isatty(STDERR_FILENO) && !quiet;
  p->drawn = 0;
}

int cli_progress(void *user, int step, int max_steps, double err) {
  cli_progress_state *p = user;
  double t = cli_now();
  if (t - p->t_start <= 1.0 && !p->tty) return 0;
  if (p->tty) {
    fprintf(stderr, "\rauthalic: step %d/%d  err %.3e ", step, max_steps, err);
    p->drawn = 1;
  } else if (t - p->t_last >= 1.0) {
    fprintf(stderr, "authalic: step %d/%d  err %.3e\n", step, max_steps, err);
    p->t_last = t;
  }
  fflush(stderr);
  return 0;
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

void cli_remove_output(const char *path) {
  char *d = au_output_target(path);
  unlink(d ? d : path);
  au_free(d);
}

int cli_write_distortion(const char *path, const char *name, const au_mesh *m, const double *P, au_domain domain,
                         int nvt, const double *vt, const int *Ft, const au_io_meta *meta) {
  au_msg msg = {{0}};
  double *d = malloc((size_t)m->nv * sizeof *d);
  if (!d) return cli_fail(name, AU_E_NOMEM, NULL);
  au_status st = vt ? au_metrics_vertex_distortion_vt(m->nv, m->nf, m->X, m->F, nvt, vt, Ft, d, NULL)
                    : au_metrics_vertex_distortion(m->nv, m->nf, m->X, P, m->F, domain, d, NULL);
  if (st == AU_OK) st = au_io_write_scalars(path, m->nv, d, m->nf, meta, &msg);
  free(d);
  return st == AU_OK ? -1 : cli_fail(name, st, &msg);
}

int cli_load(const char *in, au_target t, au_mesh **m, au_io_meta **meta, cli_warnings *w, double *t_read,
             double *t_check) {
  au_msg msg = {{0}};
  double t0 = cli_now();
  au_status st = au_io_read_meta(in, m, meta, &msg);
  if (st != AU_OK) return cli_fail(in, st, &msg);
  *t_read = cli_now() - t0;
  if ((int)t < 0) return -1;
  t0 = cli_now();
  /* The mesh the command goes on with is re-oriented here, so that the map made from it later has
   * nothing left to warn about; a non-orientable surface is named by the check below. */
  st = au_mesh_orient(*m, NULL, &msg);
  if (st > 0 && w) cli_warn(w, in, "%s", msg.text);
  st = au_mesh_check((*m)->X, (*m)->nv, (*m)->F, (*m)->nf, t, &msg);
  if (st < 0) {
    au_mesh_free(m);
    if (meta) au_io_meta_free(meta);
    return cli_fail(in, st, &msg);
  }
  if (st > 0 && w) cli_warn(w, in, "%s", msg.text[0] ? msg.text : au_status_str(st));
  *t_check = cli_now() - t0;
  return -1;
}

/* The temporary name OUT is first written under: a hidden sibling with the same extension (the
 * writer picks the format by it). */
char *cli_temp_name(const char *out) {
  const char *slash = strrchr(out, '/');
  size_t dirlen = slash ? (size_t)(slash - out + 1) : 0, n = strlen(out) + 64;
  char *t = malloc(n);
  if (t) snprintf(t, n, "%.*s.authalic-%ld-%s", (int)dirlen, out, (long)getpid(), out + dirlen);
  return t;
}

/* The temporaries a fatal signal removes: the library writers' (au_temp_path) of every output the
 * program said it would write, and the finished output waiting under its temporary name. These
 * belong to the program, which owns its process's signals. */
#define CLI_MAX_OUTPUTS 16
static char cleanup_name[CLI_MAX_OUTPUTS][4200];
static volatile sig_atomic_t cleanup_used[CLI_MAX_OUTPUTS];
static char *volatile publishing;

void cli_expect_output(const char *path) {
  for (int i = 0; path && i < CLI_MAX_OUTPUTS; i++)
    if (!cleanup_used[i]) {
      if (au_temp_path(path, cleanup_name[i], sizeof cleanup_name[i]) == AU_OK) cleanup_used[i] = 1;
      return;
    }
}

void cli_expect_temp(const char *path) {
  for (int i = 0; path && i < CLI_MAX_OUTPUTS; i++)
    if (!cleanup_used[i]) {
      snprintf(cleanup_name[i], sizeof cleanup_name[i], "%s", path);
      cleanup_used[i] = 1;
      return;
    }
}

static void on_fatal_signal(int sig) {
  for (int i = 0; i < CLI_MAX_OUTPUTS; i++)
    if (cleanup_used[i]) unlink(cleanup_name[i]);
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

int cli_publish(const char *out, int nv, const double *P, int nf, const int *F, const au_write_opts *wopts,
                const char *report, const au_result *r, au_report_extra *extra) {
  au_msg msg = {{0}};
  double t0 = cli_now();
  int rc = EXIT_INTERNAL;
  char *dest = au_output_target(out), *tmp = dest ? cli_temp_name(dest) : NULL, *json = NULL;
  if (!tmp) {
    au_free(dest);
    return cli_fail(out, AU_E_NOMEM, NULL);
  }
  cli_expect_output(tmp);
  cli_expect_output(report);
  publishing = tmp;
  au_status st = au_mesh_write(tmp, nv, P, nf, F, wopts, &msg);
  if (st != AU_OK) {
    rc = cli_fail(out, st, &msg);
    goto done;
  }
  /* A result that replaces an earlier one keeps its permissions, as the library's own writes do. */
  struct stat old;
  if (stat(dest, &old) == 0 && S_ISREG(old.st_mode)) chmod(tmp, old.st_mode & 07777);
  if (extra) extra->t_write = cli_now() - t0;
  int report_written = 0;
  if (report && r) {
    st = au_result_json(r, extra, &json, &msg);
    if (st == AU_OK) st = au_write_text(report, json, strlen(json), &msg);
    if (st != AU_OK) {
      rc = cli_fail(report, st, &msg);
      goto done;
    }
    report_written = 1;
  }
  if (rename(tmp, dest) != 0) {
    fprintf(stderr, "authalic: error: %s: cannot rename the finished output into place: %s\n", out, strerror(errno));
    /* No map, so no report of it either. */
    if (report_written) unlink(report);
    rc = EXIT_USAGE;
    goto done;
  }
  rc = EXIT_OK;
done:
  if (rc != EXIT_OK) unlink(tmp); /* the temporary may not exist; then there is nothing to remove */
  publishing = NULL;
  free(tmp), au_free(dest);
  au_free(json);
  return rc;
}
