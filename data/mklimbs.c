/* mklimbs.c - generator of the thin-limbed test meshes in data/ (issue 21): round bodies with legs,
 * fingers and tails only a handful of triangles around, made of icosphere blobs joined by tubes
 * (needs only libm).
 *
 * A limb is a tube of rings of n vertices (n = its girth in edges, 5 to 8), each ring turned half a
 * step against the last so that the triangles are nearly equilateral. It leaves a blob through a hole
 * (the blob's faces around the vertex nearest to the limb's direction removed) and ends in a cone to
 * a tip vertex or in the hole of another blob (a hand). Two loops of different sizes are joined by
 * "zipping" them in the order of their angles about the tube's axis. Faces are oriented afterwards by
 * walking across edges from one face, then all flipped if the volume came out negative, so the
 * construction itself does not track orientation. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef AU_VERSION
#define AU_VERSION "0.1.0"
#endif

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* A growable triangle mesh: X is nv x 3, F is nf x 3 (0-based); dead[f] marks removed faces. */
typedef struct mesh {
  double *X;
  int *F;
  unsigned char *dead;
  unsigned char *holed; /* [0..nv-1] vertices of a face some hole removed: holes must not touch */
  int nv, nf, cv, cf;
} mesh;

static void die_nomem(void) {
  fprintf(stderr, "au_mklimbs: out of memory\n");
  exit(1);
}

static void *xrealloc(void *p, size_t n) {
  void *q = realloc(p, n);
  if (!q) die_nomem();
  return q;
}

static int add_v(mesh *m, const double *p) {
  if (m->nv == m->cv) {
    m->cv = m->cv ? 2 * m->cv : 256;
    m->X = xrealloc(m->X, sizeof(double) * 3 * (size_t)m->cv);
    m->holed = xrealloc(m->holed, (size_t)m->cv);
  }
  m->holed[m->nv] = 0;
  memcpy(m->X + 3 * (size_t)m->nv, p, 3 * sizeof(double));
  return m->nv++;
}

static void add_f(mesh *m, int a, int b, int c) {
  if (m->nf == m->cf) {
    m->cf = m->cf ? 2 * m->cf : 256;
    m->F = xrealloc(m->F, sizeof(int) * 3 * (size_t)m->cf);
    m->dead = xrealloc(m->dead, (size_t)m->cf);
  }
  int *f = m->F + 3 * (size_t)m->nf;
  f[0] = a, f[1] = b, f[2] = c;
  m->dead[m->nf++] = 0;
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1], c[1] = a[2] * b[0] - a[0] * b[2], c[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize3(double *a) {
  double n = sqrt(dot3(a, a));
  a[0] /= n, a[1] /= n, a[2] /= n;
}

/* Two unit vectors u, v completing the unit vector t to a right-handed frame. */
static void frame(const double *t, double *u, double *v) {
  double a[3] = {1, 0, 0};
  if (fabs(t[0]) > 0.8) a[0] = 0, a[1] = 1;
  double s = dot3(a, t);
  for (int k = 0; k < 3; k++) u[k] = a[k] - s * t[k];
  normalize3(u);
  cross3(t, u, v);
}

/* ---- icosphere blobs ---- */

static const int ico_f[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9},  {5, 11, 4},
                                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6},  {3, 6, 8},
                                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};

/* A blob: the faces [f0, f1) and vertices [v0, v1) of an icosphere scaled by the semi-axes ax about c. */
typedef struct blob {
  int v0, v1, f0, f1;
  double c[3], ax[3];
} blob;

/* Subdivided icosahedron on the unit sphere (level times, edge midpoints shared through a hash table),
 * then scaled to an ellipsoid with semi-axes ax about c. */
