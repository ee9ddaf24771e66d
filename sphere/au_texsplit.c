/* au_texsplit.c - the adaptive splitting that keeps every straight-edged texture triangle the right
 * way round and close to its spherical area, and the choice of the texture's axis.
 *
 * Why split: a texture triangle joins the projections of its corners by straight lines, while the
 * spherical triangle's edges are great-circle arcs whose images bend (strongly near a cea pole, near
 * the rim of a laea chart, across the creases of the octahedral map). A long arc's image can pass on
 * the other side of the opposite corner, and the straight triangle turns over (a fold: a mirrored
 * piece of texture); or it just misses part of the area, and the face gets fewer or more texels than
 * its share. Both shrink with the square of the arcs' length, so halving edges cures them.
 *
 * The rule, per round: a face is bad for folding if its signed straight area in its chart (in
 * steradians: every chart here preserves area) is not of the map's orientation, by a margin of 1e-9
 * of its spherical area; it is bad for area if |straight area / spherical area - 1| > tol (faces
 * with a corner on a cea pole are exempt: the pole is a whole line of the image, and a triangle
 * keeps about half of its wedge whatever the splits). Each bad face's longest edge (chord on the
 * sphere) is split at its middle on the surface, together with the face on its other side, which
 * keeps the mesh conforming. Area rounds stop after opts->max_rounds rounds, when the faces have
 * grown plan->growth times (8, or 32 with a target), or, with a target (the per-face texture error
 * the texture should reach: by default the map's own, issue 18's 1.25 x its per-face error + 0.002),
 * on the first fold-free round at or below it; fold rounds go on until no fold is left, or until
 * the folds have not come down for AU_FOLD_STALL rounds.
 *
 * Exactness: the new vertex is the midpoint x of the edge on the input surface (so it lies on the
 * input's flat triangle and the surface area is kept to rounding), and its point on the sphere is
 * the image of x under the piecewise linear map: the middle of the edge's two chordal points C,
 * normalized. That is where the bake and the point location send that surface point, so the
 * texture and the located texels agree at every vertex, old or new. */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "au_texture_internal.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define AU_FOLD_STALL 1024 /* rounds without fewer folds than ever before after which the mending gives
                             up (counted afresh from a round of area splits or without folds). Progress,
                             not a count of rounds: on a map of needles (a limb stretched along its
                             axis) splitting a fold turns the needle across the split edge over, and
                             the fold walks around the limb's ring, a face every few rounds, before it
                             is gone (docs/textures.md). 256 gave up on tpose's spherical-areas map in
                             cea with 3 folds left: its longest wait for a new low is 308 rounds */
#define AU_FOLD_ROUNDS 4096 /* and after this many rounds in all (a safeguard: none needs it) */
#define AU_TARGET_STALL 4 /* growth of the faces without a lower error after which a target is given up */
#define AU_TARGET_STEP 4  /* with a target, a worst-first round grows the faces by at most 1/4, so the
                             splitting stops within a quarter of the faces the target needs */
#define AU_FOLD_RUNAWAY 8 /* rounds in a row with more folds than the last after which a try gives up:
                             needles of a map's near-degenerate triangles (the polished map of
                             hand_closed, cea, worst first with a target) turned over again in every
                             split, 1 fold to 630k in 25 rounds */
#define AU_FOLD_GROWTH 64 /* and fold splitting gives up at this many (a safeguard: none needs it) */

double au__sph_tri_area(const double *a, const double *b, const double *c) {
  /* tan(E/2) = det[a b c] / (1 + a.b + b.c + c.a), the triple product from edge vectors so small
   * triangles keep their digits. */
  double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  double det = a[0] * n[0] + a[1] * n[1] + a[2] * n[2];
  double den = 1 + (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) + (b[0] * c[0] + b[1] * c[1] + b[2] * c[2]) +
               (c[0] * a[0] + c[1] * a[1] + c[2] * a[2]);
  return 2 * atan2(det, den);
}

int au__tex_reserve(au__tex_work *w, int nv, int nf) {
  au_tex_mesh *t = w->t;
  if (nv > w->nvcap) {
    int cap = nv + nv / 2 + 16;
    double *X = realloc(t->X, 3 * (size_t)cap * sizeof *X);
    if (X) t->X = X;
    double *C = realloc(w->C, 3 * (size_t)cap * sizeof *C);
    if (C) w->C = C;
    double *Q = realloc(w->Q, 3 * (size_t)cap * sizeof *Q);
    if (Q) w->Q = Q;
    double *raw = realloc(w->raw, 4 * (size_t)cap * sizeof *raw);
    if (raw) w->raw = raw;
    unsigned char *ip = realloc(w->is_pole, (size_t)cap);
    if (ip) w->is_pole = ip;
    if (!X || !C || !Q || !raw || !ip) return 0;
    memset(w->is_pole + w->nvcap, 0, (size_t)(cap - w->nvcap));
    w->nvcap = cap;
  }
  if (nf > w->nfcap) {
    int cap = nf + nf / 2 + 16;
    int *F = realloc(t->F, 3 * (size_t)cap * sizeof *F);
    if (F) t->F = F;
    int *src = realloc(t->src_face, (size_t)cap * sizeof *src);
    if (src) t->src_face = src;
    if (!F || !src) return 0;
    w->nfcap = cap;
  }
  return 1;
}

/* ---------------------------------------------------------------- half-edge table */

/* Open addressing from the half-edge (a, b) to its face; a split edge's entries become tombstones
 * (face -1) so probing goes on past them. */
