/* cli_threads.c - what the `authalic` program does to the whole process to run fast on two cores:
 * one OpenBLAS thread, and libgomp's GOMP_parallel defined here so that an OpenMP region under a
 * one-thread limit is a plain call. The library does neither (it must not change the process that
 * loads it); the program, which owns its process, does both. See cli_threads.h. */
#include "cli_threads.h"

#include <dlfcn.h>
#include <pthread.h>
#include <string.h>

void cli_blas_one_thread(void) {
  void (*set)(int) = NULL;
  void *sym = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
  memcpy(&set, &sym, sizeof set); /* POSIX: a function's address through a data pointer */
  if (set) set(1);
  /* The threads OpenBLAS started when it was loaded (one per core but one, unless
   * OPENBLAS_NUM_THREADS said otherwise) would never be given work again: they are ended. A later
   * call at one thread runs on its caller and starts none. */
  int (*shutdown)(void) = NULL;
  sym = dlsym(RTLD_DEFAULT, "blas_thread_shutdown_");
  memcpy(&shutdown, &sym, sizeof shutdown);
  if (set && shutdown) shutdown();
}

/* CHOLMOD's supernodal factorization opens an OpenMP parallel region for every supernode. The
 * program runs them with one thread (authalic.c: cli_gomp_one_thread, or OMP_THREAD_LIMIT=1), and libgomp still sets up
 * a team of one and ends it with a futex wake-up system call for each: about 100,000 calls per
 * factorization of a 100k-face mesh. With a limit of one thread, a region is its outlined function
 * called once on the calling thread (omp_get_num_threads() is 1 and omp_get_thread_num() 0 outside a
 * team, as inside a team of one), so that is what this does; otherwise the region goes to libgomp.
 * CHOLMOD's calls come here because the executable's definition comes first in the dynamic linker's
 * search. These statics belong to the program, which owns its process. */
typedef void (*gomp_parallel_fn)(void (*)(void *), void *, unsigned, unsigned);
static gomp_parallel_fn gomp_real;
static int gomp_one_thread, gomp_forced;
static long gomp_inline; /* regions run here, counted for the tests */

static void gomp_init(void) {
  void *sym = dlsym(RTLD_NEXT, "GOMP_parallel");
  memcpy(&gomp_real, &sym, sizeof gomp_real);
  int (*limit)(void) = NULL;
  sym = dlsym(RTLD_DEFAULT, "omp_get_thread_limit");
  memcpy(&limit, &sym, sizeof limit);
  gomp_one_thread = gomp_forced || (limit && limit() == 1);
}

void cli_gomp_one_thread(void) { gomp_forced = 1; }

void GOMP_parallel(void (*fn)(void *), void *data, unsigned num_threads, unsigned flags);
void GOMP_parallel(void (*fn)(void *), void *data, unsigned num_threads, unsigned flags) {
  static pthread_once_t once = PTHREAD_ONCE_INIT;
  pthread_once(&once, gomp_init);
  if (gomp_one_thread || num_threads == 1 || !gomp_real) {
    __atomic_fetch_add(&gomp_inline, 1, __ATOMIC_RELAXED);
    fn(data);
  } else {
    gomp_real(fn, data, num_threads, flags);
  }
}

long cli_gomp_inline_regions(void) { return __atomic_load_n(&gomp_inline, __ATOMIC_RELAXED); }
