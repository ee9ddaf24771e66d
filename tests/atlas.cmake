# tests for atlas/ (surfaces of any genus): the flat cone metric that starts the atlas - cone placement
# and Gauss-Bonnet, the conformal solve's convergence and flatness on data/ meshes of genus 0 and 1 and on
# generated plates of genus 2 and 3, open surfaces, bad cones, nonsense options and inputs of each stage;
# equal-area flow with per-corner rigid motions (seams stay congruent).
au_test_module(test_atlas test_atlas.c
  metric_sphere metric_quarter metric_torus metric_genus metric_open metric_bad_cones
  layout_sphere layout_torus layout_genus layout_open
  flow_closed flow_open bad_inputs)
