# tests for the DEC operators and the CHOLMOD wrapper
au_test_module(test_dec test_dec.c stiffness_props stiffness_dirichlet grad_linear areas_sum cotan_scale solver_linear_exact
                sphere_area sphere_chord_floor spd_split ordering_holds_sigterm gomp_inline gomp_forward)
# As the command line runs: single-threaded libraries. With OpenBLAS's own threads, a SIGTERM can be
# delivered to one of them while METIS (which traps the signal process-wide) runs in the main thread.
set_tests_properties(test_dec.ordering_holds_sigterm PROPERTIES ENVIRONMENT "OPENBLAS_NUM_THREADS=1;OMP_THREAD_LIMIT=1")
# OpenMP regions run inline under the command line's thread limit of 1, and go to libgomp otherwise.
set_tests_properties(test_dec.gomp_inline PROPERTIES ENVIRONMENT "OMP_THREAD_LIMIT=1")
set_tests_properties(test_dec.gomp_forward PROPERTIES ENVIRONMENT "OMP_THREAD_LIMIT=2")
# The OpenMP shortcut is the program's, not the library's (tools/cli_threads.c): linked in for its two cases.
target_link_libraries(test_dec PRIVATE authalic_cli_threads)
target_include_directories(test_dec PRIVATE ${CMAKE_SOURCE_DIR}/tools)
