/* au_mesh.c - mesh arrays, topology (edges, fans, boundary loops, components) and validation. */
#include "au_mesh.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

au_status au_mesh_alloc(int nv, int nf, au_mesh **out) {
  if (!out) return AU_E_ARG;
  *out = NULL;
  if (nv < 0 || nf < 0) return AU_E_ARG;
  au_mesh *m = calloc(1, sizeof *m);
  if (!m) return AU_E_NOMEM;
  m->nv = nv;
  m->nf = nf;
  /* calloc(0) may return NULL legitimately, so allocate at least one element to keep the
   * pointers valid and the "NULL means failure" test simple. */
  m->X = calloc((size_t)3 * (size_t)(nv > 0 ? nv : 1), sizeof *m->X);
  m->F = calloc((size_t)3 * (size_t)(nf > 0 ? nf : 1), sizeof *m->F);
  if (!m->X || !m->F) {
    au_mesh_free(&m);
    return AU_E_NOMEM;
  }
  *out = m;
  return AU_OK;
}

au_status au_mesh_copy(const au_mesh *m, au_mesh **out) {
  if (!out) return AU_E_ARG;
  *out = NULL;
  if (!m || m->nv < 0 || m->nf < 0 || (m->nv > 0 && !m->X) || (m->nf > 0 && !m->F)) return AU_E_ARG;
  au_status s = au_mesh_alloc(m->nv, m->nf, out);
  if (s != AU_OK) return s;
  if (m->nv > 0) memcpy((*out)->X, m->X, (size_t)3 * (size_t)m->nv * sizeof *m->X);
  if (m->nf > 0) memcpy((*out)->F, m->F, (size_t)3 * (size_t)m->nf * sizeof *m->F);
  return AU_OK;
}

void au_mesh_free(au_mesh **m) {
  if (!m || !*m) return;
  free((*m)->X);
  free((*m)->F);
  free(*m);
  *m = NULL;
}

void au_topo_free(au_topo **t) {
  if (!t || !*t) return;
  au_topo *p = *t;
  free(p->E);
  free(p->EF);
  free(p->EC);
  free(p->FE);
  free(p->vb);
  free(p->vused);
  free(p->loop_start);
  free(p->loop_vert);
  free(p->loop_len);
  free(p);
  *t = NULL;
}

/* malloc of n elements of size sz with the product checked for overflow; n == 0 gets one element
 * so that NULL always means failure. */
static void *au__alloc(size_t n, size_t sz) {
  if (n == 0) n = 1;
  if (n > SIZE_MAX / sz) return NULL;
  return malloc(n * sz);
}

/* Half-edge h = 3f+k runs along the edge opposite corner k, from corner k+1 to corner k+2,
 * which is the direction in which face f traverses it. */
static int au__he_from(const int *F, int64_t h) {
  int64_t f = h / 3, k = h % 3;
  return F[3 * f + (k + 1) % 3];
}
static int au__he_to(const int *F, int64_t h) {
  int64_t f = h / 3, k = h % 3;
  return F[3 * f + (k + 2) % 3];
}

/* LSD radix sort of n (key, val) pairs on the low `bits` bits of key, 11 bits per pass; k2/v2 are
 * scratch of the same size. Sequential reads and 2048 write streams per pass beat a comparison
 * sort, and a counting sort over vertices (whose scattered reads miss the cache), on millions of
 * half-edges.
 * The sorted pairs end up in key/val. */
static void au__radix_sort(uint64_t *key, uint32_t *val, uint64_t *k2, uint32_t *v2, int64_t n, int bits) {
  int64_t cnt[2048];
  uint64_t *ka = key, *kb = k2;
  uint32_t *va = val, *vb = v2;
  for (int shift = 0; shift < bits; shift += 11) {
    memset(cnt, 0, sizeof cnt);
    for (int64_t i = 0; i < n; i++) cnt[(ka[i] >> shift) & 2047]++;
    /* A pass where every key has the same digit would only copy. */
    if (n == 0 || cnt[(ka[0] >> shift) & 2047] == n) continue;
    int64_t sum = 0;
    for (int d = 0; d < 2048; d++) {
      int64_t c = cnt[d];
      cnt[d] = sum;
      sum += c;
    }
    for (int64_t i = 0; i < n; i++) {
      int64_t pos = cnt[(ka[i] >> shift) & 2047]++;
      kb[pos] = ka[i];
      vb[pos] = va[i];
    }
    uint64_t *kt = ka;
    ka = kb, kb = kt;
    uint32_t *vt = va;
    va = vb, vb = vt;
  }
  if (ka != key) {
    memcpy(key, ka, (size_t)n * sizeof *key);
    memcpy(val, va, (size_t)n * sizeof *val);
  }
}

