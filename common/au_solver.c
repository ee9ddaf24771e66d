/* au_solver.c - CHOLMOD wrapper: analyze once, refactor numerically, solve with Dirichlet values. */
#include "au_solver.h"

#include <cholmod.h>
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

struct au_solver {
  int n, ne, nfree;
  int *E;             /* copy of the edges */
  int *idx;           /* idx [0..n-1]: row/column of a free vertex, -1 for fixed ones */
  int *diag_pos;      /* diag_pos [0..nfree-1]: position of the diagonal entry in A->x */
  int *edge_pos;      /* edge_pos [0..ne-1]: position of the off-diagonal entry, -1 if an end is fixed */
  cholmod_common c;   /* one common per solver object */
  cholmod_sparse *A;  /* upper triangle (stype 1), pattern fixed at creation */
  cholmod_factor *L;
  int factored;
  int started;        /* cholmod_start was called */
  double *w;          /* w [0..ne-1]: the weights of the last factorization, for Dirichlet right-hand sides */
};

/* Mesh Laplacians are planar-graph matrices: nested dissection (METIS) gives about half the fill and
 * flops of AMD on them (bunny: 1.1M vs 1.4M nonzeros, 118 vs 253 Mflop), and the analysis is paid once. */
static void configure(cholmod_common *c) {
  c->print = 0;
  c->nmethods = 1;
  c->method[0].ordering = CHOLMOD_METIS;
  c->postorder = 1;
  /* Always the supernodal LL' factorization: CHOLMOD's simplicial path computes LDL', which accepts
   * indefinite matrices without a word; LL' stops at the first non-positive pivot (L->minor). */
  c->supernodal = CHOLMOD_SUPERNODAL;
}

/* Numeric factorization with every outcome checked. cholmod_factorize returns TRUE on a matrix that
 * is not positive definite, so the status and L->minor are checked too. */
static au_status factorize(cholmod_sparse *A, cholmod_factor *L, cholmod_common *c, au_msg *msg) {
  int ok = cholmod_factorize(A, L, c);
  if (c->status == CHOLMOD_OUT_OF_MEMORY) return au_msg_set(msg, AU_E_NOMEM, "solver: out of memory in factorization");
  if (c->status == CHOLMOD_NOT_POSDEF || L->minor < L->n)
    return au_msg_set(msg, AU_E_NOT_SPD, "solver: matrix not positive definite (failed at column %d of %d)", (int)L->minor,
                      (int)L->n);
  if (!ok || c->status < CHOLMOD_OK) return au_msg_set(msg, AU_E_NUMERIC, "solver: factorization failed (status %d)", c->status);
  return AU_OK;
}

/* METIS (through GKlib) catches SIGTERM while it runs and turns it into an error return: a run told
 * to stop then failed with "ordering failed" instead of dying of the signal (measured: 1 in 12 runs
 * of the cli.interrupted test). And on its way out it puts the previous handler back with signal(),
 * i.e. one-shot (SA_RESETHAND). So SIGTERM is held back for the length of an ordering, the handler is
 * put back exactly as it was, and a signal that came meanwhile reaches it afterwards. */
typedef struct held_term {
  sigset_t mask;
  struct sigaction action;
} held_term;

static void hold_term(held_term *h) {
  sigset_t s;
  sigemptyset(&s);
  sigaddset(&s, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &s, &h->mask);
  sigaction(SIGTERM, NULL, &h->action);
}

static void release_term(const held_term *h) {
  sigaction(SIGTERM, &h->action, NULL);
  pthread_sigmask(SIG_SETMASK, &h->mask, NULL);
}

