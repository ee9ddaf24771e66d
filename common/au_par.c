/* au_par.c - see au_par.h. */
#include "au_par.h"

#include <pthread.h>
#include <signal.h>

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
