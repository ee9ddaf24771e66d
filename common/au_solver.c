/* au_solver.c - CHOLMOD wrapper: analyze once, refactor numerically, solve with Dirichlet values. */
#include "au_solver.h"

#include <cholmod.h>
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "au_par.h"

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

/* Mesh Laplacians are planar-graph matrices: nested dissection (METIS) gives less fill and about half
 * the flops of AMD on them (docs/flow.md), and the analysis is paid once. */
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

/* A factor at least this large gets its values in memory aligned to, and advised for, huge pages. */
#define AU_HUGE_BYTES ((size_t)4 << 20)
#define AU_HUGE_ALIGN ((size_t)2 << 20)

/* The numeric factor's memory, set up before the first factorization: CHOLMOD would allocate it there
 * and fault it in one 4 KiB page at a time while it zeroes each supernode, and on a virtual machine a
 * page fault costs microseconds (bunny's flow: 12,500 faults in its first factorization, which took 3
 * to 4 times the later ones; docs/flow-speed.md). So the values are allocated here, on huge pages where
 * the system grants them (Linux's transparent huge pages, advised), and with touch, zeroed here: the
 * flow's plan builds its solver on the second core while the start runs, and the faults go with it (a
 * one-shot solver, factored right after, is not touched twice). The block replaces CHOLMOD's own and is
 * released by CHOLMOD with SuiteSparse's free (the C library's, which also takes aligned blocks).
 * Returns 0 out of memory (L then stays symbolic, and the factorization allocates). */
static int factor_memory(cholmod_factor *L, cholmod_common *c, int touch) {
  if (!L->is_super) return 1;
  if (L->xtype == CHOLMOD_PATTERN && !cholmod_change_factor(CHOLMOD_REAL, 1, 1, 1, 1, L, c)) return 0;
  const size_t bytes = L->xsize * sizeof(double);
  void *p = NULL;
  if (bytes >= AU_HUGE_BYTES && SuiteSparse_config.free_func == free && posix_memalign(&p, AU_HUGE_ALIGN, bytes) == 0) {
#ifdef MADV_HUGEPAGE
    madvise(p, bytes, MADV_HUGEPAGE);
#endif
    free(L->x);
    L->x = p;
  }
  if (touch) memset(L->x, 0, bytes);
  return 1;
}

/* METIS (through GKlib) catches SIGTERM while it runs and turns it into an error return: a run told
 * to stop then failed with "ordering failed" instead of dying of the signal (docs/flow.md
 * has how often). And on its way out it puts the previous handler back with signal(),
 * i.e. one-shot (SA_RESETHAND). So SIGTERM is held back for the length of an ordering, the handler is
 * put back exactly as it was, and a signal that came meanwhile reaches it afterwards. */
typedef struct held_term {
  sigset_t mask;
  struct sigaction action;
} held_term;

/* The handler saved and put back is the process's: two orderings at once in two threads would each
 * save what the other had set, and could leave GKlib's handler behind. So orderings that trap SIGTERM
 * take turns (the only lock of the library; it holds no data). */
static pthread_mutex_t term_lock = PTHREAD_MUTEX_INITIALIZER;

static void hold_term(held_term *h) {
  pthread_mutex_lock(&term_lock);
  sigset_t s;
  sigemptyset(&s);
  sigaddset(&s, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &s, &h->mask);
  sigaction(SIGTERM, NULL, &h->action);
}

static void release_term(const held_term *h) {
  sigaction(SIGTERM, &h->action, NULL);
  pthread_sigmask(SIG_SETMASK, &h->mask, NULL);
  pthread_mutex_unlock(&term_lock);
}

int au__cmp_int(const void *a, const void *b) {
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
    qsort(Ai + Ap[j], (size_t)(Ap[j + 1] - Ap[j]), sizeof(int), au__cmp_int);
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
    int *hit = bsearch(&lo, base, (size_t)(Ap[hi + 1] - Ap[hi]), sizeof(int), au__cmp_int);
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
  factor_memory(s->L, &s->c, 0);
  *out = s;
  return AU_OK;
}

