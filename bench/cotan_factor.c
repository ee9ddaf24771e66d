/* cotan_factor.c - the time of one numeric CHOLMOD factorization of a mesh's cotan Laplacian, one thread:
 * the unit issue 39 measures a whole map in ("bunny's whole command <= 14 factorizations of its cotan
 * Laplacian"), so that the figure does not move with the machine or its load as seconds do.
 *
 *   au_cotan_factor IN [REPEATS]
 *
 * The Laplacian of the surface's cotan weights with vertex 0 held (Dirichlet), ordered by METIS (the
 * order the flow's repeated solves use), analysed once, then factored REPEATS times (default 9).
 * Prints the median seconds of one factorization. bench/factor_units.sh divides a command's time by it.
 * Exit 0 ok, 2 bad input, 1 failure. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#include "au_dec.h"
#include "au_mesh.h"
#include "au_solver.h"

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

int main(int argc, char **argv) {
  if (argc < 2 || argc > 3) return fprintf(stderr, "usage: %s IN [REPEATS]\n", argv[0]), 2;
  /* One thread, as the program runs (tools/authalic.c restarts itself so): CHOLMOD and OpenBLAS read
   * their thread settings when they load. */
  if (!getenv("OMP_THREAD_LIMIT")) {
    setenv("OMP_THREAD_LIMIT", "1", 1);
    if (!getenv("OPENBLAS_NUM_THREADS")) setenv("OPENBLAS_NUM_THREADS", "1", 1);
    execv("/proc/self/exe", argv);
  }
  const int reps = argc == 3 ? atoi(argv[2]) : 9;
  if (reps < 1 || reps > 1000) return fprintf(stderr, "%s: REPEATS must be 1..1000\n", argv[0]), 2;
  au_mesh *m = NULL;
  au_topo *t = NULL;
  au_solver *s = NULL;
  au_msg msg = {{0}};
  if (au_mesh_read(argv[1], &m, &msg) < 0 || au_mesh_topology(m, &t, &msg) < 0)
    return fprintf(stderr, "%s: %s\n", argv[1], msg.text), 2;
  double *w = malloc(sizeof(double) * (size_t)(t->ne > 0 ? t->ne : 1)), *sec = malloc(sizeof(double) * (size_t)reps);
  unsigned char *fixed = calloc((size_t)m->nv, 1);
  if (!w || !sec || !fixed || m->nv < 2) return fprintf(stderr, "%s: out of memory or empty mesh\n", argv[1]), 1;
  au_dec_cotan(t, m->F, m->X, w);
  fixed[m->F[0]] = 1;
  if (au_solver_create(m->nv, t->ne, t->E, fixed, AU_ORDER_FILL, &s, &msg) != AU_OK)
    return fprintf(stderr, "%s: %s\n", argv[1], msg.text), 1;
  for (int k = 0; k < reps; k++) {
    double t0 = now_s();
    if (au_solver_factor(s, w, NULL, &msg) != AU_OK) return fprintf(stderr, "%s: %s\n", argv[1], msg.text), 1;
    sec[k] = now_s() - t0;
  }
  qsort(sec, (size_t)reps, sizeof(double), cmp_double);
  printf("%.6f\n", sec[reps / 2]);
  au_solver_free(&s);
  au_topo_free(&t);
  au_mesh_free(&m);
  free(w), free(sec), free(fixed);
  return 0;
}
