/* au_par.c - see au_par.h. */
#include "au_par.h"

#include <dlfcn.h>
#include <pthread.h>
#include <signal.h>
#include <string.h>

typedef struct pair_call {
  void *(*fn)(void *);
  void *arg;
} pair_call;

static void *pair_thread(void *arg) {
  sigset_t all;
  sigfillset(&all);
  pthread_sigmask(SIG_BLOCK, &all, NULL);
  const pair_call *c = arg;
  return c->fn(c->arg);
}

void au__run_pair(void *(*fn)(void *), void *a0, void *a1) {
  pthread_t th;
  pair_call c = {fn, a1};
  int threaded = pthread_create(&th, NULL, pair_thread, &c) == 0;
  fn(a0);
  if (threaded) pthread_join(th, NULL);
  else fn(a1);
}

static void blas_one_thread(void) {
  void (*set)(int) = NULL;
  void *sym = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
  memcpy(&set, &sym, sizeof set); /* POSIX: a function's address through a data pointer */
  if (set) set(1);
}

void au__blas_one_thread(void) {
  static pthread_once_t once = PTHREAD_ONCE_INIT;
  pthread_once(&once, blas_one_thread);
}
