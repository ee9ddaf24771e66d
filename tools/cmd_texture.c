/* cmd_texture.c - `authalic texture` and `authalic sample`: equal-area spherical textures and
 * sampling. (Placeholder until the texture module lands.) */
#include <stdio.h>

#include "cli.h"

int cli_cmd_texture(int argc, char **argv) {
  (void)argc;
  fprintf(stderr, "authalic: error: the %s command is not implemented yet\n", argv[0]);
  return EXIT_INTERNAL;
}

int cli_cmd_sample(int argc, char **argv) {
  (void)argc;
  fprintf(stderr, "authalic: error: the %s command is not implemented yet\n", argv[0]);
  return EXIT_INTERNAL;
}
