/* authalic.c - the `authalic` command-line program: finds the command and hands over to it.
 * Each command lives in its own file (cmd_*.c); what they share is in cli.h. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

typedef struct command {
  const char *name, *usage;
  int (*run)(int argc, char **argv);
} command;

static const command commands[] = {
    {"sphere", "sphere IN OUT [options]    a closed genus-0 mesh onto the unit sphere", cli_cmd_sphere},
    {"disk", "disk IN OUT [options]      a mesh with one boundary loop onto the unit disk", cli_cmd_disk},
    {"annulus", "annulus IN OUT [options]   a mesh with two boundary loops onto an annulus", cli_cmd_disk},
    {"square", "square IN OUT [options]    a mesh with one boundary loop onto the unit square", cli_cmd_disk},
    {"texture", "texture IN OUT.obj [opts]  equal-area spherical texture coordinates (and baking)", cli_cmd_texture},
    {"sample", "sample IN --grid WxH OUT  the surface sampled on an equal-area grid of the sphere", cli_cmd_sample},
};
#define NCOMMANDS (int)(sizeof commands / sizeof commands[0])

static void print_help(void) {
  printf("authalic %s - equal-area (authalic) maps of triangle meshes by Lie advection\n\n", AU_VERSION);
  for (int i = 0; i < NCOMMANDS; i++) printf("%s authalic %s\n", i == 0 ? "usage:" : "      ", commands[i].usage);
  printf("       authalic COMMAND --help    one command in detail\n"
         "       authalic --help | --version\n\n"
         "IN is read as .obj .off .ply or .stl; OUT is written as .obj .off or .ply (by extension),\n"
         "with the input's vertex order and faces. Exit status: 0 ok (also with warnings), 2 bad usage\n"
         "or bad input, 1 internal or numerical failure.\n\n");
  cli_print_sphere_options();
}

int main(int argc, char **argv) {
  const char *help = "authalic --help";
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