static blob add_blob(mesh *m, int level, const double *c, const double *ax) {
  blob b;
  b.v0 = m->nv, b.f0 = m->nf;
  memcpy(b.c, c, sizeof b.c), memcpy(b.ax, ax, sizeof b.ax);
  const double g = 1.6180339887498948482;
  const double iv[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                            {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (int i = 0; i < 12; i++) {
    double p[3] = {iv[i][0], iv[i][1], iv[i][2]};
    normalize3(p);
    add_v(m, p);
  }
  for (int i = 0; i < 20; i++) add_f(m, b.v0 + ico_f[i][0], b.v0 + ico_f[i][1], b.v0 + ico_f[i][2]);
  for (int l = 0; l < level; l++) {
    int nf0 = m->nf - b.f0;
    size_t cap = 1;
    while (cap < 4 * (size_t)nf0) cap *= 2;
    uint64_t *key = malloc(sizeof(uint64_t) * cap);
    int *val = malloc(sizeof(int) * cap), *F = malloc(sizeof(int) * 3 * (size_t)nf0);
    if (!key || !val || !F) die_nomem();
    memset(key, 0xff, sizeof(uint64_t) * cap);
    memcpy(F, m->F + 3 * (size_t)b.f0, sizeof(int) * 3 * (size_t)nf0);
    m->nf = b.f0;
    for (int f = 0; f < nf0; f++) {
      int mid[3];
      for (int e = 0; e < 3; e++) {
        int a = F[3 * f + e], c2 = F[3 * f + (e + 1) % 3];
        uint64_t k = a < c2 ? (uint64_t)a << 32 | (uint64_t)c2 : (uint64_t)c2 << 32 | (uint64_t)a;
        size_t h = (size_t)((k * 0x9E3779B97F4A7C15u) >> 20) & (cap - 1);
        while (key[h] != UINT64_MAX && key[h] != k) h = (h + 1) & (cap - 1);
        if (key[h] != k) {
          double p[3];
          for (int d = 0; d < 3; d++) p[d] = m->X[3 * a + d] + m->X[3 * c2 + d];
          normalize3(p);
          key[h] = k;
          val[h] = add_v(m, p);
        }
        mid[e] = val[h];
      }
      int a = F[3 * f], bb = F[3 * f + 1], cc = F[3 * f + 2];
      add_f(m, a, mid[0], mid[2]);
      add_f(m, mid[0], bb, mid[1]);
      add_f(m, mid[2], mid[1], cc);
      add_f(m, mid[0], mid[1], mid[2]);
    }
    free(F), free(key), free(val);
  }
  for (int i = b.v0; i < m->nv; i++)
    for (int d = 0; d < 3; d++) m->X[3 * i + d] = c[d] + ax[d] * m->X[3 * i + d];
  b.v1 = m->nv, b.f1 = m->nf;
  return b;
}

/* A closed loop of vertices (a hole's rim or a tube's ring). */
typedef struct loop {
  int *v;
  int n;
} loop;

/* Cut a hole into blob b towards the unit direction dir: the faces around the blob vertex whose
 * direction from the centre is nearest to dir are removed, and their rim is returned in order. */
static loop cut_hole(mesh *m, const blob *b, const double *dir) {
  int best = -1;
  double bd = -2;
  for (int i = b->v0; i < b->v1; i++) {
    double p[3];
    for (int d = 0; d < 3; d++) p[d] = (m->X[3 * i + d] - b->c[d]) / b->ax[d];
    normalize3(p);
    double s = dot3(p, dir);
    if (s > bd) bd = s, best = i;
  }
  /* Two holes that share a vertex would leave a vertex whose faces form two fans. */
  for (int f = b->f0; f < b->f1; f++) {
    const int *c = m->F + 3 * f;
    if ((c[0] == best || c[1] == best || c[2] == best) && (m->holed[c[0]] || m->holed[c[1]] || m->holed[c[2]])) {
      fprintf(stderr, "au_mklimbs: two holes touch (blob vertex %d); space the limbs further apart\n", best);
      exit(1);
    }
  }
  /* The rim: for each removed face (best, a, c) the edge a -> c; chained into a loop. */
  int nx = 0, *from = NULL, *to = NULL;
  for (int f = b->f0; f < b->f1; f++) {
    int *c = m->F + 3 * f;
    for (int k = 0; k < 3; k++)
      if (c[k] == best && !m->dead[f]) {
        m->dead[f] = 1;
        m->holed[c[0]] = m->holed[c[1]] = m->holed[c[2]] = 1;
        from = xrealloc(from, sizeof(int) * (size_t)(nx + 1)), to = xrealloc(to, sizeof(int) * (size_t)(nx + 1));
        from[nx] = c[(k + 1) % 3], to[nx] = c[(k + 2) % 3], nx++;
      }
  }
  loop l = {malloc(sizeof(int) * (size_t)nx), nx};
  if (!l.v) die_nomem();
  l.v[0] = from[0];
  for (int k = 1; k < nx; k++)
    for (int j = 0; j < nx; j++)
      if (from[j] == l.v[k - 1]) {
        l.v[k] = to[j];
        break;
      }
  free(from), free(to);
  return l;
}

/* The unwrapped angles of loop l's vertices about the axis (c, t) in the frame (u, v), in l's order,
 * turned into increasing order (the loop is reversed if it runs the other way). */
static double *loop_angles(const mesh *m, loop *l, const double *c, const double *u, const double *v) {
  double *a = malloc(sizeof(double) * (size_t)l->n);
  if (!a) die_nomem();
  for (int pass = 0; pass < 2; pass++) {
    double turn = 0;
    for (int k = 0; k < l->n; k++) {
      const double *p = m->X + 3 * l->v[k];
      double d[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
      a[k] = atan2(dot3(d, v), dot3(d, u));
      if (k > 0) {
        while (a[k] < a[k - 1] - M_PI) a[k] += 2 * M_PI;
        while (a[k] > a[k - 1] + M_PI) a[k] -= 2 * M_PI;
        turn += a[k] - a[k - 1];
      }
    }
    if (turn > 0) break;
    for (int i = 0, j = l->n - 1; i < j; i++, j--) {
      int s = l->v[i];
      l->v[i] = l->v[j], l->v[j] = s;
    }
  }
  return a;
}

/* Join loops A and B, both about the axis (c, t), by a band of |A| + |B| triangles: walking both in the
 * order of their angles, each triangle advances on the loop whose next vertex comes first. */
static void zip(mesh *m, loop *A, loop *B, const double *c, const double *t) {
  double u[3], v[3];
  frame(t, u, v);
  double *a = loop_angles(m, A, c, u, v), *b = loop_angles(m, B, c, u, v);
  /* B's start: its vertex nearest in angle to A's first, unwrapped to within pi of it. */
  int j0 = 0;
  double bd = INFINITY;
  for (int j = 0; j < B->n; j++) {
    double d = remainder(b[j] - a[0], 2 * M_PI);
    if (fabs(d) < bd) bd = fabs(d), j0 = j;
  }
  double *bb = malloc(sizeof(double) * (size_t)(B->n + 1));
  if (!bb) die_nomem();
  bb[0] = a[0] + remainder(b[j0] - a[0], 2 * M_PI);
  for (int k = 1; k <= B->n; k++) {
    int j = (j0 + k) % B->n, jp = (j0 + k - 1) % B->n;
    double d = b[j] - b[jp];
    while (d < 0) d += 2 * M_PI;
    bb[k] = bb[k - 1] + d;
  }
  int ia = 0, ib = 0;
  while (ia < A->n || ib < B->n) {
    double na = ia < A->n ? (ia + 1 < A->n ? a[ia + 1] : a[0] + 2 * M_PI) : INFINITY;
    double nb = ib < B->n ? bb[ib + 1] : INFINITY;
    int pa = A->v[ia % A->n], pb = B->v[(j0 + ib) % B->n];
    if (na <= nb) add_f(m, pa, A->v[(ia + 1) % A->n], pb), ia++;
    else add_f(m, pa, pb, B->v[(j0 + ib + 1) % B->n]), ib++;
  }
  free(a), free(b), free(bb);
}

/* ---- tubes ---- */

/* A tube's centre line: c(s), s in [0, len], with unit tangent t(s). */
typedef struct path {
  int kind;          /* 0: straight from p along d; 1: straight for `lead`, then a helix (a coil) */
  double p[3], d[3]; /* the start and the (first) direction */
  double lead;       /* coil: the straight part's length */
  double q[3], dh[3], e1[3], e2[3], rh, w, a; /* coil: axis through q along dh, radius rh, turn rate w and
                                                 advance a per unit length (a^2 + (rh w)^2 = 1) */
} path;

static void path_at(const path *P, double s, double *c, double *t) {
  if (P->kind == 0 || s <= P->lead) {
    for (int k = 0; k < 3; k++) c[k] = P->p[k] + s * P->d[k], t[k] = P->d[k];
    return;
  }
  double sg = s - P->lead, cs = cos(P->w * sg), sn = sin(P->w * sg);
  for (int k = 0; k < 3; k++) {
    c[k] = P->q[k] + P->a * sg * P->dh[k] + P->rh * (cs * P->e1[k] + sn * P->e2[k]);
    t[k] = P->a * P->dh[k] + P->rh * P->w * (-sn * P->e1[k] + cs * P->e2[k]);
  }
  normalize3(t);
}

/* A coil after a straight lead of length lead from p along the unit d: radius rh, pitch per turn. The
 * helix's axis is tilted so that its tangent at the start is d (no kink): with e1, ez unit vectors
 * orthogonal to d and to each other, the axis is a d - rh w ez and e2 = rh w d + a ez. */
static path coil_path(const double *p, const double *d, const double *e1, const double *ez, double lead, double rh,
                      double pitch) {
  path P = {0};
  P.kind = 1;
  P.lead = lead, P.rh = rh;
  P.w = 1.0 / sqrt(rh * rh + pitch * pitch / (4 * M_PI * M_PI));
  P.a = pitch * P.w / (2 * M_PI);
  const double b = rh * P.w;
  for (int k = 0; k < 3; k++) {
    P.p[k] = p[k], P.d[k] = d[k], P.e1[k] = e1[k];
    P.dh[k] = P.a * d[k] - b * ez[k];
    P.e2[k] = b * d[k] + P.a * ez[k];
    P.q[k] = p[k] + lead * d[k] - rh * e1[k];
  }
  return P;
}

/* A tube of girth n (edges around) along path P from s = s0 to s1, radius r0 at the start and r1 at the
 * end, out of the loop `from`. Rings are spaced so the triangles are nearly equilateral, each turned
 * half a step; the frame is carried along the path without twist. If `into` is given the last ring is
 * zipped to it, else the tube ends in a cone to a tip. */
static void add_tube(mesh *m, loop *from, const double *from_c, const path *P, double s0, double s1, int n, double r0,
                     double r1, loop *into, const double *into_c) {
  double c[3], t[3], u[3], v[3];
  path_at(P, s0, c, t);
  frame(t, u, v);
  double rmean = 0.5 * (r0 + r1), edge = 2 * rmean * sin(M_PI / n);
  int rings = (int)ceil((s1 - s0) / (edge * 0.866)) + 1;
  if (rings < 2) rings = 2;
  loop prev = *from;
  double prev_c[3];
  memcpy(prev_c, from_c, sizeof prev_c);
  for (int r = 0; r < rings; r++) {
    double s = s0 + (s1 - s0) * r / (rings - 1), tn[3];
    path_at(P, s, c, tn);
    /* Carry the frame: project u onto the new normal plane (rotation-minimizing to first order). */
    double du = dot3(u, tn);
    for (int k = 0; k < 3; k++) u[k] -= du * tn[k];
    normalize3(u);
    cross3(tn, u, v);
    double rad = r0 + (r1 - r0) * (s - s0) / (s1 - s0);
    int *rv = malloc(sizeof(int) * (size_t)n);
    if (!rv) die_nomem();
    for (int j = 0; j < n; j++) {
      double ph = 2 * M_PI * (j + 0.5 * (r % 2)) / n, p[3];
      for (int k = 0; k < 3; k++) p[k] = c[k] + rad * (cos(ph) * u[k] + sin(ph) * v[k]);
      rv[j] = add_v(m, p);
    }
    loop cur = {rv, n};
    zip(m, &prev, &cur, c, tn);
    if (r > 0) free(prev.v);
    prev = cur;
    memcpy(prev_c, c, sizeof prev_c);
    memcpy(t, tn, sizeof t);
  }
  if (into) {
    zip(m, &prev, into, into_c, t);
  } else {
    double tip[3];
    for (int k = 0; k < 3; k++) tip[k] = c[k] + 0.8 * r1 * t[k];
    int ti = add_v(m, tip);
    for (int j = 0; j < n; j++) add_f(m, prev.v[j], prev.v[(j + 1) % n], ti);
  }
  free(prev.v);
}

/* A straight limb of girth n and length len (measured from the blob's surface) out of blob b along
 * the unit direction dir, ending in a tip. Its radius is that of the hole it leaves by. */
static double hole_radius(const mesh *m, const loop *h, double *centre) {
  double c[3] = {0, 0, 0}, r = 0;
  for (int k = 0; k < h->n; k++)
    for (int d = 0; d < 3; d++) c[d] += m->X[3 * h->v[k] + d] / h->n;
  for (int k = 0; k < h->n; k++) {
    const double *p = m->X + 3 * h->v[k];
    r += sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) + (p[2] - c[2]) * (p[2] - c[2])) / h->n;
  }
  if (centre) memcpy(centre, c, sizeof c);
  return r;
}

static void straight_limb(mesh *m, const blob *b, const double *dir0, int n, double len_diameters, double taper) {
  double dir[3] = {dir0[0], dir0[1], dir0[2]};
  normalize3(dir);
  loop h = cut_hole(m, b, dir);
  double hc[3];
  double r = hole_radius(m, &h, hc);
  path P = {0};
  /* The tube starts half an edge out from the hole's centre, along the direction. */
  double edge = 2 * r * sin(M_PI / n);
  for (int k = 0; k < 3; k++) P.p[k] = hc[k] + 0.6 * edge * dir[k], P.d[k] = dir[k];
  add_tube(m, &h, hc, &P, 0, len_diameters * 2 * r, n, r, r * taper, NULL, NULL);
  free(h.v);
}

/* ---- the whole mesh: orientation, checks, output ---- */

typedef struct hedge {
  int a, b, f;
} hedge;

static int cmp_hedge(const void *x, const void *y) {
  const hedge *p = x, *q = y;
  int pa = p->a < p->b ? p->a : p->b, pb = p->a < p->b ? p->b : p->a;
  int qa = q->a < q->b ? q->a : q->b, qb = q->a < q->b ? q->b : q->a;
  if (pa != qa) return pa < qa ? -1 : 1;
  if (pb != qb) return pb < qb ? -1 : 1;
  return (p->f > q->f) - (p->f < q->f);
}

/* Drop removed faces and unreferenced vertices, orient every face like its neighbours (breadth first
 * across edges), flip all if the volume is negative, and check: every edge in exactly two faces used
 * once in each direction, one component, Euler characteristic 2, positive volume. Returns 0 if good. */
static int finish(mesh *m, const char *name) {
  int nf = 0;
  for (int f = 0; f < m->nf; f++)
    if (!m->dead[f]) memmove(m->F + 3 * nf, m->F + 3 * f, 3 * sizeof(int)), nf++;
  m->nf = nf;
  int *map = malloc(sizeof(int) * (size_t)m->nv);
  if (!map) die_nomem();
  for (int i = 0; i < m->nv; i++) map[i] = -1;
  int nv = 0;
  for (int f = 0; f < 3 * nf; f++)
    if (map[m->F[f]] < 0) map[m->F[f]] = 0;
  for (int i = 0; i < m->nv; i++)
    if (map[i] == 0) {
      map[i] = nv;
      memmove(m->X + 3 * nv, m->X + 3 * i, 3 * sizeof(double));
      nv++;
    }
  for (int f = 0; f < 3 * nf; f++) m->F[f] = map[m->F[f]];
  m->nv = nv;
  free(map);
  /* Edges: half-edges sorted by their unordered pair; each pair must come exactly twice. */
  hedge *h = malloc(sizeof(hedge) * 3 * (size_t)nf);
  int *nb = malloc(sizeof(int) * 3 * (size_t)nf), *queue = malloc(sizeof(int) * (size_t)nf);
  signed char *sgn = calloc((size_t)nf, 1);
  if (!h || !nb || !queue || !sgn) die_nomem();
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) h[3 * f + k] = (hedge){m->F[3 * f + k], m->F[3 * f + (k + 1) % 3], f};
  qsort(h, 3 * (size_t)nf, sizeof(hedge), cmp_hedge);
  int bad = 0;
  for (int k = 0; k < 3 * nf; k++) nb[k] = 0; /* 0: no neighbour recorded yet */
  for (int k = 0; k < 3 * nf;) {
    int j = k + 1;
    while (j < 3 * nf && cmp_hedge(&(hedge){h[k].a, h[k].b, 0}, &(hedge){h[j].a, h[j].b, 0}) == 0) j++;
    if (j - k != 2) bad++;
    else {
      /* Remember for each face its neighbours, and whether they run the edge the same way. */
      for (int s = 0; s < 2; s++) {
        int f = h[k + s].f, g = h[k + 1 - s].f;
        for (int q = 0; q < 3; q++)
          if (nb[3 * f + q] == 0) {
            nb[3 * f + q] = h[k].a == h[k + 1].a ? -(g + 1) : g + 1; /* negative: same direction (flip) */
            break;
          }
      }
    }
    k = j;
  }
  int comps = 0;
  for (int f0 = 0; f0 < nf && !bad; f0++) {
    if (sgn[f0]) continue;
    comps++;
    sgn[f0] = 1;
    int qh = 0, qt = 0;
    queue[qt++] = f0;
    while (qh < qt) {
      int f = queue[qh++];
      for (int q = 0; q < 3; q++) {
        int e = nb[3 * f + q];
        if (!e) continue;
        int g = abs(e) - 1, want = e < 0 ? -sgn[f] : sgn[f];
        if (!sgn[g]) sgn[g] = (signed char)want, queue[qt++] = g;
        else if (sgn[g] != want) bad++; /* not orientable */
      }
    }
  }
  for (int f = 0; f < nf; f++)
    if (sgn[f] < 0) {
      int s = m->F[3 * f + 1];
      m->F[3 * f + 1] = m->F[3 * f + 2], m->F[3 * f + 2] = s;
    }
  double vol = 0;
  for (int f = 0; f < nf; f++) {
    const double *a = m->X + 3 * m->F[3 * f], *b = m->X + 3 * m->F[3 * f + 1], *c = m->X + 3 * m->F[3 * f + 2];
    double bc[3];
    cross3(b, c, bc);
    vol += dot3(a, bc) / 6;
  }
  if (vol < 0) {
    for (int f = 0; f < nf; f++) {
      int s = m->F[3 * f + 1];
      m->F[3 * f + 1] = m->F[3 * f + 2], m->F[3 * f + 2] = s;
    }
    vol = -vol;
  }
  long euler = (long)nv - 3L * nf / 2 + nf;
  free(h), free(nb), free(queue), free(sgn);
  if (bad || comps != 1 || euler != 2 || !(vol > 0)) {
    fprintf(stderr, "au_mklimbs: %s failed its check: %d bad edges, %d components, euler %ld, volume %g\n", name, bad,
            comps, euler, vol);
    return 1;
  }
  return 0;
}

