# tests for the sphere map (conformal start, balancing, quality on data/ meshes)
au_test_module(test_sphere test_sphere.c conformal_ellipsoid balance_centroid map_ellipsoid resolved_schedule map_spiky map_bumpy map_dumbbell polish_when_needed order_independent plan_in_thread undone_steps_leave_no_trace phase_transitions restore_shapes lantern_retry lantern_skipped vertex_polish vertex_polish_spherical angle_steps density_half scale_invariance folded_start_refused compressed_start_limbs8 refine_mesh_limbs4 refine_spherical_split_limbs8 global_polish_limbs4 twisted_start twist_retry_limbs4 strong_start_tpose multilevel_start_spiky multilevel_start_limbs4 robust_polish_gate_limbs4)
# One thread: the refinement runs three candidates' flows and the global polish, which threaded BLAS on
# 2 cores slows 2.5x.
set_tests_properties(test_sphere.refine_spherical_split_limbs8 test_sphere.refine_mesh_limbs4 test_sphere.global_polish_limbs4 test_sphere.multilevel_start_spiky test_sphere.multilevel_start_limbs4 test_sphere.robust_polish_gate_limbs4 PROPERTIES ENVIRONMENT "OPENBLAS_NUM_THREADS=1;OMP_THREAD_LIMIT=1")
# The staged retry before the lantern's on octopus (7316 faces, about 10 s of CPU): the plain build only.
if(NOT AU_SANITIZE)
  add_test(NAME test_sphere.staged_before_lantern COMMAND test_sphere staged_before_lantern)
  set_tests_properties(test_sphere.staged_before_lantern PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300
    ENVIRONMENT "OPENBLAS_NUM_THREADS=1;OMP_THREAD_LIMIT=1")
  # The coarse-to-fine start of ../shared's bunny and the flow from it (about 10 s).
  add_test(NAME test_sphere.near_start_bunny COMMAND test_sphere near_start_bunny)
  set_tests_properties(test_sphere.near_start_bunny PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300
                       ENVIRONMENT "OPENBLAS_NUM_THREADS=1;OMP_THREAD_LIMIT=1")
  # ../shared's bunny on the sphere's shorter resolved schedule (about 4 s on a loaded machine).
  add_test(NAME test_sphere.resolved_bunny COMMAND test_sphere resolved_bunny)
  set_tests_properties(test_sphere.resolved_bunny PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300
                       ENVIRONMENT "OPENBLAS_NUM_THREADS=1;OMP_THREAD_LIMIT=1")
  # ../shared's cow with the global polish's robust loss (about 2 s).
  add_test(NAME test_sphere.robust_polish_cow COMMAND test_sphere robust_polish_cow)
  set_tests_properties(test_sphere.robust_polish_cow PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300
                       ENVIRONMENT "OPENBLAS_NUM_THREADS=1;OMP_THREAD_LIMIT=1")
endif()
