/* au_sphere_ml.c - the coarse-to-fine start of the sphere map (docs/coarse-to-fine.md).
 *
 * A conformal start squeezes every protrusion exponentially (Zou et al. 2011, sec. 6), and the flow then
 * spends most of its steps, retries and polishes opening them up. Here the mesh is simplified by
 * half-edge collapses (u into v, v keeps its place) to a few hundred vertices, keeping the topology
 * (link condition) and the faces' orientation on the surface; the coarse mesh is mapped by the sphere
 * pipeline, where a step costs next to nothing. The collapses are then undone in reverse order
 * (a progressive mesh, Hoppe 1996; Praun & Hoppe 2003 map one the same way), each vertex placed strictly
 * inside the kernel of its 1-ring on the sphere, so no triangle can fold, where its ring keeps the surface's
 * shape (mean-value coordinates in the ring flattened from the surface); after every level (about twice
 * the vertices of the one before) a few flow steps bring the map back towards equal area. Placed by shape
 * rather than by local areas, the start has far fewer long edges and a smoother error, which the fine flow
 * removes faster, but it squeezes the thin parts that the coarser levels do not resolve (bunny's ear tips:
 * e^-4.5; docs/coarse-to-fine-placement.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_dec.h"
#include "au_solver.h"
#include "au_sphere.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Each level has at least this many times the vertices of the one before. */
#define AU_ML_LEVEL_GROWTH 2.0
/* A collapse is refused when it turns a face's surface normal by more than acos of this: the coarse
 * surface keeps the fine one's shape, so its areas stay the fine areas' sums. */
#define AU_ML_NORMAL_COS 0.2
/* ... or makes a face of a quality (quality()) below this and below the face's before: the coarse mesh's
 * conformal map folds on obtuse slivers (cow at 300 vertices: 4 folded triangles without it). */
#define AU_ML_MIN_QUALITY 0.2
/* A vertex moves towards its shape's point (shape_target) only as far as it stays in its kernel shrunk by this
 * factor about the kernel's centroid (or, already nearer an edge, no nearer): strictly inside, with room
 * for the flow's steps and the next vertices. 0.3 let edges grow (bunny: 298 edges over 4x the surface's),
 * 0.8 and 0.95 squeezed faces further (bunny's worst start face e^-5.1, e^-10.1 against e^-4.5). */
#define AU_ML_KERNEL_KEEP 0.5
/* Sweeps of the placement over every vertex once the last is back (Gauss-Seidel, each vertex towards its
 * shape's point inside its kernel): spiky_ico's map per-face 0.0220 -> 0.0192, cow's 0.0178 -> 0.0167,
 * spot_lowres's 0.0122 -> 0.0117, bunny's 0.0067 -> 0.0069; five: spiky_ico 0.0181, cow 0.0168. */
#define AU_ML_FINE_SWEEPS 2
/* The shear weight's floor in the coarse map's and the levels' flows (the flow's own default is 0.01):
 * triangles kept near their surface shapes leave every re-inserted vertex room in its ring. */
#define AU_ML_SHEAR_TAIL 0.3
/* Coarse meshes tried, from the coarsest level up, until one's conformal map does not fold. */
#define AU_ML_COARSE_TRIES 3
/* The area placement's start: at most this part of the way from the kernel's centroid to its edge. */
#define AU_ML_AREA_KEEP 0.7
/* Gauss-Newton steps of a vertex's area placement (place_opt; coarse_progressive's levels). */
#define AU_ML_PLACE_STEPS 8
/* The weight of a placed vertex's triangles' shapes (log of the sum of squared edges over the area, against
 * the surface triangle's) beside their areas in the area placement: areas alone make needles, whose rings
 * later leave a vertex no room. */
#define AU_ML_SHAPE 0.5
/* The placement leaves a vertex with more faces than this where it is (and a re-inserted one makes the
 * start fall back to the conformal one). */
#define AU_ML_STAR_MAX 64

typedef struct ml_rec {
  int u, v;       /* u was collapsed into v */
  int f0, f1;     /* the two faces that died */
  int mod, nmod;  /* the corners (3f + k) where u became v: mods[mod .. mod + nmod - 1] */
} ml_rec;

typedef struct ivec {
  int *a, n, cap;
} ivec;

static int ivec_push(ivec *v, int x) {
  if (v->n == v->cap) {
    int cap = v->cap ? 2 * v->cap : 8;
    int *a = realloc(v->a, sizeof(int) * (size_t)cap);
    if (!a) return -1;
    v->a = a, v->cap = cap;
  }
  v->a[v->n++] = x;
  return 0;
}

static void ivec_remove(ivec *v, int x) {
  for (int i = 0; i < v->n; i++)
    if (v->a[i] == x) {
      v->a[i] = v->a[--v->n];
      return;
    }
}

typedef struct ml_state {
  int nv, nf;
  const double *X;
  int *F;              /* the faces as the collapses have left them */
  unsigned char *fdead, *vdead;
  ivec *vf;            /* each vertex's live faces */
  int *stamp, tick;    /* neighbour marks */
  ml_rec *rec;
  int nrec, caprec;
  ivec mods;
  int topo_only;       /* 1: collapses keep the topology only (coarse_map's levels below the coarse mesh) */
  int area_place;      /* 1: vertices are placed by their stars' areas (place_opt), not by their rings'
                        * surface shapes: below the coarse mesh, where topology-only collapses leave rings
                        * whose surface shapes mean nothing */
} ml_state;

static void sub3(const double *a, const double *b, double *d) { d[0] = a[0] - b[0], d[1] = a[1] - b[1], d[2] = a[2] - b[2]; }
static void cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}
static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double det3(const double *a, const double *b, const double *c) {
  double n[3];
  cross3(b, c, n);
  return dot3(a, n);
}

static void face_normal(const double *X, int a, int b, int c, double *n) {
  double e1[3], e2[3];
  sub3(X + 3 * b, X + 3 * a, e1), sub3(X + 3 * c, X + 3 * a, e2);
  cross3(e1, e2, n);
}

/* 2 sqrt(3) x twice the area over the sum of the squared edges: 1 for an equilateral triangle, 0 for a
 * degenerate one. n2: twice the area. */
static double quality(const double *X, int a, int b, int c, double n2) {
  double e[3];
  double sum = 0;
  sub3(X + 3 * b, X + 3 * a, e), sum += dot3(e, e);
  sub3(X + 3 * c, X + 3 * b, e), sum += dot3(e, e);
  sub3(X + 3 * a, X + 3 * c, e), sum += dot3(e, e);
  return sum > 0 ? 2 * sqrt(3.0) * n2 / sum : 0;
}

