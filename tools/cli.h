/* cli.h - what the commands of the `authalic` program share: messages and exit codes, argument
 * checks, progress on stderr, reading + validating the input, and publishing the results (output
 * written to a temporary sibling, the report, then an atomic rename). Numerics live in the library;
 * a command file only parses its arguments, calls the library and reports. */
#ifndef AU_CLI_H
#define AU_CLI_H

#include <stdarg.h>

#include "au_io.h"
#include "au_mesh.h"
#include "au_metrics.h"
#include "au_report.h"
#include "au_status.h"

#ifndef AU_VERSION
#define AU_VERSION "unknown"
#endif

/* Exit codes (STYLE.md): 0 ok, 1 internal or numerical failure, 2 bad usage or bad input. */
enum { EXIT_OK = 0, EXIT_INTERNAL = 1, EXIT_USAGE = 2 };

/* The commands: each gets argv starting at its own name and returns an exit code. */
int cli_cmd_sphere(int argc, char **argv);
int cli_cmd_disk(int argc, char **argv);    /* disk, annulus and square: argv[0] says which */
int cli_cmd_texture(int argc, char **argv); /* texture */
int cli_cmd_sample(int argc, char **argv);  /* sample */

/* The sphere command's option list (also printed by `authalic --help`). */
void cli_print_sphere_options(void);

double cli_now(void);

/* A usage error: "authalic: error: <message> (see `<help>`)" on stderr; returns EXIT_USAGE. */
int cli_usage_error(const char *help, const char *fmt, ...);
int cli_vusage_error(const char *help, const char *fmt, va_list ap);

/* One line "authalic: KIND: PATH: message" (the path not repeated when the message starts with it). */
void cli_say(const char *kind, const char *path, au_status st, const au_msg *msg);
/* A failed library call: one error line; faults of the input exit 2, the rest 1. */
int cli_fail(const char *path, au_status st, const au_msg *msg);

/* Whole-string integer in [lo, hi]; 0 on success. */
int cli_parse_int(const char *s, long lo, long hi, int *out);
/* Whole-string finite number >= 0; 0 on success. */
int cli_parse_nonneg(const char *s, double *out);
/* 1 if a and b name the same file: the same string, or the same inode when both exist. */
int cli_same_file(const char *a, const char *b);
/* The usual checks of an output mesh path against the input and report paths (same file, a format
 * that can be written, existing directory). An OUT without a known extension is accepted here: it
 * takes the input's format or --format's (cli_output_format decides once the input is read); one
 * that names a format that cannot be written (.stl) is refused. report may be NULL. Returns 0 or a
 * usage error (help names the command's help). */
int cli_check_outputs(const char *help, const char *in, const char *out, const char *report);
/* The options of issue 19 that the map commands share: --format NAME (how OUT is written),
 * --distortion FILE (per-vertex areal distortion as a curv or .shape.gii file) and, for the sphere,
 * --radius R (the written sphere's radius). */
typedef struct cli_neuro_args {
  au_io_format format; /* --format, AU_IO_FORMAT_AUTO if not given */
  const char *distortion;
  double radius;       /* --radius, 1 if not given */
  int has_radius;
} cli_neuro_args;

/* If argv[*i] is --format or --distortion (or --radius when allow_radius), take it and its value
 * (advancing *i) and return 1; return 0 if it is none of them; print a usage error and return -1
 * when its value is missing or bad or it was given twice. */
int cli_parse_neuro(const char *help, int argc, char **argv, int *i, int allow_radius, cli_neuro_args *n);

/* The help lines of those options (radius: include --radius). */
void cli_print_neuro_options(int radius);

/* The format OUT is written in: forced (--format) if given, else OUT's extension, else the input's
 * format (in_meta; so `authalic sphere lh.white lh.sphere.authalic` writes a FreeSurfer surface).
 * Returns 0 with *fmt set, or prints a usage error and returns EXIT_USAGE (the input's format cannot
 * be written: STL). */
int cli_output_format(const char *help, const char *out, au_io_format forced, const au_io_meta *in_meta,
                      au_io_format *fmt);

/* Write the per-vertex areal distortion of the map X -> P (au_metrics_vertex_distortion) to path
 * (au_io_write_scalars: curv, or GIfTI for .gii names, with the input's metadata). Returns -1 on
 * success, else prints the error and returns the exit code. */
int cli_write_distortion(const char *path, const au_mesh *m, const double *P, au_domain domain,
                         const au_io_meta *meta);

/* Check that path can be created: its directory exists and it is not a directory. 0 or usage error. */
int cli_check_writable_path(const char *help, const char *path, const char *what);

/* Progress: a redrawn line on a terminal; elsewhere a line at most every second once the run has
 * lasted a second. Use cli_progress as an au_advect_opts.progress callback with &p as user. */
typedef struct cli_progress_state {
  double t_start, t_last;
  int tty, drawn;
} cli_progress_state;
void cli_progress_init(cli_progress_state *p, int quiet);
void cli_progress(void *user, int step, int max_steps, double err);
void cli_progress_end(cli_progress_state *p);

/* Warnings collected for the report (they are also printed when added). */
#define CLI_MAX_WARNINGS 8
typedef struct cli_warnings {
  const char *list[CLI_MAX_WARNINGS];
  char buf[CLI_MAX_WARNINGS][sizeof(au_msg) + 64];
  int n;
} cli_warnings;
/* Print "authalic: warning: PATH: text" and keep the text for the report. */
void cli_warn(cli_warnings *w, const char *path, const char *fmt, ...);

/* Read IN and validate it against ex. On success *m and *t are set (free with au_mesh_free /
 * au_topo_free), validation warnings are added to w, and the stages "read" and "validate" are
 * appended to stages[*nst] (room for 2 needed); returns -1. Otherwise prints the error and returns
 * the exit code. */
int cli_load(const char *in, const au_mesh_expect *ex, au_mesh **m, au_topo **t, cli_warnings *w,
             au_report_stage *stages, int *nst);
/* cli_load, keeping what the file carried besides the mesh in *meta (free with au_io_meta_free);
 * meta may be NULL. */
int cli_load_meta(const char *in, const au_mesh_expect *ex, au_mesh **m, au_topo **t, au_io_meta **meta,
                  cli_warnings *w, au_report_stage *stages, int *nst);

/* Write the map (positions P, optional texture coordinates in opts) and the report so that a
 * failure leaves neither a new OUT nor a clobbered old one: OUT goes to a temporary sibling, the
 * report (info may be NULL) next, and OUT is renamed into place last. The seconds spent writing OUT
 * go to write_stage->seconds before the report is rendered, so info's stage list may include it
 * (write_stage may be NULL). Returns EXIT_OK or prints the error and returns the exit code. */
int cli_publish(const char *out, const au_mesh *m, const double *P, const au_io_write_opts *wopts,
                const char *report, const au_report_info *info, au_report_stage *write_stage);

/* Install SIGINT/SIGTERM/SIGHUP handlers that remove the temporaries of the output being written
 * (cli_publish's and au_io's), then die of the signal as before: an interrupted run leaves no file. */
void cli_install_signal_cleanup(void);

/* The fold check every command makes before writing: prints the error and returns the exit code
 * when the metrics report folds, else -1. not_converged: the flow missed its tolerance (the message
 * then suggests more steps). */
int cli_refuse_folds(const char *in, const au_metrics *fin, int not_converged);

#endif