/* Union-find root with path halving. */
static int au__find(int *parent, int v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

/* Walk one fan around the vertex v of corner c: leave face c/3 through its edge `exit`, and keep
 * crossing the next edge around v until a boundary edge or an already visited corner stops us.
 * Every corner reached is marked visited. */
static void au__fan_walk(const int *F, const au_topo *t, unsigned char *visited, int64_t c, int exit) {
  int v = F[c];
  int64_t f = c / 3;
  int e = exit;
  for (;;) {
    int64_t g = t->EF[2 * e] == f ? t->EF[2 * e + 1] : t->EF[2 * e];
    if (g < 0) return;
    int kg = F[3 * g] == v ? 0 : F[3 * g + 1] == v ? 1 : 2;
    if (visited[3 * g + kg]) return;
    visited[3 * g + kg] = 1;
    int e1 = t->FE[3 * g + (kg + 1) % 3], e2 = t->FE[3 * g + (kg + 2) % 3];
    e = e1 == e ? e2 : e1;
    f = g;
  }
}

/* Count the fans of every vertex into nfans [0..nv-1]; returns 0 or -1 when out of memory. */
static int au__count_fans(const au_mesh *m, const au_topo *t, int *nfans) {
  int64_t nc = 3 * (int64_t)m->nf;
  unsigned char *visited = calloc((size_t)(nc > 0 ? nc : 1), 1);
  if (!visited) return -1;
  memset(nfans, 0, (size_t)m->nv * sizeof *nfans);
  for (int64_t c = 0; c < nc; c++) {
    if (visited[c]) continue;
    visited[c] = 1;
    nfans[m->F[c]]++;
    int64_t f = c / 3, k = c % 3;
    au__fan_walk(m->F, t, visited, c, t->FE[3 * f + (k + 1) % 3]);
    au__fan_walk(m->F, t, visited, c, t->FE[3 * f + (k + 2) % 3]);
  }
  free(visited);
  return 0;
}

/* Trace the boundary loops (boundary edges have EF[2e+1] < 0) in the faces' orientation. */
static au_status au__trace_loops(const au_mesh *m, au_topo *t, au_msg *msg) {
  int nv = m->nv, nb = 0;
  int *next = malloc((size_t)(nv > 0 ? nv : 1) * sizeof *next);
  if (!next) return au_msg_set(msg, AU_E_NOMEM, "out of memory tracing boundary loops");
  for (int v = 0; v < nv; v++) next[v] = -1;
  for (int e = 0; e < t->ne; e++) {
    if (t->EF[2 * e + 1] >= 0) continue;
    int64_t h = 3 * (int64_t)t->EF[2 * e] + t->EC[2 * e];
    int a = au__he_from(m->F, h), b = au__he_to(m->F, h);
    /* Manifold vertices with a consistent orientation have one outgoing boundary edge each;
     * the caller has checked both, so a second one is a broken invariant. */
    if (next[a] >= 0) {
      free(next);
      return au_msg_set(msg, AU_E_INTERNAL, "vertex %d starts two boundary edges", a);
    }
    next[a] = b;
    t->vb[a] = t->vb[b] = 1;
    nb++;
  }
  t->loop_vert = au__alloc((size_t)nb, sizeof *t->loop_vert);
  t->loop_start = au__alloc((size_t)nb + 1, sizeof *t->loop_start);
  if (!t->loop_vert || !t->loop_start) {
    free(next);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory tracing boundary loops");
  }
  int n = 0, nl = 0;
  t->loop_start[0] = 0;
  /* Each loop starts at its smallest vertex, so the result does not depend on the edge order.
   * A traced vertex has its next[] cleared, which also marks it as done. */
  for (int v = 0; v < nv; v++) {
    if (next[v] < 0) continue;
    int u = v;
    while (next[u] >= 0 && n < nb) {
      int w = next[u];
      t->loop_vert[n++] = u;
      next[u] = -1;
      u = w;
    }
    if (u != v) {
      free(next);
      return au_msg_set(msg, AU_E_INTERNAL, "boundary loop through vertex %d does not close", v);
    }
    t->loop_start[++nl] = n;
  }
  free(next);
  t->nloops = nl;
  if (m->X) {
    t->loop_len = au__alloc((size_t)nl, sizeof *t->loop_len);
    if (!t->loop_len) return au_msg_set(msg, AU_E_NOMEM, "out of memory tracing boundary loops");
    for (int l = 0; l < nl; l++) {
      double len = 0;
      for (int i = t->loop_start[l]; i < t->loop_start[l + 1]; i++) {
        int a = t->loop_vert[i];
        int b = t->loop_vert[i + 1 < t->loop_start[l + 1] ? i + 1 : t->loop_start[l]];
        const double *p = m->X + 3 * (int64_t)a, *q = m->X + 3 * (int64_t)b;
        len += sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                    (p[2] - q[2]) * (p[2] - q[2]));
      }
      t->loop_len[l] = len;
    }
  }
  return AU_OK;
}