/* Try to collapse u into v; returns 1 if done, 0 if refused, -1 out of memory. */
static int try_collapse(ml_state *s, int u, int v) {
  const ivec *fu = &s->vf[u], *fv = &s->vf[v];
  int common_faces = 0, opp[2] = {-1, -1};
  for (int i = 0; i < fu->n; i++) {
    const int *c = s->F + 3 * fu->a[i];
    if (c[0] == v || c[1] == v || c[2] == v) {
      if (common_faces < 2) opp[common_faces] = c[0] != u && c[0] != v ? c[0] : c[1] != u && c[1] != v ? c[1] : c[2];
      common_faces++;
    }
  }
  if (common_faces != 2) return 0;
  if (s->vf[opp[0]].n < 4 || s->vf[opp[1]].n < 4 || fu->n + fv->n - 4 < 3) return 0;
  /* The link condition: u and v share exactly the two opposite vertices. */
  s->tick++;
  for (int i = 0; i < fu->n; i++)
    for (int k = 0; k < 3; k++) s->stamp[s->F[3 * fu->a[i] + k]] = s->tick;
  int shared = 0;
  s->tick++;
  for (int i = 0; i < fv->n; i++)
    for (int k = 0; k < 3; k++) {
      int w = s->F[3 * fv->a[i] + k];
      if (w != u && w != v && s->stamp[w] == s->tick - 1) s->stamp[w] = s->tick, shared++;
    }
  if (shared != 2) return 0;
  /* The surface's faces keep their sides. */
  for (int i = 0; i < fu->n && !s->topo_only; i++) {
    const int *c = s->F + 3 * fu->a[i];
    if (c[0] == v || c[1] == v || c[2] == v) continue;
    double n0[3], n1[3];
    face_normal(s->X, c[0], c[1], c[2], n0);
    int d[3] = {c[0] == u ? v : c[0], c[1] == u ? v : c[1], c[2] == u ? v : c[2]};
    face_normal(s->X, d[0], d[1], d[2], n1);
    const double l0 = sqrt(dot3(n0, n0)), l1 = sqrt(dot3(n1, n1));
    if (!(l1 > 1e-12 * l0) || !(dot3(n0, n1) > AU_ML_NORMAL_COS * l0 * l1)) return 0;
    const double q0 = quality(s->X, c[0], c[1], c[2], l0), q1 = quality(s->X, d[0], d[1], d[2], l1);
    if (q1 < AU_ML_MIN_QUALITY && q1 < q0) return 0;
  }
  if (s->nrec == s->caprec) {
    int cap = s->caprec ? 2 * s->caprec : 1024;
    ml_rec *r = realloc(s->rec, sizeof(ml_rec) * (size_t)cap);
    if (!r) return -1;
    s->rec = r, s->caprec = cap;
  }
  ml_rec *r = &s->rec[s->nrec];
  r->u = u, r->v = v, r->f0 = r->f1 = -1, r->mod = s->mods.n, r->nmod = 0;
  for (int i = 0; i < fu->n; i++) {
    const int f = fu->a[i];
    int *c = s->F + 3 * f;
    if (c[0] == v || c[1] == v || c[2] == v) {
      if (r->f0 < 0) r->f0 = f;
      else r->f1 = f;
      s->fdead[f] = 1;
      for (int k = 0; k < 3; k++)
        if (c[k] != u) ivec_remove(&s->vf[c[k]], f);
    } else {
      for (int k = 0; k < 3; k++)
        if (c[k] == u) {
          c[k] = v;
          if (ivec_push(&s->mods, 3 * f + k) < 0 || ivec_push(&s->vf[v], f) < 0) return -1;
          r->nmod++;
        }
    }
  }
  s->vf[u].n = 0, s->vdead[u] = 1;
  s->nrec++;
  return 1;
}

typedef struct ml_edge {
  double len;
  int a, b;
} ml_edge;

static int edge_cmp(const void *x, const void *y) {
  const ml_edge *a = x, *b = y;
  return a->len < b->len ? -1 : a->len > b->len;
}

/* Rounds of collapses of the shortest edges, no two in a round touching one ring, down to about target
 * vertices. level[] (room for 64) receives the number of collapses at which each level ends, finest first
 * (level[0] = nrec, the fine mesh), *nlevel their count. Returns 0, -1 out of memory. */
static int simplify(ml_state *s, int nlive, int target, int *level, int *nlevel) {
  ml_edge *E = malloc(sizeof(ml_edge) * 3 * (size_t)s->nf);
  unsigned char *touched = calloc((size_t)s->nv, 1);
  int *count = malloc(sizeof(int) * 256), *at = malloc(sizeof(int) * 256), nround = 0, ret = 0;
  if (!E || !touched || !count || !at) ret = -1;
  count[0] = nlive, at[0] = s->nrec;
  while (ret == 0 && nlive > target && nround < 255) {
    int ne = 0;
    for (int f = 0; f < s->nf; f++) {
      if (s->fdead[f]) continue;
      for (int k = 0; k < 3; k++) {
        int a = s->F[3 * f + k], b = s->F[3 * f + (k + 1) % 3];
        if (a > b) continue;
        double d[3];
        sub3(s->X + 3 * a, s->X + 3 * b, d);
        E[ne].len = dot3(d, d), E[ne].a = a, E[ne].b = b, ne++;
      }
    }
    qsort(E, (size_t)ne, sizeof *E, edge_cmp);
    memset(touched, 0, (size_t)s->nv);
    int done = 0;
    for (int i = 0; i < ne && nlive > target; i++) {
      int a = E[i].a, b = E[i].b;
      if (touched[a] || touched[b] || s->vdead[a] || s->vdead[b]) continue;
      /* Remove the vertex with fewer faces: its ring is the smaller polygon to re-insert into. */
      int u = s->vf[a].n <= s->vf[b].n ? a : b, v = u == a ? b : a;
      int c = try_collapse(s, u, v);
      if (c == 0) u = v, v = u == a ? b : a, c = try_collapse(s, u, v);
      if (c < 0) {
        ret = -1;
        break;
      }
      if (c == 0) continue;
      const ivec *fv = &s->vf[v];
      for (int j = 0; j < fv->n; j++)
        for (int k = 0; k < 3; k++) touched[s->F[3 * fv->a[j] + k]] = 1;
      nlive--, done++;
    }
    if (!done) break;
    nround++;
    count[nround] = nlive, at[nround] = s->nrec;
  }
  /* Levels: from the coarsest, a boundary wherever the vertices have grown by the factor. */
  int n = 0;
  if (ret == 0) {
    int tmp[64], last = count[nround];
    tmp[n++] = at[nround];
    for (int r = nround - 1; r >= 0 && n < 63; r--)
      if (r == 0 || (double)count[r] >= AU_ML_LEVEL_GROWTH * last) {
        if (r > 0 && (double)count[0] < AU_ML_LEVEL_GROWTH * count[r]) continue; /* the fine level is near */
        tmp[n++] = at[r], last = count[r];
      }
    /* tmp: coarse first; level: fine first. */
    for (int i = 0; i < n; i++) level[i] = tmp[n - 1 - i];
  }
  *nlevel = n;
  free(E), free(touched), free(count), free(at);
  return ret;
}

/* The live part of the mesh as a mesh of its own: vertex map old -> new (-1 dead) in vmap, new -> old
 * in vold; faces in sub->F. Returns 0, -1 out of memory. */
static int extract(const ml_state *s, au_mesh *sub, int *vmap, int *vold) {
  int nv = 0, nf = 0;
  for (int i = 0; i < s->nv; i++) vmap[i] = s->vdead[i] ? -1 : nv++;
  for (int f = 0; f < s->nf; f++) nf += !s->fdead[f];
  sub->nv = nv, sub->nf = nf;
  sub->X = malloc(sizeof(double) * 3 * (size_t)nv), sub->F = malloc(sizeof(int) * 3 * (size_t)nf);
  if (!sub->X || !sub->F) return -1;
  for (int i = 0; i < s->nv; i++)
    if (vmap[i] >= 0) vold[vmap[i]] = i, memcpy(sub->X + 3 * vmap[i], s->X + 3 * i, sizeof(double) * 3);
  nf = 0;
  for (int f = 0; f < s->nf; f++)
    if (!s->fdead[f])
      for (int k = 0; k < 3; k++) sub->F[3 * nf + k] = vmap[s->F[3 * f + k]], nf += k == 2;
  return 0;
}