static int write_obj(const mesh *m, const char *dir, const char *name, const char *what) {
  char path[4096], tmp[4200];
  snprintf(path, sizeof path, "%s/%s.obj", dir, name);
  snprintf(tmp, sizeof tmp, "%s.tmp", path);
  FILE *fp = fopen(tmp, "w");
  if (!fp) {
    fprintf(stderr, "au_mklimbs: cannot write %s\n", tmp);
    return 2;
  }
  fprintf(fp, "# %s: %s\n# au_mklimbs %s, V=%d F=%d\n", name, what, AU_VERSION, m->nv, m->nf);
  for (int i = 0; i < m->nv; i++) fprintf(fp, "v %.17g %.17g %.17g\n", m->X[3 * i], m->X[3 * i + 1], m->X[3 * i + 2]);
  for (int f = 0; f < m->nf; f++) fprintf(fp, "f %d %d %d\n", m->F[3 * f] + 1, m->F[3 * f + 1] + 1, m->F[3 * f + 2] + 1);
  if (fclose(fp) != 0 || rename(tmp, path) != 0) {
    fprintf(stderr, "au_mklimbs: cannot write %s\n", path);
    remove(tmp);
    return 2;
  }
  printf("%s: V=%d F=%d\n", path, m->nv, m->nf);
  return 0;
}

