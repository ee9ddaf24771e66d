# tests for the sphere map (conformal start, balancing, quality on data/ meshes)
au_test_module(test_sphere test_sphere.c conformal_ellipsoid balance_centroid map_ellipsoid resolved_schedule map_spiky map_bumpy map_dumbbell polish_when_needed order_independent plan_in_thread undone_steps_leave_no_trace restore_shapes lantern_retry angle_steps density_half scale_invariance folded_start_refused)