/* Clip the convex polygon (x, y pairs, *n corners) by a x + b y + d >= 0. */
static void clip(double *poly, int *n, double *tmp, double a, double b, double d) {
  int m = 0;
  for (int i = 0; i < *n; i++) {
    const double *p = poly + 2 * i, *q = poly + 2 * ((i + 1) % *n);
    const double hp = a * p[0] + b * p[1] + d, hq = a * q[0] + b * q[1] + d;
    if (hp >= 0) tmp[2 * m] = p[0], tmp[2 * m + 1] = p[1], m++;
    if ((hp >= 0) != (hq >= 0)) {
      const double t = hp / (hp - hq);
      tmp[2 * m] = p[0] + t * (q[0] - p[0]), tmp[2 * m + 1] = p[1] + t * (q[1] - p[1]), m++;
    }
  }
  memcpy(poly, tmp, sizeof(double) * 2 * (size_t)m);
  *n = m;
}

/* The placement of a vertex w in the chart of the plane tangent at c (p = c + x e1 + y e2; the kernel's
 * constraints n . p > 0 are homogeneous in p, so the chart needs no normalization). */
typedef struct place_ctx {
  const ml_state *s;
  const int *faces;   /* w's star */
  int nstar, w;
  const double *P, *c, *e1, *e2;
  const double *H;    /* per star face: the kernel's half-plane H0 x + H1 y + H2 > 0 */
} place_ctx;

/* The residuals log(A_i / (share_i x sum A)) of the star's chord areas A_i at (x, y), share_i the face's
 * part of the star's surface area; res may be NULL. Returns their sum of squares, or INFINITY outside the
 * kernel. */
static double place_cost(const place_ctx *pc, double x, double y, double *res) {
  double A[AU_ML_STAR_MAX], S[AU_ML_STAR_MAX], Q[AU_ML_STAR_MAX], QS[AU_ML_STAR_MAX], sa = 0, ss = 0, p[3];
  for (int i = 0; i < pc->nstar; i++)
    if (pc->H[3 * i] * x + pc->H[3 * i + 1] * y + pc->H[3 * i + 2] <= 0) return INFINITY;
  for (int k = 0; k < 3; k++) p[k] = pc->c[k] + x * pc->e1[k] + y * pc->e2[k];
  const double l = sqrt(dot3(p, p));
  p[0] /= l, p[1] /= l, p[2] /= l;
  for (int i = 0; i < pc->nstar; i++) {
    const int *fc = pc->s->F + 3 * pc->faces[i];
    const int k = fc[0] == pc->w ? 0 : fc[1] == pc->w ? 1 : 2;
    const int a = fc[(k + 1) % 3], b = fc[(k + 2) % 3];
    double da[3], db[3], n[3];
    sub3(pc->P + 3 * a, p, da), sub3(pc->P + 3 * b, p, db), cross3(da, db, n);
    const double chord = sqrt(dot3(n, n));
    /* The spherical triangle's area, which vanishes where the chord one need not: on a great circle. */
    A[i] = 2 * atan2(det3(p, pc->P + 3 * a, pc->P + 3 * b), 1 + dot3(p, pc->P + 3 * a) + dot3(pc->P + 3 * a, pc->P + 3 * b) +
                                                           dot3(pc->P + 3 * b, p));
    if (!(A[i] > 0)) return INFINITY;
    double ab[3];
    sub3(pc->P + 3 * b, pc->P + 3 * a, ab);
    Q[i] = (dot3(da, da) + dot3(db, db) + dot3(ab, ab)) / chord;
    face_normal(pc->s->X, pc->w, a, b, n);
    S[i] = sqrt(dot3(n, n));
    double xa[3], xb[3];
    sub3(pc->s->X + 3 * a, pc->s->X + 3 * pc->w, xa), sub3(pc->s->X + 3 * b, pc->s->X + 3 * pc->w, xb), sub3(xb, xa, ab);
    QS[i] = (dot3(xa, xa) + dot3(xb, xb) + dot3(ab, ab)) / S[i];
    sa += A[i], ss += S[i];
  }
  double e = 0;
  for (int i = 0; i < pc->nstar; i++) {
    const double q = A[i] > 0 && S[i] > 0 ? log((A[i] / sa) / (S[i] / ss)) : INFINITY;
    const double qs = A[i] > 0 && S[i] > 0 ? AU_ML_SHAPE * log(Q[i] / QS[i]) : INFINITY;
    if (res) res[2 * i] = q, res[2 * i + 1] = qs;
    e += q * q + qs * qs;
  }
  return e;
}

/* A few Gauss-Newton steps on place_cost from (*x, *y), each halved until the cost falls; h: the
 * kernel's size, for the finite differences. */
static void place_opt(const place_ctx *pc, double *x, double *y, double h) {
  if (!(h > 0)) return;
  double r0[2 * AU_ML_STAR_MAX], rx[2 * AU_ML_STAR_MAX], ry[2 * AU_ML_STAR_MAX];
  const double d = 1e-5 * h;
  double e = place_cost(pc, *x, *y, r0);
  for (int it = 0; it < AU_ML_PLACE_STEPS && isfinite(e) && e > 1e-8; it++) {
    if (!isfinite(place_cost(pc, *x + d, *y, rx)) || !isfinite(place_cost(pc, *x, *y + d, ry))) return;
    double a11 = 0, a12 = 0, a22 = 0, b1 = 0, b2 = 0;
    for (int i = 0; i < 2 * pc->nstar; i++) {
      const double jx = (rx[i] - r0[i]) / d, jy = (ry[i] - r0[i]) / d;
      a11 += jx * jx, a12 += jx * jy, a22 += jy * jy, b1 -= jx * r0[i], b2 -= jy * r0[i];
    }
    const double damp = 1e-6 * (a11 + a22), det = (a11 + damp) * (a22 + damp) - a12 * a12;
    if (!(det > 0)) return;
    double sx = (b1 * (a22 + damp) - b2 * a12) / det, sy = ((a11 + damp) * b2 - a12 * b1) / det, t = 1;
    int moved = 0;
    for (int k = 0; k < 20 && !moved; k++, t *= 0.5) {
      const double e2 = place_cost(pc, *x + t * sx, *y + t * sy, rx);
      if (e2 < e) *x += t * sx, *y += t * sy, e = e2, memcpy(r0, rx, sizeof(double) * 2 * (size_t)pc->nstar), moved = 1;
    }
    if (!moved) return;
  }
}

/* The point of w's chart (c; e1, e2) that keeps the surface's shape of w's ring: the ring flattened about
 * w (the angles at w scaled to 2 pi, the lengths kept), w's mean-value coordinates in it (Floater 2003),
 * and that combination of the ring's chart positions (Praun & Hoppe 2003 place by shape and leave the
 * areas to the optimization; here the flow does the areas). Returns 0, or -1 where a ring vertex is not
 * in front of the chart or the ring is degenerate. */