/* ---- the shapes ---- */

/* A unit ball with four legs of girth 6, 5 to 12 diameters long, splayed downwards. */
static void make_limbs4(mesh *m) {
  const double c[3] = {0, 0, 0}, ax[3] = {1, 1, 1};
  blob b = add_blob(m, 3, c, ax);
  const double dir[4][3] = {{1, 1, -1.2}, {-1, 1, -1.2}, {-1, -1, -1.2}, {1, -1, -1.2}};
  const double len[4] = {5, 8, 10, 12};
  for (int k = 0; k < 4; k++) straight_limb(m, &b, dir[k], 6, len[k], 1.0);
}

/* A unit ball with eight legs (a spider): girths 5 to 8, lengths 5 to 20 diameters. */
static void make_limbs8(mesh *m) {
  const double c[3] = {0, 0, 0}, ax[3] = {1, 1, 1};
  blob b = add_blob(m, 3, c, ax);
  for (int k = 0; k < 8; k++) {
    double a = 2 * M_PI * (k + 0.5) / 8, dir[3] = {cos(a), sin(a), -0.35};
    straight_limb(m, &b, dir, 5 + k % 4, 5 + 15.0 * k / 7, 1.0);
  }
}

/* A T-posed stick figure: an ellipsoidal torso, a head on a short neck, two arms ending in hands with
 * five fingers each (girth 5), two legs (girth 7). */
