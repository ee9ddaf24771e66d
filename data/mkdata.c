/* mkdata.c - generator of the project's own test meshes in data/: closed genus-0 ones, a disk and an
 * annulus with a bump for the planar domains, and tori of revolution (genus 1) whose conformal and
 * equal-area flat-torus maps are known in closed form (needs only libm). */
#include <errno.h>
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

/* A growable triangle mesh: X is nv x 3, F is nf x 3 (0-based, counter-clockwise seen from outside). */
typedef struct mesh {
  double *X;
  int *F;
  int nv, nf, cv, cf;
} mesh;

static void die_nomem(void) {
  fprintf(stderr, "au_mkdata: out of memory\n");
  exit(1);
}

static int add_v(mesh *m, double x, double y, double z) {
  if (m->nv == m->cv) {
    m->cv = m->cv ? 2 * m->cv : 256;
    double *X = realloc(m->X, sizeof(double) * 3 * (size_t)m->cv);
    if (!X) die_nomem();
    m->X = X;
  }
  double *p = m->X + 3 * (size_t)m->nv;
  p[0] = x, p[1] = y, p[2] = z;
  return m->nv++;
}

static void add_f(mesh *m, int a, int b, int c) {
  if (m->nf == m->cf) {
    m->cf = m->cf ? 2 * m->cf : 256;
    int *F = realloc(m->F, sizeof(int) * 3 * (size_t)m->cf);
    if (!F) die_nomem();
    m->F = F;
  }
  int *f = m->F + 3 * (size_t)m->nf++;
  f[0] = a, f[1] = b, f[2] = c;
}