/* Numeric factorizations made by au_solver_factor and au_spd_factor in this process, for the reports
 * (au_result.factorizations): a measurement, the one mutable global, updated atomically. */
static long factor_count;

long au__solver_factorizations(void) { return __atomic_load_n(&factor_count, __ATOMIC_RELAXED); }

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
  __atomic_add_fetch(&factor_count, 1, __ATOMIC_RELAXED);
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
 * permute a copy at every factorization (a measurable share of a whole run, and the allocations of
 * the copy). */
/* A factorization split in two halves that run on two cores (au_spd_factor): B's columns are S (the
 * top separator of the elimination tree, eliminated last) and two sets of whole subtrees below it,
 * H0 and H1, which share no entry of B or of its factor. M_h = B restricted to H_h then S, factored as
 * it stands: its first block is the factor of B on H_h, and the block L22 of its last |S| columns
 * satisfies L22 L22' = C - B_h' A_h^-1 B_h (C: B's S block), so that B's Schur complement on S is
 * L22(0) L22(0)' + L22(1) L22(1)' - C, a dense matrix factored with LAPACK. */
typedef struct spd_half {
  int nm;               /* columns of M: |H| + |S| */
  int *cols;            /* [0..nm-1]: the column of B that is column k of M */
  int *vmap;            /* [0..nnz(M)-1]: the entry of B->x that is entry q of M->x */
  cholmod_common c;
  cholmod_sparse *M;    /* lower triangle, natural order */
  cholmod_factor *L;
  double *G;            /* ns x ns column-major: L22 (lower) */
  double *GG;           /* ns x ns column-major: L22 L22', as the upper triangle of its index-reversed copy */
  int ns;               /* |S| (the last ns columns of M) */
  const double *bx;     /* B's values, where M's come from */
  au_status st;         /* the factorization's outcome (factored in a thread) */
  au_msg msg;
} spd_half;

typedef struct spd_split {
  int ns;               /* |S| */
  int *scol;            /* [0..ns-1]: the columns of B in S, in order */
  int nc;               /* entries of C (B's S block, lower) */
  int *cpos, *cdst;     /* [0..nc-1]: entry of B->x and position in the dense ns x ns matrix */
  double *Sch;          /* ns x ns column-major: the Schur complement, then its Cholesky factor */
  double *y;            /* ns scratch */
  spd_half h[2];
} spd_split;

struct au_spd {
  int n;
  cholmod_common c;
  cholmod_sparse *A; /* the caller's upper triangle, natural order */
  cholmod_sparse *B; /* tril(P A P') */
  int *map;          /* [0..nnz-1]: entry p of A is entry map[p] of B */
  int *perm;         /* [0..n-1]: P, the unknown eliminated k-th */
  cholmod_factor *L; /* of B, natural order (the symbolic one only, when split) */
  spd_split *split;  /* NULL: one factorization on one core */
  int factored;
};

/* Below this many unknowns a system is factored whole: smaller, the second thread's start and the dense
 * separator block cost more than the halves save (docs/flow.md). The test sets it. */
int au__spd_split_min = 8000;

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

/* BLAS and LAPACK (the dense Schur block of a split factorization). */
extern void dpotrf_(const char *uplo, const int *n, double *a, const int *lda, int *info);
extern void dpotrs_(const char *uplo, const int *n, const int *nrhs, const double *a, const int *lda, double *b,
                    const int *ldb, int *info);
extern void dlauum_(const char *uplo, const int *n, double *a, const int *lda, int *info);
extern void dtrmv_(const char *uplo, const char *trans, const char *diag, const int *n, const double *a, const int *lda,
                   double *x, const int *incx);