static void make_tpose(mesh *m) {
  const double c[3] = {0, 0, 0}, ax[3] = {0.55, 0.35, 1.0};
  blob torso = add_blob(m, 3, c, ax);
  /* Head: a ball above the neck, joined by a tube from the torso's top hole into the head's bottom one. */
  const double hc[3] = {0, 0, 1.55}, hax[3] = {0.32, 0.32, 0.36}, up[3] = {0, 0, 1}, down[3] = {0, 0, -1};
  blob head = add_blob(m, 2, hc, hax);
  loop h0 = cut_hole(m, &torso, up), h1 = cut_hole(m, &head, down);
  double c0[3], c1[3];
  double r0 = hole_radius(m, &h0, c0), r1 = hole_radius(m, &h1, c1);
  path P = {0};
  for (int k = 0; k < 3; k++) P.p[k] = c0[k], P.d[k] = up[k];
  double gap = c1[2] - c0[2];
  add_tube(m, &h0, c0, &P, 0.25 * gap, 0.75 * gap, 6, r0, r1, &h1, c1);
  free(h0.v), free(h1.v);
  /* Arms: out along +-x from the shoulders to hands, each hand a small flat ball with five fingers. */
  for (int side = -1; side <= 1; side += 2) {
    double dir[3] = {side, 0, 0.9};
    normalize3(dir);
    double hand_c[3] = {side * 2.6, 0, 0.75}, hand_ax[3] = {0.22, 0.1, 0.2}, back[3] = {-side, 0, 0};
    blob hand = add_blob(m, 3, hand_c, hand_ax);
    loop a0 = cut_hole(m, &torso, dir), a1 = cut_hole(m, &hand, back);
    double ca[3], cb[3];
    double ra = hole_radius(m, &a0, ca), rb = hole_radius(m, &a1, cb);
    path Q = {0};
    double d[3] = {cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]}, L = sqrt(dot3(d, d));
    for (int k = 0; k < 3; k++) Q.p[k] = ca[k], Q.d[k] = d[k] / L;
    add_tube(m, &a0, ca, &Q, 0.04 * L, 0.96 * L, 6, ra, rb, &a1, cb);
    free(a0.v), free(a1.v);
    /* Fingers: fanned in the hand's plane (x, z), the thumb turned towards -z. */
    for (int f = 0; f < 5; f++) {
      double a = (f == 0 ? -85 : -39 + 26 * (f - 1)) * M_PI / 180, fd[3] = {side * cos(a), 0, sin(a)};
      straight_limb(m, &hand, fd, 5, f == 0 ? 3 : 4 + f % 2, 1.0);
    }
  }
  /* Legs: down and slightly apart, girth 7. */
  for (int side = -1; side <= 1; side += 2) {
    double dir[3] = {side * 0.45, 0, -1};
    straight_limb(m, &torso, dir, 7, 14, 1.0);
  }
}