/* Components among referenced vertices by union-find over the edges. */
static au_status au__components(const au_mesh *m, au_topo *t, au_msg *msg) {
  int nv = m->nv;
  int *parent = malloc((size_t)(nv > 0 ? nv : 1) * sizeof *parent);
  if (!parent) return au_msg_set(msg, AU_E_NOMEM, "out of memory counting components");
  for (int v = 0; v < nv; v++) parent[v] = v;
  for (int e = 0; e < t->ne; e++) {
    int a = au__find(parent, t->E[2 * e]), b = au__find(parent, t->E[2 * e + 1]);
    /* Linking the larger root under the smaller keeps roots deterministic; path halving keeps
     * the trees shallow enough in practice. */
    if (a != b) parent[a > b ? a : b] = a < b ? a : b;
  }
  int nc = 0, nused = 0;
  for (int v = 0; v < nv; v++) {
    if (!t->vused[v]) continue;
    nused++;
    if (au__find(parent, v) == v) nc++;
  }
  free(parent);
  t->ncomponents = nc;
  t->nunreferenced = nv - nused;
  t->euler = (int)((int64_t)nused - t->ne + m->nf);
  return AU_OK;
}

/* Build E, EF, EC, FE by sorting the half-edges on their (min, max) vertex pair. Reports the
 * first non-manifold edge in edge order through *bad_edge / *bad_count and the first edge whose
 * two faces traverse it in the same direction through *flip_edge (-1 when there is none). */