static void split_free(spd_split **sp) {
  if (!sp || !*sp) return;
  spd_split *q = *sp;
  for (int h = 0; h < 2; h++) {
    spd_half *a = q->h + h;
    if (a->M || a->L) {
      cholmod_free_factor(&a->L, &a->c);
      cholmod_free_sparse(&a->M, &a->c);
      cholmod_finish(&a->c);
    }
    free(a->cols), free(a->vmap), free(a->G), free(a->GG);
  }
  free(q->scol), free(q->cpos), free(q->cdst), free(q->Sch), free(q->y);
  free(q);
  *sp = NULL;
}

/* Sort units [0..nu-1] by decreasing work w (a bottom-up merge sort with a scratch half: qsort has
 * no context argument in C11, and the plan runs in a thread). */
static void sort_units(int *units, int nu, const double *w) {
  int *tmp = malloc(sizeof(int) * (size_t)(nu > 0 ? nu : 1));
  if (!tmp) { /* insertion sort then: correct, only slower */
    for (int a = 1; a < nu; a++)
      for (int b = a; b > 0 && w[units[b - 1]] < w[units[b]]; b--) {
        int t = units[b];
        units[b] = units[b - 1], units[b - 1] = t;
      }
    return;
  }
  for (int width = 1; width < nu; width *= 2) {
    for (int lo = 0; lo < nu; lo += 2 * width) {
      int mid = lo + width < nu ? lo + width : nu, hi = lo + 2 * width < nu ? lo + 2 * width : nu;
      int i = lo, j = mid, k = lo;
      while (i < mid && j < hi) tmp[k++] = w[units[i]] >= w[units[j]] ? units[i++] : units[j++];
      while (i < mid) tmp[k++] = units[i++];
      while (j < hi) tmp[k++] = units[j++];
    }
    memcpy(units, tmp, sizeof(int) * (size_t)nu);
  }
  free(tmp);
}

/* The split pays only with a separator small enough for a dense block (its Schur complement is ns^2
 * doubles and an ns^3 dense factorization) and halves of comparable work (the slower half sets the time). */
#define AU_SPLIT_MAX_SEPARATOR 4000
#define AU_SPLIT_MIN_SHARE 0.3

/* The two halves of B's unknowns from L's supernodal elimination tree: bin [0..n-1] gets 0 or 1 for the
 * halves, -1 for the separator S (*ns unknowns). Returns 1 when B splits well, 0 when it does not (no
 * separator at the root, unbalanced halves, a separator too large for a dense block), -1 when out of
 * memory. */