typedef struct he_table {
  uint64_t *key;
  int *face;
  size_t mask, used; /* used: slots holding a key (a split edge's keeps it, its face -1) */
  int *touched;      /* the faces the splits changed or made since the last scan (au__tex_refine) */
  size_t ntouched, touchcap;
} he_table;

static size_t he_slot(const he_table *h, uint64_t k) {
  uint64_t x = k * 0x9E3779B97F4A7C15ull;
  return (size_t)(x >> 17) & h->mask;
}

static void he_insert(he_table *h, uint64_t k, int f) {
  size_t s = he_slot(h, k);
  while (h->key[s] != UINT64_MAX && h->key[s] != k) s = (s + 1) & h->mask;
  h->used += h->key[s] == UINT64_MAX;
  h->key[s] = k, h->face[s] = f;
}

/* Room for cap slots (a power of two), the live half-edges of h (if any) moved in and the split ones
 * dropped. Returns 0 when out of memory (h unchanged). */
static int he_rehash(he_table *h, size_t cap) {
  he_table n = {malloc(cap * sizeof *n.key), malloc(cap * sizeof *n.face), cap - 1, 0, NULL, 0, 0};
  if (!n.key || !n.face) {
    free(n.key), free(n.face);
    return 0;
  }
  memset(n.key, 0xff, cap * sizeof *n.key);
  for (size_t s = 0; h->key && s <= h->mask; s++)
    if (h->key[s] != UINT64_MAX && h->face[s] >= 0) he_insert(&n, h->key[s], h->face[s]);
  free(h->key), free(h->face);
  h->key = n.key, h->face = n.face, h->mask = n.mask, h->used = n.used;
  return 1;
}

/* Log face f as touched. Returns 0 when out of memory. */
static int he_touch(he_table *h, int f) {
  if (h->ntouched == h->touchcap) {
    size_t cap = 2 * h->touchcap + 256;
    int *p = realloc(h->touched, cap * sizeof *p);
    if (!p) return 0;
    h->touched = p, h->touchcap = cap;
  }
  h->touched[h->ntouched++] = f;
  return 1;
}

static void he_free(he_table *h) {
  free(h->key), free(h->face), free(h->touched);
  memset(h, 0, sizeof *h);
}

/* Set the face of half-edge (a, b), growing the table past half full. Returns 0 when out of memory. */
static int he_put(he_table *h, int a, int b, int f) {
  if (2 * (h->used + 1) > h->mask + 1 && !he_rehash(h, 2 * (h->mask + 1))) return 0;
  he_insert(h, ((uint64_t)(uint32_t)a << 32) | (uint32_t)b, f);
  return 1;
}

/* The face of half-edge (a, b): a pointer into the table, valid until the next he_put; NULL if none. */
static int *he_find(const he_table *h, int a, int b) {
  uint64_t k = ((uint64_t)(uint32_t)a << 32) | (uint32_t)b;
  size_t s = he_slot(h, k);
  while (h->key[s] != UINT64_MAX) {
    if (h->key[s] == k) return &h->face[s];
    s = (s + 1) & h->mask;
  }
  return NULL;
}

/* A table of the current faces at load 1/4 at most; the splits keep it current. Returns 0 when out of
 * memory. */
static int he_build(he_table *h, const au_tex_mesh *t) {
  size_t need = 4 * 3 * (size_t)t->nf, cap = 1024;
  while (cap < need) cap <<= 1;
  free(h->key), free(h->face);
  h->key = NULL, h->face = NULL, h->used = 0, h->mask = 0, h->ntouched = 0;
  if (!he_rehash(h, cap)) return 0;
  for (int f = 0; f < t->nf; f++)
    for (int k = 0; k < 3; k++)
      if (!he_put(h, t->F[3 * f + k], t->F[3 * f + (k + 1) % 3], f)) return 0;
  return 1;
}

/* ---------------------------------------------------------------- splitting */

/* Split face f at its half-edge (p, q) with the vertex m: f keeps (p, m, r), a new face gets
 * (m, q, r). Room must be reserved. Returns 0 when out of memory. */
static int split_face(au__tex_work *w, he_table *h, int f, int p, int q, int m) {
  au_tex_mesh *t = w->t;
  int *c = t->F + 3 * (size_t)f, k = 0;
  while (c[k] != p) k++;
  int r = c[(k + 2) % 3], g = t->nf++;
  c[0] = p, c[1] = m, c[2] = r;
  int *d = t->F + 3 * (size_t)g;
  d[0] = m, d[1] = q, d[2] = r;
  t->src_face[g] = t->src_face[f];
  return he_put(h, p, m, f) && he_put(h, m, r, f) && he_put(h, m, q, g) && he_put(h, q, r, g) && he_put(h, r, m, g) &&
         he_touch(h, f) && he_touch(h, g);
}

/* Split the edge (a, b) and its two faces at the surface point (1 - s) x_a + s x_b. Returns 1 if
 * split, 0 if the edge is gone (split earlier in the round), -1 when out of memory. */
static int split_edge(au__tex_work *w, he_table *h, int a, int b, double sp) {
  int *fa = he_find(h, a, b), *fb = he_find(h, b, a);
  if (!fa || !fb || *fa < 0 || *fb < 0) return 0;
  if (!au__tex_reserve(w, w->t->nv + 1, w->t->nf + 2)) return -1;
  int f = *fa, g = *fb;
  *fa = -1, *fb = -1;
  au_tex_mesh *t = w->t;
  int m = t->nv++;
  double s = 0;
  for (int j = 0; j < 3; j++) {
    t->X[3 * (size_t)m + j] = (1 - sp) * t->X[3 * (size_t)a + j] + sp * t->X[3 * (size_t)b + j];
    w->C[3 * (size_t)m + j] = (1 - sp) * w->C[3 * (size_t)a + j] + sp * w->C[3 * (size_t)b + j];
    s += w->C[3 * (size_t)m + j] * w->C[3 * (size_t)m + j];
  }
  s = sqrt(s);
  for (int j = 0; j < 3; j++) w->Q[3 * (size_t)m + j] = w->C[3 * (size_t)m + j] / s;
  w->is_pole[m] = 0;
  if (!split_face(w, h, f, a, b, m) || !split_face(w, h, g, b, a, m)) return -1;
  return 1;
}

