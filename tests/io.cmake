# Tests of mesh file reading and writing (common/au_io.c and the OpenMesh bridge).
au_test_module(test_io test_io.c
  roundtrip_obj roundtrip_off roundtrip_ply obj_uv write_halves write_precision order_kept ply_binary obj_forms off_forms
  nonfinite nonmanifold_kept stl
  err_missing err_directory err_extension err_empty err_truncated err_index err_face err_garbage
  write_missing_dir write_atomic write_mode write_text write_args shared_cow)
