/* cli.h - what the commands of the `authalic` program share: the option table's parser and help,
 * messages and exit codes, argument checks, progress on stderr, reading and checking the input, and
 * publishing the results (output written to a temporary sibling, the report, then an atomic rename).
 * The program uses the library only through its public header; a command file parses, calls the
 * library and writes. */
#ifndef AU_CLI_H
#define AU_CLI_H

#include <stdarg.h>

#include "authalic.h"
#include "cli_options.h"

#ifndef AU_VERSION
#define AU_VERSION "unknown"
#endif

/* Exit codes (STYLE.md): 0 ok, 1 internal or numerical failure, 2 bad usage or bad input. */
enum { EXIT_OK = 0, EXIT_INTERNAL = 1, EXIT_USAGE = 2 };

/* The commands: each gets argv starting at its own name and returns an exit code. */
int cli_cmd_map(int argc, char **argv);     /* sphere, disk, annulus, square and torus: argv[0] says which */
int cli_cmd_texture(int argc, char **argv); /* texture */
int cli_cmd_sample(int argc, char **argv);  /* sample */
int cli_cmd_atlas(int argc, char **argv);   /* atlas */
int cli_cmd_view(int argc, char **argv);    /* view (cmd_view.c) */

/* Write the page of au_view_html to path (a temporary of the output name) and say so unless quiet.
 * Returns -1 on success, else prints the error and returns the exit code. */
int cli_write_view(const char *path, const char *name, const au_view_input *in, int quiet);

double cli_now(void);

/* ---- the option table (cli_options.h) */

/* Parse argv (argv[0] the command's name) for command cmd (a CLI_* bit): positional arguments (at most
 * maxpos) and the options of the table that cmd takes; "--" ends the options. Rejects unknown
 * options, missing values, empty file names and repeats with a usage error. --help prints the
 * command's help (usage_text, then the options) and returns EXIT_OK. Returns -1 to go on, else the
 * exit code. */
int cli_parse(int argc, char **argv, int cmd, int maxpos, const char *usage_text, cli_args *a);
/* Print the options of command cmd from the table, with their defaults. */
void cli_print_options(int cmd);
/* The command's name ("sphere") from its bit. */
const char *cli_cmd_name(int cmd);
/* The library's target of a map command's bit (CLI_SPHERE .. CLI_TORUS); the sphere for others. */
au_target cli_cmd_target(int cmd);

/* Typed values of parsed options: 0 if absent or converted, else a usage error printed and EXIT_USAGE.
 * The messages say "--NAME 'VALUE': expected ...". */
int cli_opt_int(const cli_args *a, cli_opt_id id, long lo, long hi, int *out);
int cli_opt_nonneg(const cli_args *a, cli_opt_id id, double *out);
/* "WxH" with W and H in [1, 16384]. */
int cli_opt_size(const cli_args *a, cli_opt_id id, int *W, int *H);

/* ---- messages */