static int shape_target(const ml_state *s, int w, const int *faces, int nstar, const double *P, const double *c,
                        const double *e1, const double *e2, double *tx, double *ty) {
  double ang[AU_ML_STAR_MAX], tot = 0;
  for (int i = 0; i < nstar; i++) {
    const int *fc = s->F + 3 * faces[i];
    const int k = fc[0] == w ? 0 : fc[1] == w ? 1 : 2;
    double xa[3], xb[3], n[3];
    sub3(s->X + 3 * fc[(k + 1) % 3], s->X + 3 * w, xa), sub3(s->X + 3 * fc[(k + 2) % 3], s->X + 3 * w, xb);
    cross3(xa, xb, n);
    ang[i] = atan2(sqrt(dot3(n, n)), dot3(xa, xb));
    tot += ang[i];
  }
  if (!(tot > 0)) return -1;
  double sx = 0, sy = 0, sw = 0;
  for (int i = 0; i < nstar; i++) {
    const int *fc = s->F + 3 * faces[i];
    const int k = fc[0] == w ? 0 : fc[1] == w ? 1 : 2;
    /* The flattened angle, kept below pi so that every weight stays positive. */
    const double t = tan(0.5 * fmin(ang[i] * 2 * M_PI / tot, M_PI - 1e-3));
    for (int j = 1; j <= 2; j++) {
      const int a = fc[(k + j) % 3];
      double d[3];
      sub3(s->X + 3 * a, s->X + 3 * w, d);
      const double r = sqrt(dot3(d, d)), ca = dot3(P + 3 * a, c);
      if (!(r > 0) || !(ca > 1e-3)) return -1;
      const double wt = t / r;
      sx += wt * dot3(P + 3 * a, e1) / ca, sy += wt * dot3(P + 3 * a, e2) / ca, sw += wt;
    }
  }
  if (!(sw > 0)) return -1;
  *tx = sx / sw, *ty = sy / sw;
  return 0;
}

/* Place vertex w (star: its faces, nstar of them) inside the kernel of its ring on the sphere, at its shape's
 * point (shape_target) as far as the shrunk kernel allows (AU_ML_KERNEL_KEEP), or with s->area_place by
 * its star's areas (place_opt). fresh: w was just re-inserted
 * beside v (the chart is v's, whose closure touches the kernel; w starts at the kernel's centroid); else w
 * starts where it is, inside its kernel, and stays where its ring has no shape's point. Returns 0, or < 0
 * where the kernel is empty to rounding (P[w] unchanged unless fresh). */
static int place(const ml_state *s, int w, int v, const int *faces, int nstar, int fresh, double *P) {
  if (nstar > AU_ML_STAR_MAX) return fresh ? -1 : 0;
  double H[3 * AU_ML_STAR_MAX], poly[2 * (AU_ML_STAR_MAX + 4)], tmp[2 * (AU_ML_STAR_MAX + 4)];
  const double *c = P + 3 * (fresh ? v : w);
  double e1[3], e2[3], t[3] = {1, 0, 0};
  if (fabs(c[0]) > 0.6) t[0] = 0, t[1] = 1;
  cross3(c, t, e1);
  double l = sqrt(dot3(e1, e1));
  e1[0] /= l, e1[1] /= l, e1[2] /= l;
  cross3(c, e1, e2);
  double reach = 0, q[3] = {0, 0, 0}, wsum = 0;
  for (int i = 0; i < nstar; i++) {
    const int *fc = s->F + 3 * faces[i];
    const int k = fc[0] == w ? 0 : fc[1] == w ? 1 : 2;
    const int a = fc[(k + 1) % 3], b = fc[(k + 2) % 3];
    double n[3];
    cross3(P + 3 * a, P + 3 * b, n);
    const double ln = sqrt(dot3(n, n));
    if (!(ln > 0)) return fresh ? -1 : 0;
    H[3 * i] = dot3(n, e1) / ln, H[3 * i + 1] = dot3(n, e2) / ln, H[3 * i + 2] = dot3(n, c) / ln;
    const double ca = dot3(P + 3 * a, c);
    if (ca > 1e-3) {
      const double xa = dot3(P + 3 * a, e1) / ca, ya = dot3(P + 3 * a, e2) / ca;
      reach = fmax(reach, sqrt(xa * xa + ya * ya));
    } else reach = 1e3;
    if (s->area_place) {
      double d[3];
      sub3(s->X + 3 * a, s->X + 3 * w, d);
      const double wt = 1 / fmax(sqrt(dot3(d, d)), 1e-300);
      q[0] += wt * P[3 * a], q[1] += wt * P[3 * a + 1], q[2] += wt * P[3 * a + 2], wsum += wt;
    }
  }
  const double R = fmin(fmax(2 * reach, 1e-6), 1e3);
  double sq[8] = {-R, -R, R, -R, R, R, -R, R};
  memcpy(poly, sq, sizeof sq);
  int np = 4;
  for (int i = 0; i < nstar && np >= 3; i++) clip(poly, &np, tmp, H[3 * i], H[3 * i + 1], H[3 * i + 2]);
  if (np < 3) return fresh ? -2 : 0;
  double A = 0, gx = 0, gy = 0;
  for (int i = 0; i < np; i++) {
    const double *p0 = poly + 2 * i, *p1 = poly + 2 * ((i + 1) % np);
    const double cr = p0[0] * p1[1] - p1[0] * p0[1];
    A += cr, gx += (p0[0] + p1[0]) * cr, gy += (p0[1] + p1[1]) * cr;
  }
  if (!(A > 0)) return fresh ? -3 : 0;
  gx /= 3 * A, gy /= 3 * A;
  double px = 0, py = 0;
  if (fresh) {
    double hmin = INFINITY;
    for (int i = 0; i < nstar; i++) hmin = fmin(hmin, H[3 * i] * gx + H[3 * i + 1] * gy + H[3 * i + 2]);
    if (!(hmin > 0)) return -4;
    px = gx, py = gy;
  }
  if (s->area_place) {
    /* A fresh vertex starts towards its ring's corners weighted by their inverse surface distance, at most
     * AU_ML_AREA_KEEP of the way to the kernel's edge; then Gauss-Newton on its star's areas and shapes. */
    const double qc = fresh && wsum > 0 ? dot3(q, c) : 0;
    if (qc > 0) {
      const double qx = dot3(q, e1) / qc - gx, qy = dot3(q, e2) / qc - gy;
      double smax = INFINITY;
      for (int i = 0; i < nstar; i++) {
        const double h = H[3 * i] * gx + H[3 * i + 1] * gy + H[3 * i + 2], dh = H[3 * i] * qx + H[3 * i + 1] * qy;
        if (dh < 0) smax = fmin(smax, -h / dh);
      }
      const double sgo = fmin(1, AU_ML_AREA_KEEP * smax);
      px += sgo * qx, py += sgo * qy;
    }
    place_ctx pc = {s, faces, nstar, w, P, c, e1, e2, H};
    if (!fresh && !isfinite(place_cost(&pc, 0, 0, NULL))) return 0;
    place_opt(&pc, &px, &py, sqrt(A / 2));
  } else {
    double tx, ty;
    if (shape_target(s, w, faces, nstar, P, c, e1, e2, &tx, &ty) == 0) {
      /* Along the segment towards the shape's point, each half-plane keeps at least (1 - keep) of its value at
       * the centroid, or its value at the start where that is less: the shrunk kernel, never left nearer an
       * edge than before. */
      const double qx = tx - px, qy = ty - py;
      double go = 1;
      for (int i = 0; i < nstar; i++) {
        const double h = H[3 * i] * px + H[3 * i + 1] * py + H[3 * i + 2], dh = H[3 * i] * qx + H[3 * i + 1] * qy;
        const double hg = H[3 * i] * gx + H[3 * i + 1] * gy + H[3 * i + 2], low = fmin((1 - AU_ML_KERNEL_KEEP) * hg, h);
        if (dh < 0) go = fmin(go, fmax(0, (h - low) / -dh));
      }
      px += go * qx, py += go * qy;
    } else if (!fresh)
      return 0;
  }
  double old[3];
  memcpy(old, P + 3 * w, sizeof old);
  double *p = P + 3 * w;
  for (int k = 0; k < 3; k++) p[k] = c[k] + px * e1[k] + py * e2[k];
  l = sqrt(dot3(p, p));
  p[0] /= l, p[1] /= l, p[2] /= l;
  /* The check in the flow's own terms. */
  for (int i = 0; i < nstar; i++) {
    const int *fc = s->F + 3 * faces[i];
    if (!(au_dec_sphere_orient(P + 3 * fc[0], P + 3 * fc[1], P + 3 * fc[2]) > 0)) {
      memcpy(P + 3 * w, old, sizeof old);
      return fresh ? -5 : 0;
    }
  }
  return 0;
}