static int split_bins(const cholmod_factor *L, int n, int *bin, int *ns_out) {
  const int ns_ = (int)L->nsuper;
  const int *super = L->super, *pi = L->pi, *Ls = L->s;
  int *snode = malloc(sizeof(int) * (size_t)n), *parent = malloc(sizeof(int) * (size_t)ns_);
  int *head = malloc(sizeof(int) * (size_t)ns_), *next = malloc(sizeof(int) * (size_t)ns_), *nchild = calloc((size_t)ns_, sizeof(int));
  int *unit = malloc(sizeof(int) * (size_t)ns_);
  double *sw = calloc((size_t)ns_, sizeof(double));
  int ret = -1;
  if (!snode || !parent || !head || !next || !nchild || !unit || !sw) goto done;
  for (int k = 0; k < ns_; k++)
    for (int j = super[k]; j < super[k + 1]; j++) snode[j] = k;
  for (int k = 0; k < ns_; k++) head[k] = -1;
  /* The supernodal elimination tree (postordered: a parent comes after its children) and the work of
   * every subtree (columns x rows^2 per supernode). */
  for (int k = 0; k < ns_; k++) {
    int nc = super[k + 1] - super[k], nr = pi[k + 1] - pi[k];
    parent[k] = nr > nc ? snode[Ls[pi[k] + nc]] : -1;
    sw[k] += (double)nc * nr * nr;
    if (parent[k] >= 0) {
      sw[parent[k]] += sw[k];
      nchild[parent[k]]++;
      next[k] = head[parent[k]], head[parent[k]] = k;
    }
  }
  /* The separator: from the heaviest root down the chain of single children. */
  int root = -1;
  for (int k = 0; k < ns_; k++)
    if (parent[k] < 0 && (root < 0 || sw[k] > sw[root])) root = k;
  double total = 0;
  for (int k = 0; k < ns_; k++)
    if (parent[k] < 0) total += sw[k];
  for (int k = 0; k < ns_; k++) unit[k] = -2; /* -1: in S; >= 0: the unit (whole subtree) it belongs to */
  int bottom = root, ns = 0;
  for (;;) {
    unit[bottom] = -1;
    ns += super[bottom + 1] - super[bottom];
    if (nchild[bottom] != 1) break;
    bottom = head[bottom];
  }
  ret = 0;
  if (nchild[bottom] < 2 || ns > AU_SPLIT_MAX_SEPARATOR) goto done;
  /* Units: the subtrees under the chain and the other trees (isolated unknowns, say); each goes
   * whole to the lighter half, heaviest first (greedy). nchild[] is free from here: it holds them. */
  int nu = 0;
  for (int k = head[bottom]; k >= 0; k = next[k]) nchild[nu++] = k;
  for (int k = 0; k < ns_; k++)
    if (parent[k] < 0 && k != root) nchild[nu++] = k;
  int *units = nchild;
  sort_units(units, nu, sw);
  double w[2] = {0, 0};
  for (int a = 0; a < nu; a++) {
    int hb = w[0] <= w[1] ? 0 : 1;
    unit[units[a]] = hb;
    w[hb] += sw[units[a]];
  }
  if (w[0] < AU_SPLIT_MIN_SHARE * total || w[1] < AU_SPLIT_MIN_SHARE * total) goto done;
  for (int k = ns_ - 1; k >= 0; k--)
    if (unit[k] == -2) unit[k] = unit[parent[k]]; /* parents first: they come later in the order */
  for (int j = 0; j < n; j++) bin[j] = unit[snode[j]];
  *ns_out = ns;
  ret = 1;
done:
  free(snode), free(parent), free(head), free(next), free(nchild), free(unit), free(sw);
  return ret;
}

/* The separator's columns (q->scol) and where B's S block goes in the dense Schur block (C: cpos, cdst);
 * loc [0..n-1] scratch. Returns 0 when out of memory. */
static int split_separator(const au_spd *s, spd_split *q, const int *bin, int *loc, int ns) {
  const int n = s->n;
  q->ns = ns;
  q->scol = malloc(sizeof(int) * (size_t)ns);
  q->Sch = malloc(sizeof(double) * (size_t)ns * (size_t)ns);
  q->y = malloc(sizeof(double) * (size_t)ns);
  if (!q->scol || !q->Sch || !q->y) return 0;
  memset(q->Sch, 0, sizeof(double) * (size_t)ns * (size_t)ns); /* touched here (see factor_memory) */
  const int *Bp = s->B->p, *Bi = s->B->i;
  int m = 0;
  for (int j = 0; j < n; j++)
    if (bin[j] < 0) loc[j] = m, q->scol[m++] = j;
  for (int t = 0; t < ns; t++)
    for (int p = Bp[q->scol[t]]; p < Bp[q->scol[t] + 1]; p++) q->nc += bin[Bi[p]] < 0;
  q->cpos = malloc(sizeof(int) * (size_t)(q->nc + 1));
  q->cdst = malloc(sizeof(int) * (size_t)(q->nc + 1));
  if (!q->cpos || !q->cdst) return 0;
  int c = 0;
  for (int t = 0; t < ns; t++)
    for (int p = Bp[q->scol[t]]; p < Bp[q->scol[t] + 1]; p++)
      if (bin[Bi[p]] < 0) {
        int r = loc[Bi[p]], a = r > t ? r : t, b = r > t ? t : r;
        q->cpos[c] = p, q->cdst[c++] = a + ns * b;
      }
  return 1;
}

/* Half h of the split: M_h = B on H_h then S, lower triangle, rows sorted, analyzed in its own CHOLMOD
 * common with the natural order (B's order already is a fill-reducing one). loc [0..n-1] scratch.
 * Returns 0 on failure. */
