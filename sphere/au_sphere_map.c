/* au_sphere_map.c - (being written) */
