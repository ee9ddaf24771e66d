/* map_sphere.c - the smallest program over libauthalic: read a closed genus-0 mesh, map it onto the
 * unit sphere with equal area, write the map, print what it measured.
 * Build: cc map_sphere.c $(pkg-config --cflags --libs authalic) -o map_sphere
 * Run:   ./map_sphere IN.obj OUT.obj */
#include <authalic.h>
#include <stdio.h>

int main(int argc, char **argv) {
  if (argc != 3) return fprintf(stderr, "usage: map_sphere IN OUT\n"), 2;
  au_msg msg = {{0}};
  au_mesh *m = NULL;
  au_result *r = NULL;
  au_status st = au_mesh_read(argv[1], &m, &msg);
  if (st >= 0) {
    au_options o = au_options_default();
    st = au_map(m->X, m->nv, m->F, m->nf, AU_TARGET_SPHERE, &o, &r, &msg);
  }
  if (st >= 0) st = au_mesh_write(argv[2], r->nv, r->P, r->nf, r->F, NULL, &msg);
  if (st >= 0)
    printf("V=%d F=%d steps=%d folds=%d mean|r-1|=%.4f vertex|log r|=%.5f\n", r->nv, r->nf, r->conv.steps,
           r->metrics.folds, r->metrics.r_mean_abs_dev, r->metrics.vertex_logr_mean_abs);
  else
    fprintf(stderr, "map_sphere: %s: %s\n", au_status_str(st), msg.text);
  au_result_free(&r);
  au_mesh_free(&m);
  return st < 0 ? (au_status_is_input_error(st) ? 2 : 1) : 0;
}