static void mesh_free(mesh *m) {
  free(m->X);
  free(m->F);
  memset(m, 0, sizeof *m);
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void normalize3(double *a) {
  double n = sqrt(dot3(a, a));
  a[0] /= n, a[1] /= n, a[2] /= n;
}

/* Angle between two unit vectors; atan2 keeps it accurate near 0, where the spikes are sharpest. */
static double angle3(const double *a, const double *b) {
  double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  return atan2(sqrt(dot3(c, c)), dot3(a, b));
}

/* The 12 icosahedron vertices as unit vectors and its 20 faces, oriented outward. */
static const int ico_f[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};

static void ico_vertex(int i, double *p) {
  const double t = 1.6180339887498948482; /* the golden ratio */
  const double v[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (int k = 0; k < 3; k++) p[k] = v[i][k];
  normalize3(p);
}

/* Icosphere: the icosahedron subdivided `level` times (each triangle into four), vertices on the
 * unit sphere. Edge midpoints are shared through an open-addressing table keyed by the vertex pair,
 * so the result has no duplicated vertices. Faces: 20 * 4^level. */
static void icosphere(mesh *m, int level) {
  for (int i = 0; i < 12; i++) {
    double p[3];
    ico_vertex(i, p);
    add_v(m, p[0], p[1], p[2]);
  }
  for (int i = 0; i < 20; i++) add_f(m, ico_f[i][0], ico_f[i][1], ico_f[i][2]);
  for (int l = 0; l < level; l++) {
    size_t cap = 1;
    while (cap < 4 * (size_t)m->nf) cap *= 2;
    uint64_t *key = malloc(sizeof(uint64_t) * cap);
    int *val = malloc(sizeof(int) * cap);
    int *F = m->F, nf = m->nf;
    if (!key || !val) die_nomem();
    memset(key, 0xff, sizeof(uint64_t) * cap);
    m->F = NULL, m->nf = m->cf = 0;
    for (int f = 0; f < nf; f++) {
      int mid[3];
      for (int e = 0; e < 3; e++) {
        int a = F[3 * f + e], b = F[3 * f + (e + 1) % 3];
        uint64_t k = a < b ? (uint64_t)a << 32 | (uint64_t)b : (uint64_t)b << 32 | (uint64_t)a;
        size_t h = (size_t)((k * 0x9E3779B97F4A7C15u) >> 20) & (cap - 1);
        while (key[h] != UINT64_MAX && key[h] != k) h = (h + 1) & (cap - 1);
        if (key[h] != k) {
          double p[3];
          for (int c = 0; c < 3; c++) p[c] = m->X[3 * a + c] + m->X[3 * b + c];
          normalize3(p);
          key[h] = k;
          val[h] = add_v(m, p[0], p[1], p[2]);
        }
        mid[e] = val[h];
      }
      int a = F[3 * f], b = F[3 * f + 1], c = F[3 * f + 2];
      add_f(m, a, mid[0], mid[2]);
      add_f(m, mid[0], b, mid[1]);
      add_f(m, mid[2], mid[1], c);
      add_f(m, mid[0], mid[1], mid[2]);
    }
    free(F);
    free(key);
    free(val);
  }
}

/* Push every vertex u of a unit icosphere out to r(u) * u with
 *   r(u) = 1 + sum_k amp_k * exp(-(angle(u, dir_k) / width_k)^2).
 * Any positive r keeps the mesh embedded and outward-oriented: each flat triangle stays inside the
 * cone of its spherical triangle (the cones tile space), and det(r_a u_a, r_b u_b, r_c u_c) has the
 * sign of det(u_a, u_b, u_c) > 0. So however long the fingers, the surface stays star-shaped. */
static void radial_bumps(mesh *m, int n, const double (*dir)[3], const double *amp, const double *width) {
  for (int i = 0; i < m->nv; i++) {
    double *p = m->X + 3 * i, r = 1;
    for (int k = 0; k < n; k++) {
      double t = angle3(p, dir[k]) / width[k];
      r += amp[k] * exp(-t * t);
    }
    p[0] *= r, p[1] *= r, p[2] *= r;
  }
}

/* A tiny fixed-seed generator (xorshift64*), so the meshes are identical on every platform. */
static double rng_uniform(uint64_t *s) {
  *s ^= *s >> 12, *s ^= *s << 25, *s ^= *s >> 27;
  return (double)((*s * 0x2545F4914F6CDD1Du) >> 11) * 0x1.0p-53;
}

static void rng_direction(uint64_t *s, double *d) {
  double z = 2 * rng_uniform(s) - 1, phi = 2 * M_PI * rng_uniform(s), q = sqrt(1 - z * z);
  d[0] = q * cos(phi), d[1] = q * sin(phi), d[2] = z;
}

/* bumpy_star: icosphere level 4 (5120 faces) with six long fingers of different lengths along a
 * tilted octahedral frame, plus twelve low bumps at fixed pseudo-random directions. */
static void make_bumpy_star(mesh *m) {
  enum { NF = 6, NB = 12 };
  double dir[NF + NB][3], amp[NF + NB], width[NF + NB];
  static const double len[NF] = {2.5, 2.5, 2.0, 3.0, 1.5, 2.5};
  /* A fixed rotation (about (1,2,3) by 0.4 rad) keeps the fingers off the icosahedron's symmetry axes. */
  double ax[3] = {1, 2, 3}, th = 0.4;
  normalize3(ax);
  for (int k = 0; k < NF; k++) {
    double e[3] = {0, 0, 0};
    e[k / 2] = k % 2 ? -1 : 1;
    double c = cos(th), s = sin(th), d = dot3(ax, e);
    double x[3] = {ax[1] * e[2] - ax[2] * e[1], ax[2] * e[0] - ax[0] * e[2], ax[0] * e[1] - ax[1] * e[0]};
    for (int j = 0; j < 3; j++) dir[k][j] = e[j] * c + x[j] * s + ax[j] * d * (1 - c);
    amp[k] = len[k];
    width[k] = 0.32;
  }
  uint64_t seed = 0x5EED0001u;
  for (int k = NF; k < NF + NB; k++) {
    rng_direction(&seed, dir[k]);
    amp[k] = 0.06 + 0.08 * rng_uniform(&seed);
    width[k] = 0.35 + 0.2 * rng_uniform(&seed);
  }
  icosphere(m, 4);
  radial_bumps(m, NF + NB, (const double(*)[3])dir, amp, width);
}

/* spiky_ico: icosphere level 3 (1280 faces) with a sharp spike of length 2 at each of the 12
 * icosahedron vertices (which the subdivision keeps, so every spike ends in a vertex). */
static void make_spiky_ico(mesh *m) {
  double dir[12][3], amp[12], width[12];
  for (int k = 0; k < 12; k++) {
    ico_vertex(k, dir[k]);
    amp[k] = 2.0;
    width[k] = 0.2;
  }
  icosphere(m, 3);
  radial_bumps(m, 12, (const double(*)[3])dir, amp, width);
}

/* Surface of revolution about the z axis of a profile rho(z) > 0 on (z0, z1), rho(z0) = rho(z1) = 0.
 * The profile is resampled into nlat rings equally spaced in arc length (so the poles, where rho has a
 * vertical tangent, get as many rings as their length deserves); each ring has nlon vertices and is
 * turned half a step against the previous one, so the quads split into near-isosceles triangles.
 * Pole fans close both ends: 2 * nlon * nlat faces, nlon * nlat + 2 vertices. */
typedef double (*profile_fn)(double z, const void *par);

static void revolve(mesh *m, profile_fn rho, const void *par, double z0, double z1, int nlat, int nlon) {
  enum { NS = 20000 };
  double *zs = malloc(sizeof(double) * (NS + 1)), *rs = malloc(sizeof(double) * (NS + 1));
  double *s = malloc(sizeof(double) * (NS + 1));
  if (!zs || !rs || !s) die_nomem();
  /* Sample with z clustered at the ends (cosine spacing), where the arc length per unit z explodes. */
  for (int i = 0; i <= NS; i++) {
    zs[i] = z0 + (z1 - z0) * 0.5 * (1 - cos(M_PI * i / NS));
    rs[i] = i == 0 || i == NS ? 0 : rho(zs[i], par);
    s[i] = i ? s[i - 1] + hypot(zs[i] - zs[i - 1], rs[i] - rs[i - 1]) : 0;
  }
  int south = add_v(m, 0, 0, z0);
  for (int i = 1, j = 0; i <= nlat; i++) {
    double t = s[NS] * i / (nlat + 1);
    while (s[j + 1] < t) j++;
    double w = (t - s[j]) / (s[j + 1] - s[j]);
    double z = zs[j] + w * (zs[j + 1] - zs[j]), r = rs[j] + w * (rs[j + 1] - rs[j]);
    for (int k = 0; k < nlon; k++) {
      double phi = 2 * M_PI * (k + 0.5 * i) / nlon;
      add_v(m, r * cos(phi), r * sin(phi), z);
    }
  }
  int north = add_v(m, 0, 0, z1);
  for (int k = 0; k < nlon; k++) {
    int k1 = (k + 1) % nlon;
    add_f(m, south, 1 + k1, 1 + k);
    for (int i = 0; i + 1 < nlat; i++) {
      int a = 1 + i * nlon, b = a + nlon; /* ring i and ring i+1, turned half a step ahead */
      add_f(m, a + k, a + k1, b + k);
      add_f(m, b + k, a + k1, b + k1);
    }
    add_f(m, 1 + (nlat - 1) * nlon + k, 1 + (nlat - 1) * nlon + k1, north);
  }
  free(zs);
  free(rs);
  free(s);
}

/* Dumbbell: spheres of radius R at z = +-c joined by a neck of radius n. rho^2 is a smooth maximum
 * (log-sum-exp, sharpness k) of the two spheres' R^2 - (z -+ c)^2 and a neck term that is n^2 at
 * z = 0 and falls off beyond the spheres, so the blend is smooth and the ends are the spheres' poles. */
typedef struct dumbbell_par {
  double R, c, n, k;
} dumbbell_par;

static double dumbbell_rho2(double z, const dumbbell_par *d) {
  double t[3] = {d->R * d->R - (z - d->c) * (z - d->c), d->R * d->R - (z + d->c) * (z + d->c),
                 d->n * d->n * (1 - (z / d->c) * (z / d->c))};
  double mx = fmax(t[0], fmax(t[1], t[2])), sum = 0;
  for (int i = 0; i < 3; i++) sum += exp(d->k * (t[i] - mx));
  return mx + log(sum) / d->k;
}

static double dumbbell_rho(double z, const void *par) { return sqrt(fmax(dumbbell_rho2(z, par), 0)); }

static void make_dumbbell(mesh *m) {
  const dumbbell_par d = {1.0, 1.6, 0.25, 15.0};
  /* The smooth maximum lies slightly above the spheres, so find the true pole by bisection. */
  double lo = d.c + d.R - 0.5, hi = d.c + d.R + 0.5;
  for (int it = 0; it < 200; it++) {
    double mid = 0.5 * (lo + hi);
    if (dumbbell_rho2(mid, &d) > 0) lo = mid;
    else hi = mid;
  }
  revolve(m, dumbbell_rho, &d, -lo, lo, 72, 32);
}

/* Prolate ellipsoid with semi-axes 1, 1, 4 (a mild, smooth case). */
static double ellipsoid_rho(double z, const void *par) {
  double c = *(const double *)par;
  return sqrt(fmax(1 - (z / c) * (z / c), 0));
}

static void make_ellipsoid(mesh *m) {
  static const double c = 4.0;
  revolve(m, ellipsoid_rho, &c, -c, c, 40, 26);
}

/* Open meshes for the planar domains: concentric rings in the plane, lifted by a height field. */

/* Join ring a (na vertices from index a0, angles 2 pi (k + oa) / na) to the larger-radius ring b
 * (nb vertices from b0, offset ob) by walking both in angle: counter-clockwise seen from +z. */
static void join_rings(mesh *m, int a0, int na, double oa, int b0, int nb, double ob) {
  int i = 0, j = 0;
  while (i < na || j < nb) {
    double ta = (i + 1 + oa) / na, tb = (j + 1 + ob) / nb; /* angle of the next vertex, in turns */
    if (j < nb && (i >= na || tb <= ta)) {
      add_f(m, a0 + i % na, b0 + j % nb, b0 + (j + 1) % nb);
      j++;
    } else {
      add_f(m, a0 + i % na, b0 + (j % nb), a0 + (i + 1) % na);
      i++;
    }
  }
}

/* Height of the bumps: a tall Gaussian off the centre and a low one opposite it. */
static double bump_height(double x, double y) {
  double d1 = (x - 0.3) * (x - 0.3) + (y - 0.1) * (y - 0.1), d2 = (x + 0.45) * (x + 0.45) + (y + 0.35) * (y + 0.35);
  return 1.2 * exp(-d1 / (2 * 0.18 * 0.18)) + 0.3 * exp(-d2 / (2 * 0.15 * 0.15));
}

/* Unit disk: a centre vertex and 24 rings with 6k vertices on ring k (each turned a little against
 * the previous one), lifted by bump_height. 1801 vertices, 3456 faces. */
static void make_disk_bump(mesh *m) {
  enum { NR = 24 };
  add_v(m, 0, 0, bump_height(0, 0));
  int prev0 = 0, prevn = 1;
  double prevo = 0;
  for (int k = 1; k <= NR; k++) {
    int n = 6 * k, start = m->nv;
    double r = (double)k / NR, o = 0.5 * (k % 2);
    for (int i = 0; i < n; i++) {
      double phi = 2 * M_PI * (i + o) / n, x = r * cos(phi), y = r * sin(phi);
      add_v(m, x, y, bump_height(x, y));
    }
    if (k == 1)
      for (int i = 0; i < n; i++) add_f(m, 0, start + i, start + (i + 1) % n);
    else
      join_rings(m, prev0, prevn, prevo, start, n, o);
    prev0 = start, prevn = n, prevo = o;
  }
}

/* Annulus 0.35 <= r <= 1: 20 rings of 96 vertices, every other ring turned half a step, lifted by
 * bump_height (the tall bump sits between the two boundary circles). 1920 vertices, 3648 faces. */
static void make_annulus_bump(mesh *m) {
  enum { NR = 20, NL = 96 };
  for (int k = 0; k < NR; k++) {
    double r = 0.35 + 0.65 * k / (NR - 1), o = 0.5 * (k % 2);
    for (int i = 0; i < NL; i++) {
      double phi = 2 * M_PI * (i + o) / NL, x = r * cos(phi), y = r * sin(phi);
      add_v(m, x, y, bump_height(x, y));
    }
    if (k > 0) join_rings(m, (k - 1) * NL, NL, 0.5 * ((k - 1) % 2), k * NL, NL, o);
  }
}

/* ---- disks with many holes (for `authalic circles`) */

static int cmp_u64(const void *a, const void *b);

/* A hole: an ellipse with centre (cx, cy), semi-axes a, b (b = a: a circle). */
typedef struct hole {
  double cx, cy, a, b;
} hole;

static int in_hole(const hole *h, int nh, double x, double y) {
  for (int k = 0; k < nh; k++)
    if ((x - h[k].cx) * (x - h[k].cx) / (h[k].a * h[k].a) + (y - h[k].cy) * (y - h[k].cy) / (h[k].b * h[k].b) < 1) return 1;
  return 0;
}

/* The unit disk of NR rings (as make_disk_bump) without the faces whose centroid lies in a hole, then
 * without the faces at a vertex where two boundary edges leave (a pinch, which a hole's jagged rim can
 * make), the vertices renumbered in order; z = height(x, y). */
static void holed_disk(mesh *m, int nr, const hole *h, int nh, double (*height)(double, double)) {
  mesh d = {0};
  add_v(&d, 0, 0, 0);
  int prev0 = 0, prevn = 1;
  double prevo = 0;
  for (int k = 1; k <= nr; k++) {
    int n = 6 * k, start = d.nv;
    double r = (double)k / nr, o = 0.5 * (k % 2);
    for (int i = 0; i < n; i++) add_v(&d, r * cos(2 * M_PI * (i + o) / n), r * sin(2 * M_PI * (i + o) / n), 0);
    if (k == 1)
      for (int i = 0; i < n; i++) add_f(&d, 0, start + i, start + (i + 1) % n);
    else
      join_rings(&d, prev0, prevn, prevo, start, n, o);
    prev0 = start, prevn = n, prevo = o;
  }
  unsigned char *keep = malloc((size_t)d.nf);
  int *out = malloc(sizeof(int) * (size_t)d.nv), *map = malloc(sizeof(int) * (size_t)d.nv);
  if (!keep || !out || !map) die_nomem();
  for (int f = 0; f < d.nf; f++) {
    const int *v = d.F + 3 * f;
    double x = 0, y = 0;
    for (int k = 0; k < 3; k++) x += d.X[3 * v[k]] / 3, y += d.X[3 * v[k] + 1] / 3;
    keep[f] = !in_hole(h, nh, x, y);
  }
  /* Clean the holes' rims until none has a pinch (two boundary edges leaving one vertex) or an interior
   * edge between two rim vertices (a chord of the hole: no map can keep both ends on its circle and the
   * triangles beside it outside), dropping the faces at them. */
  uint64_t *key = malloc(sizeof(uint64_t) * 3 * (size_t)d.nf);
  if (!key) die_nomem();
  for (int changed = 1; changed;) {
    changed = 0;
    size_t nk = 0;
    for (int f = 0; f < d.nf; f++)
      for (int k = 0; k < 3 && keep[f]; k++) key[nk++] = (uint64_t)d.F[3 * f + k] << 32 | (uint64_t)d.F[3 * f + (k + 1) % 3];
    qsort(key, nk, sizeof *key, cmp_u64);
    memset(out, 0, sizeof(int) * (size_t)d.nv);
    for (size_t i = 0; i < nk; i++) {
      uint64_t rev = (key[i] & 0xffffffffu) << 32 | key[i] >> 32;
      int a = (int)(key[i] >> 32);
      if (!bsearch(&rev, key, nk, sizeof *key, cmp_u64)) out[a]++;
    }
    for (int f = 0; f < d.nf; f++)
      for (int k = 0; k < 3 && keep[f]; k++) {
        int a = d.F[3 * f + k], b = d.F[3 * f + (k + 1) % 3];
        uint64_t rev = (uint64_t)b << 32 | (uint64_t)a;
        int rim = hypot(d.X[3 * a], d.X[3 * a + 1]) > 1 - 1e-9 || hypot(d.X[3 * b], d.X[3 * b + 1]) > 1 - 1e-9;
        if (out[a] > 1 || (out[a] && out[b] && !rim && bsearch(&rev, key, nk, sizeof *key, cmp_u64))) keep[f] = 0, changed = 1;
      }
  }
  free(key);
  for (int i = 0; i < d.nv; i++) map[i] = -1;
  for (int f = 0; f < d.nf; f++)
    for (int k = 0; k < 3 && keep[f]; k++) map[d.F[3 * f + k]] = 0;
  for (int i = 0; i < d.nv; i++)
    if (map[i] == 0) map[i] = add_v(m, d.X[3 * i], d.X[3 * i + 1], height(d.X[3 * i], d.X[3 * i + 1]));
  for (int f = 0; f < d.nf; f++)
    if (keep[f]) add_f(m, map[d.F[3 * f]], map[d.F[3 * f + 1]], map[d.F[3 * f + 2]]);
  free(keep), free(out), free(map);
  mesh_free(&d);
}

/* n round holes by rejection sampling (fixed seed): radii from rmin to rmax, each at least gap from
 * the others and from the unit circle (a few edges of the ring mesh: close, yet never touching). */
static int place_holes(hole *h, int n, double rmin, double rmax, double gap, uint64_t seed) {
  int k = 0;
  for (int tries = 0; k < n && tries < 200000; tries++) {
    double r = rmin + (rmax - rmin) * pow(rng_uniform(&seed), 2), ang = 2 * M_PI * rng_uniform(&seed);
    double rho = sqrt(rng_uniform(&seed)) * (1 - gap - r), x = rho * cos(ang), y = rho * sin(ang);
    int ok = 1;
    for (int j = 0; j < k && ok; j++) ok = hypot(x - h[j].cx, y - h[j].cy) > r + h[j].a + gap;
    if (ok) h[k++] = (hole){x, y, r, r};
  }
  return k;
}

/* Gentle hills: the bumps of disk_bump, lower. */
static double hills(double x, double y) { return 0.4 * bump_height(x, y); }

/* A disk with 3 holes of different sizes, one close to the rim and two close to each other. */
static void make_holes3(mesh *m) {
  static const hole h[3] = {{-0.35, 0.2, 0.3, 0.3}, {0.3, -0.05, 0.14, 0.14}, {0.2, 0.68, 0.2, 0.2}};
  holed_disk(m, 32, h, 3, hills);
}

static void make_holes10(mesh *m) {
  hole h[10];
  if (place_holes(h, 10, 0.04, 0.2, 0.07, 0x9e3779b97f4a7c15u) < 10) die_nomem();
  holed_disk(m, 40, h, 10, hills);
}

static void make_holes40(mesh *m) {
  hole h[40];
  if (place_holes(h, 40, 0.025, 0.09, 0.07, 0xd1b54a32d192ed03u) < 40) die_nomem();
  holed_disk(m, 64, h, 40, hills);
}

/* A face-like height field: forehead, nose, cheeks and chin over the unit disk, with open eyes and mouth
 * (three elliptic holes). */
static double face_height(double x, double y) {
  double nose = 0.45 * exp(-(x * x / (2 * 0.1 * 0.1) + (y - 0.05) * (y - 0.05) / (2 * 0.22 * 0.22)));
  double brow = 0.12 * exp(-(y - 0.45) * (y - 0.45) / (2 * 0.08 * 0.08)) * exp(-x * x / (2 * 0.4 * 0.4));
  double cheeks = 0.15 * (exp(-((x - 0.45) * (x - 0.45) + (y + 0.1) * (y + 0.1)) / 0.05) +
                          exp(-((x + 0.45) * (x + 0.45) + (y + 0.1) * (y + 0.1)) / 0.05));
  double chin = 0.15 * exp(-(x * x + (y + 0.75) * (y + 0.75)) / 0.03);
  return 0.6 * (1 - x * x - y * y) + nose + brow + cheeks + chin;
}

static void make_face_holes(mesh *m) {
  static const hole h[3] = {{-0.32, 0.28, 0.16, 0.07}, {0.32, 0.28, 0.16, 0.07}, {0, -0.42, 0.26, 0.06}};
  holed_disk(m, 48, h, 3, face_height);
}

/* The unit sphere with a small hole: an icosphere of level 4 without the faces whose centroid lies
 * within 12 degrees of the south pole, the vertices renumbered in order (2543 vertices, 5066 faces).
 * A disk whose boundary is short for its area (the rim is 1.3 long, the area 3.96 pi), like a
 * cortical surface cut open at one place: an equal-area disk map stretches the rim about 9 times and
 * must lay the triangles along the circle out long and thin. Counter-clockwise seen from +z in the
 * signed-area sense that check() uses: the upper half counts positive, the lower half without the
 * hole a little less. */
/* 1 if face f of s has its centroid direction within the cone cos(angle) > cosmax about -z. */
static int in_south_cap(const mesh *s, int f, double cosmax) {
  const int *v = s->F + 3 * f;
  double c[3] = {0, 0, 0};
  for (int k = 0; k < 3; k++)
    for (int d = 0; d < 3; d++) c[d] += s->X[3 * v[k] + d];
  normalize3(c);
  return -c[2] > cosmax;
}

static void make_holed_sphere(mesh *m) {
  mesh s = {0};
  icosphere(&s, 4);
  const double cosmax = cos(12 * M_PI / 180);
  int *map = malloc(sizeof(int) * (size_t)s.nv);
  if (!map) die_nomem();
  for (int i = 0; i < s.nv; i++) map[i] = -1;
  for (int f = 0; f < s.nf; f++)
    if (!in_south_cap(&s, f, cosmax))
      for (int k = 0; k < 3; k++) map[s.F[3 * f + k]] = -2; /* used */
  for (int i = 0; i < s.nv; i++)
    if (map[i] == -2) map[i] = add_v(m, s.X[3 * i], s.X[3 * i + 1], s.X[3 * i + 2]);
  for (int f = 0; f < s.nf; f++)
    if (!in_south_cap(&s, f, cosmax)) add_f(m, map[s.F[3 * f]], map[s.F[3 * f + 1]], map[s.F[3 * f + 2]]);
  free(map);
  mesh_free(&s);
}

/* A torus of revolution about z: X(u, v) = ((R + r cos v) cos u, (R + r cos v) sin u, r sin v) with
 * r = 1 and R = ratio; nv_tube vertices around the tube (v) and ratio x nv_tube around the axis (u),
 * both equally spaced from u = v = 0, so the quads are square where cos v = 0. Vertex (i, j) (u_i, v_j)
 * is row i * nv_tube + j; each quad is split along its (i, j)-(i+1, j+1) diagonal. Counter-clockwise
 * in (u, v) is outward: X_u x X_v = (R + r cos v) r (cos u cos v, sin u cos v, sin v). */
static void make_torus(mesh *m, double ratio, int nv_tube) {
  const double r = 1, R = ratio * r;
  int nu = (int)lround(ratio * nv_tube), nt = nv_tube;
  for (int i = 0; i < nu; i++)
    for (int j = 0; j < nt; j++) {
      double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nt;
      add_v(m, (R + r * cos(v)) * cos(u), (R + r * cos(v)) * sin(u), r * sin(v));
    }
  for (int i = 0; i < nu; i++)
    for (int j = 0; j < nt; j++) {
      int a = i * nt + j, b = ((i + 1) % nu) * nt + j, c = ((i + 1) % nu) * nt + (j + 1) % nt, d = i * nt + (j + 1) % nt;
      add_f(m, a, b, c);
      add_f(m, a, c, d);
    }
}

static void make_torus_r2(mesh *m) { make_torus(m, 2, 24); }
static void make_torus_r3(mesh *m) { make_torus(m, 3, 24); }
static void make_torus_r5(mesh *m) { make_torus(m, 5, 24); }


/* Surfaces of higher genus: the boundary of a plate of unit cubes (nx x ny x 1) with holes through it, each
 * cube face cut into PLATE_S x PLATE_S quads of two triangles (outward-oriented). A pretzel of genus g is a
 * row of 2g+1 by 3 cubes with a hole at every odd x in the middle row; the thin-handle plate has a long
 * hole beside a one-cube-wide bar of 10 cubes. open_cells lists cubes whose bottom face is left out (one
 * boundary loop each). */
#define PLATE_S 4
typedef struct plate {
  int nx, ny, thin, nopen;
  int open_cells[2][2];
} plate;

static int plate_solid(const plate *p, int x, int y, int z) {
  if (x < 0 || x >= p->nx || y < 0 || y >= p->ny || z != 0) return 0;
  if (p->thin) return !((x == 1 && y == 1) || (x == 3 && y >= 1 && y <= p->ny - 2));
  return !(y == 1 && x % 2 == 1);
}

static void make_plate(mesh *m, const plate *p) {
  const int S = PLATE_S, gx = p->nx * S + 1, gy = p->ny * S + 1, gz = S + 1;
  int *id = malloc(sizeof(int) * (size_t)gx * gy * gz);
  if (!id) die_nomem();
  for (int i = 0; i < gx * gy * gz; i++) id[i] = -1;
  for (int x = 0; x < p->nx; x++)
    for (int y = 0; y < p->ny; y++) {
      if (!plate_solid(p, x, y, 0)) continue;
      int cell[3] = {x, y, 0};
      for (int a = 0; a < 3; a++)
        for (int sg = -1; sg <= 1; sg += 2) {
          int nb[3] = {x, y, 0};
          nb[a] += sg;
          if (plate_solid(p, nb[0], nb[1], nb[2])) continue;
          int skip = 0;
          for (int k = 0; k < p->nopen; k++) skip |= a == 2 && sg < 0 && p->open_cells[k][0] == x && p->open_cells[k][1] == y;
          if (skip) continue;
          int b = (a + 1) % 3, c = (a + 2) % 3;
          for (int i = 0; i < S; i++)
            for (int j = 0; j < S; j++) {
              static const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
              int q[4];
              for (int k = 0; k < 4; k++) {
                int g[3];
                g[a] = (cell[a] + (sg > 0)) * S, g[b] = cell[b] * S + i + du[k], g[c] = cell[c] * S + j + dv[k];
                int key = (g[0] * gy + g[1]) * gz + g[2];
                if (id[key] < 0) id[key] = add_v(m, (double)g[0] / S, (double)g[1] / S, (double)g[2] / S);
                q[k] = id[key];
              }
              if (sg > 0) add_f(m, q[0], q[1], q[2]), add_f(m, q[0], q[2], q[3]);
              else add_f(m, q[0], q[2], q[1]), add_f(m, q[0], q[3], q[2]);
            }
        }
    }
  free(id);
}

static void make_genus2(mesh *m) { make_plate(m, &(plate){5, 3, 0, 0, {{0}}}); }
static void make_genus3(mesh *m) { make_plate(m, &(plate){7, 3, 0, 0, {{0}}}); }
static void make_genus5(mesh *m) { make_plate(m, &(plate){11, 3, 0, 0, {{0}}}); }
static void make_genus2_1loop(mesh *m) { make_plate(m, &(plate){5, 3, 0, 1, {{0, 0}}}); }
static void make_genus2_2loops(mesh *m) { make_plate(m, &(plate){5, 3, 0, 2, {{0, 0}, {4, 2}}}); }
static void make_genus2_thin(mesh *m) { make_plate(m, &(plate){5, 10, 1, 0, {{0}}}); }

/* Genus-1 mugs: a body of revolution (a rounded cylinder of radius 1) on an aligned grid, nlon vertices a
 * ring and rings not turned, so that a hole is a block of grid quads; a thin handle, a tube from one hole
 * in the body's side to another (the handle makes the genus); and a long thin spout, a tube from a third
 * hole to a closed round tip. Faces are built unoriented and oriented afterwards by a walk (orient()). */
typedef struct mug_par {
  double H;             /* the body's height; its radius is 1, its rim rounded with radius 0.3 */
  double hr, hreach;    /* the handle tube's radius and how far its centreline reaches out from the body */
  double hz0, hz1;      /* the heights of the handle's holes */
  double sr, slen;      /* the spout tube's radius and the length of its centreline */
  double sz, sang;      /* the spout hole's height and the spout's final direction above the horizontal */
  int nlon, girth;      /* vertices around the body and around each tube */
} mug_par;

#define MUG_RIM 0.3

/* The body's profile at arc length s from the bottom pole: bottom disk, rounded rim, side, rim, top. */
static void mug_profile(double s, double H, double *rho, double *z) {
  const double c = MUG_RIM, flat = 1 - c, arc = 0.5 * M_PI * c, side = H - 2 * c;
  if (s < flat) *rho = s, *z = 0;
  else if ((s -= flat) < arc) *rho = flat + c * sin(s / c), *z = c - c * cos(s / c);
  else if ((s -= arc) < side) *rho = 1, *z = c + s;
  else if ((s -= side) < arc) *rho = flat + c * cos(s / c), *z = H - c + c * sin(s / c);
  else *rho = fmax(flat - (s - arc), 0), *z = H;
}

/* A cubic Bezier centreline, resampled by arc length. */
typedef struct curve {
  double P[4][3];
  double len;
  double nrm[3]; /* the unit normal of the plane the centreline lies in */
} curve;

static void bez(const curve *c, double t, double *p, double *d) {
  double u = 1 - t, b[4] = {u * u * u, 3 * u * u * t, 3 * u * t * t, t * t * t};
  double db[4] = {-3 * u * u, 3 * u * u - 6 * u * t, 6 * u * t - 3 * t * t, 3 * t * t};
  for (int k = 0; k < 3; k++) {
    p[k] = d[k] = 0;
    for (int i = 0; i < 4; i++) p[k] += b[i] * c->P[i][k], d[k] += db[i] * c->P[i][k];
  }
  normalize3(d);
}

enum { CURVE_NS = 4000 };

/* Point and unit tangent at arc length s (beyond the end: continued along the end's tangent). */
static void curve_at(curve *c, double s, double *p, double *d) {
  double q[3], e[3], acc = 0, t0 = 0;
  bez(c, 0, q, e);
  for (int i = 1; i <= CURVE_NS; i++) {
    double t = (double)i / CURVE_NS, r[3];
    bez(c, t, r, e);
    double dl = sqrt((r[0] - q[0]) * (r[0] - q[0]) + (r[1] - q[1]) * (r[1] - q[1]) + (r[2] - q[2]) * (r[2] - q[2]));
    if (acc + dl >= s && dl > 0) {
      bez(c, t0 + (t - t0) * (s - acc) / dl, p, d);
      return;
    }
    acc += dl, t0 = t;
    memcpy(q, r, sizeof q);
  }
  c->len = acc;
  bez(c, 1, p, d);
  for (int k = 0; k < 3; k++) p[k] += (s - acc) * d[k];
}

static double curve_length(curve *c) {
  double p[3], d[3];
  curve_at(c, 1e300, p, d);
  return c->len;
}

/* A loop of vertices with their angles about a tube's axis, for join_loops. */
typedef struct loop {
  int *v, n;
  double *a;
} loop;

/* Angles of the loop's vertices about centre o in the plane of the frame (nx, ny); the loop is turned to
 * run by increasing angle from its vertex of least angle in [0, 2 pi), angles unwrapped. */
static void loop_angles(loop *l, const mesh *m, const double *o, const double *nx, const double *ny) {
  int n = l->n, *v = malloc(sizeof(int) * (size_t)n);
  double *a = malloc(sizeof(double) * (size_t)n);
  if (!v || !a) die_nomem();
  for (int i = 0; i < n; i++) {
    const double *p = m->X + 3 * l->v[i];
    double d[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]};
    a[i] = atan2(dot3(d, ny), dot3(d, nx));
    if (a[i] < 0) a[i] += 2 * M_PI;
  }
  double turn = 0; /* the loop's winding sense: the sum of its angle steps, wrapped to (-pi, pi] */
  for (int i = 0; i < n; i++) turn += remainder(a[(i + 1) % n] - a[i], 2 * M_PI);
  int dir = turn > 0 ? 1 : -1, s = 0;
  for (int i = 1; i < n; i++)
    if (a[i] < a[s]) s = i;
  for (int i = 0; i < n; i++) {
    int j = ((s + dir * i) % n + n) % n;
    v[i] = l->v[j];
    double x = a[j];
    while (i && x < l->a[i - 1]) x += 2 * M_PI;
    l->a[i] = x;
  }
  memcpy(l->v, v, sizeof(int) * (size_t)n);
  free(v);
  free(a);
}

/* Triangulates the band between loops A and B by walking both in angle (each face gets one edge of a
 * loop and a vertex of the other). Orientation is left to orient(). */
static void join_loops(mesh *m, const loop *A, const loop *B) {
  int i = 0, j = 0;
  while (i < A->n || j < B->n) {
    double ta = i + 1 < A->n ? A->a[i + 1] : A->a[0] + 2 * M_PI;
    double tb = j + 1 < B->n ? B->a[j + 1] : B->a[0] + 2 * M_PI;
    if (j < B->n && (i >= A->n || tb <= ta)) {
      add_f(m, A->v[i % A->n], B->v[j % B->n], B->v[(j + 1) % B->n]);
      j++;
    } else {
      add_f(m, A->v[i % A->n], B->v[j % B->n], A->v[(i + 1) % A->n]);
      i++;
    }
  }
}

static void loop_alloc(loop *l, int n) {
  l->n = n;
  l->v = malloc(sizeof(int) * (size_t)n);
  l->a = malloc(sizeof(double) * (size_t)n);
  if (!l->v || !l->a) die_nomem();
}

static void loop_free(loop *l) {
  free(l->v);
  free(l->a);
}

/* The tube's frame at a point of a centreline in the plane of unit normal nrm: nx = nrm x d, ny = nrm
 * (a plane curve's rotation-minimizing frame: no tube twists). */
static void tube_frame(const double *d, const double *nrm, double *nx, double *ny) {
  nx[0] = nrm[1] * d[2] - nrm[2] * d[1], nx[1] = nrm[2] * d[0] - nrm[0] * d[2], nx[2] = nrm[0] * d[1] - nrm[1] * d[0];
  memcpy(ny, nrm, 3 * sizeof *ny);
}

/* A ring of g vertices about centreline point p (tangent d), radius r, turned by `turn` steps. */
static void tube_ring(mesh *m, loop *l, const double *p, const double *d, const double *nrm, double r, int g,
                      double turn) {
  double nx[3], ny[3];
  tube_frame(d, nrm, nx, ny);
  loop_alloc(l, g);
  for (int k = 0; k < g; k++) {
    double t = 2 * M_PI * (k + turn) / g;
    l->v[k] = add_v(m, p[0] + r * (cos(t) * nx[0] + sin(t) * ny[0]), p[1] + r * (cos(t) * nx[1] + sin(t) * ny[1]),
                    p[2] + r * (cos(t) * nx[2] + sin(t) * ny[2]));
  }
  loop_angles(l, m, p, nx, ny);
}

/* A tube along c from loop `from` (a hole's rim, radius r0) to loop `to` (another hole's rim) or, when
 * `to` is NULL, to a round closed tip. The radius eases from r0 to r over the first (and, into a hole,
 * the last) `ease` of its length; rings are about one edge of the thin part apart, turned half a step. */
static void tube(mesh *m, curve *c, loop *from, loop *to, double r0, double r, int g) {
  const double L = curve_length(c), step = 2 * M_PI * r / g, ease = 4 * r0;
  double p[3], d[3], nx[3], ny[3];
  curve_at(c, 0, p, d);
  tube_frame(d, c->nrm, nx, ny);
  loop_angles(from, m, p, nx, ny);
  int nr = (int)lround((to ? L : L - step) / step) - 1;
  loop prev = *from;
  for (int j = 1; j <= nr; j++) {
    double s = L * j / (nr + 1), w = 1;
    if (s < ease) w = fmin(w, 0.5 - 0.5 * cos(M_PI * s / ease));
    if (to && L - s < ease) w = fmin(w, 0.5 - 0.5 * cos(M_PI * (L - s) / ease));
    loop cur;
    curve_at(c, s, p, d);
    tube_ring(m, &cur, p, d, c->nrm, r0 + (r - r0) * w, g, 0.5 * j);
    join_loops(m, &prev, &cur);
    if (prev.v != from->v) loop_free(&prev);
    prev = cur;
  }
  if (to) {
    curve_at(c, L, p, d);
    tube_frame(d, c->nrm, nx, ny);
    loop_angles(to, m, p, nx, ny);
    join_loops(m, &prev, to);
  } else {
    /* The tip: two rings on a quarter circle, then the apex. */
    for (int q = 1; q <= 3; q++) {
      double phi = 0.5 * M_PI * q / 4;
      loop cur;
      curve_at(c, L + r * sin(phi), p, d);
      tube_ring(m, &cur, p, d, c->nrm, r * cos(phi), g, 0.5 * (nr + 1 + q));
      join_loops(m, &prev, &cur);
      loop_free(&prev);
      prev = cur;
    }
    curve_at(c, L + r, p, d);
    int tip = add_v(m, p[0], p[1], p[2]);
    for (int k = 0; k < g; k++) add_f(m, prev.v[k], prev.v[(k + 1) % g], tip);
  }
  if (prev.v != from->v) loop_free(&prev);
}

/* Keeps only the vertices that faces use, renumbered in order. */
static void compact(mesh *m) {
  int *map = malloc(sizeof(int) * (size_t)m->nv), n = 0;
  if (!map) die_nomem();
  for (int i = 0; i < m->nv; i++) map[i] = -1;
  for (int i = 0; i < 3 * m->nf; i++) map[m->F[i]] = 0;
  for (int i = 0; i < m->nv; i++)
    if (!map[i]) {
      memmove(m->X + 3 * n, m->X + 3 * i, sizeof(double) * 3);
      map[i] = n++;
    }
  for (int i = 0; i < 3 * m->nf; i++) m->F[i] = map[m->F[i]];
  m->nv = n;
  free(map);
}

/* Orients the faces consistently by a breadth-first walk across edges (a face next to an oriented one
 * must use their shared edge the other way round), then flips them all if the volume is negative. An
 * edge in other than two faces is left for check() to refuse. */
typedef struct edge_face {
  uint64_t key;
  int f;
} edge_face;

static int cmp_edge_face(const void *a, const void *b) {
  const edge_face *x = a, *y = b;
  return x->key != y->key ? (x->key > y->key) - (x->key < y->key) : (x->f > y->f) - (x->f < y->f);
}

static void orient(mesh *m) {
  int nf = m->nf, ne = 3 * nf;
  edge_face *ef = malloc(sizeof(edge_face) * (size_t)ne);
  int *queue = malloc(sizeof(int) * (size_t)nf), *other = malloc(sizeof(int) * (size_t)ne);
  unsigned char *done = calloc((size_t)nf, 1);
  if (!ef || !queue || !other || !done) die_nomem();
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) {
      uint64_t a = (uint64_t)m->F[3 * f + k], b = (uint64_t)m->F[3 * f + (k + 1) % 3];
      ef[3 * f + k] = (edge_face){a < b ? a << 32 | b : b << 32 | a, 3 * f + k};
    }
  qsort(ef, (size_t)ne, sizeof *ef, cmp_edge_face);
  for (int i = 0; i < ne; i++) other[i] = -1;
  for (int i = 0; i + 1 < ne; i++)
    if (ef[i].key == ef[i + 1].key && (i + 2 >= ne || ef[i + 2].key != ef[i].key)) {
      other[ef[i].f] = ef[i + 1].f / 3;
      other[ef[i + 1].f] = ef[i].f / 3;
    }
  for (int head = 0, tail = 0, seed = 0; seed < nf; seed++) {
    if (done[seed]) continue;
    done[seed] = 1, queue[tail++] = seed;
    while (head < tail) {
      int f = queue[head++];
      for (int k = 0; k < 3; k++) {
        int a = m->F[3 * f + k], b = m->F[3 * f + (k + 1) % 3], g = other[3 * f + k];
        if (g < 0 || done[g]) continue;
        int *t = m->F + 3 * g;
        for (int j = 0; j < 3; j++)
          if (t[j] == a && t[(j + 1) % 3] == b) { /* the same direction: turn g over */
            int x = t[1];
            t[1] = t[2], t[2] = x;
            int o = other[3 * g];
            other[3 * g] = other[3 * g + 2], other[3 * g + 2] = o;
            break;
          }
        done[g] = 1, queue[tail++] = g;
      }
    }
  }
  double vol = 0;
  for (int f = 0; f < nf; f++) {
    const double *a = m->X + 3 * m->F[3 * f], *b = m->X + 3 * m->F[3 * f + 1], *c = m->X + 3 * m->F[3 * f + 2];
    vol += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  if (vol < 0)
    for (int f = 0; f < nf; f++) {
      int x = m->F[3 * f + 1];
      m->F[3 * f + 1] = m->F[3 * f + 2], m->F[3 * f + 2] = x;
    }
  free(ef);
  free(queue);
  free(other);
  free(done);
}

/* A hole in the body's grid: the block of quads of rings [ic - hw, ic + hw) and columns [kc - hw, kc + hw). */
typedef struct grid_hole {
  int ic, kc, hw;
} grid_hole;

static int in_grid_hole(const grid_hole *h, int nh, int i, int k, int nlon) {
  for (int j = 0; j < nh; j++) {
    int dk = ((k - h[j].kc) % nlon + nlon + nlon / 2) % nlon - nlon / 2;
    if (i >= h[j].ic - h[j].hw && i < h[j].ic + h[j].hw && dk >= -h[j].hw && dk < h[j].hw) return 1;
  }
  return 0;
}

static void make_mug_from(mesh *m, const mug_par *p) {
  const double c = MUG_RIM, h = 2 * M_PI / p->nlon;
  const double Ls = 2 * (1 - c) + M_PI * c + (p->H - 2 * c);
  const int nlon = p->nlon, nlat = (int)lround(Ls / h) - 1;
  int south = add_v(m, 0, 0, 0);
  for (int i = 1; i <= nlat; i++) {
    double rho, z;
    mug_profile(Ls * i / (nlat + 1), p->H, &rho, &z);
    for (int k = 0; k < nlon; k++) add_v(m, rho * cos(2 * M_PI * k / nlon), rho * sin(2 * M_PI * k / nlon), z);
  }
  int north = add_v(m, 0, 0, p->H);
#define GV(i, k) (1 + ((i) - 1) * nlon + (((k) % nlon + nlon) % nlon))
  /* The ring nearest to height z on the side. */
#define SIDE_RING(z) ((int)lround((1 - c + 0.5 * M_PI * c + (z) - c) / Ls * (nlat + 1)))
  grid_hole hole[3] = {{SIDE_RING(p->hz0), 0, 1}, {SIDE_RING(p->hz1), 0, 1}, {SIDE_RING(p->sz), nlon / 2, 1}};
  for (int k = 0; k < nlon; k++) {
    add_f(m, south, GV(1, k + 1), GV(1, k));
    add_f(m, GV(nlat, k), GV(nlat, k + 1), north);
    for (int i = 1; i < nlat; i++) {
      if (in_grid_hole(hole, 3, i, k, nlon)) continue;
      add_f(m, GV(i, k), GV(i, k + 1), GV(i + 1, k + 1));
      add_f(m, GV(i, k), GV(i + 1, k + 1), GV(i + 1, k));
    }
  }
  /* Each hole's rim, walked around the block, and its centre vertex (left out by compact()). */
  loop rim[3];
  double centre[3][3];
  for (int j = 0; j < 3; j++) {
    int ic = hole[j].ic, kc = hole[j].kc, w = hole[j].hw, n = 0;
    loop_alloc(&rim[j], 8 * w);
    for (int t = -w; t < w; t++) rim[j].v[n++] = GV(ic - w, kc + t);
    for (int t = -w; t < w; t++) rim[j].v[n++] = GV(ic + t, kc + w);
    for (int t = w; t > -w; t--) rim[j].v[n++] = GV(ic + w, kc + t);
    for (int t = w; t > -w; t--) rim[j].v[n++] = GV(ic + t, kc - w);
    memcpy(centre[j], m->X + 3 * GV(ic, kc), sizeof centre[j]);
  }
  const double r0 = 1.1 * h;
  /* The handle: a C in the plane y = 0 from the lower hole out to x = 1 + hreach and back. */
  curve ch = {{{0}}, 0, {0, 1, 0}};
  for (int k = 0; k < 3; k++) ch.P[0][k] = centre[0][k], ch.P[3][k] = centre[1][k];
  memcpy(ch.P[1], ch.P[0], sizeof ch.P[1]);
  memcpy(ch.P[2], ch.P[3], sizeof ch.P[2]);
  ch.P[1][0] += 4.0 / 3 * p->hreach, ch.P[2][0] += 4.0 / 3 * p->hreach;
  tube(m, &ch, &rim[0], &rim[1], r0, p->hr, p->girth);
  /* The spout: out of the far side along -x, bending up to the angle sang over the horizontal. */
  curve cs = {{{0}}, 0, {0, 1, 0}};
  double dir[3] = {-cos(p->sang), 0, sin(p->sang)};
  for (int k = 0; k < 3; k++) {
    cs.P[0][k] = centre[2][k];
    cs.P[1][k] = centre[2][k] + (k == 0 ? -0.3 * p->slen : 0);
    cs.P[3][k] = centre[2][k] + (k == 0 ? -0.3 * p->slen : 0) + 0.75 * p->slen * dir[k];
    cs.P[2][k] = cs.P[3][k] - 0.35 * p->slen * dir[k];
  }
  tube(m, &cs, &rim[2], NULL, r0, p->sr, p->girth);
  for (int j = 0; j < 3; j++) loop_free(&rim[j]);
#undef GV
#undef SIDE_RING
  compact(m);
  orient(m);
}

/* A genus-1 ring with long legs: a torus of revolution (R = 2, tube radius 0.5; 192 x 48 vertices, the
 * grid of make_torus) with a hole of 2 x 2 quads under it at each of four longitudes, and from each a
 * straight leg of girth 8 and radius 0.05 hanging down `len`, closed by a round tip. */
static void make_ring_legs_of(mesh *m, double len) {
  const double R = 2, r = 0.5, rleg = 0.05;
  const int nu = 192, nt = 48, g = 8, nleg = 4;
  for (int i = 0; i < nu; i++)
    for (int j = 0; j < nt; j++) {
      double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nt;
      add_v(m, (R + r * cos(v)) * cos(u), (R + r * cos(v)) * sin(u), r * sin(v));
    }
#define TV(i, j) ((((i) % nu + nu) % nu) * nt + (((j) % nt + nt) % nt))
  const int jc = 3 * nt / 4; /* v = 3 pi / 2: the ring's underside */
  int ic[4];
  for (int k = 0; k < nleg; k++) ic[k] = nu / 8 + k * nu / nleg;
  for (int i = 0; i < nu; i++)
    for (int j = 0; j < nt; j++) {
      int hole = 0;
      for (int k = 0; k < nleg; k++) hole |= (i == ic[k] - 1 || i == ic[k]) && (j == jc - 1 || j == jc);
      if (hole) continue;
      add_f(m, TV(i, j), TV(i + 1, j), TV(i + 1, j + 1));
      add_f(m, TV(i, j), TV(i + 1, j + 1), TV(i, j + 1));
    }
  const double h = r * 2 * M_PI / nt;
  for (int k = 0; k < nleg; k++) {
    loop rim;
    int n = 0, c = ic[k];
    loop_alloc(&rim, 8);
    for (int t = -1; t < 1; t++) rim.v[n++] = TV(c + t, jc - 1);
    for (int t = -1; t < 1; t++) rim.v[n++] = TV(c + 1, jc + t);
    for (int t = 1; t > -1; t--) rim.v[n++] = TV(c + t, jc + 1);
    for (int t = 1; t > -1; t--) rim.v[n++] = TV(c - 1, jc + t);
    double u = 2 * M_PI * c / nu;
    curve cl = {{{0}}, 0, {-sin(u), cos(u), 0}};
    memcpy(cl.P[0], m->X + 3 * TV(c, jc), sizeof cl.P[0]);
    for (int q = 1; q < 4; q++) {
      memcpy(cl.P[q], cl.P[0], sizeof cl.P[q]);
      cl.P[q][2] -= len * q / 3;
    }
    tube(m, &cl, &rim, NULL, 1.1 * h, rleg, g);
    loop_free(&rim);
  }
#undef TV
  compact(m);
  orient(m);
}

static void make_ring_legs(mesh *m) { make_ring_legs_of(m, 2.5); }

static void make_mug(mesh *m) {
  make_mug_from(m, &(mug_par){.H = 2.4, .hr = 0.04, .hreach = 0.8, .hz0 = 0.7, .hz1 = 1.8, .sr = 0.06, .slen = 1.6,
                              .sz = 0.6, .sang = 0.8, .nlon = 96, .girth = 8});
}

static void make_mug_long(mesh *m) {
  make_mug_from(m, &(mug_par){.H = 2.4, .hr = 0.03, .hreach = 0.8, .hz0 = 0.7, .hz1 = 1.8, .sr = 0.04, .slen = 3.0,
                              .sz = 0.6, .sang = 0.8, .nlon = 96, .girth = 8});
}

/* Self-check that every mesh is what the README promises: each directed edge used once and its
 * reverse present (closed, manifold along edges, consistently oriented), Euler characteristic 2 on
 * one component (genus 0), and positive signed volume (outward normals). Returns 0 if all hold.
 * Open meshes (loops > 0) instead: each directed edge used once, the edges without a reverse forming
 * exactly `loops` boundary loops, Euler characteristic 2 - loops (genus 0), one component, and a
 * positive projected area in the xy plane (counter-clockwise seen from +z); *volume gets the area.
 * Closed meshes of genus g (the tori: g = 1) have Euler characteristic 2 - 2g instead of 2. */
static int cmp_u64(const void *a, const void *b) {
  uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
  return (x > y) - (x < y);
}

static int find_root(int *parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

static int check(const mesh *m, const char *name, int loops, int genus, double *volume) {
  size_t ne = 3 * (size_t)m->nf;
  uint64_t *e = malloc(sizeof(uint64_t) * ne);
  int *parent = malloc(sizeof(int) * (size_t)m->nv);
  if (!e || !parent) die_nomem();
  double vol = 0;
  for (int i = 0; i < m->nv; i++) parent[i] = i;
  for (int f = 0; f < m->nf; f++) {
    const int *t = m->F + 3 * f;
    const double *a = m->X + 3 * t[0], *b = m->X + 3 * t[1], *c = m->X + 3 * t[2];
    vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
            a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
    for (int k = 0; k < 3; k++) {
      e[3 * f + k] = (uint64_t)t[k] << 32 | (uint64_t)t[(k + 1) % 3];
      parent[find_root(parent, t[k])] = find_root(parent, t[(k + 1) % 3]);
    }
  }
  qsort(e, ne, sizeof *e, cmp_u64);
  int bad = 0, comps = 0;
  for (size_t i = 0; i < ne; i++) {
    uint64_t rev = (e[i] & 0xffffffffu) << 32 | e[i] >> 32;
    if ((i + 1 < ne && e[i + 1] == e[i]) || !bsearch(&rev, e, ne, sizeof *e, cmp_u64)) bad++;
  }
  for (int i = 0; i < m->nv; i++) comps += find_root(parent, i) == i;
  long euler = (long)m->nv - (long)(ne / 2) + m->nf;
  if (loops > 0) {
    /* Directed edges without a reverse are boundary edges: count them and trace their loops. */
    int nb = 0, nl = 0, *next = malloc(sizeof(int) * (size_t)m->nv);
    unsigned char *seen = calloc((size_t)m->nv, 1);
    if (!next || !seen) die_nomem();
    for (int i = 0; i < m->nv; i++) next[i] = -1;
    bad = 0;
    for (size_t i = 0; i < ne; i++) {
      uint64_t rev = (e[i] & 0xffffffffu) << 32 | e[i] >> 32;
      if (i + 1 < ne && e[i + 1] == e[i]) bad++;
      if (!bsearch(&rev, e, ne, sizeof *e, cmp_u64)) {
        int a = (int)(e[i] >> 32), b = (int)(e[i] & 0xffffffffu);
        if (next[a] >= 0) bad++; /* two boundary edges leave a: not a manifold boundary */
        next[a] = b, nb++;
      }
    }
    for (int i = 0; i < m->nv; i++) {
      if (next[i] < 0 || seen[i]) continue;
      nl++;
      for (int v = i; v >= 0 && !seen[v]; v = next[v]) seen[v] = 1;
    }
    euler = (long)m->nv - (long)((ne + (size_t)nb) / 2) + m->nf;
    vol = 0;
    for (int f = 0; f < m->nf; f++) {
      const int *t = m->F + 3 * f;
      const double *a = m->X + 3 * t[0], *b = m->X + 3 * t[1], *c = m->X + 3 * t[2];
      vol += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    }
    free(next);
    free(seen);
    if (nl != loops) bad++;
    euler += loops; /* compare with 2 below: V - E + F = 2 - loops for genus 0 */
  }
  euler += 2 * genus; /* V - E + F = 2 - 2g */
  free(e);
  free(parent);
  *volume = vol;
  if (bad || comps != 1 || euler != 2 || !(vol > 0)) {
    fprintf(stderr, "au_mkdata: %s failed its check: %d bad half-edges, %d components, euler %ld, volume %g\n",
            name, bad, comps, euler, vol);
    return 1;
  }
  return 0;
}

/* Write OBJ through a temporary file and a rename, so a failed run never leaves a half-written mesh. */
static int write_obj(const mesh *m, double vol, int loops, const char *dir, const char *name, const char *what) {
  char path[4096], tmp[4200];
  if (snprintf(path, sizeof path, "%s/%s.obj", dir, name) >= (int)sizeof path) {
    fprintf(stderr, "au_mkdata: output path too long\n");
    return 1;
  }
  snprintf(tmp, sizeof tmp, "%s.tmp", path);
  FILE *fp = fopen(tmp, "w");
  if (!fp) {
    fprintf(stderr, "au_mkdata: cannot write %s: %s\n", tmp, strerror(errno));
    return 1;
  }
  fprintf(fp, "# %s.obj - %s\n# generated by au_mkdata (data/mkdata.c); V %d F %d\n", name, what, m->nv, m->nf);
  for (int i = 0; i < m->nv; i++)
    fprintf(fp, "v %.17g %.17g %.17g\n", m->X[3 * i], m->X[3 * i + 1], m->X[3 * i + 2]);
  for (int f = 0; f < m->nf; f++)
    fprintf(fp, "f %d %d %d\n", m->F[3 * f] + 1, m->F[3 * f + 1] + 1, m->F[3 * f + 2] + 1);
  int ok = !ferror(fp);
  ok &= fclose(fp) == 0;
  if (!ok || rename(tmp, path) != 0) {
    fprintf(stderr, "au_mkdata: cannot write %s: %s\n", path, strerror(errno));
    remove(tmp);
    return 1;
  }
  printf("%-12s V %5d  F %5d  %s %.6g  -> %s\n", name, m->nv, m->nf, loops ? "area" : "volume", vol, path);
  return 0;
}

static const struct {
  const char *name, *what;
  void (*make)(mesh *);
  int loops; /* boundary loops: 0 closed, 1 disk, 2 annulus, more: a disk with holes */
  int genus; /* 0, 1 for the tori, 2..5 for the plates */
} meshes[] = {
    {"bumpy_star", "icosphere level 4 with six long fingers and low bumps (default for make run)", make_bumpy_star, 0, 0},
    {"dumbbell", "two unit spheres joined by a thin neck (surface of revolution)", make_dumbbell, 0, 0},
    {"spiky_ico", "icosphere level 3 with 12 long spikes at the icosahedron vertices", make_spiky_ico, 0, 0},
    {"ellipsoid", "prolate ellipsoid 1:1:4 (surface of revolution)", make_ellipsoid, 0, 0},
    {"disk_bump", "unit disk lifted by a tall Gaussian bump and a low one (one boundary loop)", make_disk_bump, 1, 0},
    {"annulus_bump", "annulus 0.35 <= r <= 1 lifted by the same bumps (two boundary loops)", make_annulus_bump, 2, 0},
    {"holed_sphere", "the unit sphere with a hole of 12 degrees: a short boundary for its area (one boundary loop)", make_holed_sphere, 1, 0},
    {"holes3", "disk with 3 round holes of different sizes, near the rim and each other, on hills (4 boundary loops)", make_holes3, 4, 0},
    {"holes10", "disk with 10 round holes of varied sizes on hills (11 boundary loops)", make_holes10, 11, 0},
    {"holes40", "disk with 40 round holes of varied sizes, close together, on hills (41 boundary loops)", make_holes40, 41, 0},
    {"face_holes", "face-like height field with open eyes and mouth (4 boundary loops)", make_face_holes, 4, 0},
    {"torus_r2", "torus of revolution R/r = 2, 48 x 24 vertices (genus 1)", make_torus_r2, 0, 1},
    {"torus_r3", "torus of revolution R/r = 3, 72 x 24 vertices (genus 1)", make_torus_r3, 0, 1},
    {"torus_r5", "torus of revolution R/r = 5, 120 x 24 vertices (genus 1)", make_torus_r5, 0, 1},
    {"genus2", "double torus: the surface of a 5 x 3 plate of cubes with two holes", make_genus2, 0, 2},
    {"genus3", "pretzel of genus 3: a 7 x 3 plate of cubes with three holes", make_genus3, 0, 3},
    {"genus5", "pretzel of genus 5: an 11 x 3 plate of cubes with five holes", make_genus5, 0, 5},
    {"genus2_1loop", "the double torus with one cube's bottom face left out (one boundary loop)", make_genus2_1loop, 1, 2},
    {"genus2_2loops", "the double torus with two cubes' bottom faces left out (two boundary loops)", make_genus2_2loops, 2, 2},
    {"genus2_thin", "genus 2 with a long thin handle: a 5 x 10 plate, a one-cube hole and a long one beside a bar 1 x 10",
     make_genus2_thin, 0, 2},
    {"mug", "genus-1 mug: a rounded body, a thin handle (the genus) and a long thin spout", make_mug, 0, 1},
    {"mug_long", "the mug with a thinner handle and a spout twice as long and two thirds as thick", make_mug_long, 0, 1},
    {"ring_legs", "genus-1 ring (torus of revolution) with four long thin legs hanging down", make_ring_legs, 0, 1},
};

int main(int argc, char **argv) {
  if (argc == 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
    printf("usage: au_mkdata OUTDIR\n"
           "Writes the project's test meshes (genus 0, and tori of genus 1; closed ones outward-oriented,\n"
           "open ones counter-clockwise seen from +z) as OBJ into OUTDIR:\n");
    for (size_t i = 0; i < sizeof meshes / sizeof *meshes; i++)
      printf("  %-12s %s\n", meshes[i].name, meshes[i].what);
    return 0;
  }
  if (argc == 2 && !strcmp(argv[1], "--version")) {
    printf("au_mkdata (authalic) %s\n", AU_VERSION);
    return 0;
  }
  if (argc != 2 || argv[1][0] == '-') {
    fprintf(stderr, "usage: au_mkdata OUTDIR   (--help for details)\n");
    return 2;
  }
  int status = 0;
  for (size_t i = 0; i < sizeof meshes / sizeof *meshes; i++) {
    mesh m = {0};
    double vol;
    meshes[i].make(&m);
    if (check(&m, meshes[i].name, meshes[i].loops, meshes[i].genus, &vol)) status = 1;
    else if (write_obj(&m, vol, meshes[i].loops, argv[1], meshes[i].name, meshes[i].what)) status = 2;
    mesh_free(&m);
  }
  return status;
}
