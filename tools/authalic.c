/* authalic.c - the `authalic` command-line program: argument parsing, the sphere pipeline, reports, messages. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "au_advect.h"
#include "au_io.h"
#include "au_mesh.h"
#include "au_metrics.h"
#include "au_report.h"
#include "au_sphere.h"
#include "au_status.h"

#ifndef AU_VERSION
#define AU_VERSION "unknown"
#endif

/* Exit codes (STYLE.md): 0 ok, 1 internal or numerical failure, 2 bad usage or bad input. */
enum { EXIT_OK = 0, EXIT_INTERNAL = 1, EXIT_USAGE = 2 };

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A usage error: one line naming the problem and the help that explains it. */
static int usage_error_in(const char *help, const char *fmt, va_list ap) {
  fputs("authalic: error: ", stderr);
  vfprintf(stderr, fmt, ap);
  fprintf(stderr, " (see `%s`)\n", help);
  return EXIT_USAGE;
}

/* A usage error of the sphere command. */
static int usage_error(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  int rc = usage_error_in("authalic sphere --help", fmt, ap);
  va_end(ap);
  return rc;
}

/* A usage error before any command was recognized. */
static int top_usage_error(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  int rc = usage_error_in("authalic --help", fmt, ap);
  va_end(ap);
  return rc;
}

/* One line "authalic: KIND: PATH: message". The readers already start their messages with
 * "PATH:" (or "PATH:LINE:"); those are printed as they are, so the path is not said twice. */
static void say(const char *kind, const char *path, au_status st, const au_msg *msg) {
  const char *text = msg && msg->text[0] ? msg->text : au_status_str(st);
  size_t n = strlen(path);
  if (strncmp(text, path, n) == 0 && text[n] == ':')
    fprintf(stderr, "authalic: %s: %s\n", kind, text);
  else
    fprintf(stderr, "authalic: %s: %s: %s\n", kind, path, text);
}

/* A failed library call: one error line; faults of the input exit 2, the rest 1. */
static int fail(const char *path, au_status st, const au_msg *msg) {
  say("error", path, st, msg);
  return au_status_is_input_error(st) ? EXIT_USAGE : EXIT_INTERNAL;
}

/* The options of the sphere command, with the defaults read from the library. */
static void print_sphere_options(void) {
  au_sphere_opts d = au_sphere_opts_default();
  printf("options of sphere:\n"
         "  --report R.json  write a JSON report: metrics of the result and of the initial conformal\n"
         "                   map, per-step errors, stage times, warnings\n"
         "  --steps K        most advection steps, 1..%d (default %d)\n"
         "  --tol T          stop when the vertex mean |log area ratio| is below T, T >= 0 (default %g)\n"
         "  --no-balance     skip the Moebius balancing of the conformal start\n"
         "  --init-only      stop after the conformal start (and balancing), for comparison\n"
         "  --quiet          no progress and no summary on stderr (errors and warnings remain)\n"
         "  --help           this text\n",
         AU_ADVECT_MAX_STEPS, d.flow.max_steps, d.flow.tol);
}

static void print_help(void) {
  printf("authalic %s - equal-area (authalic) maps of triangle meshes by Lie advection\n\n"
         "usage: authalic sphere IN OUT [options]   map a closed genus-0 mesh onto the unit sphere\n"
         "       authalic sphere --help             the sphere command in detail\n"
         "       authalic --help | --version\n\n"
         "IN is read as .obj .off .ply or .stl; OUT is written as .obj .off or .ply (by extension),\n"
         "with the input's vertex order and faces. Exit status: 0 ok (also with warnings), 2 bad usage\n"
         "or bad input, 1 internal or numerical failure.\n\n",
         AU_VERSION);
  print_sphere_options();
}

static void print_sphere_help(void) {
  printf("usage: authalic sphere IN OUT [options]\n\n"
         "Maps the closed genus-0 triangle mesh IN onto the unit sphere so that every vertex cell keeps\n"
         "its share of the surface area, and writes the map to OUT (.obj .off or .ply). Progress and a\n"
         "summary line go to stderr; OUT and the report are written only when the whole run succeeded.\n\n");
  print_sphere_options();
}

/* Everything the sphere command was asked to do. */
typedef struct cli_args {
  const char *in, *out, *report;
  int steps, has_steps; /* --steps, and whether it was given */
  double tol;
  int has_tol;
  int no_balance, quiet, init_only;
} cli_args;

/* Whole-string integer in [lo, hi]; 0 on success. */
static int parse_int(const char *s, long lo, long hi, int *out) {
  char *end = NULL;
  errno = 0;
  long v = strtol(s, &end, 10);
  if (!*s || *end || errno == ERANGE || v < lo || v > hi) return -1;
  *out = (int)v;
  return 0;
}