static au_status au__build_edges(const au_mesh *m, au_topo *t, int *bad_edge, int *bad_count, int *flip_edge,
                                 au_msg *msg) {
  int64_t nh = 3 * (int64_t)m->nf;
  const int *F = m->F;
  int bits = 1;
  while (bits < 31 && (1 << bits) < m->nv) bits++;
  uint64_t mask = ((uint64_t)1 << bits) - 1;
  /* Each half-edge carries its index and, in the low bit, whether it runs from max to min. */
  uint64_t *key = au__alloc((size_t)nh, sizeof *key), *k2 = au__alloc((size_t)nh, sizeof *k2);
  uint32_t *val = au__alloc((size_t)nh, sizeof *val), *v2 = au__alloc((size_t)nh, sizeof *v2);
  if (!key || !k2 || !val || !v2) {
    free(key), free(k2), free(val), free(v2);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory building edges");
  }
  for (int64_t h = 0; h < nh; h++) {
    int a = au__he_from(F, h), b = au__he_to(F, h);
    key[h] = a < b ? (uint64_t)a << bits | (uint64_t)b : (uint64_t)b << bits | (uint64_t)a;
    val[h] = (uint32_t)(2 * h + (a > b));
  }
  au__radix_sort(key, val, k2, v2, nh, 2 * bits);
  free(k2);
  free(v2);

  int64_t ne = 0;
  for (int64_t i = 0; i < nh; i++) ne += i == 0 || key[i] != key[i - 1];
  t->ne = (int)ne;
  t->E = au__alloc((size_t)2 * (size_t)ne, sizeof *t->E);
  t->EF = au__alloc((size_t)2 * (size_t)ne, sizeof *t->EF);
  t->EC = au__alloc((size_t)2 * (size_t)ne, sizeof *t->EC);
  if (!t->E || !t->EF || !t->EC) {
    free(key), free(val);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory building edges");
  }
  *bad_edge = *flip_edge = -1;
  *bad_count = 0;
  int e = -1;
  int64_t i = 0;
  while (i < nh) {
    int64_t j = i;
    while (j < nh && key[j] == key[i]) j++;
    e++;
    t->E[2 * e] = (int)(key[i] >> bits);
    t->E[2 * e + 1] = (int)(key[i] & mask);
    for (int s = 0; s < 2; s++) {
      t->EF[2 * e + s] = t->EC[2 * e + s] = -1;
      if (i + s < j) {
        uint32_t h = val[i + s] >> 1;
        t->EF[2 * e + s] = (int)(h / 3);
        t->EC[2 * e + s] = (int)(h % 3);
      }
    }
    for (int64_t k = i; k < j; k++) t->FE[val[k] >> 1] = e;
    if (j - i > 2 && *bad_edge < 0) *bad_edge = e, *bad_count = (int)(j - i);
    if (j - i == 2 && (val[i] & 1) == (val[i + 1] & 1) && *flip_edge < 0) *flip_edge = e;
    i = j;
  }
  free(key);
  free(val);
  return AU_OK;
}

au_status au_mesh_topology(const au_mesh *m, au_topo **out, au_msg *msg) {
  if (msg) msg->text[0] = '\0';
  if (!out) return au_msg_set(msg, AU_E_ARG, "no output pointer for the topology");
  *out = NULL;
  if (!m || m->nv < 0 || m->nf < 0 || (m->nf > 0 && !m->F))
    return au_msg_set(msg, AU_E_ARG, "invalid mesh arrays");
  int nv = m->nv, nf = m->nf;
  const int *F = m->F;
  /* Half-edge indices (times two, plus a direction bit) must fit in 32 bits. */
  if (nf > INT32_MAX / 6) return au_msg_set(msg, AU_E_ARG, "mesh has too many faces (%d)", nf);
  /* The precondition is cheap to check and protects every array access below. */
  for (int64_t c = 0; c < 3 * (int64_t)nf; c++) {
    if (F[c] < 0 || F[c] >= nv)
      return au_msg_set(msg, AU_E_ARG, "face %d refers to vertex %d but the mesh has %d vertices",
                        (int)(c / 3), F[c], nv);
    if (F[c] == F[3 * (c / 3) + (c % 3 + 1) % 3])
      return au_msg_set(msg, AU_E_ARG, "face %d repeats vertex %d", (int)(c / 3), F[c]);
  }

  au_topo *t = calloc(1, sizeof *t);
  if (!t) return au_msg_set(msg, AU_E_NOMEM, "out of memory for the topology");
  t->nv = nv;
  t->nf = nf;
  au_status s = AU_OK;
  int *nfans = NULL;
  t->FE = au__alloc((size_t)3 * (size_t)nf, sizeof *t->FE);
  t->vb = calloc((size_t)(nv > 0 ? nv : 1), 1);
  t->vused = calloc((size_t)(nv > 0 ? nv : 1), 1);
  if (!t->FE || !t->vb || !t->vused) {
    s = au_msg_set(msg, AU_E_NOMEM, "out of memory for the topology");
    goto fail;
  }
  for (int64_t c = 0; c < 3 * (int64_t)nf; c++) t->vused[F[c]] = 1;

  int bad_edge = -1, bad_count = 0, flip_edge = -1;
  if ((s = au__build_edges(m, t, &bad_edge, &bad_count, &flip_edge, msg)) != AU_OK) goto fail;
  if (bad_edge >= 0) {
    s = au_msg_set(msg, AU_E_NONMANIFOLD_EDGE, "non-manifold edge (%d, %d): shared by %d faces",
                   t->E[2 * bad_edge], t->E[2 * bad_edge + 1], bad_count);
    goto fail;
  }

  nfans = malloc((size_t)(nv > 0 ? nv : 1) * sizeof *nfans);
  if (!nfans || au__count_fans(m, t, nfans) != 0) {
    s = au_msg_set(msg, AU_E_NOMEM, "out of memory checking vertex fans");
    goto fail;
  }
  for (int v = 0; v < nv; v++) {
    if (nfans[v] > 1) {
      s = au_msg_set(msg, AU_E_NONMANIFOLD_VERTEX,
                     "vertex %d is non-manifold (its faces form %d separate fans)", v, nfans[v]);
      goto fail;
    }
  }
  free(nfans);
  nfans = NULL;

  /* Two faces agree on orientation when they traverse their shared edge in opposite directions. */
  if (flip_edge >= 0) {
    int e = flip_edge;
    s = au_msg_set(msg, AU_E_ORIENTATION,
                   "inconsistent orientation at edge (%d, %d): faces %d and %d traverse it in the same "
                   "direction",
                   t->E[2 * e], t->E[2 * e + 1], t->EF[2 * e], t->EF[2 * e + 1]);
    goto fail;
  }

  if ((s = au__trace_loops(m, t, msg)) != AU_OK) goto fail;
  if ((s = au__components(m, t, msg)) != AU_OK) goto fail;
  t->genus = (2 * t->ncomponents - t->euler - t->nloops) / 2;
  *out = t;
  return AU_OK;

fail:
  free(nfans);
  au_topo_free(&t);
  return s;
}

