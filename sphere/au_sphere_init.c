/* au_sphere_init.c - (being written) */
