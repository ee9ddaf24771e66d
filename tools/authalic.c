/* authalic.c - the `authalic` command-line program: finds the command and hands over to it.
 * Each command lives in its own file (cmd_*.c); what they share is in cli.h. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "cli_threads.h"

typedef struct command {
  const char *name, *usage;
  int (*run)(int argc, char **argv);
} command;

static const command commands[] = {
    {"sphere", "sphere IN OUT [options]    a closed genus-0 mesh onto the unit sphere", cli_cmd_map},
    {"disk", "disk IN OUT [options]      a mesh with one boundary loop onto the unit disk", cli_cmd_map},
    {"annulus", "annulus IN OUT [options]   a mesh with two boundary loops onto an annulus", cli_cmd_map},
    {"square", "square IN OUT [options]    a mesh with one boundary loop onto the unit square", cli_cmd_map},
    {"torus", "torus IN OUT.obj [options] a closed genus-1 mesh onto a flat torus (seamless vt)", cli_cmd_map},
    {"circles", "circles IN OUT [options]   a genus-0 mesh with any boundary loops onto a disk with round holes", cli_cmd_map},
    {"texture", "texture IN OUT.obj [opts]  equal-area spherical texture coordinates (and baking)", cli_cmd_texture},
    {"sample", "sample IN --grid WxH OUT  the surface sampled on an equal-area grid of the sphere", cli_cmd_sample},
    {"view", "view IN MAP OUT.html       a surface and its map as one interactive page", cli_cmd_view},
    {"atlas", "atlas IN OUT.obj [options] an equal-area seamless atlas of any genus (per-corner vt)",
     cli_cmd_atlas},
};
#define NCOMMANDS (int)(sizeof commands / sizeof commands[0])

static void print_help(void) {
  printf("authalic %s - equal-area (authalic) maps of triangle meshes by Lie advection\n\n", AU_VERSION);
  for (int i = 0; i < NCOMMANDS; i++) printf("%s authalic %s\n", i == 0 ? "usage:" : "      ", commands[i].usage);
  printf("       authalic COMMAND --help    one command in detail\n"
         "       authalic --help | --version\n\n"
         "IN is read as .obj .off .ply .stl, a FreeSurfer surface (lh.white: by its magic number) or\n"
         "GIfTI (.gii .gii.gz); OUT is written as .obj .off .ply .gii or .gii.gz (by extension; another\n"
         "name gets IN's format; --format chooses), with the input's vertex order and faces.\n"
         "Exit status: 0 ok (also with warnings), 2 bad usage or bad input, 1 internal or numerical\n"
         "failure.\n\n");
  cli_print_options(CLI_SPHERE);
}

/* CHOLMOD's supernodal factorization opens an OpenMP team of a fixed size (ignoring
 * OMP_NUM_THREADS) at every supernode, and OpenBLAS starts threads of its own: on a 2-core machine
 * they spin against each other. Measured on lion_statue (100k faces): 28.6 s wall with 26.5 s of
 * system time as it comes; 20.9 s wall and 1.9 s of system time single-threaded. So CHOLMOD's regions
 * run on their caller (cli_gomp_one_thread, as OMP_THREAD_LIMIT=1 would) unless the caller set
 * OMP_THREAD_LIMIT (a choice that is respected), and OpenBLAS runs at one thread
 * (cli_blas_one_thread). The program used to restart itself with OMP_THREAD_LIMIT=1 and
 * OPENBLAS_NUM_THREADS=1 set instead (both libraries read them when loaded, before main; an
 * environment set before main is undone by the C library's own start-up): the same settings, at the
 * price of every library loaded and relocated twice, about 400 page faults and 20-35 ms of CPU per
 * run (docs/overhead.md). */
static void single_threaded_libraries(void) {
#ifndef AU_CLI_EMBEDDED /* the fuzz harness calls main in-process: its process is not the program's */
  if (!getenv("OMP_THREAD_LIMIT")) cli_gomp_one_thread();
#endif
}

int main(int argc, char **argv) {
  const char *help = "authalic --help";
  single_threaded_libraries();
  cli_blas_one_thread();
  cli_install_signal_cleanup();
  if (argc < 2) return cli_usage_error(help, "no command given");
  const char *cmd = argv[1];
  if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "--version") == 0) {
    if (argc > 2) return cli_usage_error(help, "unexpected argument '%s' after '%s'", argv[2], cmd);
    if (strcmp(cmd, "--version") == 0)
      printf("authalic %s\n", AU_VERSION);
    else
      print_help();
    return EXIT_OK;
  }
  for (int i = 0; i < NCOMMANDS; i++)
    if (strcmp(cmd, commands[i].name) == 0) return commands[i].run(argc - 1, argv + 1);
  if (cmd[0] == '-') return cli_usage_error(help, "unknown option '%s'", cmd);
  return cli_usage_error(help, "unknown command '%s'", cmd);
}