/* The direction in which face EF[2e+s] traverses edge e: 1 from E[2e] to E[2e+1], 0 the other way. */
static int au__edge_dir(const int *F, const au_topo *t, int e, int s) {
  int64_t h = 3 * (int64_t)t->EF[2 * e + s] + t->EC[2 * e + s];
  return au__he_from(F, h) == t->E[2 * e];
}

au_status au_mesh_orient(au_mesh *m, int *nflipped, au_msg *msg) {
  if (msg) msg->text[0] = '\0';
  if (nflipped) *nflipped = 0;
  if (!m || m->nv < 0 || m->nf < 0 || (m->nf > 0 && !m->F)) return au_msg_set(msg, AU_E_ARG, "invalid mesh");
  int nf = m->nf;
  if (nf > INT32_MAX / 6) return au_msg_set(msg, AU_E_ARG, "mesh has too many faces (%d)", nf);
  int *F = m->F;
  for (int64_t c = 0; c < 3 * (int64_t)nf; c++)
    if (F[c] < 0 || F[c] >= m->nv)
      return au_msg_set(msg, AU_E_INDEX, "face %d refers to vertex %d but the mesh has %d vertices", (int)(c / 3), F[c],
                        m->nv);
  for (int f = 0; f < nf; f++) {
    const int *c = F + 3 * (int64_t)f;
    if (c[0] == c[1] || c[0] == c[2]) return au_msg_set(msg, AU_E_FACE, "face %d repeats vertex %d", f, c[0]);
    if (c[1] == c[2]) return au_msg_set(msg, AU_E_FACE, "face %d repeats vertex %d", f, c[1]);
  }
  if (nf == 0) return AU_OK;

  au_topo t;
  memset(&t, 0, sizeof t);
  t.nv = m->nv, t.nf = nf;
  au_status s = AU_OK;
  signed char *sign = NULL;
  int *queue = NULL;
  if (!(t.FE = au__alloc((size_t)3 * (size_t)nf, sizeof *t.FE))) {
    s = au_msg_set(msg, AU_E_NOMEM, "out of memory orienting the faces");
    goto done;
  }
  int bad_edge, bad_count, flip_edge;
  if ((s = au__build_edges(m, &t, &bad_edge, &bad_count, &flip_edge, msg)) != AU_OK) goto done;
  if (bad_edge >= 0) {
    s = au_msg_set(msg, AU_E_NONMANIFOLD_EDGE, "non-manifold edge (%d, %d): shared by %d faces", t.E[2 * bad_edge],
                   t.E[2 * bad_edge + 1], bad_count);
    goto done;
  }
  if (flip_edge < 0) goto done; /* already consistent */
  sign = calloc((size_t)nf, 1);
  queue = au__alloc((size_t)nf, sizeof *queue);
  if (!sign || !queue) {
    s = au_msg_set(msg, AU_E_NOMEM, "out of memory orienting the faces");
    goto done;
  }
  /* sign[f] = +1 keeps face f, -1 reverses it. Across an edge the two faces must end up traversing it
   * in opposite directions, which fixes a neighbour's sign from its face's; meeting a face again with
   * the other sign means no choice of signs works: the surface is not orientable. */
  int head = 0, tail = 0;
  for (int f0 = 0; f0 < nf; f0++) {
    if (sign[f0]) continue;
    int start = tail, neg = 0;
    sign[f0] = 1;
    queue[tail++] = f0;
    while (head < tail) {
      int f = queue[head++];
      for (int k = 0; k < 3; k++) {
        int e = t.FE[3 * (int64_t)f + k];
        if (t.EF[2 * e + 1] < 0) continue;
        int side = t.EF[2 * e] == f ? 0 : 1;
        int g = t.EF[2 * e + 1 - side];
        int same = au__edge_dir(F, &t, e, 0) == au__edge_dir(F, &t, e, 1);
        signed char want = (signed char)(same ? -sign[f] : sign[f]);
        if (!sign[g]) {
          sign[g] = want;
          neg += want < 0;
          queue[tail++] = g;
        } else if (sign[g] != want) {
          s = au_msg_set(msg, AU_E_ORIENTATION,
                         "non-orientable surface (a Moebius strip or a Klein bottle): no orientation of the faces "
                         "agrees across edge (%d, %d) (faces %d and %d)",
                         t.E[2 * e], t.E[2 * e + 1], f, g);
          goto done;
        }
      }
    }
    /* Of the two orientations, the one that reverses fewer faces: a few flipped faces in a large mesh
     * are the faces that are wrong. */
    if (2 * neg > tail - start)
      for (int i = start; i < tail; i++) sign[queue[i]] = (signed char)-sign[queue[i]];
  }
  int n = 0, first = -1;
  for (int f = 0; f < nf; f++) {
    if (sign[f] > 0) continue;
    int tmp = F[3 * (int64_t)f + 1];
    F[3 * (int64_t)f + 1] = F[3 * (int64_t)f + 2];
    F[3 * (int64_t)f + 2] = tmp;
    if (first < 0) first = f;
    n++;
  }
  if (nflipped) *nflipped = n;
  s = au_msg_set(msg, AU_W_REORIENTED, "re-oriented %d of %d faces to agree with their neighbours (first: face %d)", n,
                 nf, first);
done:
  free(sign);
  free(queue);
  free(t.FE);
  free(t.E);
  free(t.EF);
  free(t.EC);
  return s;
}

