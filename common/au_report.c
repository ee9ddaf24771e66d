/* au_report.c - (being written) */
