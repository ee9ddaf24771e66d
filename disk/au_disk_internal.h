/* au_disk_internal.h - cross-file internals of disk/: edge weights, Dirichlet solves, fold counts. */
#ifndef AU_DISK_INTERNAL_H
#define AU_DISK_INTERNAL_H

#include "au_disk.h"

/* Symmetrized mean-value weights w [0..ne-1] of the surface X: w_ij = (l_ij + l_ji)/2 with
 * l_ij = (tan(a/2) + tan(b/2)) / |x_i - x_j| over the angles at i of the faces of edge ij
 * (Floater 2003). Always positive on a mesh without zero-area faces. */
void au__disk_meanvalue_weights(const au_topo *t, const int *F, const double *X, double *w);

/* Number of faces whose planar orientation (z of the cross product) is <= 0. */
int au__disk_count_folds(int nf, const int *F, const double *P);

/* Solve sum_j w_ij (x_i - x_j) = 0 at the free vertices for the x and y columns of P (nv x 3),
 * whose rows at fixed vertices hold the Dirichlet values. Unreferenced vertices must be fixed.
 * Returns AU_OK, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_NUMERIC. */
au_status au__disk_dirichlet(const au_topo *t, const double *w, const unsigned char *fixed, double *P, au_msg *msg);

/* The harmonic interior for a boundary already placed in P (rows of fixed vertices): cotan weights,
 * then symmetrized mean-value weights if the cotan map folds. Sets *method.
 * Returns AU_OK, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_NUMERIC, AU_E_FOLD. */
au_status au__disk_harmonic(const au_mesh *m, const au_topo *t, const unsigned char *fixed, double *P,
                            au_disk_init_method *method, const char *what, au_msg *msg);

double au__disk_now(void);

#endif