/* Whole-string finite number >= 0; 0 on success. */
static int parse_nonneg(const char *s, double *out) {
  char *end = NULL;
  errno = 0;
  double v = strtod(s, &end);
  if (!*s || *end || errno == ERANGE || !isfinite(v) || v < 0) return -1;
  *out = v;
  return 0;
}

/* 1 if a and b name the same file: the same string, or the same inode when both exist. */
static int same_file(const char *a, const char *b) {
  struct stat sa, sb;
  if (strcmp(a, b) == 0) return 1;
  return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

/* Check that path can be created: its directory exists and it is not itself a directory, so a
 * bad name fails before any work is done. Returns 0 or a usage error. */
static int check_writable_path(const char *path, const char *what) {
  struct stat st;
  if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) return usage_error("%s '%s' is a directory", what, path);
  const char *slash = strrchr(path, '/');
  if (!slash) return 0;
  size_t n = slash == path ? 1 : (size_t)(slash - path);
  char *dir = malloc(n + 1);
  if (!dir) return usage_error("out of memory");
  memcpy(dir, path, n);
  dir[n] = '\0';
  int ok = stat(dir, &st) == 0 && S_ISDIR(st.st_mode);
  int rc = ok ? 0 : usage_error("%s '%s': directory '%s' does not exist", what, path, dir);
  free(dir);
  return rc;
}

/* Parse `authalic sphere ...` (argv[0] is "sphere"). Returns -1 to go on, else an exit code. */
static int parse_sphere(int argc, char **argv, cli_args *a) {
  int npos = 0, dashdash = 0;
  for (int i = 1; i < argc; i++) {
    const char *s = argv[i];
    if (dashdash || s[0] != '-' || s[1] == '\0') {
      if (npos == 0) a->in = s;
      else if (npos == 1) a->out = s;
      else return usage_error("unexpected extra argument '%s'", s);
      npos++;
      continue;
    }
    if (strcmp(s, "--") == 0) {
      dashdash = 1;
    } else if (strcmp(s, "--help") == 0 || strcmp(s, "-h") == 0) {
      print_sphere_help();
      return EXIT_OK;
    } else if (strcmp(s, "--no-balance") == 0) {
      if (a->no_balance++) return usage_error("option '%s' given twice", s);
    } else if (strcmp(s, "--quiet") == 0) {
      if (a->quiet++) return usage_error("option '%s' given twice", s);
    } else if (strcmp(s, "--init-only") == 0) {
      if (a->init_only++) return usage_error("option '%s' given twice", s);
    } else if (strcmp(s, "--report") == 0 || strcmp(s, "--steps") == 0 || strcmp(s, "--tol") == 0) {
      if (i + 1 >= argc) return usage_error("option '%s' needs a value", s);
      const char *v = argv[++i];
      if (strcmp(s, "--report") == 0) {
        if (a->report) return usage_error("option '%s' given twice", s);
        if (!*v) return usage_error("option '--report' needs a file name");
        a->report = v;
      } else if (strcmp(s, "--steps") == 0) {
        if (a->has_steps++) return usage_error("option '%s' given twice", s);
        if (parse_int(v, 1, AU_ADVECT_MAX_STEPS, &a->steps))
          return usage_error("--steps '%s': expected a whole number from 1 to %d", v, AU_ADVECT_MAX_STEPS);
      } else {
        if (a->has_tol++) return usage_error("option '%s' given twice", s);
        if (parse_nonneg(v, &a->tol)) return usage_error("--tol '%s': expected a finite number >= 0", v);
      }
    } else {
      return usage_error("unknown option '%s'", s);
    }
  }
  if (npos < 2) return usage_error(npos == 0 ? "missing input and output files" : "missing output file");
  if (!*a->in || !*a->out) return usage_error("empty file name");
  if (a->init_only && (a->has_steps || a->has_tol))
    return usage_error("--init-only runs no advection: --steps and --tol do not apply");
  if (same_file(a->in, a->out)) return usage_error("output '%s' is the input file; refusing to overwrite it", a->out);
  if (a->report && same_file(a->report, a->in)) return usage_error("report '%s' is the input file", a->report);
  if (a->report && same_file(a->report, a->out)) return usage_error("report '%s' is the output file", a->report);
  if (!au_io_can_write(a->out)) {
    const char *dot = strrchr(a->out, '.'), *slash = strrchr(a->out, '/');
    if (!dot || (slash && dot < slash)) return usage_error("output '%s' has no extension (use .obj, .off or .ply)", a->out);
    return usage_error("cannot write '%s' files (output '%s'; use .obj, .off or .ply)", dot, a->out);
  }
  int rc = check_writable_path(a->out, "output");
  if (rc == 0 && a->report) rc = check_writable_path(a->report, "report");
  return rc ? rc : -1;
}

