/* au_advect.c - (being written) */