/* oct: split every edge that crosses one of the planes x = 0, y = 0, z = 0 of the texture's frame
 * (the octahedron's creases: the map is smooth inside an octant only) where it crosses it, so every
 * face lies in one closed octant and its straight texture triangle in one smooth piece of the map.
 * The crossing point of the chordal segment C_a C_b is found exactly (the plane's coordinate is
 * linear along it and the normalization keeps its zero), and the new vertex is the surface point of
 * the same parameter, as in every other split. Counted into fold_splits: without it, straight edges
 * across a crease fold near it and splits at the foot point do not converge (spiky_ico). Ends within
 * 1e-12 of a plane count as on it. */
static au_status oct_creases(au__tex_work *w, au_msg *msg) {
  au_tex_mesh *t = w->t;
  he_table h = {NULL, NULL, 0, 0, NULL, 0, 0};
  int *e = NULL;
  au_status st = AU_OK;
  for (int j = 0; j < 3 && st == AU_OK; j++) {
    int ne = 0;
    free(e);
    e = malloc(3 * 2 * (size_t)t->nf * sizeof *e);
    if (!e || !he_build(&h, t)) {
      st = au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
      break;
    }
    for (int f = 0; f < t->nf; f++)
      for (int k = 0; k < 3; k++) {
        int a = t->F[3 * f + k], b = t->F[3 * f + (k + 1) % 3];
        double qa = w->Q[3 * (size_t)a + j], qb = w->Q[3 * (size_t)b + j];
        if (a < b && fabs(qa) >= 1e-12 && fabs(qb) >= 1e-12 && (qa < 0) != (qb < 0)) e[2 * ne] = a, e[2 * ne + 1] = b, ne++;
      }
    for (int i = 0; i < ne; i++) {
      int a = e[2 * i], b = e[2 * i + 1];
      double ca = w->C[3 * (size_t)a + j], cb = w->C[3 * (size_t)b + j];
      int r = split_edge(w, &h, a, b, ca / (ca - cb));
      if (r < 0) {
        st = au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
        break;
      }
      if (r) {
        int m = t->nv - 1;
        w->C[3 * (size_t)m + j] = 0, w->Q[3 * (size_t)m + j] = 0;
        t->fold_splits++;
      }
    }
  }
  free(e), he_free(&h);
  return st;
}

/* What is wrong with face f: 2 fold, 1 area, 0 nothing; err: |straight / spherical area - 1|
 * (NaN for a pole face or a face of no spherical area). */
static int face_state(const au__tex_work *w, au_tex_proj proj, int f, double sigma, double tol, double *err,
                      double *straight) {
  const int *c = w->t->F + 3 * (size_t)f;
  const double *Q = w->Q;
  double As = au__sph_tri_area(Q + 3 * (size_t)c[0], Q + 3 * (size_t)c[1], Q + 3 * (size_t)c[2]);
  double xy[6];
  int which[3];
  int pole = au__tex_face_raw(w, proj, f, xy, which);
  double At = 0.5 * ((xy[2] - xy[0]) * (xy[5] - xy[1]) - (xy[4] - xy[0]) * (xy[3] - xy[1]));
  *straight = At;
  *err = NAN;
  if (!(fabs(As) > 0)) return 0; /* corners coincide on the sphere: nothing a split could mend */
  if (sigma * At <= 1e-9 * fabs(As)) return 2;
  if (pole) return 0;
  /* A sliver along a great circle (spherical area under half its chordal triangle's) has almost
   * no spherical area whatever its size: its relative error says nothing about the projection. */
  const double *a = Q + 3 * (size_t)c[0], *b = Q + 3 * (size_t)c[1], *d = Q + 3 * (size_t)c[2];
  double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  if (fabs(As) < 0.25 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])) return 0;
  *err = fabs(At / As - 1);
  return *err > tol ? 1 : 0;
}

/* The longest edge of face f, by its chord on the sphere: its first corner's slot. */
static int longest_edge(const au__tex_work *w, int f) {
  const int *c = w->t->F + 3 * (size_t)f;
  int best = 0;
  double lmax = -1;
  for (int k = 0; k < 3; k++) {
    const double *p = w->Q + 3 * (size_t)c[k], *q = w->Q + 3 * (size_t)c[(k + 1) % 3];
    double l = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
    if (l > lmax) lmax = l, best = k;
  }
  return best;
}

/* Where to split the edge (a, b) of a turned-over face with third corner c: at the surface point
 * whose image is the foot of c on the arc (a, b), so the two parts meet c across a short edge
 * nearly perpendicular to the arc and come out the right way round (a turned-over face is mostly a
 * sliver along the arc, whose midpoint split would leave two slivers). But when the foot lies
 * within AU_FOOT_END of an end (or past it), at the middle: the face is a needle (c next to a or b,
 * the shape every foot split leaves behind), and a split at the foot would only chip a sliver off
 * its end, leaving a needle nearly as long and still turned over; round after round the chips pile
 * up along the arc (an unconverged cow map near the cea south pole: 61 folds after 64 rounds, the
 * long needles shrinking 2-10% a round). Halving it shortens it geometrically, and an image arc's
 * bend shrinks with the square of its length. */
