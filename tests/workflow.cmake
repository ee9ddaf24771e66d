# tests for workflow/ (the Snakemake cohort workflow, issue 22): bash scripts in tests/workflow/,
# each run as: bash SCRIPT PROG SOURCE_DIR SHARED_DIR WORK_DIR; exit 0 pass, 1 fail, 77 skip.
#   workflow.scripts  the Python scripts alone (distortion fallback vs the reports, previews, readers)
#   workflow.local    six meshes and one bad input on two cores: outputs, cohort.tsv vs the reports
#   workflow.rerun    on workflow.local's cohort (a fixture): nothing redone; touch / new options
#                     redo exactly that row
#   workflow.slurm    the same cohort through a one-node Slurm started (and stopped) by the test
#   workflow.circles  one row with command circles (a disk with three holes)
#   workflow.atlas    rows with command atlas (genus 2, genus 0) and one bad input: metrics as param-eval's
#
# Registered in the normal build only, not in the sanitizer build (AU_SANITIZE): these tests check
# the workflow (Snakemake, Slurm, the scripts), not new C code, and the program paths they run are
# the cli.* cases, which the sanitizer pass already covers; a second pass would add minutes (most of
# it starting Slurm jobs) without adding a check.
if(NOT AU_SANITIZE)
  set(au_wf_work "${CMAKE_BINARY_DIR}/workflow-test")
  function(au_workflow_test name script)
    add_test(NAME workflow.${name}
             COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/workflow/${script} $<TARGET_FILE:authalic>
                     ${CMAKE_SOURCE_DIR} ${AU_SHARED_DIR} ${au_wf_work})
    set_tests_properties(workflow.${name} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 600)
  endfunction()
  au_workflow_test(scripts scripts.sh)
  au_workflow_test(local local.sh)
  au_workflow_test(rerun rerun.sh)
  au_workflow_test(slurm slurm.sh)
  au_workflow_test(circles circles.sh)
  au_workflow_test(atlas atlas.sh)
  set_tests_properties(workflow.local PROPERTIES FIXTURES_SETUP workflow_cohort)
  set_tests_properties(workflow.rerun PROPERTIES FIXTURES_REQUIRED workflow_cohort)
  # Each run uses both cores (--cores 2; the Slurm node has 2 CPUs): one at a time under ctest -j2.
  set_tests_properties(workflow.local workflow.rerun workflow.slurm workflow.circles workflow.atlas PROPERTIES RESOURCE_LOCK workflow_cores)
endif()