/* Undo collapse r's topology (faces and face lists), placing nothing. Returns 0, -1 out of memory. */
static int unsplit(ml_state *s, const ml_rec *r) {
  const int u = r->u, v = r->v;
  s->fdead[r->f0] = s->fdead[r->f1] = 0, s->vdead[u] = 0;
  for (int i = 0; i < r->nmod; i++) {
    const int f = s->mods.a[r->mod + i] / 3;
    s->F[s->mods.a[r->mod + i]] = u;
    ivec_remove(&s->vf[v], f);
    if (ivec_push(&s->vf[u], f) < 0) return -1;
  }
  for (int j = 0; j < 2; j++) {
    const int f = j ? r->f1 : r->f0;
    for (int k = 0; k < 3; k++)
      if (ivec_push(&s->vf[s->F[3 * f + k]], f) < 0) return -1;
  }
  return 0;
}

/* Undo collapse r (the face lists too), place u inside its ring's kernel, then let v and u settle in
 * theirs. Returns 0, or < 0 where u's kernel is empty to rounding. */
static int split(ml_state *s, const ml_rec *r, double *P) {
  const int u = r->u, v = r->v;
  if (unsplit(s, r) < 0) return -1;
  int e = place(s, u, v, s->vf[u].a, s->vf[u].n, 1, P);
  if (e < 0) return e;
  /* u's ring settles (one Gauss-Seidel pass, v first), then u once more. */
  place(s, v, v, s->vf[v].a, s->vf[v].n, 0, P);
  int ring[AU_ML_STAR_MAX], nr = 0;
  for (int i = 0; i < s->vf[u].n && nr < AU_ML_STAR_MAX; i++) {
    const int *fc = s->F + 3 * s->vf[u].a[i];
    const int k = fc[0] == u ? 0 : fc[1] == u ? 1 : 2;
    if (fc[(k + 1) % 3] != v) ring[nr++] = fc[(k + 1) % 3];
  }
  for (int i = 0; i < nr; i++) place(s, ring[i], ring[i], s->vf[ring[i]].a, s->vf[ring[i]].n, 0, P);
  place(s, u, u, s->vf[u].a, s->vf[u].n, 0, P);
  return 0;
}

static void free_state(ml_state *s) {
  free(s->F), free(s->fdead), free(s->vdead), free(s->stamp), free(s->rec), free(s->mods.a);
  if (s->vf)
    for (int i = 0; i < s->nv; i++) free(s->vf[i].a);
  free(s->vf);
}

au_sphere_ml_opts au_sphere_ml_opts_default(void) {
  au_sphere_ml_opts o = {300, 3};
  return o;
}

/* Run the flow on the live part of the mesh with positions from P (by vold), then write them back. */
static au_status level_flow(const ml_state *s, const au_sphere_opts *o, int steps, double *P, int *nsteps, au_msg *msg) {
  au_mesh sub = {0};
  int *vmap = malloc(sizeof(int) * (size_t)s->nv), *vold = malloc(sizeof(int) * (size_t)s->nv);
  double *Ps = NULL, *wv = NULL;
  au_topo *t = NULL;
  au_status st = AU_OK;
  if (!vmap || !vold || extract(s, &sub, vmap, vold) < 0 || !(Ps = malloc(sizeof(double) * 3 * (size_t)sub.nv))) {
    st = au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
    goto done;
  }
  for (int i = 0; i < sub.nv; i++) memcpy(Ps + 3 * i, P + 3 * vold[i], sizeof(double) * 3);
  st = au_mesh_topology(&sub, &t, msg);
  if (st != AU_OK) goto done;
  au_advect_opts fo = o->flow;
  if (o->flow.weight) {
    if (!(wv = malloc(sizeof(double) * (size_t)sub.nv))) {
      st = au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
      goto done;
    }
    for (int i = 0; i < sub.nv; i++) wv[i] = o->flow.weight[vold[i]];
    fo.weight = wv;
  }
  fo.progress = NULL, fo.max_steps = steps;
  /* The levels' flows keep their shape restoring: every level's start is sheared and near equal area. */
  fo.sphere_areas = 2, fo.shear_tail = AU_ML_SHEAR_TAIL, fo.angle_steps = 0, fo.restore_gate = 0;
  au_advect_plain_schedule(&fo);
  au_advect_report *rep = malloc(sizeof *rep);
  if (!rep) {
    st = au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
    goto done;
  }
  au_advect_domain dom = au_sphere_domain();
  if (steps > 0) st = au_advect_run(&sub, t, &dom, &fo, Ps, rep, msg);
  else rep->steps = 0;
  *nsteps += rep->steps;
  free(rep);
  if (st == AU_W_NOT_CONVERGED) st = AU_OK;
  if (st == AU_OK)
    for (int i = 0; i < sub.nv; i++) memcpy(P + 3 * vold[i], Ps + 3 * i, sizeof(double) * 3);
done:
  au_topo_free(&t);
  free(sub.X), free(sub.F), free(vmap), free(vold), free(Ps), free(wv);
  return st;
}

/* The progressive coarse map (coarse_progressive): a conformal map squeezes a limb by e^(-2 pi length /
 * girth) whatever the resolution, so the coarse mesh's conformal start folds where the fine one does
 * (limbs4, limbs8, coil, hammer, tpose; bunny, hand_closed, airplane and cow at 300 vertices). A Tutte
 * embedding squeezes a limb the same way (limbs4 at 300 vertices: plane triangles of 1e-35), but of a
 * tetrahedron, with no limb left, it folds nowhere (Tutte 1963; Floater 2003); the limbs then come back
 * one vertex at a time, each given room by the flow at its level (docs/coarse-to-fine-coarse-map.md). */
/* Flow steps at most on the coarse mesh itself (a coarse step costs a millisecond). */
#define AU_ML_COARSE_STEPS 150
/* The Tutte map is tried at these many scales (x 2^k about the median radius's, nearest first) before
 * its stereographic image is given up as folded. */
