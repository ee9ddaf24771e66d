/* au_par.h - two-way parallelism for the flow's heavy loops and factorizations (the target machine
 * has two cores; see docs/flow.md, "Where the time goes"). */
#ifndef AU_PAR_H
#define AU_PAR_H

#ifdef __cplusplus
extern "C" {
#endif

/* Run fn(a0) on the calling thread and fn(a1) on a second thread, and return when both are done.
 * The second thread blocks every signal, so that signals keep reaching the caller's thread (the
 * program's SIGTERM handling, and METIS's, assume that). If no thread can be had, fn(a1) runs after
 * fn(a0) on the calling thread. fn's return value is ignored. */
void au__run_pair(void *(*fn)(void *), void *a0, void *a1);


#ifdef __cplusplus
}
#endif
#endif
