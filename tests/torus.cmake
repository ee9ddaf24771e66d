# tests for torus/ (closed genus-1 meshes onto a flat torus): the tree-cotree forms, the conformal
# start's invariants, the closed-form maps of the tori of revolution under refinement (data/torus_r*.obj
# and generated ones), the shared genus-1 meshes (bob, rocker_arm), the statuses of wrong topologies,
# the public API's torus result (au_map with AU_TARGET_TORUS) and its preview picture.
au_test_module(test_torus test_torus.c
  homology_forms conformal_modulus data_tori scale_invariance shared_meshes bad_topology api_result square_lattice
  corner_shifts flow_tori flow_square_lattice flow_meshes flow_cancel preview hard_mug)
# The generated genus-1 shapes (docs/torus-hard-shapes.md): mug in both builds; mug_long and ring_legs,
# which take the same paths, only in the plain build (the sanitizer build runs the whole suite again).
if(NOT AU_SANITIZE)
  foreach(c hard_mug_long hard_ring_legs)
    add_test(NAME test_torus.${c} COMMAND test_torus ${c})
    set_tests_properties(test_torus.${c} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300)
  endforeach()
endif()

# `authalic torus` end to end (tests/cli/torus_runs.sh).
foreach(c data shared flow preview distortion genus0 open not_obj bad_lattice)
  au_cli_test(torus.${c} torus_runs.sh ${c})
endforeach()
