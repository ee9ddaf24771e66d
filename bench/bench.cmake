# Benchmark programs (generators for scaling runs); included by the top-level CMakeLists.txt.

# au_mkbig: large closed genus-0 meshes (bumpy geodesic icospheres) for bench/scale.sh.
add_executable(au_mkbig ${CMAKE_CURRENT_LIST_DIR}/mkbig.c)
target_link_libraries(au_mkbig PRIVATE ${MATH_LIBRARY})

# au_texture_patches: the acceptance measure of equal-area textures and sampling (issue 4).
add_executable(au_texture_patches ${CMAKE_CURRENT_LIST_DIR}/texture_patches.c)
target_link_libraries(au_texture_patches PRIVATE authalic_core)

# au_sphere_areas_map: the spherical-areas sphere map that `authalic texture` computes without --map.
add_executable(au_sphere_areas_map ${CMAKE_CURRENT_LIST_DIR}/sphere_areas_map.c)
target_link_libraries(au_sphere_areas_map PRIVATE authalic_core)

# au_texture_split_diag: a texture's per-face area error split into the map's and the projection's.
add_executable(au_texture_split_diag ${CMAKE_CURRENT_LIST_DIR}/texture_split_diag.c)
target_link_libraries(au_texture_split_diag PRIVATE authalic_core)

# au_cotan_factor: one factorization of a mesh's cotan Laplacian, the unit of bench/factor_units.sh.
add_executable(au_cotan_factor ${CMAKE_CURRENT_LIST_DIR}/cotan_factor.c)
target_link_libraries(au_cotan_factor PRIVATE authalic_core)
