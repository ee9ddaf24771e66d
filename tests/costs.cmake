# The cases that take longest, with their rough seconds under the sanitizer build (the longer of
# the two runs of `make test`). `ctest -j` starts the costliest cases first, so that a long case does
# not begin near the end of the run with one core left idle; without these, a clean checkout has
# no cost data and ctest runs the cases in the order they were declared. The figures only order
# the cases: a stale one costs a few seconds of wall time, never a result.
set(au_test_costs
  test_api.staged_retry 105  test_sphere.strong_start_tpose 95  test_sphere.refine_spherical_split_limbs8 80
  workflow.slurm 110  cli.refine_mesh.limbs8_auto 65  test_sphere.compressed_start_limbs8 45
  cli.refine_mesh.cheburashka 43  test_api.inputs_untouched 39  test_api.spherical_areas 35
  cli.squeezed 30  test_api.global_polish 29  test_io.write_halves 25  cli.refine_budget 25
  test_sphere.refine_mesh_limbs4 22  cli.view.page.sphere 21  test_texture.area_target 20  cli.interrupted 20
  cli.refine_mesh.cow 20  install.examples 19  test_texture.vt_spiky 18
  test_sphere.map_spiky 17  test_torus.flow_tori 17  workflow.local 17  cli.torus.shared 16  workflow.rerun 16
  python.test_cli 115  python.test_api 90  python.test_threads 40  python.test_bitwise 25  python.test_atlas 15)
list(LENGTH au_test_costs n)
math(EXPR last "${n} - 1")
foreach(i RANGE 0 ${last} 2)
  math(EXPR j "${i} + 1")
  list(GET au_test_costs ${i} name)
  list(GET au_test_costs ${j} cost)
  if(TEST ${name})
    set_tests_properties(${name} PROPERTIES COST ${cost})
  endif()
endforeach()
