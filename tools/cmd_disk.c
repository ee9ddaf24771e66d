/* cmd_disk.c - `authalic disk | annulus | square IN OUT`: open meshes onto planar domains.
 * (Placeholder until the disk module lands.) */
#include <stdio.h>

#include "cli.h"

int cli_cmd_disk(int argc, char **argv) {
  (void)argc;
  fprintf(stderr, "authalic: error: the %s command is not implemented yet\n", argv[0]);
  return EXIT_INTERNAL;
}