#define AU_FOOT_END 0.1
static double foot_param(const au__tex_work *w, int a, int b, int c) {
  const double *qa = w->Q + 3 * (size_t)a, *qb = w->Q + 3 * (size_t)b, *qc = w->Q + 3 * (size_t)c;
  const double *ca = w->C + 3 * (size_t)a, *cb = w->C + 3 * (size_t)b;
  double n[3] = {qa[1] * qb[2] - qa[2] * qb[1], qa[2] * qb[0] - qa[0] * qb[2], qa[0] * qb[1] - qa[1] * qb[0]};
  double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  if (!(nn > 0)) return 0.5;
  double k = (qc[0] * n[0] + qc[1] * n[1] + qc[2] * n[2]) / nn, f[3];
  for (int j = 0; j < 3; j++) f[j] = qc[j] - k * n[j];
  /* f = alpha C_a + beta C_b (both in the arc's plane); the split parameter is beta / (alpha + beta). */
  double g11 = ca[0] * ca[0] + ca[1] * ca[1] + ca[2] * ca[2], g22 = cb[0] * cb[0] + cb[1] * cb[1] + cb[2] * cb[2];
  double g12 = ca[0] * cb[0] + ca[1] * cb[1] + ca[2] * cb[2];
  double r1 = ca[0] * f[0] + ca[1] * f[1] + ca[2] * f[2], r2 = cb[0] * f[0] + cb[1] * f[1] + cb[2] * f[2];
  double det = g11 * g22 - g12 * g12;
  if (!(det > 0)) return 0.5;
  double al = (r1 * g22 - r2 * g12) / det, be = (r2 * g11 - r1 * g12) / det;
  if (!(al + be > 0)) return 0.5;
  double p = be / (al + be);
  return p < AU_FOOT_END || p > 1 - AU_FOOT_END ? 0.5 : p;
}

/* The map's orientation: the sign of the sum of the spherical areas. */
static double map_sign(const au__tex_work *w) {
  double s = 0;
  for (int f = 0; f < w->t->nf; f++) {
    const int *c = w->t->F + 3 * (size_t)f;
    s += au__sph_tri_area(w->Q + 3 * (size_t)c[0], w->Q + 3 * (size_t)c[1], w->Q + 3 * (size_t)c[2]);
  }
  return s < 0 ? -1.0 : 1.0;
}

/* The worst-first area splitting (au__tex_refine's worst_first): per round the faces whose straight
 * area misses their spherical one the most are split first, until a 1/AU_AREA_SHARE of the remaining
 * growth budget is spent. The per-face mean counts a face at 0.3 like a hundred at 0.003, and
 * rounds over every face above the tolerance spent the 8x budget with the worst ones (caps whose apex
 * lies near their long edge) still whole: spot, spherical-areas map, laea with --area-tol auto, 1385
 * of 47308 faces above 0.1 held half the projection's error (bench/texture_split_diag.c). Each split
 * follows the longest-edge propagation path (Rivara): splitting a face's longest edge together with
 * whatever edge that is of its neighbour made needles and slivers that no later split mends (oct:
 * 0.0196 -> 0.0423 without it). Neither rule wins everywhere (the splits concentrate where the
 * projection bends, and the per-face mean then weights the map's error there more), so
 * au_tex_coords_opts makes both and keeps the better (docs/textures.md). */
#define AU_AREA_SHARE 4

typedef struct err_idx {
  double e;
  int i;
} err_idx;

static int cmp_err_desc(const void *a, const void *b) {
  const err_idx *x = a, *y = b;
  if (x->e != y->e) return x->e < y->e ? 1 : -1;
  return (x->i > y->i) - (x->i < y->i);
}

