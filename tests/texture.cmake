# tests for the spherical textures and sampling (sphere/ texture module)
au_test_module(test_texture test_texture.c geo_cea_roundtrip geo_laea_roundtrip geo_areas geo_gnomonic_lines
               layout_roundtrip orient_exact locate_random coords_cea_seam_poles coords_laea bake_linear cell_areas npy_file
               png_roundtrip pictures obj_file scalars_file bad_args star_cells render_seam
               oct_equal_area vt_star vt_spiky vt_shared_spot vt_shared_hippocampus axis_auto
               vt_short_flow spherical_map area_rules area_target)

# End-to-end runs of `authalic texture` and `authalic sample` (au_cli_test comes from tests/cli.cmake).
foreach(c texture_help sample_help missing_args bad_values bad_combination bad_outputs unknown_flag)
  au_cli_test(texture.${c} texture_usage.sh ${c})
endforeach()
foreach(c obj_cea laea bake_normal bake_scalar long_names sample sample_csv bad_map mirrored on_the_fly on_the_fly_spherical area_target)
  au_cli_test(texture.${c} texture_runs.sh ${c})
endforeach()
# The thin-limbed family (issue 21): the fold mending goes on while it makes progress.
foreach(m limbs4 limbs8 coil tpose)
  au_cli_test(texture.limbs.${m} texture_limbs.sh ${m})
endforeach()