au_mesh_expect au_mesh_expect_default(void) {
  au_mesh_expect e = {0, 0, NULL};
  return e;
}

/* Describe the loop sizes, e.g. "64 vertices" or "sizes 64, 32, 8" (at most four listed), into buf. */
static void au__loop_sizes(const au_topo *t, char *buf, size_t len) {
  if (t->nloops == 1) {
    snprintf(buf, len, "%d vertices", t->loop_start[1] - t->loop_start[0]);
    return;
  }
  size_t n = (size_t)snprintf(buf, len, "sizes");
  for (int l = 0; l < t->nloops && n < len; l++) {
    if (l == 4) {
      snprintf(buf + n, len - n, ", ...");
      return;
    }
    n += (size_t)snprintf(buf + n, len - n, "%s%d", l == 0 ? " " : ", ",
                          t->loop_start[l + 1] - t->loop_start[l]);
  }
}

/* The boundary-count problem in one line, with a hint at the right target when one applies. */
static au_status au__boundary_problem(const au_topo *t, const au_mesh_expect *x, au_msg *msg) {
  const char *cmd = x->command;
  if (t->nloops == 0) {
    if (cmd && t->genus == 0)
      return au_msg_set(msg, AU_E_BOUNDARY, "closed mesh given to the %s map: map it onto the sphere", cmd);
    if (cmd)
      return au_msg_set(msg, AU_E_BOUNDARY,
                        "closed mesh of genus %d given to the %s map, which needs %d boundary loop%s (cut the "
                        "surface open first)",
                        t->genus, cmd, x->loops, x->loops == 1 ? "" : "s");
    return au_msg_set(msg, AU_E_BOUNDARY, "mesh is closed (no boundary loop; expected %d)", x->loops);
  }
  char sizes[96];
  au__loop_sizes(t, sizes, sizeof sizes);
  const char *plural = t->nloops == 1 ? "" : "s";
  if (x->loops == 0 && x->genus == 1 && cmd) /* the torus: the genus matters more than which loops */
    return au_msg_set(msg, AU_E_BOUNDARY, "mesh has %d boundary loop%s (%s) and genus %d; the %s map needs a closed "
                      "genus-1 surface", t->nloops, plural, sizes, t->genus, cmd);
  if (x->loops == 0 && cmd)
    return au_msg_set(msg, AU_E_BOUNDARY,
                      "mesh has %d boundary loop%s (%s); the %s map needs a closed surface: map "
                      "%s onto the %s",
                      t->nloops, plural, sizes, cmd,
                      t->nloops == 1 ? "a disk-like mesh" : t->nloops == 2 ? "a mesh with two loops" :
                      "a disk-like mesh (fill all but one hole)",
                      t->nloops == 1 ? "disk" : t->nloops == 2 ? "annulus" : "disk");
  if (x->loops == 0)
    return au_msg_set(msg, AU_E_BOUNDARY, "mesh has %d boundary loop%s (%s); a closed surface was expected",
                      t->nloops, plural, sizes);
  if (cmd)
    return au_msg_set(msg, AU_E_BOUNDARY, "mesh has %d boundary loop%s (%s); the %s map needs %d",
                      t->nloops, plural, sizes, cmd, x->loops);
  return au_msg_set(msg, AU_E_BOUNDARY, "mesh has %d boundary loop%s (%s); expected %d", t->nloops,
                    plural, sizes, x->loops);
}