static int cmp_int(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

/* ord [0..n-1] (indices into err) sorted by err, largest first (ties by index: the same order on
 * every run). Returns 0, or -1 when out of memory. */
static int sort_by_error(int *ord, int n, const double *err) {
  err_idx *p = malloc((size_t)(n > 0 ? n : 1) * sizeof *p);
  if (!p) return -1;
  for (int k = 0; k < n; k++) p[k].e = err[ord[k]], p[k].i = ord[k];
  qsort(p, (size_t)n, sizeof *p, cmp_err_desc);
  for (int k = 0; k < n; k++) ord[k] = p[k].i;
  free(p);
  return 0;
}

/* Is (a, b) the longest edge of face f (by its chord)? */
static int is_longest(const au__tex_work *w, int f, int a, int b) {
  const int *c = w->t->F + 3 * (size_t)f;
  int k = longest_edge(w, f);
  return (c[k] == a && c[(k + 1) % 3] == b) || (c[k] == b && c[(k + 1) % 3] == a);
}

/* Split the edge (a0, b0) by longest-edge propagation (Rivara): walk from its face across longest
 * edges until two faces share their longest edge, split that at the middle, and repeat until
 * (a0, b0) itself is split. Keeps the pieces' angles bounded, where splitting a face's longest edge
 * together with whatever edge of its neighbour that is makes needles. Returns 1, 0 (the edge is
 * gone), -1 (out of memory). */
static int lepp_split(au__tex_work *w, he_table *h, int a0, int b0, int *count) {
  for (int guard = 0; guard < 64; guard++) {
    int *fp = he_find(h, a0, b0);
    if (!fp || *fp < 0) return guard > 0;
    int a = a0, b = b0;
    for (int depth = 0; depth < 64; depth++) {
      int *gp = he_find(h, b, a);
      if (!gp || *gp < 0) break;
      int g = *gp;
      if (is_longest(w, g, a, b)) break;
      const int *c = w->t->F + 3 * (size_t)g;
      int k = longest_edge(w, g);
      a = c[k], b = c[(k + 1) % 3];
    }
    int r = split_edge(w, h, a, b, 0.5);
    if (r < 0) return -1;
    if (r == 0) return guard > 0;
    (*count)++;
  }
  return 1;
}

/* The area splits of one round, of the bad faces that are not folds (bad [3 per face]: the edge's
 * ends, fold flag; berr: their errors): every one at its edge's middle, or (worst_first) the worst
 * first by longest-edge propagation within the round's budget. Returns 0, or -1 when out of memory. */
static int area_splits(au__tex_work *w, he_table *h, const int *bad, const double *berr, int nbad,
                       const au__tex_area *plan, int nf0) {
  int worst_first = plan->worst_first;
  au_tex_mesh *t = w->t;
  if (!worst_first) {
    for (int j = 0; j < nbad; j++) {
      if (bad[3 * j + 2]) continue;
      int r = split_edge(w, h, bad[3 * j], bad[3 * j + 1], 0.5);
      if (r < 0) return -1;
      t->area_splits += r;
    }
    return 0;
  }
  int *ord = malloc((size_t)(nbad > 0 ? nbad : 1) * sizeof *ord), na = 0;
  if (!ord) return -1;
  for (int j = 0; j < nbad; j++)
    if (!bad[3 * j + 2]) ord[na++] = j;
  int rc = sort_by_error(ord, na, berr);
  long stop = t->nf + ((long)plan->growth * nf0 - t->nf) / AU_AREA_SHARE;
  if (plan->target > 0 && stop > t->nf + t->nf / AU_TARGET_STEP) stop = t->nf + t->nf / AU_TARGET_STEP;
  for (int i = 0; rc == 0 && i < na && t->nf < stop; i++)
    if (lepp_split(w, h, bad[3 * ord[i]], bad[3 * ord[i] + 1], &t->area_splits) < 0) rc = -1;
  free(ord);
  return rc;
}

static const char *pname(au_tex_proj p) { return p == AU_TEX_CEA ? "cea" : p == AU_TEX_LAEA ? "laea" : "oct"; }

/* The per-face mean |straight chart area share / surface share - 1| of the faces, from their signed
 * straight areas in the chart (At, as face_state measures them): the texture's per-face error
 * (vt_error in au_texture.c) before the coordinates are written, since every chart's raw units are
 * proportional to the vt ones. A face turned over in its chart (sigma: the map's orientation), which
 * the next round splits, counts as 1 and stays out of the shares: across oct's gutter its straight
 * triangle can span the square. */
static double chart_error(const au__tex_work *w, const double *At, double sigma) {
  const au_tex_mesh *t = w->t;
  double sc = 0, ss = 0, e = 0;
  for (int pass = 0; pass < 2; pass++)
    for (int f = 0; f < t->nf; f++) {
      const int *c = t->F + 3 * (size_t)f;
      const double *x = t->X + 3 * (size_t)c[0], *y = t->X + 3 * (size_t)c[1], *z = t->X + 3 * (size_t)c[2];
      double u[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]}, v[3] = {z[0] - x[0], z[1] - x[1], z[2] - x[2]};
      double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
      double as = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), at = sigma * At[f];
      if (pass == 0 && at > 0) ss += as, sc += at;
      if (pass == 1) e += at > 0 ? fabs((at / sc) / (as / ss) - 1) : 1;
    }
  return t->nf ? e / t->nf : 0;
}

/* The faces touched since the last scan, once each, in increasing order, into *list (n: out); the log
 * is emptied. Returns 0 when out of memory. */
static int take_touched(he_table *h, int **list, int *n) {
  int *p = realloc(*list, (h->ntouched > 0 ? h->ntouched : 1) * sizeof *p);
  if (!p) return 0;
  *list = p;
  if (h->ntouched) memcpy(p, h->touched, h->ntouched * sizeof *p);
  qsort(p, h->ntouched, sizeof *p, cmp_int);
  int k = 0;
  for (size_t i = 0; i < h->ntouched; i++)
    if (k == 0 || p[k - 1] != p[i]) p[k++] = p[i];
  *n = k, h->ntouched = 0;
  return 1;
}

/* The splitting's state across rounds (au__tex_refine). */
typedef struct refine_state {
  au__tex_work *w;
  const au_tex_opts *opts;
  au__tex_area *plan;
  he_table h;
  int *bad, nbad, badcap; /* bad [3 per face]: the face, its state (face_state), then its edge's ends */
  double *berr;           /* [badcap]: an area-bad face's |straight / spherical area - 1|; a fold's inf */
  double sigma;           /* the map's orientation */
  int nf0;                /* the faces before any split */
  int nf_best;            /* the faces when the texture's error was lowest, best_e */
  double best_e;
  int area_done;          /* the target (met, or given up) ended the area splitting */
  double *straight;       /* with a target: each face's signed straight area in its chart (chart_error) */
  int *scan, nscan;       /* a repair round's faces: those the last splits touched */
  int last_folds, rising; /* folds of the last round; rounds in a row with more than the last */
  int low_folds, low_round; /* the fewest folds since the last round of area splits or without folds, and
                               the round they were seen (or that round) */
} refine_state;

/* Look at the faces (all, or in a repair round the touched ones) and list the bad ones: folds, and
 * with area_on those above the tolerance. Returns the folds, or -1 when out of memory. */