static int cmp_int(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

au_status au_solver_create(int n, int ne, const int *E, const unsigned char *fixed, au_order order, au_solver **out,
                           au_msg *msg) {
  if (!out || n <= 0 || ne < 0 || (ne > 0 && !E)) return au_msg_set(msg, AU_E_ARG, "solver: bad arguments");
  *out = NULL;
  au_solver *s = calloc(1, sizeof *s);
  if (!s) return au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
  s->n = n;
  s->ne = ne;
  s->E = malloc(sizeof(int) * 2 * (size_t)(ne > 0 ? ne : 1));
  s->idx = malloc(sizeof(int) * (size_t)n);
  s->edge_pos = malloc(sizeof(int) * (size_t)(ne > 0 ? ne : 1));
  s->w = calloc((size_t)(ne > 0 ? ne : 1), sizeof(double));
  int *count = calloc((size_t)n + 1, sizeof(int));
  if (!s->E || !s->idx || !s->edge_pos || !s->w || !count) {
    free(count);
    au_solver_free(&s);
    return au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
  }
  if (ne > 0) memcpy(s->E, E, sizeof(int) * 2 * (size_t)ne);
  for (int i = 0; i < n; i++) s->idx[i] = (fixed && fixed[i]) ? -1 : s->nfree++;
  if (s->nfree == 0) {
    free(count);
    au_solver_free(&s);
    return au_msg_set(msg, AU_E_ARG, "solver: every vertex is fixed");
  }
  /* Column j of the upper triangle holds rows i <= j: the diagonal and each free edge's smaller index. */
  for (int e = 0; e < ne; e++) {
    int a = s->idx[E[2 * e]], b = s->idx[E[2 * e + 1]];
    if (E[2 * e] == E[2 * e + 1] || E[2 * e] < 0 || E[2 * e] >= n || E[2 * e + 1] < 0 || E[2 * e + 1] >= n) {
      free(count);
      au_solver_free(&s);
      return au_msg_set(msg, AU_E_ARG, "solver: edge %d is invalid", e);
    }
    if (a >= 0 && b >= 0) count[a > b ? a : b]++;
  }
  int nf = s->nfree;
  size_t nnz = (size_t)nf;
  for (int j = 0; j < nf; j++) nnz += (size_t)count[j];
  cholmod_start(&s->c);
  s->started = 1;
  s->c.print = 0;
  configure(&s->c);
  if (order == AU_ORDER_FAST) s->c.method[0].ordering = CHOLMOD_AMD;
  s->A = cholmod_allocate_sparse((size_t)nf, (size_t)nf, nnz, 1, 1, 1, CHOLMOD_REAL, &s->c);
  s->diag_pos = malloc(sizeof(int) * (size_t)nf);
  if (!s->A || !s->diag_pos) {
    free(count);
    au_solver_free(&s);
    return au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
  }
  int *Ap = s->A->p, *Ai = s->A->i;
  Ap[0] = 0;
  for (int j = 0; j < nf; j++) Ap[j + 1] = Ap[j] + count[j] + 1;
  /* Fill rows: off-diagonals first (then sorted), diagonal last in each column. */
  int *fillp = count; /* reuse as per-column cursor */
  for (int j = 0; j < nf; j++) fillp[j] = Ap[j];
  for (int e = 0; e < ne; e++) {
    int a = s->idx[E[2 * e]], b = s->idx[E[2 * e + 1]];
    if (a >= 0 && b >= 0) {
      int lo = a < b ? a : b, hi = a < b ? b : a;
      Ai[fillp[hi]++] = lo;
    }
  }
  for (int j = 0; j < nf; j++) {
    Ai[fillp[j]] = j;
    qsort(Ai + Ap[j], (size_t)(Ap[j + 1] - Ap[j]), sizeof(int), cmp_int);
    s->diag_pos[j] = Ap[j + 1] - 1; /* the diagonal is the largest row index of an upper column */
  }
  free(count);
  /* Map each edge to its entry by binary search in its column (columns are short). */
  for (int e = 0; e < ne; e++) {
    int a = s->idx[E[2 * e]], b = s->idx[E[2 * e + 1]];
    s->edge_pos[e] = -1;
    if (a < 0 || b < 0) continue;
    int lo = a < b ? a : b, hi = a < b ? b : a;
    int *base = Ai + Ap[hi];
    int *hit = bsearch(&lo, base, (size_t)(Ap[hi + 1] - Ap[hi]), sizeof(int), cmp_int);
    s->edge_pos[e] = (int)(hit - Ai);
  }
  /* Duplicate edges would share an entry; that is fine, weights accumulate. */
  /* Only METIS traps SIGTERM: AMD orders without holding it (a plan may be ordering with METIS in
   * another thread meanwhile, and the handler saved here would be GKlib's). */
  held_term held;
  if (order != AU_ORDER_FAST) hold_term(&held);
  s->L = cholmod_analyze(s->A, &s->c);
  if (order != AU_ORDER_FAST) release_term(&held);
  if (!s->L || s->c.status < CHOLMOD_OK) {
    int st = s->c.status;
    au_solver_free(&s);
    return au_msg_set(msg, st == CHOLMOD_OUT_OF_MEMORY ? AU_E_NOMEM : AU_E_NUMERIC,
                      "solver: symbolic analysis failed (CHOLMOD status %d)", st);
  }
  *out = s;
  return AU_OK;
}

au_status au_solver_factor(au_solver *s, const double *w, const double *d, au_msg *msg) {
  if (!s || (s->ne > 0 && !w)) return au_msg_set(msg, AU_E_ARG, "solver: bad arguments");
  double *Ax = s->A->x;
  memset(Ax, 0, sizeof(double) * (size_t)((int *)s->A->p)[s->nfree]);
  for (int e = 0; e < s->ne; e++) {
    int a = s->idx[s->E[2 * e]], b = s->idx[s->E[2 * e + 1]];
    if (a >= 0) Ax[s->diag_pos[a]] += w[e];
    if (b >= 0) Ax[s->diag_pos[b]] += w[e];
    if (s->edge_pos[e] >= 0) Ax[s->edge_pos[e]] -= w[e];
  }
  memcpy(s->w, w, sizeof(double) * (size_t)s->ne);
  if (d)
    for (int i = 0; i < s->n; i++)
      if (s->idx[i] >= 0) Ax[s->diag_pos[s->idx[i]]] += d[i];
  s->factored = 0;
  au_status st = factorize(s->A, s->L, &s->c, msg);
  s->factored = st == AU_OK;
  return st;
}

au_status au_solver_solve(au_solver *s, int nrhs, const double *b, double *x, au_msg *msg) {
  if (!s || nrhs <= 0 || !b || !x) return au_msg_set(msg, AU_E_ARG, "solver: bad arguments");
  if (!s->factored) return au_msg_set(msg, AU_E_ARG, "solver: solve before a successful factorization");
  int n = s->n, nf = s->nfree;
  cholmod_dense *B = cholmod_allocate_dense((size_t)nf, (size_t)nrhs, (size_t)nf, CHOLMOD_REAL, &s->c);
  if (!B) return au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
  double *Bx = B->x;
  for (int c = 0; c < nrhs; c++) {
    const double *bc = b + (size_t)c * n;
    const double *xc = x + (size_t)c * n;
    double *Bc = Bx + (size_t)c * nf;
    for (int i = 0; i < n; i++)
      if (s->idx[i] >= 0) Bc[s->idx[i]] = bc[i];
    /* Dirichlet values move to the right-hand side: row a of A x = b gains + w_e x_j for a fixed j. */
    for (int e = 0; e < s->ne; e++) {
      int i = s->E[2 * e], j = s->E[2 * e + 1];
      int a = s->idx[i], bb = s->idx[j];
      if (a >= 0 && bb < 0) Bc[a] += s->w[e] * xc[j];
      if (bb >= 0 && a < 0) Bc[bb] += s->w[e] * xc[i];
    }
  }
  cholmod_dense *X = cholmod_solve(CHOLMOD_A, s->L, B, &s->c);
  cholmod_free_dense(&B, &s->c);
  if (!X) return au_msg_set(msg, AU_E_NUMERIC, "solver: solve failed (CHOLMOD status %d)", s->c.status);
  const double *Xx = X->x;
  int bad = 0;
  for (int c = 0; c < nrhs; c++) {
    double *xc = x + (size_t)c * n;
    const double *Xc = Xx + (size_t)c * nf;
    for (int i = 0; i < n; i++)
      if (s->idx[i] >= 0) {
        xc[i] = Xc[s->idx[i]];
        if (!(xc[i] - xc[i] == 0)) bad = 1;
      }
  }
  cholmod_free_dense(&X, &s->c);
  if (bad) return au_msg_set(msg, AU_E_NUMERIC, "solver: the solution is not finite");
  return AU_OK;
}

void au_solver_free(au_solver **sp) {
  if (!sp || !*sp) return;
  au_solver *s = *sp;
  if (s->started) {
    cholmod_free_factor(&s->L, &s->c);
    cholmod_free_sparse(&s->A, &s->c);
    cholmod_finish(&s->c);
  }
  free(s->E);
  free(s->w);
  free(s->idx);
  free(s->diag_pos);
  free(s->edge_pos);
  free(s);
  *sp = NULL;
}

/* The matrix is filled by the caller in its own order (upper triangle of A, au_spd_values) and copied,
 * through map, into B = tril(P A P'), P the elimination order found once: the lower triangle in
 * factor order is the one form cholmod_factorize takes as it is. Given A itself it would transpose and
 * permute a copy at every factorization (measured on lion_statue: cholmod_transpose_sym 6.7% of a
 * whole run, and the allocations of the copy). */
struct au_spd {
  int n;
  cholmod_common c;
  cholmod_sparse *A; /* the caller's upper triangle, natural order */
  cholmod_sparse *B; /* tril(P A P') */
  int *map;          /* [0..nnz-1]: entry p of A is entry map[p] of B */
  int *perm;         /* [0..n-1]: P, the unknown eliminated k-th */
  cholmod_factor *L; /* of B, natural order */
  int factored;
};

au_status au_graph_order(int n, int ne, const int *E, int *perm, au_msg *msg) {
  if (n <= 0 || ne < 0 || (ne > 0 && !E) || !perm) return au_msg_set(msg, AU_E_ARG, "solver: bad arguments");
  for (int e = 0; e < ne; e++)
    if (E[2 * e] < 0 || E[2 * e] >= n || E[2 * e + 1] < 0 || E[2 * e + 1] >= n || E[2 * e] == E[2 * e + 1])
      return au_msg_set(msg, AU_E_ARG, "solver: edge %d is invalid", e);
  cholmod_common c;
  cholmod_start(&c);
  configure(&c);
  au_status st = AU_OK;
  /* The upper triangle, column by column (rows unsorted: METIS does not mind). */
  cholmod_sparse *A = cholmod_allocate_sparse((size_t)n, (size_t)n, (size_t)ne + (size_t)n, 0, 1, 1, CHOLMOD_PATTERN, &c);
  if (!A) {
    st = au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
    goto done;
  }
  int *Ap = A->p, *Ai = A->i;
  memset(Ap, 0, sizeof(int) * ((size_t)n + 1));
  for (int e = 0; e < ne; e++) Ap[(E[2 * e] > E[2 * e + 1] ? E[2 * e] : E[2 * e + 1]) + 1]++;
  for (int j = 0; j < n; j++) Ap[j + 1] += Ap[j] + 1;
  for (int j = 0; j < n; j++) Ai[Ap[j + 1] - 1] = j; /* the diagonal, last */
  int *fill = malloc(sizeof(int) * (size_t)n);
  if (!fill) {
    st = au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
    goto done;
  }
  memcpy(fill, Ap, sizeof(int) * (size_t)n);
  for (int e = 0; e < ne; e++) {
    int a = E[2 * e], b = E[2 * e + 1];
    int lo = a < b ? a : b, hi = a < b ? b : a;
    Ai[fill[hi]++] = lo;
  }
  free(fill);
  held_term held;
  hold_term(&held);
  int ok = cholmod_metis(A, NULL, 0, 1, perm, &c);
  release_term(&held);
  if (!ok || c.status < CHOLMOD_OK)
    st = au_msg_set(msg, c.status == CHOLMOD_OUT_OF_MEMORY ? AU_E_NOMEM : AU_E_NUMERIC, "solver: ordering failed (CHOLMOD status %d)",
                    c.status);
done:
  cholmod_free_sparse(&A, &c);
  cholmod_finish(&c);
  return st;
}

au_status au_spd_create(int n, const int *colstart, const int *rows, const int *perm, au_spd **out, au_msg *msg) {
  if (!out || n <= 0 || !colstart || !rows) return au_msg_set(msg, AU_E_ARG, "solver: bad arguments");
  *out = NULL;
  au_spd *s = calloc(1, sizeof *s);
  if (!s) return au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
  s->n = n;
  cholmod_start(&s->c);
  configure(&s->c);
  size_t nnz = (size_t)colstart[n];
  s->A = cholmod_allocate_sparse((size_t)n, (size_t)n, nnz, 1, 1, 1, CHOLMOD_REAL, &s->c);
  s->B = cholmod_allocate_sparse((size_t)n, (size_t)n, nnz, 1, 1, -1, CHOLMOD_REAL, &s->c);
  s->map = malloc(sizeof(int) * (nnz > 0 ? nnz : 1));
  s->perm = malloc(sizeof(int) * (size_t)n);
  int *inv = malloc(sizeof(int) * (size_t)n), *fill = calloc((size_t)n + 1, sizeof(int));
  cholmod_factor *L0 = NULL;
  au_status st = AU_OK;
  if (!s->A || !s->B || !s->map || !s->perm || !inv || !fill) {
    st = au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
    goto done;
  }
  memcpy(s->A->p, colstart, sizeof(int) * ((size_t)n + 1));
  memcpy(s->A->i, rows, sizeof(int) * nnz);
  memset(s->A->x, 0, sizeof(double) * nnz);
  /* 1. The elimination order: the given one or METIS, then CHOLMOD's postorder of its tree. */
  held_term held;
  hold_term(&held);
  if (perm) {
    s->c.method[0].ordering = CHOLMOD_GIVEN;
    L0 = cholmod_analyze_p(s->A, (int *)perm, NULL, 0, &s->c);
  } else {
    L0 = cholmod_analyze(s->A, &s->c);
  }
  release_term(&held);
  if (!L0 || s->c.status < CHOLMOD_OK) {
    st = au_msg_set(msg, s->c.status == CHOLMOD_OUT_OF_MEMORY ? AU_E_NOMEM : AU_E_NUMERIC, "solver: analysis failed (status %d)",
                    s->c.status);
    goto done;
  }
  memcpy(s->perm, L0->Perm, sizeof(int) * (size_t)n);
  for (int k = 0; k < n; k++) inv[s->perm[k]] = k;
  /* 2. B's pattern: entry (i, j) of A goes to column min(inv i, inv j), row max; rows sorted. */
  const int *Ap = s->A->p, *Ai = s->A->i;
  int *Bp = s->B->p, *Bi = s->B->i;
  for (int j = 0; j < n; j++)
    for (int p = Ap[j]; p < Ap[j + 1]; p++) {
      int a = inv[Ai[p]], b = inv[j];
      fill[(a < b ? a : b) + 1]++;
    }
  for (int k = 0; k < n; k++) fill[k + 1] += fill[k];
  memcpy(Bp, fill, sizeof(int) * ((size_t)n + 1));
  for (int j = 0; j < n; j++)
    for (int p = Ap[j]; p < Ap[j + 1]; p++) {
      int a = inv[Ai[p]], b = inv[j];
      int c = a < b ? a : b, q = fill[c]++;
      Bi[q] = a < b ? b : a, s->map[p] = q;
    }
  /* Sort each column's rows (insertion sort: columns are short), carrying along at[q], the entry of A
   * at position q of B. */
  int *at = malloc(sizeof(int) * (nnz > 0 ? nnz : 1));
  if (!at) {
    st = au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
    goto done;
  }
  for (size_t p = 0; p < nnz; p++) at[s->map[p]] = (int)p;
  for (int c = 0; c < n; c++)
    for (int q = Bp[c] + 1; q < Bp[c + 1]; q++)
      for (int r = q; r > Bp[c] && Bi[r - 1] > Bi[r]; r--) {
        int ti = Bi[r], ta = at[r];
        Bi[r] = Bi[r - 1], at[r] = at[r - 1];
        Bi[r - 1] = ti, at[r - 1] = ta;
      }
  for (int q = 0; q < Bp[n]; q++) s->map[at[q]] = q;
  free(at);
  memset(s->B->x, 0, sizeof(double) * nnz);
  /* 3. The symbolic factor of B as it stands (natural order, no postorder: it is postordered). */
  s->c.nmethods = 1;
  s->c.method[0].ordering = CHOLMOD_NATURAL;
  s->c.postorder = 0;
  s->L = cholmod_analyze(s->B, &s->c);
  if (!s->L || s->c.status < CHOLMOD_OK) {
    st = au_msg_set(msg, s->c.status == CHOLMOD_OUT_OF_MEMORY ? AU_E_NOMEM : AU_E_NUMERIC, "solver: analysis failed (status %d)",
                    s->c.status);
    goto done;
  }
done:
  cholmod_free_factor(&L0, &s->c);
  free(fill);
  free(inv);
  if (st != AU_OK) {
    au_spd_free(&s);
    return st;
  }
  *out = s;
  return AU_OK;
}

double *au_spd_values(au_spd *s) { return s ? (double *)s->A->x : NULL; }

au_status au_spd_factor(au_spd *s, au_msg *msg) {
  if (!s) return au_msg_set(msg, AU_E_ARG, "solver: bad arguments");
  s->factored = 0;
  const double *ax = s->A->x;
  double *bx = s->B->x;
  const int nnz = ((const int *)s->A->p)[s->n];
  for (int p = 0; p < nnz; p++) bx[s->map[p]] = ax[p];
  au_status st = factorize(s->B, s->L, &s->c, msg);
  s->factored = st == AU_OK;
  return st;
}

au_status au_spd_solve(au_spd *s, const double *b, double *x, au_msg *msg) {
  if (!s || !b || !x || !s->factored) return au_msg_set(msg, AU_E_ARG, "solver: bad arguments");
  cholmod_dense *B = cholmod_allocate_dense((size_t)s->n, 1, (size_t)s->n, CHOLMOD_REAL, &s->c);
  if (!B) return au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
  double *bp = B->x;
  for (int k = 0; k < s->n; k++) bp[k] = b[s->perm[k]];
  cholmod_dense *X = cholmod_solve(CHOLMOD_A, s->L, B, &s->c);
  cholmod_free_dense(&B, &s->c);
  if (!X) return au_msg_set(msg, AU_E_NUMERIC, "solver: solve failed (status %d)", s->c.status);
  const double *xp = X->x;
  for (int k = 0; k < s->n; k++) x[s->perm[k]] = xp[k];
  cholmod_free_dense(&X, &s->c);
  for (int i = 0; i < s->n; i++)
    if (!(x[i] - x[i] == 0)) return au_msg_set(msg, AU_E_NUMERIC, "solver: the solution is not finite");
  return AU_OK;
}

void au_spd_free(au_spd **sp) {
  if (!sp || !*sp) return;
  au_spd *s = *sp;
  cholmod_free_factor(&s->L, &s->c);
  cholmod_free_sparse(&s->A, &s->c);
  cholmod_free_sparse(&s->B, &s->c);
  cholmod_finish(&s->c);
  free(s->map), free(s->perm);
  free(s);
  *sp = NULL;
}
