# tests for the DEC operators and the CHOLMOD wrapper
au_test_module(test_dec test_dec.c stiffness_props stiffness_dirichlet grad_linear areas_sum cotan_scale solver_linear_exact
                sphere_area)
