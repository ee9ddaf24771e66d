/* authalic.c - (being written) */
