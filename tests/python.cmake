# The Python package (python/, issue 23) over this build's libauthalic.so.1, run with Debian's own
# interpreter (python3-numpy, python3-pytest), not a python3 found first on PATH. One ctest case
# per test file runs pytest on it; pytest's exit status 5 (no tests collected) fails it like any nonzero one.
set(AU_PYTHON /usr/bin/python3 CACHE FILEPATH "The interpreter the Python package is tested with")
set(au_py_env
  PYTHONDONTWRITEBYTECODE=1
  AUTHALIC_LIBRARY=$<TARGET_FILE:authalic_shared>
  AUTHALIC_CLI=$<TARGET_FILE:authalic>
  AUTHALIC_SHARED=${AU_SHARED_DIR})
if(AU_SANITIZE)
  # The interpreter is not built with the sanitizers, so their runtime must be loaded first
  # (LD_PRELOAD). LeakSanitizer is off: CPython keeps its own objects to the end and would report
  # them. The shared meshes take minutes under the sanitizers; the suite maps the small ones.
  execute_process(COMMAND ${CMAKE_C_COMPILER} -print-file-name=libasan.so OUTPUT_VARIABLE au_libasan
                  OUTPUT_STRIP_TRAILING_WHITESPACE)
  list(APPEND au_py_env LD_PRELOAD=${au_libasan} ASAN_OPTIONS=detect_leaks=0:exitcode=86 AUTHALIC_TEST_QUICK=1)
endif()
# One ctest case per test file, so that `ctest -j` runs them side by side instead of one long case
# at the end of the run (the suite is the longest single case under the sanitizers).
file(GLOB au_py_tests CONFIGURE_DEPENDS RELATIVE ${CMAKE_SOURCE_DIR}/python/tests ${CMAKE_SOURCE_DIR}/python/tests/test_*.py)
foreach(f ${au_py_tests})
  string(REGEX REPLACE "\\.py$" "" stem ${f})
  add_test(NAME python.${stem}
           COMMAND ${CMAKE_COMMAND} -E env ${au_py_env}
                   ${AU_PYTHON} -m pytest -p no:cacheprovider -q -rs ${CMAKE_SOURCE_DIR}/python/tests/${f}
           WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}/python)
  set_tests_properties(python.${stem} PROPERTIES TIMEOUT 1200)
endforeach()
