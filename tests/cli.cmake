# tests for cli (owned by the cli module): end-to-end runs of the `authalic` program.
# Each case runs a POSIX sh script from tests/cli/ as: sh SCRIPT PROG SOURCE_DIR SHARED_DIR ARGS...
# Scripts exit 0 pass, 1 fail, 77 skip (data/ or ../shared/tools/param-eval absent).

function(au_cli_test name script)
  add_test(NAME cli.${name}
           COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/cli/${script} $<TARGET_FILE:authalic> ${CMAKE_SOURCE_DIR}
                   ${AU_SHARED_DIR} ${ARGN})
  set_tests_properties(cli.${name} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300)
endfunction()

foreach(c help sphere_help version no_command unknown_command unknown_flag prefix_flag missing_args
          missing_value bad_number duplicate_flag bad_combination extra_arg in_eq_out bad_extension)
  au_cli_test(${c} usage.sh ${c})
endforeach()

foreach(c missing_input dir_input missing_outdir out_is_dir keep_existing)
  au_cli_test(${c} files.sh ${c})
endforeach()

# The bad-input corpus: file, then a regular expression the one error line must match (grep -Ei).
set(au_cli_bad
  empty.obj              "empty"
  truncated.off          "ends after .* of 4 faces"
  garbage.obj            "binary data"
  index_range.obj        "index 9 is out of range"
  nan_coord.obj          "vertex 2 has a non-finite coordinate"
  nonmanifold_edge.obj   "non-manifold edge \\(0, 1\\).*3 faces"
  nonmanifold_vertex.obj "vertex 0 is non-manifold"
  flipped_face.obj       "inconsistent orientation"
  two_components.obj     "2 connected components"
  disk.off               "boundary loop.*use `authalic disk`"
  torus.obj              "genus 1"
  zero_area.obj          "face 0 has zero area"
  quad.obj               "4 corners.*only triangles")
list(LENGTH au_cli_bad n)
math(EXPR last "${n} - 1")
foreach(i RANGE 0 ${last} 2)
  math(EXPR j "${i} + 1")
  list(GET au_cli_bad ${i} file)
  list(GET au_cli_bad ${j} pattern)
  string(REGEX REPLACE "\\.[a-z]+$" "" stem ${file})
  au_cli_test(bad.${stem} bad_input.sh ${file} ${pattern})
endforeach()

foreach(c replace_existing not_converged options)
  au_cli_test(${c} runs.sh ${c})
endforeach()

au_cli_test(unreferenced unreferenced.sh)
foreach(mesh spiky_ico bumpy_star)
  au_cli_test(quality.${mesh} quality.sh map data/${mesh}.obj)
  au_cli_test(param_eval.${mesh} param_eval.sh data/${mesh}.obj)
endforeach()
au_cli_test(init_only.spiky_ico quality.sh init_only data/spiky_ico.obj)
