/* cli_threads.h - the program's process-wide thread settings (cli_threads.c). Linked only into the
 * `authalic` program and the test of these settings, never into the library. */
#ifndef AU_CLI_THREADS_H
#define AU_CLI_THREADS_H

/* Set OpenBLAS, when that is the BLAS, to one thread for the process (other BLAS are left as they
 * are). The flow runs two threads of its own that both call BLAS; OpenBLAS's threads on top
 * oversubscribe two cores. The threads OpenBLAS started when it was loaded are ended. */
void cli_blas_one_thread(void);

/* Every OpenMP region of the process (CHOLMOD's) run on its caller, as under OMP_THREAD_LIMIT=1;
 * call before the first region. */
void cli_gomp_one_thread(void);

/* The OpenMP regions that this program's GOMP_parallel ran as plain calls (for the tests). */
long cli_gomp_inline_regions(void);

#endif
