# tests for common/au_treecotree (the tree-cotree decomposition shared by torus/ and atlas/): the trees span
# without cycles, 2 genus (+ loops - 1) generators, closed simple dual loops across the face tree, independent
# in homology and dual to the primal loops, on generated and data/ meshes of genus 0 to 3 with 0 to 3 boundary
# loops; bad arguments. Well under a second.
au_test_module(test_treecotree test_treecotree.c
  torus closed_genus open_surfaces bad_args)
