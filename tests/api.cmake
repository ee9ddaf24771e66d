# tests of the public API (include/authalic.h), linked against libauthalic.so as a user's program is
add_executable(test_api test_api.c au_test.c)
target_link_libraries(test_api PRIVATE authalic_shared Threads::Threads ${CJSON_LIBRARY} ${MATH_LIBRARY})
target_include_directories(test_api PRIVATE ${CMAKE_CURRENT_SOURCE_DIR} ${CJSON_INCLUDE_DIR})
target_compile_definitions(test_api PRIVATE
  AU_SHARED_DIR="${AU_SHARED_DIR}" AU_SOURCE_DIR="${CMAKE_SOURCE_DIR}" AU_BINARY_DIR="${CMAKE_BINARY_DIR}")
foreach(c sphere_map planar_targets bad_input bad_options inputs_untouched two_threads cancel_from_thread
          cancel_from_progress report_json presets_and_expert files_and_names staged_retry global_polish spherical_areas)
  add_test(NAME test_api.${c} COMMAND test_api ${c})
  set_tests_properties(test_api.${c} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300)
endforeach()