/* A unit ball with a long tail coiled like a corkscrew (girth 6, about 24 diameters) and four short
 * legs (girth 6, 4 diameters). */
static void make_coil(mesh *m) {
  const double c[3] = {0, 0, 0}, ax[3] = {1, 1, 1};
  blob b = add_blob(m, 3, c, ax);
  double dir[3] = {1, 0, 0};
  loop h = cut_hole(m, &b, dir);
  double hc[3];
  double r = hole_radius(m, &h, hc);
  /* Out along +x for a body radius, then a corkscrew of radius 0.45 hanging down beside the body. */
  const double e1[3] = {0, -1, 0}, ez[3] = {0, 0, 1}, p0[3] = {hc[0] + 0.6 * r, hc[1], hc[2]};
  path P = coil_path(p0, dir, e1, ez, 1.0, 0.45, 5.0 * r);
  add_tube(m, &h, hc, &P, 0, 24 * 2 * r, 6, r, r, NULL, NULL);
  free(h.v);
  const double legs[4][3] = {{-0.3, 1, -1.2}, {-0.3, -1, -1.2}, {0.5, 1, -1.2}, {0.5, -1, -1.2}};
  for (int k = 0; k < 4; k++) straight_limb(m, &b, legs[k], 6, 4, 1.0);
}

