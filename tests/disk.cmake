# tests for disk/ (disk, annulus, square maps): unit tests of the boundary constraints and initial
# maps, quality of the maps on the project's own open meshes (data/disk_bump.obj, data/annulus_bump.obj),
# bad-input statuses; then end-to-end runs of `authalic disk | annulus | square` (tests/cli/disk_*.sh).
au_test_module(test_disk test_disk.c
  bc_circle_projection bc_square_sides meanvalue_positive init_disk annulus_modulus annulus_inner_radius
  map_disk_bump resolved_schedule arc_radius_of_domains refine_floor angle_steps map_short_boundary map_disk_fixed map_annulus_bump map_square square_split_ear bad_topology folded_start_refused)

foreach(c disk_help annulus_help square_help unknown_flag foreign_flag bad_boundary bad_inner_radius bad_corners
          bad_outer_loop init_only_combination missing_args)
  au_cli_test(disk.usage.${c} disk_usage.sh ${c})
endforeach()

foreach(c closed_to_disk closed_to_square disk_to_annulus annulus_to_disk corners_not_on_boundary
          outer_loop_not_on_boundary)
  au_cli_test(disk.bad.${c} disk_bad_input.sh ${c})
endforeach()

foreach(c disk annulus square square_fixed init_only annulus_options refine_faces)
  au_cli_test(disk.run.${c} disk_runs.sh ${c})
endforeach()

# `authalic circles` (disk/au_circles.c) and `square --aspect`: tests/cli/circles.sh. The 40-hole disk
# and ../shared's beetle (11 loops, 39k faces) only in the plain build: the sanitizer build runs the
# smaller holed disks, which take the same paths.
foreach(c disk annulus outer bad_outer bad_closed bad_genus bad_shared_vertex bad_chord aspect bad_aspect help)
  au_cli_test(circles.${c} circles.sh ${c})
endforeach()
foreach(m holes3.obj holes10.obj face_holes.obj)
  au_cli_test(circles.run.${m} circles.sh run ${m})
endforeach()
if(NOT AU_SANITIZE)
  foreach(m holes40.obj beetle.off)
    au_cli_test(circles.run.${m} circles.sh run ${m})
  endforeach()
endif()
