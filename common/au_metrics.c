/* au_metrics.c - (being written) */