/* A usage error: "authalic: error: <message> (see `<help>`)" on stderr; returns EXIT_USAGE. */
int cli_usage_error(const char *help, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
int cli_vusage_error(const char *help, const char *fmt, va_list ap);

/* One line "authalic: KIND: PATH: message" (the path not repeated when the message starts with it). */
void cli_say(const char *kind, const char *path, au_status st, const au_msg *msg);
/* A failed library call: one error line; faults of the input exit 2, the rest 1. */
int cli_fail(const char *path, au_status st, const au_msg *msg);

/* Whole-string integer in [lo, hi]; 0 on success. */
int cli_parse_int(const char *s, long lo, long hi, int *out);
/* Whole-string finite number >= 0; 0 on success. */
int cli_parse_nonneg(const char *s, double *out);
/* 1 if a and b name the same file: the same string, the same inode when both exist, or else the same
 * name in the same directory (a file not made yet: out.obj and ./out.obj). */
int cli_same_file(const char *a, const char *b);
/* 1 if path's extension is ext (".png"), any case. */
int cli_has_ext(const char *path, const char *ext);
/* The usual checks of an output mesh path against the input and report paths (same file, a format
 * that can be written, existing directory). An OUT without a known extension is accepted here: it
 * takes the input's format or --format's (cli_output_format decides once the input is read); one
 * that names a format that cannot be written (.stl) is refused. report may be NULL. Returns 0 or a
 * usage error (help names the command's help). */
int cli_check_outputs(const char *help, const char *in, const char *out, const char *report);
/* The format OUT is written in: forced (--format) if given, else OUT's extension, else the input's
 * format (in_meta; so `authalic sphere lh.white lh.sphere.authalic` writes a FreeSurfer surface).
 * Returns 0 with *fmt set, or prints a usage error and returns EXIT_USAGE (the input's format cannot
 * be written: STL). */
int cli_output_format(const char *help, const char *out, au_io_format forced, const au_io_meta *in_meta,
                      au_io_format *fmt);

/* Write the per-vertex areal distortion of the map X -> P (au_metrics_vertex_distortion), or of the
 * per-corner map (nvt, vt, Ft) when vt is given (a torus result: au_metrics_vertex_distortion_vt), to
 * path (au_io_write_scalars: curv, or GIfTI for .gii names, with the input's metadata); errors name
 * the file name (the option's value, when path is its temporary). Returns -1 on success, else prints
 * the error and returns the exit code. */
int cli_write_distortion(const char *path, const char *name, const au_mesh *m, const double *P, au_domain domain,
                         int nvt, const double *vt, const int *Ft, const au_io_meta *meta);
/* Remove an output this run wrote: the file a symbolic link names (au_output_target), not the link. */
void cli_remove_output(const char *path);

/* Check that path can be created: its directory exists and it is not a directory. 0 or usage error. */
int cli_check_writable_path(const char *help, const char *path, const char *what);

/* ---- progress */

/* A redrawn line on a terminal; elsewhere a line at most every second once the run has lasted a
 * second. Use cli_progress as an au_options.progress callback with &p as user. */
typedef struct cli_progress_state {
  double t_start, t_last;
  int tty, drawn;
} cli_progress_state;
void cli_progress_init(cli_progress_state *p, int quiet);
int cli_progress(void *user, int step, int max_steps, double err);
void cli_progress_end(cli_progress_state *p);

/* Warnings of the program's own, for the report (they are also printed when added). */
#define CLI_MAX_WARNINGS 8
typedef struct cli_warnings {
  const char *list[CLI_MAX_WARNINGS];
  char buf[CLI_MAX_WARNINGS][sizeof(au_msg) + 64];
  int n;
} cli_warnings;
/* Print "authalic: warning: PATH: text" and keep the text for the report. */
void cli_warn(cli_warnings *w, const char *path, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* ---- input and output */

/* Read IN and check it for target t (t < 0: read only, as before au_map, which checks itself). What
 * the file carries besides the mesh goes to *meta (free with au_io_meta_free; meta may be NULL). On success *m is set (free with au_mesh_free), a check warning
 * (unreferenced vertices) goes to w, the seconds go to t_read and t_check, and -1 is returned;
 * otherwise the error is printed and the exit code returned. */
int cli_load(const char *in, au_target t, au_mesh **m, au_io_meta **meta, cli_warnings *w, double *t_read,
             double *t_check);

/* Write the map (nv positions P, nf faces F, optional texture coordinates in wopts) and the report
 * (r's JSON with extra; report may be NULL) so that a failure leaves neither a new OUT nor a clobbered
 * old one: OUT goes to a temporary sibling, the report next, and OUT is renamed into place last.
 * The seconds spent writing OUT go to extra->t_write. Returns EXIT_OK or prints the error and returns
 * the exit code. */
int cli_publish(const char *out, int nv, const double *P, int nf, const int *F, const au_write_opts *wopts,
                const char *report, const au_result *r, au_report_extra *extra);

/* Remember that path is about to be written, so that a fatal signal removes its temporary
 * (au_temp_path) and a run interrupted at any point leaves no file behind. At most 16 paths. */
void cli_expect_output(const char *path);
/* The same for a temporary of the program's own (cli_temp_name): a fatal signal removes path itself. */
void cli_expect_temp(const char *path);
/* A temporary name beside path that keeps its extension (DIR/.authalic-PID-NAME); malloc'ed, NULL out
 * of memory. */
char *cli_temp_name(const char *path);
/* An option's name without the dashes ("refine-mesh"). */
const char *cli_option_name(cli_opt_id id);


/* Install SIGINT/SIGTERM/SIGHUP handlers that remove the temporaries of the outputs being written,
 * then die of the signal as before. */
void cli_install_signal_cleanup(void);

#endif
