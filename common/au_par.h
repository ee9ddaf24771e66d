/* au_par.h - two-way parallelism for the flow's heavy loops and factorizations (the target machine
 * has two cores; see docs/multilevel.md, "Both cores"). */
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

/* Set OpenBLAS, when that is the BLAS, to one thread for the process (once; other BLAS are left as
 * they are). Our own two threads both call BLAS, and OpenBLAS's threads on top oversubscribe the two
 * cores: lion_statue's flow took 8.4 s with OPENBLAS_NUM_THREADS=2 in the environment against 2.6 s
 * without it, and one thread is as fast as the default for a whole factorization (2.68 against
 * 2.73 s). Called where the program starts a second thread of its own. */
void au__blas_one_thread(void);

/* The program defines libgomp's GOMP_parallel (au_par.c): with OMP_THREAD_LIMIT=1, as the command
 * line runs, an OpenMP parallel region (CHOLMOD opens one per supernode) is a plain call of its body
 * instead of a team of one ended by a system call; otherwise the region goes to libgomp. This
 * counts the regions that were plain calls, for the tests. */
long au__gomp_inline_regions(void);

#ifdef __cplusplus
}
#endif
#endif
