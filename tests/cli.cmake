# tests for cli (owned by the cli module): end-to-end runs of the `authalic` program.
# Each case runs a POSIX sh script from tests/cli/ as: sh SCRIPT PROG SOURCE_DIR SHARED_DIR ARGS...
# Scripts exit 0 pass, 1 fail, 77 skip (data/ or ../shared/tools/param-eval absent).

function(au_cli_test name script)
  add_test(NAME cli.${name}
           COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/cli/${script} $<TARGET_FILE:authalic> ${CMAKE_SOURCE_DIR}
                   ${AU_SHARED_DIR} ${ARGN})
  set_tests_properties(cli.${name} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300)
endfunction()

foreach(c help sphere_help version no_command unknown_command unknown_flag unknown_flag_help prefix_flag missing_args
          missing_value bad_number duplicate_flag bad_combination refine_outputs extra_arg in_eq_out bad_extension
          special_outputs)
  au_cli_test(${c} usage.sh ${c})
endforeach()

foreach(c missing_input dir_input missing_outdir out_is_dir keep_existing interrupted
          interrupted_write)
  au_cli_test(${c} files.sh ${c})
endforeach()

# An output that cannot be renamed into place (tests/cli/fail_rename.c, preloaded): no temporaries, no
# report without its map. The preload library is built without the sanitizers, which it does not need.
add_library(au_fail_rename MODULE cli/fail_rename.c)
target_compile_options(au_fail_rename PRIVATE -fno-sanitize=all)
target_link_options(au_fail_rename PRIVATE -fno-sanitize=all)
target_link_libraries(au_fail_rename PRIVATE ${CMAKE_DL_LIBS})
au_cli_test(rename_fault rename_fault.sh $<TARGET_FILE:au_fail_rename>)

# The bad-input corpus (tests/cli/bad/, described in its README.md): file, then a regular expression
# the one error line must match (grep -Ei). Every case exits 2 and leaves no output (bad_input.sh);
# the test is named after the file, e.g. cli.bad.truncated.off.
set(au_cli_bad
  # OBJ
  empty.obj              "empty"
  truncated.obj          "3 vertices and 0 faces"
  garbage.obj            "binary data"
  bad_number.obj         ":4: vertex 2: expected three numbers"
  no_faces.obj           "4 vertices and 0 faces"
  index_range.obj        "index 9 is out of range"
  index_negative.obj     "face 3: index -7 is out of range \\(4 vertices defined before it\\)"
  index_zero.obj         "face 0: index 0 is out of range"
  huge_index.obj         "face 3: bad corner '9+'"
  face_two.obj           "face 3 has 2 corners"
  repeated_index.obj     "face 3 repeats vertex 2"
  quad.obj               "4 corners.*only triangles"
  nan_coord.obj          "vertex 2 has a non-finite coordinate"
  inf_coord.obj          "vertex 1 has a non-finite coordinate"
  huge_coord.obj         "total area inf.*overflow"
  nonmanifold_edge.obj   "non-manifold edge \\(0, 1\\).*3 faces"
  nonmanifold_vertex.obj "vertex 0 is non-manifold"
  moebius.obj            "non-orientable surface.*edge \\(4, 13\\)"
  two_components.obj     "2 connected components"
  single_triangle.obj    "1 boundary loop.*closed surface"
  duplicate_vertex.obj   "1 boundary loop.*closed surface"
  ring.obj               "2 boundary loops.*closed surface: map a mesh with two loops onto the annulus"
  torus.obj              "genus 1"
  zero_area.obj          "face 0 has zero area"
  # OFF
  blank.off              "no OFF header"
  bad_header.off         "not an OFF file.*'OFX'"
  garbage.off            "binary data in an OFF file"
  truncated.off          "ends after .* of 4 faces"
  count_high.off         "ends after 3 of 4 faces"
  count_low.off          "data after the last of the 3 faces"
  huge_count.off         "1000000000 vertices.*more than a [0-9]+-byte file holds"
  index_range.off        "face 3: index 4 is out of range \\(4 vertices, counted from 0\\)"
  index_negative.off     "face 3: index -1 is out of range"
  face_two.off           "face 3: not a polygon"
  quad.off               "face 0 has 4 corners"
  nan_coord.off          "vertex 3 has a non-finite coordinate"
  disk.off               "boundary loop.*onto the disk"
  # PLY
  bad_format.ply         "unknown PLY format 'binary_middle_endian'"
  no_end_header.ply      ":10: data line '0' before end_header"
  garbage.ply            "binary data in the PLY header"
  truncated.ply          "face 3: malformed or missing value \\(truncated"
  truncated_binary.ply   "face 3: the file ends early"
  count_high.ply         "1000000 face records, more than the file holds"
  count_low.ply          "8 bytes of data after the last record"
  no_indices.ply         "lacks a vertex_indices list"
  index_range.ply        "face 3: index 7 is out of range"
  index_negative.ply     "face 3: index -1 is out of range"
  quad.ply               "face 0 has 4 corners"
  nan_coord.ply          "vertex 2 has a non-finite coordinate"
  empty_element.ply      "element 'nothing'.*no properties"
  # STL
  garbage.stl            "not an ASCII STL.*binary STL.*announces [0-9]+ facets"
  truncated.stl          "announces 4 facets \\(284 bytes\\) but the file has 264 bytes \\(truncated"
  truncated_ascii.stl    "the file has 3 facets"
  empty_solid.stl        "no facets"
  degenerate.stl         "4 facets but OpenMesh kept 3"
  open.stl               "1 boundary loop.*closed surface"
  nonmanifold.stl        "non-manifold edge \\(0, 1\\)"
  # FreeSurfer (found by the magic number, whatever the name) and GIfTI (issue 19;
  # scripts/neuro_bad_corpus.py writes them)
  truncated.white        "announces 4 vertices and 4 faces \\(96 bytes\\) but 86 bytes follow its header \\(truncated"
  lying_count.white      "announces 1000000 vertices"
  index_range.white      "face 3: index 7 is out of range \\(4 vertices"
  no_stamp.white         "without its created-by line"
  quad.white             "magic number 0xFFFFFF: a curv file .* not a triangle surface"
  truncated.gii          "not well-formed XML \\(line 6: unclosed token\\)"
  mismatched_tag.gii     "not well-formed XML \\(line 5: mismatched tag\\)"
  misplaced.gii          "not a GIfTI document: element <Data> is not allowed under <GIFTI>"
  truncated.gii.gz       "the gzip data ends early \\(truncated"
  lying_dims.gii         "announces 6000000000 values, more than a 692-byte file holds"
  short_data.gii         "GIfTI data cannot be read: uncompressed buf is 48 bytes, expected 480"
  corrupt_data.gii       "GIfTI data cannot be read: 4 bad base64 chars"
  no_triangles.gii       "0 TRIANGLE arrays"
  values.shape.gii       "0 POINTSET arrays"
  index_range.gii        "face 3: index 9 is out of range"
  external.gii           "external file, which is not read"
  short_ascii.gii        "GIfTI array 0 holds 11 numbers but its dimensions announce 12"
  # any format
  mesh.xyz               "unknown mesh file extension"
  unreadable.obj         "cannot open.*permission denied")