static int scan_round(refine_state *r, int repair, int area_on) {
  au_tex_mesh *t = r->w->t;
  if (repair && !take_touched(&r->h, &r->scan, &r->nscan)) return -1;
  if (!repair) r->h.ntouched = 0;
  free(r->straight), r->straight = NULL;
  if (area_on && r->plan->target > 0 && !(r->straight = malloc((size_t)t->nf * sizeof *r->straight))) return -1;
  int folds = 0, n = repair ? r->nscan : t->nf, ne = 0;
  double emax = 0, esum = 0;
  r->nbad = 0;
  for (int i = 0; i < n; i++) {
    int f = repair ? r->scan[i] : i;
    double e, at;
    int s = face_state(r->w, r->opts->proj, f, r->sigma, area_on ? r->plan->tol : INFINITY, &e, &at);
    if (r->straight) r->straight[f] = at;
    if (e == e) emax = fmax(emax, e), esum += e, ne++;
    if (!s) continue;
    folds += s == 2;
    if (r->nbad == r->badcap) {
      int cap = 2 * r->badcap + 64;
      int *b = realloc(r->bad, 3 * (size_t)cap * sizeof *b);
      if (b) r->bad = b;
      double *be = realloc(r->berr, (size_t)cap * sizeof *be);
      if (be) r->berr = be;
      if (!b || !be) return -1;
      r->badcap = cap;
    }
    r->bad[3 * r->nbad] = f, r->bad[3 * r->nbad + 1] = s, r->berr[r->nbad] = s == 2 ? INFINITY : e;
    r->nbad++;
  }
  if (!repair) t->area_err_max = emax, t->area_err_mean = ne ? esum / ne : 0;
  t->folds_left = folds;
  return folds;
}

/* With a target, after a full scan: measured only on a fold-free round (next to a fold the faces are
 * not yet the texture's: on bumpy_star's oct texture a face beside a crease fold came out at 3000x
 * its share, and 1 after the fold's split), so a round with folds mends them alone. Then stop at the
 * target, or when the error has not gone down while the faces grew AU_TARGET_STALL times (where the
 * splits only add slivers, as near oct's creases on bumpy_star, more would spend faces). Stopping
 * drops the area-bad faces from the list. */
static void target_round(refine_state *r, int folds) {
  const au_tex_mesh *t = r->w->t;
  int stop = 1;
  if (folds == 0) {
    double e = chart_error(r->w, r->straight, r->sigma);
    stop = e == e && e <= r->plan->target;
    if (e == e && e < r->best_e) r->best_e = e, r->nf_best = t->nf;
    else if (t->nf > AU_TARGET_STALL * (long)r->nf_best) stop = 1;
    r->area_done = stop;
  }
  if (stop) {
    int k = 0;
    for (int j = 0; j < r->nbad; j++)
      if (r->bad[3 * j + 1] == 2) r->bad[3 * k] = r->bad[3 * j], r->bad[3 * k + 1] = 2, r->berr[k++] = r->berr[j];
    r->nbad = k;
  }
}

/* The ways a splitting gives up on its folds: AU_E_NUMERIC with the reason, else AU_OK. since: the
 * rounds that count (with a target, those after the last area split). */
static au_status give_up(refine_state *r, int round, int since, int folds, au_msg *msg) {
  const char *p = pname(r->opts->proj);
  r->rising = folds > r->last_folds ? r->rising + 1 : 0;
  r->last_folds = folds;
  /* A round of area splits, or one without folds (area splits only), starts the count again: the
   * folds that follow are new ones. */
  if (since == 0 || folds == 0) r->low_folds = INT_MAX, r->low_round = round;
  else if (folds < r->low_folds) r->low_folds = folds, r->low_round = round;
  if (r->rising >= AU_FOLD_RUNAWAY)
    return au_msg_set(msg, AU_E_NUMERIC, "au_tex_coords: projection %s: the folds multiply under splitting (%d after %d rounds)",
                      p, folds, round);
  if (round - r->low_round >= AU_FOLD_STALL || since >= AU_FOLD_ROUNDS)
    return au_msg_set(msg, AU_E_NUMERIC,
                      "au_tex_coords: projection %s: %d faces stay turned over in the texture after %d rounds of splitting "
                      "(%s may avoid them)", p, folds, round,
                      r->opts->axis == AU_TEX_AXIS_AUTO ? "another projection" : "a different texture axis, --axis auto,");
  if (r->w->t->nf > AU_FOLD_GROWTH * r->nf0)
    return au_msg_set(msg, AU_E_NUMERIC,
                      "au_tex_coords: projection %s: %d faces stay turned over in the texture after splitting to %d faces", p,
                      folds, r->w->t->nf);
  return AU_OK;
}

/* Split the listed faces: folds first at their foot points (so that an edge asked for by a fold is
 * split there), then the area splits. The faces' corners and the split points are read before any
 * split of the round changes them. Returns 0, or -1 when out of memory. */