#define AU_ML_TUTTE_SCALES 13
/* The coarse mesh is simplified further, keeping its topology only, down to this many vertices, and mapped
 * from there (coarse_map). */
#define AU_ML_BASE_VERTICES 4
/* Flow steps after each level below the coarse mesh (a step there costs next to nothing). */
#define AU_ML_BASE_STEPS 10
/* Runs of the flow per level below and at the coarse mesh at most (coarse_map). */
#define AU_ML_FLOW_RUNS 8
/* ... while a run lowers the vertex error by this fraction. */
#define AU_ML_RUN_GAIN 0.02
/* coarse_progressive's map is given up above this vertex error (spherical triangles): from a coarse map that
 * far from equal area the map ends worse than from the conformal start (data/tpose.obj: coarse map at
 * 0.24 without the polish, the final map's vertex error 1.01 against 0.19; limbs8's coarse map at 0.060
 * ends as from the conformal start). */
#define AU_ML_COARSE_GATE 0.1
/* Sweeps of the vertex polish (au_sphere_vertex_polish, spherical triangles) of the coarse map at most. */
#define AU_ML_COARSE_POLISH 200

/* The face to pin as the Tutte embedding's outer triangle: the one whose centre is nearest the surface's
 * area centroid (a body's face, not a limb's: the limbs the pinned face is not on are the ones squeezed,
 * and the body holds the most surface). */
static int pinned_face(const au_mesh *m) {
  double c[3] = {0, 0, 0}, at = 0;
  for (int f = 0; f < m->nf; f++) {
    double n[3];
    face_normal(m->X, m->F[3 * f], m->F[3 * f + 1], m->F[3 * f + 2], n);
    const double a = sqrt(dot3(n, n));
    for (int k = 0; k < 3; k++)
      for (int d = 0; d < 3; d++) c[d] += a * m->X[3 * m->F[3 * f + k] + d] / 3;
    at += a;
  }
  for (int d = 0; d < 3; d++) c[d] = at > 0 ? c[d] / at : 0;
  int best = 0;
  double bd = INFINITY;
  for (int f = 0; f < m->nf; f++) {
    double g[3];
    for (int d = 0; d < 3; d++)
      g[d] = (m->X[3 * m->F[3 * f] + d] + m->X[3 * m->F[3 * f + 1] + d] + m->X[3 * m->F[3 * f + 2] + d]) / 3 - c[d];
    if (dot3(g, g) < bd) bd = dot3(g, g), best = f;
  }
  return best;
}

