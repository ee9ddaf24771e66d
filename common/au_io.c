/* au_io.c - (being written) */