static int split_round(refine_state *r) {
  au__tex_work *w = r->w;
  au_tex_mesh *t = w->t;
  double *sp = malloc((size_t)(r->nbad > 0 ? r->nbad : 1) * sizeof *sp);
  if (!sp) return -1;
  int *bad = r->bad, rc = 0;
  for (int i = 0; i < r->nbad; i++) {
    int f = bad[3 * i], fold = bad[3 * i + 1] == 2, k = longest_edge(w, f);
    /* a fold whose edge cannot be split (no face across it) is looked at again, not lost */
    if (fold && !he_touch(&r->h, f)) rc = -1;
    const int *c = t->F + 3 * (size_t)f;
    bad[3 * i] = c[k], bad[3 * i + 1] = c[(k + 1) % 3], bad[3 * i + 2] = fold;
    sp[i] = fold ? foot_param(w, c[k], c[(k + 1) % 3], c[(k + 2) % 3]) : 0.5;
  }
  for (int j = 0; j < r->nbad && rc == 0; j++) {
    if (!bad[3 * j + 2]) continue;
    int s = split_edge(w, &r->h, bad[3 * j], bad[3 * j + 1], sp[j]);
    if (s < 0) rc = -1;
    else t->fold_splits += s;
  }
  free(sp);
  if (rc == 0 && area_splits(w, &r->h, bad, r->berr, r->nbad, r->plan, r->nf0)) rc = -1;
  return rc;
}

au_status au__tex_refine(au__tex_work *w, const au_tex_opts *opts, au__tex_area *plan, au_msg *msg) {
  au_tex_mesh *t = w->t;
  refine_state r;
  memset(&r, 0, sizeof r);
  r.w = w, r.opts = opts, r.plan = plan, r.sigma = map_sign(w), r.best_e = INFINITY;
  au_status st = AU_OK;
  r.nf0 = r.nf_best = t->nf; /* the budgets count from the faces before oct's crease splits */
  if (opts->proj == AU_TEX_OCT) {
    st = oct_creases(w, msg);
    if (st != AU_OK) return st;
  }
  if (!he_build(&r.h, t)) {
    he_free(&r.h);
    return au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
  }
  /* A round after splits that no area split can follow (only folds are left to mend) looks at the
   * faces those splits touched alone: a face no split touched keeps its corners and its state. The
   * mending used to scan every face for a handful of folds, round after round (lion statue, cea:
   * 60 rounds over 0.1-1M faces for 1-80 folds each). */
  int repair = 0, area_rounds = 0, last_area = 0;
  for (int round = 0;; round++) {
    st = au__tex_raw_update(w, opts->proj, msg);
    if (st != AU_OK) break;
    int area_open = !r.area_done && (plan->stop_nf <= 0 || t->nf < plan->stop_nf) &&
                    (plan->target > 0 ? area_rounds : round) < opts->max_rounds && t->nf < (long)plan->growth * r.nf0 &&
                    plan->tol > 0;
    int area_on = area_open && !repair;
    int folds = scan_round(&r, repair, area_on);
    if (folds < 0) {
      st = au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
      break;
    }
    if (area_on && plan->target > 0) target_round(&r, folds);
    int area_split = area_on && r.nbad > folds;
    if (area_split) area_rounds++, last_area = round;
    if (r.nbad == 0) {
      /* Nothing left to mend: done, unless the area splitting may go on (a full scan next). */
      if (!repair || !area_open) break;
      repair = 0;
      continue;
    }
    st = give_up(&r, round, round - (plan->target > 0 ? last_area : 0), folds, msg);
    if (st != AU_OK) break;
    if (split_round(&r)) {
      st = au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
      break;
    }
    /* Without a target a round splits for area and folds alike while the area splitting lasts
     * (every face is looked at each round); with one, the folds are mended before the error is
     * measured again. */
    repair = plan->target > 0 ? 1 : !area_open || !area_split;
  }
  if (st == AU_OK && repair) {
    /* The statistics of the final faces (the last round looked at some only). */
    double emax = 0, esum = 0, e, at;
    int ne = 0;
    for (int f = 0; f < t->nf; f++) {
      face_state(w, opts->proj, f, r.sigma, INFINITY, &e, &at);
      if (e == e) emax = fmax(emax, e), esum += e, ne++;
    }
    t->area_err_max = emax, t->area_err_mean = ne ? esum / ne : 0;
  }
  plan->best_e = r.best_e, plan->best_nf = r.nf_best;
  t->edge_splits = t->fold_splits + t->area_splits;
  he_free(&r.h);
  free(r.bad), free(r.berr), free(r.straight), free(r.scan);
  return st;
}

/* ---------------------------------------------------------------- the axis */

/* The rotation whose rows are the texture's x, y, z axes in the map's frame: z = a (unit), x the
 * direction at angle beta about a from a fixed perpendicular (the map's z or, for an axis near it,
 * the map's x, made perpendicular to a). */
static void frame(const double a[3], double beta, double R[9]) {
  double ref[3] = {0, 0, 1};
  if (fabs(a[2]) > 0.99) ref[0] = 1, ref[2] = 0;
  double d = ref[0] * a[0] + ref[1] * a[1] + ref[2] * a[2], b1[3], b2[3];
  for (int j = 0; j < 3; j++) b1[j] = ref[j] - d * a[j];
  double n = sqrt(b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2]);
  for (int j = 0; j < 3; j++) b1[j] /= n;
  b2[0] = a[1] * b1[2] - a[2] * b1[1], b2[1] = a[2] * b1[0] - a[0] * b1[2], b2[2] = a[0] * b1[1] - a[1] * b1[0];
  double c = cos(beta), s = sin(beta);
  for (int j = 0; j < 3; j++) {
    R[j] = c * b1[j] + s * b2[j];
    R[3 + j] = -s * b1[j] + c * b2[j];
    R[6 + j] = a[j];
  }
}

/* Mean spherical area of the faces whose centroids (unit vectors cen [0..3nf-1], areas A) lie within
 * AU_AXIS_CAP of the point a, with the face nearest to a always counted. */