/* Progress: a redrawn line on a terminal; elsewhere (logs) a line at most every second once the
 * run has lasted a second, so short runs stay silent and long ones show they are alive. */
typedef struct progress {
  double t_start, t_last;
  int tty, drawn;
} progress;

static void on_progress(void *user, int step, int max_steps, double err) {
  progress *p = user;
  double t = now_s();
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

/* End a redrawn progress line so that what follows starts on its own line. */
static void progress_end(progress *p) {
  if (p->drawn) fputc('\n', stderr);
  p->drawn = 0;
}

/* The temporary name OUT is first written under: a hidden sibling with the same extension (the
 * writer picks the format by it), renamed over OUT only when the report has been written too. */
static char *temp_name(const char *out) {
  const char *slash = strrchr(out, '/');
  size_t dirlen = slash ? (size_t)(slash - out + 1) : 0, n = strlen(out) + 64;
  char *t = malloc(n);
  if (t) snprintf(t, n, "%.*s.authalic-%ld-%s", (int)dirlen, out, (long)getpid(), out + dirlen);
  return t;
}

#define MAX_WARNINGS 4

/* The sphere command after parsing. All resources are released at `done`. */
static int run_sphere(const cli_args *a) {
  double t_start = now_s(), t0;
  au_report_stage stages[6];
  int nst = 0, rc = EXIT_INTERNAL;
  const char *warnings[MAX_WARNINGS];
  char wbuf[MAX_WARNINGS][sizeof(au_msg) + 64];
  int nw = 0;
  au_mesh *m = NULL;
  au_topo *topo = NULL;
  double *P = NULL, *Pinit = NULL;
  char *tmp = NULL;
  au_msg msg = {{0}}, wmsg = {{0}};
  au_status st;
  au_metrics fin, ini;
  int have_init = 0;

  progress prog = {t_start, t_start, isatty(STDERR_FILENO) && !a->quiet, 0};
  au_sphere_opts opts = au_sphere_opts_default();
  if (a->has_steps) opts.flow.max_steps = a->steps;
  if (a->has_tol) opts.flow.tol = a->tol;
  if (a->no_balance) opts.balance = 0;
  if (!a->quiet) opts.flow.progress = on_progress, opts.flow.user = &prog;

  t0 = now_s();
  st = au_io_read(a->in, &m, &msg);
  if (st != AU_OK) {
    rc = fail(a->in, st, &msg);
    goto done;
  }
  stages[nst++] = (au_report_stage){"read", now_s() - t0};

  t0 = now_s();
  au_mesh_expect ex = au_mesh_expect_default();
  ex.loops = 0, ex.genus = 0, ex.command = "sphere";
  st = au_mesh_validate(m, &ex, &topo, &wmsg);
  if (st < 0) {
    rc = fail(a->in, st, &wmsg);
    goto done;
  }
  if (st > 0) {
    say("warning", a->in, st, &wmsg);
    snprintf(wbuf[nw], sizeof wbuf[nw], "%s", wmsg.text[0] ? wmsg.text : au_status_str(st));
    warnings[nw] = wbuf[nw], nw++;
  }
  stages[nst++] = (au_report_stage){"validate", now_s() - t0};

  size_t n3 = 3 * (size_t)m->nv;
  P = malloc(n3 * sizeof *P);
  if (!P) {
    rc = fail(a->in, AU_E_NOMEM, NULL);
    goto done;
  }

  au_sphere_report rep;
  memset(&rep, 0, sizeof rep);
  double t_extra = 0; /* the initial map computed again only for the report's initial metrics */
  if (a->init_only) {
    t0 = now_s();
    st = au_sphere_conformal(m, topo, P, &msg);
    if (st == AU_OK && opts.balance) st = au_sphere_balance(m, topo, P, &msg);
    rep.t_init = now_s() - t0;
  } else {
    /* au_sphere_map does not hand out its starting point, so the initial map's metrics cost one
     * more conformal solve; only a run that asks for a report pays for it. */
    if (a->report) {
      t0 = now_s();
      Pinit = malloc(n3 * sizeof *Pinit);
      st = Pinit ? au_sphere_conformal(m, topo, Pinit, &msg) : AU_E_NOMEM;
      if (st == AU_OK && opts.balance) st = au_sphere_balance(m, topo, Pinit, &msg);
      if (st == AU_OK) st = au_metrics_compute(m->nv, m->nf, m->X, Pinit, m->F, AU_DOMAIN_SPHERE, &ini, NULL, NULL);
      if (st != AU_OK) {
        rc = fail(a->in, st, &msg);
        goto done;
      }
      have_init = 1;
      t_extra = now_s() - t0;
    }
    st = au_sphere_map(m, topo, &opts, P, &rep, &msg);
    progress_end(&prog);
  }
  if (st < 0) {
    rc = fail(a->in, st, &msg);
    goto done;
  }
  if (st == AU_W_NOT_CONVERGED) {
    int k = rep.flow.steps;
    snprintf(wbuf[nw], sizeof wbuf[nw], "tolerance %g not reached in %d steps (error %.3e)", opts.flow.tol, k,
             rep.flow.err[k]);
    fprintf(stderr, "authalic: warning: %s: %s\n", a->in, wbuf[nw]);
    warnings[nw] = wbuf[nw], nw++;
  }
  stages[nst++] = (au_report_stage){"init", rep.t_init};
  stages[nst++] = (au_report_stage){"flow", rep.t_flow};

  t0 = now_s();
  st = au_metrics_compute(m->nv, m->nf, m->X, P, m->F, AU_DOMAIN_SPHERE, &fin, NULL, NULL);
  if (st != AU_OK) {
    rc = fail(a->in, st, NULL);
    goto done;
  }
  /* A folded map is never written: zero folds is the tool's promise, not a hope. */
  if (fin.folds > 0) {
    au_msg_set(&msg, AU_E_FOLD, "the map has %d folded triangle%s; nothing written", fin.folds,
               fin.folds == 1 ? "" : "s");
    rc = fail(a->in, AU_E_FOLD, &msg);
    goto done;
  }
  stages[nst++] = (au_report_stage){"metrics", now_s() - t0 + t_extra};

  /* OUT goes to a temporary sibling first, the report next, and OUT is renamed into place last,
   * so a failure anywhere leaves neither a new OUT nor a clobbered old one. */
  t0 = now_s();
  tmp = temp_name(a->out);
  if (!tmp) {
    rc = fail(a->out, AU_E_NOMEM, NULL);
    goto done;
  }
  st = au_io_write(tmp, m, P, NULL, &msg);
  if (st != AU_OK) {
    rc = fail(a->out, st, &msg);
    goto done;
  }
  /* A result that replaces an earlier one keeps its permissions, as au_io_write's own would. */
  struct stat old;
  if (stat(a->out, &old) == 0 && S_ISREG(old.st_mode)) chmod(tmp, old.st_mode & 07777);
  stages[nst++] = (au_report_stage){"write", now_s() - t0};

  if (a->report) {
    au_report_info info = {AU_VERSION, "sphere", a->in, a->out, m->nv, m->nf,
                           rep.flow.steps, a->init_only ? 0 : rep.flow.converged,
                           have_init ? &ini : NULL, &fin, stages, nst,
                           a->init_only ? NULL : rep.flow.err, a->init_only ? NULL : rep.flow.frac,
                           warnings, nw};
    st = au_report_write(a->report, &info, &msg);
    if (st != AU_OK) {
      rc = fail(a->report, st, &msg);
      goto done;
    }
  }
  if (rename(tmp, a->out) != 0) {
    fprintf(stderr, "authalic: error: %s: cannot rename the finished output into place: %s\n", a->out,
            strerror(errno));
    rc = EXIT_USAGE;
    goto done;
  }
  free(tmp);
  tmp = NULL;

  if (!a->quiet)
    fprintf(stderr, "authalic: sphere: V=%d F=%d steps=%d folds=%d mean|r-1|=%.3g vertex|log r|=%.3g time=%.2fs\n",
            m->nv, m->nf, rep.flow.steps, fin.folds, fin.r_mean_abs_dev, fin.vertex_logr_mean_abs,
            now_s() - t_start);
  rc = EXIT_OK;

done:
  progress_end(&prog);
  if (tmp) {
    unlink(tmp); /* the temporary may not exist yet; then there is nothing to remove */
    free(tmp);
  }
  free(P);
  free(Pinit);
  au_topo_free(&topo);
  au_mesh_free(&m);
  return rc;
}

int main(int argc, char **argv) {
  if (argc < 2) return top_usage_error("no command given");
  const char *cmd = argv[1];
  if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "--version") == 0) {
    if (argc > 2) return top_usage_error("unexpected argument '%s' after '%s'", argv[2], cmd);
    if (strcmp(cmd, "--version") == 0)
      printf("authalic %s\n", AU_VERSION);
    else
      print_help();
    return EXIT_OK;
  }
  if (strcmp(cmd, "sphere") != 0) {
    if (cmd[0] == '-') return top_usage_error("unknown option '%s'", cmd);
    return top_usage_error("unknown command '%s'", cmd);
  }
  cli_args a;
  memset(&a, 0, sizeof a);
  int rc = parse_sphere(argc - 1, argv + 1, &a);
  return rc >= 0 ? rc : run_sphere(&a);
}
