/* au_mesh.c - (being written) */