#define AU_AXIS_CAP (10 * M_PI / 180)
static double cap_mean_area(int nf, const double *cen, const double *A, const double a[3]) {
  double cc = cos(AU_AXIS_CAP), sum = 0, best = -2, Abest = 0;
  int n = 0;
  for (int f = 0; f < nf; f++) {
    const double *q = cen + 3 * (size_t)f;
    double d = q[0] * a[0] + q[1] * a[1] + q[2] * a[2];
    if (d >= cc) sum += A[f], n++;
    if (d > best) best = d, Abest = A[f];
  }
  return n ? sum / n : Abest;
}

/* The angle beta about the axis that puts the seam where it crosses the fewest faces: cea's seam is
 * the meridian at longitude 180 degrees, oct's the four southern half meridians at 0, 90, 180, 270
 * (counted modulo 90 on faces with a southern corner); laea's seam, the equator, does not turn. */
static au_status seam_angle(au_tex_proj proj, const double a[3], int nv, const double *P, int nf, const int *F,
                            double *beta, au_msg *msg) {
  *beta = 0;
  if (proj == AU_TEX_LAEA) return AU_OK;
  double R[9];
  frame(a, 0, R);
  double *lon = malloc((size_t)nv * sizeof *lon), *z = malloc((size_t)nv * sizeof *z);
  if (!lon || !z) {
    free(lon), free(z);
    return au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
  }
  for (int i = 0; i < nv; i++) {
    const double *p = P + 3 * (size_t)i;
    double x = R[0] * p[0] + R[1] * p[1] + R[2] * p[2], y = R[3] * p[0] + R[4] * p[1] + R[5] * p[2];
    z[i] = R[6] * p[0] + R[7] * p[1] + R[8] * p[2];
    lon[i] = atan2(y, x) * 180 / M_PI;
  }
  int period = proj == AU_TEX_OCT ? 90 : 360;
  long cnt[360] = {0};
  for (int f = 0; f < nf; f++) {
    const int *c = F + 3 * (size_t)f;
    if (proj == AU_TEX_OCT && z[c[0]] >= 0 && z[c[1]] >= 0 && z[c[2]] >= 0) continue;
    double lo = lon[c[0]], hi = lo;
    for (int k = 1; k < 3; k++) {
      double d = lon[c[k]] - lon[c[0]];
      d -= 360 * nearbyint(d / 360);
      lo = fmin(lo, lon[c[0]] + d), hi = fmax(hi, lon[c[0]] + d);
    }
    if (hi - lo >= 180) continue; /* a face around the pole crosses every meridian alike */
    for (long d = (long)ceil(lo); d <= (long)floor(hi); d++) cnt[((d % period) + period) % period]++;
  }
  int best = 0;
  for (int d = 1; d < period; d++)
    if (cnt[d] < cnt[best]) best = d;
  /* The seam at the map-frame longitude `best` (+ 180 for cea's, whose seam is at 180): the new x
   * axis turns by best - 180 (cea) or best (oct). */
  *beta = (proj == AU_TEX_CEA ? best - 180 : best) * M_PI / 180;
  free(lon), free(z);
  return AU_OK;
}

au_status au__tex_axis(const au_tex_opts *opts, int nv, const double *P, int nf, const int *F, double R[9],
                       au_msg *msg) {
  static const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  if (opts->axis == AU_TEX_AXIS_Z) {
    memcpy(R, I, sizeof I);
    return AU_OK;
  }
  double a[3] = {opts->axis_dir[0], opts->axis_dir[1], opts->axis_dir[2]};
  if (opts->axis == AU_TEX_AXIS_VECTOR) {
    double n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    if (!(n > 0) || !isfinite(n)) return au_msg_set(msg, AU_E_ARG, "au_tex_coords: the axis is zero or not finite");
    for (int j = 0; j < 3; j++) a[j] /= n;
    frame(a, 0, R);
    return AU_OK;
  }
  /* AU_TEX_AXIS_AUTO: the poles where the map's triangles are smallest (least mean spherical area of
   * the faces within 10 degrees of the two poles, over 500 Fibonacci directions), then the seam. */
  double *cen = malloc(3 * (size_t)nf * sizeof *cen), *A = malloc((size_t)nf * sizeof *A);
  if (!cen || !A) {
    free(cen), free(A);
    return au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
  }
  for (int f = 0; f < nf; f++) {
    const double *p0 = P + 3 * (size_t)F[3 * f], *p1 = P + 3 * (size_t)F[3 * f + 1], *p2 = P + 3 * (size_t)F[3 * f + 2];
    double *q = cen + 3 * (size_t)f, s = 0;
    for (int j = 0; j < 3; j++) q[j] = p0[j] + p1[j] + p2[j], s += q[j] * q[j];
    s = sqrt(s);
    for (int j = 0; j < 3; j++) q[j] = s > 0 ? q[j] / s : 0;
    A[f] = fabs(au__sph_tri_area(p0, p1, p2));
  }
  enum { NDIR = 500 };
  double best = INFINITY, ga = M_PI * (3 - sqrt(5.0));
  for (int i = 0; i < NDIR; i++) {
    double z = 1 - (2 * i + 1.0) / NDIR, r = sqrt(1 - z * z), d[3] = {r * cos(ga * i), r * sin(ga * i), z};
    double md[3] = {-d[0], -d[1], -d[2]};
    double cost = cap_mean_area(nf, cen, A, d) + cap_mean_area(nf, cen, A, md);
    if (cost < best) best = cost, a[0] = d[0], a[1] = d[1], a[2] = d[2];
  }
  free(cen), free(A);
  double beta;
  au_status st = seam_angle(opts->proj, a, nv, P, nf, F, &beta, msg);
  if (st == AU_OK) frame(a, beta, R);
  return st;
}
