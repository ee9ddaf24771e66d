/* au_solver.h - sparse SPD solves of weighted graph Laplacians with CHOLMOD (the only file that
 * includes cholmod.h is au_solver.c).
 *
 * The matrix is A = sum_e w_e (d_i - d_j)(d_i - d_j)^T + diag(d) over the edges e = (i, j) of a
 * fixed graph, restricted to the free (non-fixed) vertices: fixed vertices act as Dirichlet values.
 * The sparsity pattern is analyzed once (fill-reducing ordering, supernodal symbolic factor) at
 * creation; each au_solver_factor only refactors numerically. */
#ifndef AU_SOLVER_H
#define AU_SOLVER_H

#include "au_status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct au_solver au_solver;

/* How the unknowns are ordered for elimination: AU_ORDER_FILL (METIS nested dissection: least fill,
 * for a matrix refactored many times) or AU_ORDER_FAST (AMD: found in a fraction of the time, for one
 * or two factorizations: the conformal starts, where finding the order costs more than the fill saves). */
typedef enum au_order { AU_ORDER_FILL = 0, AU_ORDER_FAST = 1 } au_order;

/* Create a solver for n vertices and ne edges E [0..2*ne-1] (0 <= E < n, no self loops), ordered by order.
 * fixed [0..n-1]: 1 marks a Dirichlet vertex; may be NULL (all free: then A must be made definite
 * by diag). At least one vertex must be free. On success *out owns the solver (au_solver_free).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC (CHOLMOD's analysis failed). */
au_status au_solver_create(int n, int ne, const int *E, const unsigned char *fixed, au_order order, au_solver **out,
                           au_msg *msg);

/* Numeric factorization with edge weights w [0..ne-1] and diagonal d [0..n-1] (may be NULL: zero).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NOT_SPD (msg names the column where it failed). */
au_status au_solver_factor(au_solver *s, const double *w, const double *d, au_msg *msg);

/* Solve A x = b for nrhs right-hand sides. b, x: n x nrhs, column-major (column c at b + c*n).
 * On entry x holds the Dirichlet values at fixed vertices (other entries are ignored); on exit the
 * free entries hold the solution, fixed entries are unchanged. b at fixed vertices is ignored.
 * Requires a successful au_solver_factor. Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_solver_solve(au_solver *s, int nrhs, const double *b, double *x, au_msg *msg);

/* A nested-dissection (METIS) elimination order perm [0..n-1] of the graph with n vertices and ne edges
 * E [0..2*ne-1]. A system with k unknowns per vertex (k x k blocks on the graph's pattern) is ordered
 * as well by expanding it, block by block, as by ordering its own larger graph, and at a fraction of
 * the cost (the graph has k^2 times fewer edges).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_graph_order(int n, int ne, const int *E, int *perm, au_msg *msg);

/* Free the solver and set *s to NULL; NULL-safe. */
void au_solver_free(au_solver **s);


/* A general sparse SPD matrix with a fixed pattern (used where the matrix is not a graph Laplacian,
 * e.g. the Gauss-Newton system of the vertex areas). The upper triangle is given column by column:
 * rows [colstart[j]..colstart[j+1]-1] are the sorted row indices <= j of column j, diagonal included. */
typedef struct au_spd au_spd;

/* Create and analyze. colstart [0..n], rows [0..colstart[n]-1] are copied. perm [0..n-1]: the
 * fill-reducing elimination order to use (perm[k] is eliminated k-th), or NULL for METIS on the pattern.
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. On success free with au_spd_free. */
au_status au_spd_create(int n, const int *colstart, const int *rows, const int *perm, au_spd **out, au_msg *msg);
/* The value array to fill, aligned with rows [0..colstart[n]-1]; owned by s. */
double *au_spd_values(au_spd *s);
/* Numeric factorization of the current values. Returns AU_OK, AU_E_NOMEM, AU_E_NOT_SPD, AU_E_NUMERIC. */
au_status au_spd_factor(au_spd *s, au_msg *msg);
/* Solve for one right-hand side b [0..n-1] into x [0..n-1]. Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_NUMERIC. */
au_status au_spd_solve(au_spd *s, const double *b, double *x, au_msg *msg);
/* Free and set *s to NULL; NULL-safe. */
void au_spd_free(au_spd **s);
/* Systems of at least au__spd_split_min unknowns are factored in two halves on two threads when their
 * elimination tree allows it (au_solver.c, spd_split); au__spd_split_size gives the size of the
 * separator that joins the halves (0: factored whole). For tests and measurements. */
extern int au__spd_split_min;
/* Numeric factorizations (au_solver_factor, au_spd_factor; a split one counts once) made so far in this
 * process, by every thread: a map's count is the difference across it (au_result.factorizations). */
long au__solver_factorizations(void);
/* The qsort/bsearch comparator of ints that the sparse-pattern builders share. */
int au__cmp_int(const void *a, const void *b);
int au__spd_split_size(const au_spd *s);

#ifdef __cplusplus
}
#endif
#endif