static int split_half(const au_spd *s, spd_split *q, const int *bin, int *loc, int h) {
  const int n = s->n, ns = q->ns;
  const int *Bp = s->B->p, *Bi = s->B->i;
  spd_half *a = q->h + h;
  int nm = ns;
  for (int j = 0; j < n; j++) nm += bin[j] == h;
  a->nm = nm, a->ns = ns, a->bx = s->B->x;
  a->cols = malloc(sizeof(int) * (size_t)nm);
  if (!a->cols) return 0;
  int k = 0;
  for (int j = 0; j < n; j++)
    if (bin[j] == h) a->cols[k++] = j;
  for (int t = 0; t < ns; t++) a->cols[k++] = q->scol[t];
  for (int j = 0; j < n; j++) loc[j] = -1;
  for (int t = 0; t < nm; t++) loc[a->cols[t]] = t;
  size_t nnz = 0;
  for (int t = 0; t < nm; t++)
    for (int p = Bp[a->cols[t]]; p < Bp[a->cols[t] + 1]; p++) nnz += loc[Bi[p]] >= 0;
  cholmod_start(&a->c);
  configure(&a->c);
  a->c.nmethods = 1;
  a->c.method[0].ordering = CHOLMOD_NATURAL;
  a->c.postorder = 0;
  a->M = cholmod_allocate_sparse((size_t)nm, (size_t)nm, nnz, 1, 1, -1, CHOLMOD_REAL, &a->c);
  a->vmap = malloc(sizeof(int) * (nnz > 0 ? nnz : 1));
  a->G = malloc(sizeof(double) * (size_t)ns * (size_t)ns);
  a->GG = malloc(sizeof(double) * (size_t)ns * (size_t)ns);
  if (!a->M || !a->vmap || !a->G || !a->GG) return 0;
  int *Mp = a->M->p, *Mi = a->M->i;
  memset(Mp, 0, sizeof(int) * ((size_t)nm + 1));
  for (int t = 0; t < nm; t++)
    for (int p = Bp[a->cols[t]]; p < Bp[a->cols[t] + 1]; p++) {
      int r = loc[Bi[p]];
      if (r >= 0) Mp[(r < t ? r : t) + 1]++;
    }
  for (int t = 0; t < nm; t++) Mp[t + 1] += Mp[t];
  int *fill = malloc(sizeof(int) * (size_t)nm);
  if (!fill) return 0;
  memcpy(fill, Mp, sizeof(int) * (size_t)nm);
  for (int t = 0; t < nm; t++)
    for (int p = Bp[a->cols[t]]; p < Bp[a->cols[t] + 1]; p++) {
      int r = loc[Bi[p]];
      if (r < 0) continue;
      int col = r < t ? r : t, qq = fill[col]++;
      Mi[qq] = r < t ? t : r, a->vmap[qq] = p;
    }
  free(fill);
  for (int t = 0; t < nm; t++)
    for (int qq = Mp[t] + 1; qq < Mp[t + 1]; qq++)
      for (int r = qq; r > Mp[t] && Mi[r - 1] > Mi[r]; r--) {
        int ti = Mi[r], tv = a->vmap[r];
        Mi[r] = Mi[r - 1], a->vmap[r] = a->vmap[r - 1];
        Mi[r - 1] = ti, a->vmap[r - 1] = tv;
      }
  memset(a->M->x, 0, sizeof(double) * nnz);
  a->L = cholmod_analyze(a->M, &a->c);
  if (!a->L || a->c.status < CHOLMOD_OK || !a->L->is_super) return 0;
  /* The dense blocks are touched here too (see factor_memory). */
  memset(a->G, 0, sizeof(double) * (size_t)ns * (size_t)ns);
  memset(a->GG, 0, sizeof(double) * (size_t)ns * (size_t)ns);
  factor_memory(a->L, &a->c, 1);
  return 1;
}

