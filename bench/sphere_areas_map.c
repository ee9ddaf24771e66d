/* sphere_areas_map.c - the sphere map `authalic texture` and `authalic sample` compute when they get
 * no --map (expert sphere_areas 2: the spherical triangles' areas only, no chord polish), written to
 * a file so that bench/texture_table.sh and au_texture_patches can measure it as they measure the
 * maps of `authalic sphere` (which has no option for it).
 *
 *   au_sphere_areas_map IN OUT
 *
 * Prints one line: steps, folds, per-face mean |r-1| with chord and with spherical areas. Exit 0 ok
 * (also not converged), 2 bad input, 1 failure. */
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "authalic.h"

int main(int argc, char **argv) {
  if (argc != 3) return fprintf(stderr, "usage: %s IN OUT\n", argv[0]), 2;
  /* As the program does (tools/authalic.c): CHOLMOD and OpenBLAS read their thread settings when
   * they load, before main, and a map's last digits follow them; restart once single-threaded so
   * the map is the one `authalic texture` computes. */
  if (!getenv("OMP_THREAD_LIMIT")) {
    setenv("OMP_THREAD_LIMIT", "1", 1);
    if (!getenv("OPENBLAS_NUM_THREADS")) setenv("OPENBLAS_NUM_THREADS", "1", 1);
    execv("/proc/self/exe", argv);
  }
  au_mesh *m = NULL;
  au_result *r = NULL;
  au_msg msg = {{0}};
  if (au_mesh_read(argv[1], &m, &msg) < 0) return fprintf(stderr, "%s\n", msg.text), 2;
  au_options o = au_options_default();
  o.spherical_areas = 1;
  au_status st = au_map(m->X, m->nv, m->F, m->nf, AU_TARGET_SPHERE, &o, &r, &msg);
  if (st < 0) return fprintf(stderr, "%s: %s\n", argv[1], msg.text), au_status_is_input_error(st) ? 2 : 1;
  if (au_mesh_write(argv[2], r->nv, r->P, r->nf, r->F, NULL, &msg) < 0) return fprintf(stderr, "%s\n", msg.text), 1;
  printf("%s: steps=%d folds=%d chord mean|r-1|=%.5f sph mean|r-1|=%.5f\n", argv[1], r->conv.steps, r->metrics.folds,
         r->metrics.r_mean_abs_dev, r->metrics.sph_r_mean_abs_dev);
  au_result_free(&r);
  au_mesh_free(&m);
  return 0;
}
