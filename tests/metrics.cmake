# tests for metrics (owned by the metrics module)
au_test_module(test_metrics test_metrics.c
  identity_plane uniform_scale anisotropic flipped sphere_identity chord_floor excluded percentiles
  scale_invariance bad_args agree_plane agree_sphere report_json report_write)
