# Tests of the neuroimaging formats (issue 19): FreeSurfer and GIfTI readers and writers
# (common/au_io_freesurfer.c, common/au_io_gifti.c), per-vertex values, the per-vertex distortion.
# The end-to-end checks with nibabel and Connectome Workbench are cli.neuro.* (tests/cli/neuro.sh).
au_test_module(test_neuro test_neuro.c
  fs_read fs_roundtrip fs_bad curv text_scalars gifti_roundtrip gifti_meta gifti_bad fsaverage5 distortion)