/* The zero-area check: returns AU_OK or AU_E_DEGENERATE naming the first such face. */
static au_status au__check_areas(const au_mesh *m, au_msg *msg) {
  double *area = au__alloc((size_t)m->nf, sizeof *area);
  if (!area) return au_msg_set(msg, AU_E_NOMEM, "out of memory checking face areas");
  double total = 0;
  for (int f = 0; f < m->nf; f++) {
    const double *p = m->X + 3 * (int64_t)m->F[3 * f], *q = m->X + 3 * (int64_t)m->F[3 * f + 1],
                 *r = m->X + 3 * (int64_t)m->F[3 * f + 2];
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    double c0 = u[1] * v[2] - u[2] * v[1], c1 = u[2] * v[0] - u[0] * v[2], c2 = u[0] * v[1] - u[1] * v[0];
    area[f] = 0.5 * sqrt(c0 * c0 + c1 * c1 + c2 * c2);
    total += area[f];
  }
  au_status s = AU_OK;
  if (!(total > 0) || !isfinite(total)) {
    s = au_msg_set(msg, AU_E_DEGENERATE, "mesh has total area %g: every face is degenerate or the coordinates overflow", total);
  } else {
    /* Relative to the total, so the check does not depend on the mesh's units. */
    double thr = 1e-14 * total;
    int first = -1, count = 0;
    for (int f = 0; f < m->nf; f++) {
      if (area[f] <= thr) {
        if (first < 0) first = f;
        count++;
      }
    }
    if (count > 0)
      s = au_msg_set(msg, AU_E_DEGENERATE, "face %d has zero area (%d such face%s)", first, count,
                     count == 1 ? "" : "s");
  }
  free(area);
  return s;
}