static int cmp_double(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The Tutte map of the base mesh m (closed, genus 0, a few vertices) into P (nv x 3, unit vectors): face
 * pinned_face() pinned as an equilateral triangle on the unit circle, every other vertex the average of
 * its neighbours (uniform weights: the tetrahedron comes out regular; one sparse solve, refined in
 * extended precision), then the inverse stereographic projection, scaled so that half the vertices lie
 * on each hemisphere, or by the nearest power of 2 of that at which no spherical triangle is turned over
 * (a planar triangle maps to a region bounded by circular arcs, the mesh's triangle is the one through its
 * corners; the pinned face, the disk's outside, must stay smaller than a hemisphere). Returns AU_OK,
 * AU_E_NOMEM, AU_E_FOLD (folded at every scale tried) or the solver's error. */

static au_status coarse_tutte(const au_mesh *m, const au_topo *t, double *P, au_msg *msg) {
  const int nv = m->nv, fp = pinned_face(m);
  double *w = malloc(sizeof(double) * (size_t)t->ne), *x = calloc(2 * (size_t)nv, sizeof(double));
  double *b = calloc(2 * (size_t)nv, sizeof(double)), *dx = malloc(sizeof(double) * 2 * (size_t)nv);
  double *rad = malloc(sizeof(double) * (size_t)nv);
  long double *xx = malloc(sizeof(long double) * 2 * (size_t)nv), *res = malloc(sizeof(long double) * 2 * (size_t)nv);
  unsigned char *fixed = calloc((size_t)nv, 1);
  au_solver *solver = NULL;
  au_status st = AU_OK;
  if (!w || !x || !b || !dx || !rad || !xx || !res || !fixed) {
    st = au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
    goto done;
  }
  for (int e = 0; e < t->ne; e++) w[e] = 1;
  /* The pinned face is the disk's outside: its corners go round clockwise. */
  for (int k = 0; k < 3; k++) {
    const int i = m->F[3 * fp + k];
    const double ang = M_PI / 2 - 2 * M_PI * k / 3;
    fixed[i] = 1, x[i] = cos(ang), x[nv + i] = sin(ang);
  }
  st = au_solver_create(nv, t->ne, t->E, fixed, AU_ORDER_FAST, &solver, msg);
  if (st == AU_OK) st = au_solver_factor(solver, w, NULL, msg);
  if (st == AU_OK) st = au_solver_solve(solver, 2, b, x, msg);
  for (int i = 0; i < 2 * nv; i++) xx[i] = x[i];
  /* Iterative refinement: the free rows' residuals in extended precision, corrections by the factor. */
  for (int it = 0; it < 3 && st == AU_OK; it++) {
    for (int i = 0; i < 2 * nv; i++) res[i] = 0, dx[i] = 0;
    for (int e = 0; e < t->ne; e++) {
      const int i = t->E[2 * e], j = t->E[2 * e + 1];
      for (int c = 0; c < 2; c++) {
        const long double d = (long double)w[e] * (xx[c * nv + i] - xx[c * nv + j]);
        res[c * nv + i] -= d, res[c * nv + j] += d;
      }
    }
    for (int i = 0; i < 2 * nv; i++) b[i] = (double)res[i];
    st = au_solver_solve(solver, 2, b, dx, msg);
    for (int i = 0; st == AU_OK && i < nv; i++)
      if (!fixed[i]) xx[i] += dx[i], xx[nv + i] += dx[nv + i];
  }
  if (st != AU_OK) goto done;
  int n = 0;
  for (int i = 0; i < nv; i++) rad[n++] = (double)sqrtl(xx[i] * xx[i] + xx[nv + i] * xx[nv + i]);
  qsort(rad, (size_t)n, sizeof(double), cmp_double);
  const double s0 = rad[n / 2] > 1e-3 ? 1 / rad[n / 2] : 1;
  int folds = m->nf;
  for (int k = 0; k < AU_ML_TUTTE_SCALES && folds > 0; k++) {
    /* Scales 2^0, 2^1, 2^-1, 2^2, ... times s0. */
    const long double s = (long double)s0 * powl(2, (k + 1) / 2 * (k % 2 ? 1 : -1));
    for (int i = 0; i < nv; i++) {
      /* v is reflected: the projection turns the plane's counter-clockwise over on the outward sphere. */
      const long double u = s * xx[i], v = -s * xx[nv + i], r2 = u * u + v * v;
      P[3 * i] = (double)(2 * u / (1 + r2)), P[3 * i + 1] = (double)(2 * v / (1 + r2));
      P[3 * i + 2] = (double)((r2 - 1) / (r2 + 1));
    }
    folds = 0;
    for (int f = 0; f < m->nf; f++)
      folds += !(au_dec_sphere_orient(P + 3 * m->F[3 * f], P + 3 * m->F[3 * f + 1], P + 3 * m->F[3 * f + 2]) > 0);
  }
  if (folds > 0) st = au_msg_set(msg, AU_E_FOLD, "sphere: the coarse Tutte map has %d folded triangles", folds);
done:
  au_solver_free(&solver);
  free(w), free(x), free(b), free(dx), free(rad), free(xx), free(res), free(fixed);
  return st;
}

/* The vertex mean |log r| of the live part of s in P: each vertex's third of its spherical triangles' area
 * over its third of their surface area (times weight[i], the per-vertex density, where not NULL), both as
 * shares of their totals. */
static double live_error(const ml_state *s, const double *weight, const double *P) {
  double *cell = calloc(2 * (size_t)s->nv, sizeof(double)), sd = 0, sx = 0, e = 0, wt = 0;
  if (!cell) return INFINITY;
  for (int f = 0; f < s->nf; f++) {
    if (s->fdead[f]) continue;
    const int *c = s->F + 3 * f;
    double n[3];
    face_normal(s->X, c[0], c[1], c[2], n);
    const double ax = 0.5 * sqrt(dot3(n, n)), ad = au_dec_sphere_area(P + 3 * c[0], P + 3 * c[1], P + 3 * c[2], NULL);
    for (int k = 0; k < 3; k++) cell[2 * c[k]] += ad / 3, cell[2 * c[k] + 1] += ax / 3;
    sd += ad, sx += ax;
  }
  if (weight) {
    sx = 0;
    for (int i = 0; i < s->nv; i++) cell[2 * i + 1] *= weight[i], sx += s->vdead[i] ? 0 : cell[2 * i + 1];
  }
  for (int i = 0; i < s->nv; i++)
    if (!s->vdead[i] && cell[2 * i] > 0 && cell[2 * i + 1] > 0)
      e += fabs(log((cell[2 * i] / sd) / (cell[2 * i + 1] / sx))), wt++;
  free(cell);
  return wt > 0 ? e / wt : INFINITY;
}

/* On the live part of s: its map by coarse_tutte into P (the other vertices at (0, 0, 1)), or, with
 * polish > 0, at most that many sweeps of the vertex polish of its spherical triangles on P (in, out). */
static au_status live_map(const ml_state *s, int polish, double tol, double *P, au_msg *msg) {
  au_mesh sub = {0};
  au_topo *tc = NULL;
  int *vmap = malloc(sizeof(int) * (size_t)s->nv), *vold = malloc(sizeof(int) * (size_t)s->nv);
  double *Pc = NULL;
  au_status st = AU_OK;
  if (!vmap || !vold || extract(s, &sub, vmap, vold) < 0 || !(Pc = malloc(sizeof(double) * 3 * (size_t)sub.nv)))
    st = au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
  if (st == AU_OK) st = au_mesh_topology(&sub, &tc, msg);
  if (st == AU_OK && polish > 0) {
    for (int i = 0; i < sub.nv; i++) memcpy(Pc + 3 * i, P + 3 * vold[i], sizeof(double) * 3);
    au_polish_opts po = {polish, 1, tol, NULL, 1};
    st = au_sphere_vertex_polish(&sub, tc, NULL, Pc, &po, NULL, msg);
  } else if (st == AU_OK) {
    st = coarse_tutte(&sub, tc, Pc, msg);
    if (st == AU_OK)
      for (int i = 0; i < s->nv; i++) P[3 * i] = 0, P[3 * i + 1] = 0, P[3 * i + 2] = 1;
  }
  if (st == AU_OK)
    for (int i = 0; i < sub.nv; i++) memcpy(P + 3 * vold[i], Pc + 3 * i, sizeof(double) * 3);
  au_topo_free(&tc);
  free(sub.X), free(sub.F), free(vmap), free(vold), free(Pc);
  return st;
}

/* The coarse mesh's map (the live part of s) into P (the other vertices at (0, 0, 1)) from the conformal
 * start: the sphere pipeline, as a start only: the spherical areas (a coarse triangle's chord runs far
 * beneath it), no lantern or staged retry nor polish, and a shear floor that keeps the triangles' shapes. */
static au_status coarse_conformal(const ml_state *s, const au_sphere_opts *o, double *P, int *steps, au_msg *msg) {
  au_mesh sub = {0};
  au_topo *tc = NULL;
  int *vmap = malloc(sizeof(int) * (size_t)s->nv), *vold = malloc(sizeof(int) * (size_t)s->nv);
  double *Pc = NULL;
  au_sphere_report *cr = malloc(sizeof *cr);
  au_status st = AU_OK;
  if (!vmap || !vold || !cr || extract(s, &sub, vmap, vold) < 0 || !(Pc = malloc(sizeof(double) * 3 * (size_t)sub.nv)))
    st = au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
  if (st == AU_OK) st = au_mesh_topology(&sub, &tc, msg);
  if (st == AU_OK) {
    au_sphere_opts co = *o;
    co.start = AU_SPHERE_START_CONFORMAL, co.flow.progress = NULL, co.flow.weight = NULL;
    /* twist_retry stays: where every conformal attempt folds (nested protrusions, tpose) the strong
     * twisted start is the coarse map's start. */
    co.lantern_retry = 0, co.vertex_polish = 0, co.global_polish = 0, co.staged_retry = 0;
    co.flow.sphere_areas = 2, co.flow.shear_tail = AU_ML_SHEAR_TAIL, co.flow.angle_steps = 0, co.flow.restore_gate = 0;
    au_advect_plain_schedule(&co.flow);
    st = au_sphere_map(&sub, tc, &co, Pc, NULL, cr, msg);
    if (st == AU_W_NOT_CONVERGED) st = AU_OK;
    if (st == AU_OK) {
      *steps = cr->flow.steps;
      for (int i = 0; i < s->nv; i++) P[3 * i] = 0, P[3 * i + 1] = 0, P[3 * i + 2] = 1;
      for (int i = 0; i < sub.nv; i++) memcpy(P + 3 * vold[i], Pc + 3 * i, sizeof(double) * 3);
    }
  }
  au_topo_free(&tc);
  free(sub.X), free(sub.F), free(vmap), free(vold), free(Pc), free(cr);
  return st;
}

/* The coarse mesh's map (the live part of s) into P (the other vertices at (0, 0, 1)) where its conformal
 * start folds. The coarse mesh is simplified further, keeping its topology only, to a base of a few
 * vertices (a tetrahedron where the collapses allow), which coarse_tutte maps without a squeeze worth the
 * name (no limb is left to squeeze); the collapses are then undone as the fine ones are (split), with
 * AU_ML_BASE_STEPS flow steps after each level, and the coarse mesh's map is flowed (at most
 * AU_ML_COARSE_STEPS), then polished vertex by vertex (not with a density, which the polish ignores).
 * The flows are of the spherical areas, with a shear floor that keeps the triangles' shapes. The collapses
 * below the coarse mesh are dropped from s at the end. Returns AU_OK, AU_W_NOT_CONVERGED (the coarse map
 * missed AU_ML_COARSE_GATE), AU_E_FOLD (no room for a vertex, or the base's Tutte map folded),
 * AU_E_NOMEM, or the flow's error. */
static au_status coarse_progressive(ml_state *s, const au_sphere_opts *o, double *P, int *steps, au_msg *msg) {
  const int n0 = s->nrec;
  int nlive = 0, level[64], nlevel = 0;
  for (int i = 0; i < s->nv; i++) nlive += !s->vdead[i];
  s->topo_only = 1;
  const int e = simplify(s, nlive, AU_ML_BASE_VERTICES, level, &nlevel);
  s->topo_only = 0;
  s->area_place = 1;
  if (e < 0) return au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
  *steps = 0;
  au_status st = live_map(s, 0, 0, P, msg);
  if (st == AU_OK) st = level_flow(s, o, AU_ML_BASE_STEPS, P, steps, msg);
  for (int L = nlevel - 2; st == AU_OK && L >= 0; L--) {
    for (int i = s->nrec - 1; i >= level[L]; i--) {
      const int r = split(s, &s->rec[i], P);
      if (r < 0) {
        st = r == -1 ? au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory")
                     : au_msg_set(msg, AU_E_FOLD, "sphere: the coarse map found no room for vertex %d", s->rec[i].u);
        break;
      }
    }
    if (st != AU_OK) break;
    s->nrec = level[L];
    /* The flow is restarted where it stops short of its budget while a run gains (an undone step ends
     * it on these small meshes long before it has converged); each run starts where the last one ended. */
    double err = live_error(s, o->flow.weight, P);
    for (int run = 0, used = 0; st == AU_OK && run < AU_ML_FLOW_RUNS; run++) {
      const int before = *steps;
      st = level_flow(s, o, L > 0 ? AU_ML_BASE_STEPS : AU_ML_COARSE_STEPS - used, P, steps, msg);
      used += *steps - before;
      const double e1 = live_error(s, o->flow.weight, P);
      if (!(e1 < (1 - AU_ML_RUN_GAIN) * err) || e1 <= o->flow.tol || used >= AU_ML_COARSE_STEPS - 1) break;
      err = e1;
    }
  }
  /* The flow stalls on the coarse mesh's few, long limbs (limbs4 at 0.027, limbs8 at 0.091); the vertex
   * polish takes the coarse map on from there (0.010, 0.060) for a fraction of a second. */
  if (st == AU_OK && !o->flow.weight) st = live_map(s, AU_ML_COARSE_POLISH, o->flow.tol, P, msg);
  if (st == AU_OK) {
    const double err = live_error(s, o->flow.weight, P);
    if (!(err <= AU_ML_COARSE_GATE))
      st = au_msg_set(msg, AU_W_NOT_CONVERGED, "sphere: the coarse map stayed at a vertex error of %.3f", err);
  }
  s->area_place = 0;
  /* On failure, the coarse mesh is restored for the caller's next try. */
  for (int i = s->nrec - 1; i >= n0; i--)
    if (unsplit(s, &s->rec[i]) < 0) return au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
  s->nrec = n0;
  return st;
}

/* The coarse mesh's map (the live part of s) into P: from the conformal start (coarse_conformal), or where
 * that folds (a limb squeezed below a double's rounding: the squeeze depends on the shape, not on the
 * resolution), coarse_progressive's. */
static au_status coarse_map(ml_state *s, const au_sphere_opts *o, double *P, int *steps, au_msg *msg) {
  au_status st = coarse_conformal(s, o, P, steps, msg);
  if (st == AU_E_FOLD) st = coarse_progressive(s, o, P, steps, msg);
  return st;
}

au_status au_sphere_multilevel(const au_mesh *m, const au_topo *t, const au_sphere_opts *o, double *P,
                               au_sphere_ml_report *rep, au_msg *msg) {
  if (!m || !t || !o || !P) return au_msg_set(msg, AU_E_ARG, "sphere: bad arguments");
  au_sphere_ml_report local;
  if (!rep) rep = &local;
  memset(rep, 0, sizeof *rep);
  if (o->flow.face_weight) return au_msg_set(msg, AU_E_ARG, "sphere: the coarse-to-fine start takes no per-face density");
  const au_sphere_ml_opts mo = o->ml.coarse_vertices > 0 ? o->ml : au_sphere_ml_opts_default();
  ml_state s;
  memset(&s, 0, sizeof s);
  s.nv = m->nv, s.nf = m->nf, s.X = m->X;
  s.F = malloc(sizeof(int) * 3 * (size_t)m->nf);
  s.fdead = calloc((size_t)m->nf, 1), s.vdead = calloc((size_t)m->nv, 1);
  s.vf = calloc((size_t)m->nv, sizeof(ivec)), s.stamp = calloc((size_t)m->nv, sizeof(int));
  int level[64], nlevel = 0, nlive = 0;
  au_status st = AU_OK;
  if (!s.F || !s.fdead || !s.vdead || !s.vf || !s.stamp) goto nomem;
  memcpy(s.F, m->F, sizeof(int) * 3 * (size_t)m->nf);
  for (int f = 0; f < m->nf; f++)
    for (int k = 0; k < 3; k++)
      if (ivec_push(&s.vf[m->F[3 * f + k]], f) < 0) goto nomem;
  for (int i = 0; i < m->nv; i++) nlive += s.vf[i].n > 0, s.vdead[i] = s.vf[i].n == 0;
  if (simplify(&s, nlive, mo.coarse_vertices, level, &nlevel) < 0) goto nomem;
  /* The coarse map, by the sphere pipeline from the conformal start. Where that start folds (obtuse coarse
   * triangles), the next finer level is the coarse mesh, up to AU_ML_COARSE_TRIES times. */
  int top = nlevel - 1;
  for (int tries = 0;; tries++) {
    st = coarse_map(&s, o, P, &rep->coarse_steps, msg);
    if ((st != AU_E_FOLD && st != AU_W_NOT_CONVERGED) || tries + 1 >= AU_ML_COARSE_TRIES || top <= 1) break;
    top--;
    for (int i = s.nrec - 1; i >= level[top]; i--)
      if (unsplit(&s, &s.rec[i]) < 0) goto nomem;
    s.nrec = level[top];
  }
  rep->coarse_vertices = nlive - s.nrec, rep->levels = top + 1;
  nlevel = top + 1;
  /* The levels, coarse to fine; the finest is left to the caller's flow. */
  for (int L = nlevel - 2; st == AU_OK && L >= 0; L--) {
    for (int i = s.nrec - 1; i >= level[L]; i--) {
      int e = split(&s, &s.rec[i], P);
      if (e < 0) {
        st = e == -1 ? au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory")
                     : au_msg_set(msg, AU_E_FOLD, "sphere: the coarse-to-fine start found no room for vertex %d", s.rec[i].u);
        break;
      }
    }
    if (st != AU_OK) break;
    s.nrec = level[L];
    if (o->flow.cancel && __atomic_load_n(o->flow.cancel, __ATOMIC_ACQUIRE)) {
      st = au_msg_set(msg, AU_E_CANCELLED, "cancelled");
      break;
    }
    if (L > 0) st = level_flow(&s, o, mo.level_steps, P, &rep->level_steps, msg);
  }
  /* The finest level gets no flow of its own: sweeps of the same placement over every vertex smooth it. */
  for (int it = 0; st == AU_OK && it < AU_ML_FINE_SWEEPS; it++)
    for (int w = 0; w < s.nv; w++)
      if (!s.vdead[w]) place(&s, w, w, s.vf[w].a, s.vf[w].n, 0, P);
  goto out;
nomem:
  st = au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
out:
  free_state(&s);
  return st;
}