/* A hammer: an elongated head (an ellipsoid 2.4 x 0.7 x 0.7) on a long, thin handle of girth 6 and 30
 * diameters, straight down from the head's middle: a conformal map squeezes the handle far past e^-20. */
static void make_hammer(mesh *m) {
  const double c[3] = {0, 0, 0}, ax[3] = {1.2, 0.35, 0.35}, down[3] = {0, 0, -1};
  blob head = add_blob(m, 3, c, ax);
  straight_limb(m, &head, down, 6, 30, 1.0);
}

/* A unit ball with twelve long legs of girth 6, 10 to 25 diameters, straight out along the directions of an
 * icosahedron's vertices: every leg squeezed far past a double by a conformal map, on the coarse mesh as on
 * the fine one (coarse-to-fine start, issue 39). */
static void make_octopus(mesh *m) {
  const double c[3] = {0, 0, 0}, ax[3] = {1, 1, 1}, g = (1 + sqrt(5.0)) / 2;
  blob b = add_blob(m, 3, c, ax);
  /* The icosahedron's vertices (0, +-1, +-g) and their cyclic permutations, turned a little so that no
   * leg leaves through a vertex of the blob's own icosahedron. */
  for (int k = 0; k < 12; k++) {
    const double s1 = k & 1 ? -1 : 1, s2 = k & 2 ? -1 : 1, v[3] = {0, s1, s2 * g};
    const int r = k / 4;
    double dir[3] = {v[(3 - r) % 3], v[(4 - r) % 3], v[(5 - r) % 3]};
    dir[0] += 0.21, dir[1] += 0.13;
    straight_limb(m, &b, dir, 6, 10 + 15.0 * k / 11, 1.0);
  }
}