au_status au_mesh_validate(const au_mesh *m, const au_mesh_expect *expect, au_topo **topo, au_msg *msg) {
  if (msg) msg->text[0] = '\0';
  if (topo) *topo = NULL;
  if (!m || m->nv < 0 || m->nf < 0) return au_msg_set(msg, AU_E_ARG, "invalid mesh");
  au_mesh_expect x = expect ? *expect : au_mesh_expect_default();
  if (m->nv == 0 || m->nf == 0)
    return au_msg_set(msg, AU_E_EMPTY, "mesh is empty (%d vertices, %d faces)", m->nv, m->nf);
  if (!m->X || !m->F) return au_msg_set(msg, AU_E_ARG, "mesh has no coordinate or face array");
  for (int v = 0; v < m->nv; v++) {
    const double *p = m->X + 3 * (int64_t)v;
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
      return au_msg_set(msg, AU_E_NONFINITE, "vertex %d has a non-finite coordinate", v);
  }
  for (int64_t c = 0; c < 3 * (int64_t)m->nf; c++) {
    if (m->F[c] < 0 || m->F[c] >= m->nv)
      return au_msg_set(msg, AU_E_INDEX, "face %d refers to vertex %d but the mesh has %d vertices",
                        (int)(c / 3), m->F[c], m->nv);
  }
  for (int f = 0; f < m->nf; f++) {
    const int *c = m->F + 3 * (int64_t)f;
    if (c[0] == c[1] || c[0] == c[2]) return au_msg_set(msg, AU_E_FACE, "face %d repeats vertex %d", f, c[0]);
    if (c[1] == c[2]) return au_msg_set(msg, AU_E_FACE, "face %d repeats vertex %d", f, c[1]);
  }

  au_topo *t = NULL;
  au_status s = au_mesh_topology(m, &t, msg);
  if (s != AU_OK) return s;
  if (t->ncomponents > 1) {
    s = au_msg_set(msg, AU_E_COMPONENTS, "mesh has %d connected components (expected 1)", t->ncomponents);
  } else if (x.loops >= 0 && t->nloops != x.loops) {
    s = au__boundary_problem(t, &x, msg);
  } else if (x.genus >= 0 && t->genus != x.genus) {
    if (x.command && x.genus == 1)
      s = au_msg_set(msg, AU_E_GENUS, "mesh has genus %d (expected genus 1): the %s map needs a closed genus-1 surface%s",
                     t->genus, x.command, t->genus == 0 ? " (map a genus-0 mesh onto the sphere)" : "; higher genus is not supported");
    else if (x.command && x.genus == 0 && x.loops < 0 && t->nloops > 0) /* the circle domain */
      s = au_msg_set(msg, AU_E_GENUS, "mesh has genus %d and %d boundary loop%s (expected genus 0): the %s map needs a "
                     "genus-0 surface; map it with `authalic atlas`, which takes any genus", t->genus, t->nloops,
                     t->nloops == 1 ? "" : "s", x.command);
    else if (x.command && x.genus == 0 && t->genus == 1 && t->nloops == 0)
      s = au_msg_set(msg, AU_E_GENUS, "mesh has genus 1 (expected genus 0): map a closed genus-1 mesh onto the torus");
    else
      s = au_msg_set(msg, AU_E_GENUS, "mesh has genus %d (expected genus %d)", t->genus, x.genus);
  } else {
    s = au__check_areas(m, msg);
  }
  if (s == AU_OK && t->nunreferenced > 0) {
    int first = 0;
    while (t->vused[first]) first++;
    if (t->nunreferenced == 1)
      s = au_msg_set(msg, AU_W_UNREFERENCED,
                     "1 vertex is referenced by no face (%d); it keeps its place in the output", first);
    else
      s = au_msg_set(msg, AU_W_UNREFERENCED,
                     "%d vertices are referenced by no face (first: %d); they keep their place in the output",
                     t->nunreferenced, first);
  }
  if (s < 0) {
    au_topo_free(&t);
    return s;
  }
  if (topo)
    *topo = t;
  else
    au_topo_free(&t);
  return s;
}
