# tests for the DEC operators and the CHOLMOD wrapper
au_test_module(test_dec test_dec.c stiffness_props stiffness_dirichlet grad_linear areas_sum cotan_scale solver_linear_exact
                sphere_area sphere_chord_floor spd_split ordering_holds_sigterm gomp_inline gomp_forward)
# As the command line runs: single-threaded libraries. With OpenBLAS's own threads, a SIGTERM can be
# delivered to one of them while METIS (which traps the signal process-wide) runs in the main thread.
set_tests_properties(test_dec.ordering_holds_sigterm PROPERTIES ENVIRONMENT "OPENBLAS_NUM_THREADS=1;OMP_THREAD_LIMIT=1")
# OpenMP regions run inline under the command line's thread limit of 1, and go to libgomp otherwise.
set_tests_properties(test_dec.gomp_inline PROPERTIES ENVIRONMENT "OMP_THREAD_LIMIT=1")
set_tests_properties(test_dec.gomp_forward PROPERTIES ENVIRONMENT "OMP_THREAD_LIMIT=2")