list(LENGTH au_cli_bad n)
math(EXPR last "${n} - 1")
foreach(i RANGE 0 ${last} 2)
  math(EXPR j "${i} + 1")
  list(GET au_cli_bad ${i} file)
  list(GET au_cli_bad ${j} pattern)
  au_cli_test(bad.${file} bad_input.sh ${file} ${pattern})
endforeach()
# Found by fuzz_read_ply: the reader looped over the 2^63-1 records of a property-less element (a
# hang); it now rejects such an element. Should it regress, the timeout fails the case quickly.
set_tests_properties(cli.bad.empty_element.ply PROPERTIES TIMEOUT 30)

# The same for the commands that need a boundary: command, file, regular expression.
set(au_cli_bad_cmd
  disk    closed.obj         "closed mesh given to the disk map"
  disk    ring.obj           "2 boundary loops.*the disk map needs 1"
  disk    torus_hole.obj     "genus 1 \\(expected genus 0\\)"
  disk    torus.obj          "closed mesh of genus 1 given to the disk map"
  disk    nonmanifold_edge.obj "non-manifold edge \\(0, 1\\)"
  disk    two_components.obj "2 connected components"
  disk    moebius.obj        "non-orientable surface.*edge \\(4, 13\\)"
  atlas   moebius.obj        "non-orientable surface.*edge \\(4, 13\\)"
  atlas   two_components.obj "2 connected components"
  atlas   nonmanifold_edge.obj "non-manifold edge \\(0, 1\\)"
  annulus closed.obj         "closed mesh given to the annulus map"
  annulus disk.off           "1 boundary loop.*the annulus map needs 2"
  annulus torus_hole.obj     "1 boundary loop.*the annulus map needs 2"
  square  closed.obj         "closed mesh given to the square map"
  square  ring.obj           "2 boundary loops.*the square map needs 1"
  circles closed.obj         "closed.*the circles map needs at least one"
  circles torus_hole.obj     "genus 1 and 1 boundary loop.*authalic atlas"
  circles two_components.obj "2 connected components")