/* Build the split of s (see spd_split) from L, a symbolic supernodal factor of B (the analysis that
 * chose B's order, whose columns are B's). Returns 1 when built,
 * 0 when B does not split well (see split_bins), -1 when out of memory. */
static int split_build(au_spd *s, const cholmod_factor *L) {
  if (!L->is_super || L->nsuper < 3) return 0;
  const int n = s->n;
  int *bin = malloc(sizeof(int) * (size_t)n), *loc = malloc(sizeof(int) * (size_t)n);
  spd_split *q = calloc(1, sizeof *q);
  int ns = 0, ret = -1;
  if (bin && loc && q) ret = split_bins(L, n, bin, &ns);
  if (ret == 1) {
    ret = -1;
    if (split_separator(s, q, bin, loc, ns) && split_half(s, q, bin, loc, 0) && split_half(s, q, bin, loc, 1)) ret = 1;
  }
  free(bin), free(loc);
  if (ret == 1) s->split = q;
  else split_free(&q);
  return ret;
}

/* Factor one half and copy its L22 into G (column-major, lower, zero above). */
static void *half_factor(void *arg) {
  spd_half *a = arg;
  const double *bx = a->bx;
  const int ns = a->ns;
  double *mx = a->M->x;
  const int nnz = ((const int *)a->M->p)[a->nm];
  for (int qq = 0; qq < nnz; qq++) mx[qq] = bx[a->vmap[qq]];
  a->st = factorize(a->M, a->L, &a->c, &a->msg);
  if (a->st != AU_OK) return NULL;
  const cholmod_factor *L = a->L;
  const int *super = L->super, *pi = L->pi, *px = L->px, *Ls = L->s, off = a->nm - ns;
  const double *x = L->x;
  memset(a->G, 0, sizeof(double) * (size_t)ns * (size_t)ns);
  for (int k = (int)L->nsuper - 1; k >= 0 && super[k + 1] > off; k--) {
    int nr = pi[k + 1] - pi[k];
    for (int j = super[k] > off ? super[k] : off; j < super[k + 1]; j++) {
      int cc = j - super[k];
      for (int r = cc; r < nr; r++) a->G[(Ls[pi[k] + r] - off) + (size_t)ns * (size_t)(j - off)] = x[px[k] + r + nr * cc];
    }
  }
  /* L22 L22' in this thread too: with J the index reversal, J L22 J is upper triangular and LAPACK's
   * dlauum forms U U' in a third of a general product's flops; GG keeps it in reversed indices. */
  const size_t n2 = (size_t)ns;
  for (size_t j = 0; j < n2; j++)
    for (size_t i = 0; i < n2; i++) a->GG[i + n2 * j] = a->G[(n2 - 1 - i) + n2 * (n2 - 1 - j)];
  int info = 0;
  dlauum_("U", &ns, a->GG, &ns, &info);
  if (info != 0) a->st = au_msg_set(&a->msg, AU_E_NUMERIC, "solver: dense product failed (argument %d)", -info);
  return NULL;
}

/* The split factorization: the halves on two threads, then the dense Schur complement on S. */
static au_status split_factor(au_spd *s, au_msg *msg) {
  spd_split *q = s->split;
  const double *bx = s->B->x;
  au__run_pair(half_factor, q->h + 0, q->h + 1);
  for (int h = 0; h < 2; h++)
    if (q->h[h].st != AU_OK) {
      if (msg) *msg = q->h[h].msg;
      return q->h[h].st;
    }
  const size_t ns2 = (size_t)q->ns;
  const int ns = q->ns;
  const double *P0 = q->h[0].GG, *P1 = q->h[1].GG;
  for (size_t b = 0; b < ns2; b++)
    for (size_t a = b; a < ns2; a++) {
      size_t r = (ns2 - 1 - a) + ns2 * (ns2 - 1 - b); /* (a, b) of L22 L22' in the reversed upper copy */
      q->Sch[a + ns2 * b] = P0[r] + P1[r];
    }
  for (int c = 0; c < q->nc; c++) q->Sch[q->cdst[c]] -= bx[q->cpos[c]];
  int info = 0;
  dpotrf_("L", &ns, q->Sch, &ns, &info);
  if (info > 0)
    return au_msg_set(msg, AU_E_NOT_SPD, "solver: matrix not positive definite (failed at column %d of the %d-column separator)",
                      info, ns);
  if (info < 0) return au_msg_set(msg, AU_E_NUMERIC, "solver: dense factorization failed (argument %d)", -info);
  return AU_OK;
}

