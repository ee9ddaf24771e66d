/* mkdata.c - (being written) */
