# tests for the sphere map (conformal start, balancing, quality on data/ meshes)
au_test_module(test_sphere test_sphere.c conformal_ellipsoid balance_centroid map_ellipsoid resolved_schedule map_spiky map_bumpy map_dumbbell polish_when_needed chord_polish_cut order_independent plan_in_thread undone_steps_leave_no_trace phase_transitions restore_shapes lantern_retry lantern_skipped lantern_resumed vertex_polish vertex_polish_spherical angle_steps density_half scale_invariance folded_start_refused compressed_start_limbs8 refine_mesh_limbs4 refine_spherical_split_limbs8 global_polish_limbs4 twisted_start twist_retry_limbs4 strong_start_tpose multilevel_start_spiky multilevel_start_limbs4 robust_polish_gate_limbs4)
# One thread: the refinement runs three candidates' flows and the global polish, which threaded BLAS on
# 2 cores slows 2.5x.
set_tests_properties(test_sphere.chord_polish_cut test_sphere.refine_spherical_split_limbs8 test_sphere.refine_mesh_limbs4 test_sphere.global_polish_limbs4 test_sphere.multilevel_start_spiky test_sphere.multilevel_start_limbs4 test_sphere.robust_polish_gate_limbs4 PROPERTIES ENVIRONMENT "OPENBLAS_NUM_THREADS=1;OMP_THREAD_LIMIT=1")
# The plain build only, one BLAS thread: the staged retry before the lantern's on octopus (7316 faces,
# about 10 s of CPU); ../shared's bunny from the coarse-to-fine start (about 10 s) and on the sphere's
# shorter resolved schedule (about 4 s); ../shared's cow with the global polish's robust loss (about 2 s);
# ../shared's hand_closed's lantern retry resumed (about 4 s).
if(NOT AU_SANITIZE)
  foreach(c staged_before_lantern near_start_bunny resolved_bunny robust_polish_cow lantern_resumed_hand_closed)
    add_test(NAME test_sphere.${c} COMMAND test_sphere ${c})
    set_tests_properties(test_sphere.${c} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300
                         ENVIRONMENT "OPENBLAS_NUM_THREADS=1;OMP_THREAD_LIMIT=1")
  endforeach()
endif()