/* One half of a split solve. Forward (fwd = 1): z = L^-1 (b_H, 0), and t = L22 z_S, so that
 * B_h' A_h^-1 b_h = -t. Backward: from (z_H, L22' x_S), x_H = the back substitution's first part. */
typedef struct half_solve {
  spd_half *a;
  int ns, fwd;
  const double *bb, *xs; /* B's right-hand side; the separator's solution (backward) */
  double *xb, *t;        /* B's solution (backward); t [0..ns-1] (forward) */
  cholmod_dense *Z;
  au_status st;
} half_solve;

static void *half_solve_run(void *arg) {
  half_solve *w = arg;
  spd_half *a = w->a;
  const int ns = w->ns, nh = a->nm - ns, one = 1;
  if (w->fwd) {
    cholmod_dense *R = cholmod_allocate_dense((size_t)a->nm, 1, (size_t)a->nm, CHOLMOD_REAL, &a->c);
    if (!R) return w->st = AU_E_NOMEM, NULL;
    double *r = R->x;
    for (int k = 0; k < nh; k++) r[k] = w->bb[a->cols[k]];
    for (int k = nh; k < a->nm; k++) r[k] = 0;
    w->Z = cholmod_solve(CHOLMOD_L, a->L, R, &a->c);
    cholmod_free_dense(&R, &a->c);
    if (!w->Z) return w->st = AU_E_NUMERIC, NULL;
    memcpy(w->t, (double *)w->Z->x + nh, sizeof(double) * (size_t)ns);
    dtrmv_("L", "N", "N", &ns, a->G, &ns, w->t, &one);
    return NULL;
  }
  double *z = w->Z->x;
  memcpy(z + nh, w->xs, sizeof(double) * (size_t)ns);
  dtrmv_("L", "T", "N", &ns, a->G, &ns, z + nh, &one);
  cholmod_dense *X = cholmod_solve(CHOLMOD_Lt, a->L, w->Z, &a->c);
  if (!X) return w->st = AU_E_NUMERIC, NULL;
  const double *xx = X->x;
  for (int k = 0; k < nh; k++) w->xb[a->cols[k]] = xx[k];
  cholmod_free_dense(&X, &a->c);
  return NULL;
}

/* Solve B xb = bb (both in B's order) with the split factors: the halves' forward substitutions on
 * two threads, the separator's dense solve, the halves' back substitutions on two threads. */
