/* au_dec.c - (being written) */