list(LENGTH au_cli_bad_cmd n)
math(EXPR last "${n} - 1")
foreach(i RANGE 0 ${last} 3)
  math(EXPR j "${i} + 1")
  math(EXPR k "${i} + 2")
  list(GET au_cli_bad_cmd ${i} cmd)
  list(GET au_cli_bad_cmd ${j} file)
  list(GET au_cli_bad_cmd ${k} pattern)
  au_cli_test(bad.${cmd}.${file} bad_input.sh ${file} ${pattern} ${cmd})
endforeach()

foreach(c replace_existing not_converged options start)
  au_cli_test(${c} runs.sh ${c})
endforeach()

au_cli_test(unreferenced unreferenced.sh)
au_cli_test(reoriented reoriented.sh)
# The atlas of ../shared's bob and fertility and of the larger generated surfaces (genus 5, the thin
# handle) only in the plain build: the sanitizer build runs the smaller surfaces of genus 0 to 2, which
# take the same paths (cones, metric, cut, splits, flow, packing).
foreach(c data genus quarter cones usage html)
  au_cli_test(atlas.${c} atlas_runs.sh ${c})
endforeach()
if(NOT AU_SANITIZE)
  foreach(c genus_large shared)
    au_cli_test(atlas.${c} atlas_runs.sh ${c})
  endforeach()
endif()
foreach(mesh spiky_ico bumpy_star)
  au_cli_test(quality.${mesh} quality.sh map data/${mesh}.obj)
  au_cli_test(param_eval.${mesh} param_eval.sh data/${mesh}.obj)
endforeach()
au_cli_test(init_only.spiky_ico quality.sh init_only data/spiky_ico.obj)
# limbs4: both retries run and the twisted start's map is kept (docs/sphere.md).
au_cli_test(quality.limbs4 quality.sh map data/limbs4.obj)
# --refine-mesh (issue 21) where it meets the issue's bounds for a refined map: cheburashka, and cow
# (rounds spending half the budget left: 0.0079 / 0.0025).
au_cli_test(refine_mesh.cheburashka refine_mesh.sh cheburashka.off)
au_cli_test(refine_mesh.cow refine_mesh.sh cow.off)
au_cli_test(refine_mesh.nothing refine_nothing.sh)
# limbs4 meets them at three times the faces with the spherical split candidate (0.0124 /
# 0.0033; 0.0185 / 0.0088 without it).
au_cli_test(refine_mesh.limbs4_3x refine_mesh.sh data/limbs4.obj 3)
# limbs4 and coil meet them at twice the faces with the global polish of the refined map
# (0.0189 / 0.0038 and 0.0137 / 0.0031; 0.0258 / 0.0083 and 0.0219 / 0.0102 without it).
au_cli_test(refine_mesh.limbs4 refine_mesh.sh data/limbs4.obj)
au_cli_test(refine_mesh.coil refine_mesh.sh data/coil.obj)
# limbs8 meets them at three times the faces with the spherical candidate's splits where the
# chord triangles lack the most area for their size (0.0166 / 0.0019; 0.0199 / 0.0020 with the relative key), not at
# twice (0.0350 / 0.0027): --refine-budget auto tries 2x, then keeps 3x.
au_cli_test(refine_mesh.limbs8_auto refine_mesh.sh data/limbs8.obj auto 3)
# limbs4 meets them at 2x: auto stops there.
au_cli_test(refine_mesh.limbs4_auto refine_mesh.sh data/limbs4.obj auto 2)
# --refine-budget: a larger face budget than the default 2x on the generated coil (issue 21).
au_cli_test(refine_budget refine_budget.sh)
# Squeezed limbs (tpose): the staged retry, and the warning when they stay squeezed.
au_cli_test(squeezed squeezed.sh)
au_cli_test(thin_limbs.cow thin_limbs.sh cow.off)
au_cli_test(thin_limbs.cheburashka thin_limbs.sh cheburashka.off)
au_cli_test(thin_limbs.hand_closed thin_limbs.sh hand_closed.obj)
# The generated family's --spherical-areas maps meet the unrefined bounds on the spherical triangles.
foreach(m limbs4 limbs8 coil tpose)
  au_cli_test(thin_limbs.spherical.${m} thin_limbs_spherical.sh ${m})
endforeach()

# --density FILE (issue 6): per-face density 4 on half the ellipsoid, and bad density files.
foreach(c half count negative missing)
  au_cli_test(density_${c} density.sh ${c})
endforeach()

# Neuroimaging formats (issue 19): nibabel reads what we write and we read what it writes, the
# FreeSurfer footer kept, Connectome Workbench on our sphere, fsaverage5's bounds (tests/cli/neuro.sh).
foreach(c nibabel_reads nibabel_writes fs_roundtrip fsaverage5 workbench sample_sulc planar)
  au_cli_test(neuro.${c} neuro.sh ${c})
endforeach()