static au_status split_solve(au_spd *s, const double *bb, double *xb, au_msg *msg) {
  spd_split *q = s->split;
  const int ns = q->ns, one = 1;
  double *t = malloc(sizeof(double) * 2 * (size_t)ns);
  if (!t) return au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
  half_solve w[2];
  for (int h = 0; h < 2; h++)
    w[h] = (half_solve){q->h + h, ns, 1, bb, q->y, xb, t + (size_t)h * (size_t)ns, NULL, AU_OK};
  au__run_pair(half_solve_run, w + 0, w + 1);
  au_status st = w[0].st != AU_OK ? w[0].st : w[1].st;
  if (st == AU_OK) {
    for (int k = 0; k < ns; k++) q->y[k] = bb[q->scol[k]] + t[k] + t[ns + k];
    int info = 0;
    dpotrs_("L", &ns, &one, q->Sch, &ns, q->y, &ns, &info);
    w[0].fwd = w[1].fwd = 0;
    au__run_pair(half_solve_run, w + 0, w + 1);
    st = w[0].st != AU_OK ? w[0].st : w[1].st;
    for (int k = 0; k < ns; k++) xb[q->scol[k]] = q->y[k];
  }
  for (int h = 0; h < 2; h++) cholmod_free_dense(&w[h].Z, &q->h[h].c);
  free(t);
  if (st == AU_E_NOMEM) return au_msg_set(msg, st, "solver: out of memory");
  if (st != AU_OK) return au_msg_set(msg, st, "solver: solve failed");
  return AU_OK;
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
  /* 3. Large systems: the split over two cores (spd_split), planned on the analysis that ordered B. */
  if (n >= au__spd_split_min) {
    int r = split_build(s, L0);
    if (r < 0) {
      st = au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
      goto done;
    }
    if (r > 0) goto done; /* B is never factored whole */
  }
  /* 4. The symbolic factor of B as it stands (natural order, no postorder: it is postordered). */
  s->c.nmethods = 1;
  s->c.method[0].ordering = CHOLMOD_NATURAL;
  s->c.postorder = 0;
  s->L = cholmod_analyze(s->B, &s->c);
  if (!s->L || s->c.status < CHOLMOD_OK) {
    st = au_msg_set(msg, s->c.status == CHOLMOD_OUT_OF_MEMORY ? AU_E_NOMEM : AU_E_NUMERIC, "solver: analysis failed (status %d)",
                    s->c.status);
    goto done;
  }
  factor_memory(s->L, &s->c, 1);
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

int au__spd_split_size(const au_spd *s) { return s && s->split ? s->split->ns : 0; }

au_status au_spd_factor(au_spd *s, au_msg *msg) {
  if (!s) return au_msg_set(msg, AU_E_ARG, "solver: bad arguments");
  s->factored = 0;
  const double *ax = s->A->x;
  double *bx = s->B->x;
  const int nnz = ((const int *)s->A->p)[s->n];
  for (int p = 0; p < nnz; p++) bx[s->map[p]] = ax[p];
  __atomic_add_fetch(&factor_count, 1, __ATOMIC_RELAXED);
  au_status st = s->split ? split_factor(s, msg) : factorize(s->B, s->L, &s->c, msg);
  s->factored = st == AU_OK;
  return st;
}

au_status au_spd_solve(au_spd *s, const double *b, double *x, au_msg *msg) {
  if (!s || !b || !x || !s->factored) return au_msg_set(msg, AU_E_ARG, "solver: bad arguments");
  cholmod_dense *B = cholmod_allocate_dense((size_t)s->n, 1, (size_t)s->n, CHOLMOD_REAL, &s->c);
  if (!B) return au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
  double *bp = B->x;
  for (int k = 0; k < s->n; k++) bp[k] = b[s->perm[k]];
  if (s->split) {
    cholmod_dense *Xs = cholmod_allocate_dense((size_t)s->n, 1, (size_t)s->n, CHOLMOD_REAL, &s->c);
    au_status st = Xs ? split_solve(s, bp, Xs->x, msg) : au_msg_set(msg, AU_E_NOMEM, "solver: out of memory");
    cholmod_free_dense(&B, &s->c);
    if (st == AU_OK) {
      const double *xp = Xs->x;
      for (int k = 0; k < s->n; k++) x[s->perm[k]] = xp[k];
    }
    cholmod_free_dense(&Xs, &s->c);
    if (st != AU_OK) return st;
    for (int i = 0; i < s->n; i++)
      if (!(x[i] - x[i] == 0)) return au_msg_set(msg, AU_E_NUMERIC, "solver: the solution is not finite");
    return AU_OK;
  }
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
  split_free(&s->split);
  cholmod_free_factor(&s->L, &s->c);
  cholmod_free_sparse(&s->A, &s->c);
  cholmod_free_sparse(&s->B, &s->c);
  cholmod_finish(&s->c);
  free(s->map), free(s->perm);
  free(s);
  *sp = NULL;
}
