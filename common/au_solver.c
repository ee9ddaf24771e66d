/* au_solver.c - (being written) */