int main(int argc, char **argv) {
  if (argc == 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
    printf("usage: au_mklimbs DIR\nwrites limbs4.obj, limbs8.obj, tpose.obj, coil.obj, hammer.obj and octopus.obj into DIR (see data/README.md)\n");
    return 0;
  }
  if (argc == 2 && !strcmp(argv[1], "--version")) {
    printf("au_mklimbs %s\n", AU_VERSION);
    return 0;
  }
  if (argc != 2) {
    fprintf(stderr, "usage: au_mklimbs DIR\n");
    return 2;
  }
  struct {
    const char *name, *what;
    void (*make)(mesh *);
  } shapes[] = {
      {"limbs4", "unit ball, four legs of girth 6 and 5-12 diameters (thin-limbed family, issue 21)", make_limbs4},
      {"limbs8", "unit ball, eight legs of girth 5-8 and 5-20 diameters (thin-limbed family, issue 21)", make_limbs8},
      {"tpose", "T-posed stick figure with ten fingers (thin-limbed family, issue 21)", make_tpose},
      {"coil", "unit ball with a corkscrew tail of 24 diameters and four short legs (thin-limbed family, issue 21)",
       make_coil},
      {"hammer", "ellipsoidal head on a handle of girth 6 and 30 diameters (coarse-to-fine start, issue 39)",
       make_hammer},
      {"octopus", "unit ball, twelve legs of girth 6 and 10-25 diameters (coarse-to-fine start, issue 39)",
       make_octopus},
  };
  int status = 0;
  for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++) {
    mesh m = {0};
    shapes[i].make(&m);
    if (finish(&m, shapes[i].name)) status = 1;
    else if (write_obj(&m, argv[1], shapes[i].name, shapes[i].what)) status = status ? status : 2;
    free(m.X), free(m.F), free(m.dead), free(m.holed);
  }
  return status;
}
