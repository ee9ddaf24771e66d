/* texture_patches.c - the acceptance measure of equal-area textures (issue 4): how fairly a texture
 * of a sphere map shares its texels among equal-area surface patches, and how equal the surface
 * areas of the cells of an equal-area sampling grid are.
 *
 *   au_texture_patches MESH MAP [--projection cea|laea|oct] [--area-tol T|auto] [--patches K]
 *                      [--size WxH] [--cells WxH] [--sub S] [--iters T]
 *
 * Patches: K connected groups of faces of (nearly) equal area, built on the dual graph of MESH
 * (faces joined across edges, weighted by the distance of their centroids): K seeds by farthest-point
 * sampling, then a multiplicatively weighted geodesic Voronoi partition by multi-source Dijkstra
 * (every face inherits its label from the face it was reached from, so patches are connected), whose
 * per-patch speeds are rescaled T times by (target area / patch area)^0.5 until the areas agree.
 * The texture: au_tex_coords_opts of MAP in the projection (default cea; --area-tol as `authalic
 * texture`), whose layout (chart size, rotation) both measures below use.
 * Texel share, exact: every texel centre of a W x H image in the projection's primary region (cea:
 * all; laea: each chart's disc of radius sqrt 2, not the ring holding the other hemisphere's
 * continuation, which would count the equator twice; oct: the square [-1, 1]^2, not the gutter)
 * goes to the sphere (au_tex_to_sphere), is located exactly in MAP's triangles, and counts for the
 * patch of that face. This is the projection's own promise.
 * Texel share, through the vt: every texel centre is tested against the texture's straight-edged
 * vt triangles (what a GPU reads; cea's faces across the seam wrap in u) and counts for the patch
 * of the input face the vt triangle comes from. This includes the per-face area error of the
 * straight triangles (issue 18), which the exact measure does not see.
 * Both figures are |texel share / area share - 1| per patch: mean and max.
 * Cells: the surface area of the preimage of every cell of a W x H cea grid (au_tex_cell_areas,
 * S x S sub-samples per cell), std/mean; cea whatever the projection.
 * Defaults: 1024x512 texels (cea, laea: two square charts side by side), 1024x1024 (oct: one square).
 * Prints one JSON object on stdout. Exit 0 ok, 2 bad usage or input, 1 failure. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "au_io.h"
#include "au_mesh.h"
#include "au_metrics.h"
#include "au_texture.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef struct heap {
  double *key;
  int *node;
  int n, cap;
} heap;

static int heap_push(heap *h, double k, int v) {
  if (h->n == h->cap) {
    int nc = h->cap ? 2 * h->cap : 1024;
    double *nk = realloc(h->key, (size_t)nc * sizeof *nk);
    if (!nk) return -1;
    h->key = nk;
    int *nn = realloc(h->node, (size_t)nc * sizeof *nn);
    if (!nn) return -1;
    h->node = nn, h->cap = nc;
  }
  int i = h->n++;
  while (i > 0) {
    int p = (i - 1) / 2;
    if (h->key[p] <= k) break;
    h->key[i] = h->key[p], h->node[i] = h->node[p];
    i = p;
  }
  h->key[i] = k, h->node[i] = v;
  return 0;
}

static int heap_pop(heap *h, double *k, int *v) {
  if (h->n == 0) return -1;
  *k = h->key[0], *v = h->node[0];
  double lk = h->key[--h->n];
  int lv = h->node[h->n], i = 0;
  for (;;) {
    int c = 2 * i + 1;
    if (c >= h->n) break;
    if (c + 1 < h->n && h->key[c + 1] < h->key[c]) c++;
    if (h->key[c] >= lk) break;
    h->key[i] = h->key[c], h->node[i] = h->node[c];
    i = c;
  }
  h->key[i] = lk, h->node[i] = lv;
  return 0;
}

/* Neighbour j (0..2) of face f across its edges, -1 if none; weight: distance of centroids. */
static int nb(const au_topo *t, int f, int j) {
  int e = t->FE[3 * f + j];
  int a = t->EF[2 * e], b = t->EF[2 * e + 1];
  return a == f ? b : a;
}

static double cdist(const double *C, int a, int b) {
  double d0 = C[3 * a] - C[3 * b], d1 = C[3 * a + 1] - C[3 * b + 1], d2 = C[3 * a + 2] - C[3 * b + 2];
  return sqrt(d0 * d0 + d1 * d1 + d2 * d2);
}

/* Multi-source Dijkstra: dist/speed per seed; label out. Returns 0 or -1 (memory). */
static int voronoi(const au_topo *t, const double *C, int nf, int K, const int *seed, const double *speed, double *dist,
                   int *label, heap *h) {
  for (int f = 0; f < nf; f++) dist[f] = INFINITY, label[f] = -1;
  h->n = 0;
  for (int k = 0; k < K; k++) {
    dist[seed[k]] = 0, label[seed[k]] = k;
    if (heap_push(h, 0, seed[k])) return -1;
  }
  double d;
  int f;
  while (heap_pop(h, &d, &f) == 0) {
    if (d > dist[f]) continue;
    for (int j = 0; j < 3; j++) {
      int g = nb(t, f, j);
      if (g < 0) continue;
      double nd = d + cdist(C, f, g) / speed[label[f]];
      if (nd < dist[g]) {
        dist[g] = nd, label[g] = label[f];
        if (heap_push(h, nd, g)) return -1;
      }
    }
  }
  return 0;
}

/* Whether the texel centre (u, v) lies in the layout's primary region, where every point of the
 * sphere has exactly one texel position (see the header). */
static int primary(const au_tex_layout *lay, double u, double v) {
  if (lay->proj == AU_TEX_OCT) {
    double s = (2 * u - 1) * lay->half, t = (2 * v - 1) * lay->half;
    return fabs(s) <= 1 && fabs(t) <= 1;
  }
  if (lay->proj == AU_TEX_LAEA) {
    double uu = u >= 0.5 ? u - 0.5 : u, x = (4 * uu - 1) * lay->half, y = (2 * v - 1) * lay->half;
    return x * x + y * y <= 2;
  }
  return 1;
}

/* Count the texel centres inside every vt triangle of t for the patch of its input face: cnt[k]
 * gets the count of patch k, the total is returned. Texel (r, c) has its centre at u = (c + 0.5)/W,
 * v = 1 - (r + 0.5)/H; the test runs in texel units (x = u W - 0.5, y = (1 - v) H - 0.5, centres on
 * integers). A centre on an edge shared by two triangles would count twice with a closed test and
 * not at all with an open one, so an edge owns the centres on it only from one side (the edge's
 * direction decides, a fixed rule both neighbours agree on). cea: u is periodic, so columns wrap
 * (faces across the seam have u outside [0, 1]). */
static double count_vt(const au_tex_mesh *t, const int *label, int W, int H, double *cnt) {
  double total = 0;
  int wrap = t->layout.proj == AU_TEX_CEA;
  for (int f = 0; f < t->nf; f++) {
    double x[3], y[3];
    for (int j = 0; j < 3; j++) {
      const double *q = t->vt + 2 * (size_t)t->Ft[3 * f + j];
      x[j] = q[0] * W - 0.5, y[j] = (1 - q[1]) * H - 0.5;
    }
    /* y grows downwards, so a counter-clockwise vt triangle has a negative signed area here. */
    double area2 = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    if (area2 == 0) continue;
    double sgn = area2 > 0 ? 1 : -1;
    int c0 = (int)ceil(fmin(x[0], fmin(x[1], x[2]))), c1 = (int)floor(fmax(x[0], fmax(x[1], x[2])));
    int r0 = (int)ceil(fmin(y[0], fmin(y[1], y[2]))), r1 = (int)floor(fmax(y[0], fmax(y[1], y[2])));
    if (r0 < 0) r0 = 0;
    if (r1 > H - 1) r1 = H - 1;
    if (!wrap) {
      if (c0 < 0) c0 = 0;
      if (c1 > W - 1) c1 = W - 1;
    }
    long n = 0;
    for (int r = r0; r <= r1; r++)
      for (int c = c0; c <= c1; c++) {
        int in = 1;
        for (int j = 0; j < 3 && in; j++) {
          int a = (j + 1) % 3, b = (j + 2) % 3;
          double ex = x[b] - x[a], ey = y[b] - y[a];
          double e = sgn * (ex * (r - y[a]) - ey * (c - x[a]));
          /* On the edge: owned by the triangle that sees the edge going up, or going right when level. */
          double dx = sgn * ex, dy = sgn * ey;
          in = e > 0 || (e == 0 && (dy < 0 || (dy == 0 && dx > 0)));
        }
        n += in;
      }
    cnt[label[t->src_face[f]]] += (double)n;
    total += (double)n;
  }
  return total;
}

static int parse_wh(const char *s, int *W, int *H) {
  return sscanf(s, "%dx%d", W, H) == 2 && *W > 0 && *H > 0 && *W <= 16384 && *H <= 16384 ? 0 : -1;
}

int main(int argc, char **argv) {
  const char *mesh_path = NULL, *map_path = NULL;
  int K = 200, W = 0, H = 0, CW = 0, CH = 0, sub = 4, iters = 60;
  au_tex_opts topt = au_tex_opts_default();
  const char *pname = "cea";
  for (int i = 1; i < argc; i++) {
    const char *s = argv[i];
    if (strcmp(s, "--patches") == 0 && i + 1 < argc) K = atoi(argv[++i]);
    else if (strcmp(s, "--projection") == 0 && i + 1 < argc) {
      pname = argv[++i];
      if (strcmp(pname, "cea") == 0) topt.proj = AU_TEX_CEA;
      else if (strcmp(pname, "laea") == 0) topt.proj = AU_TEX_LAEA;
      else if (strcmp(pname, "oct") == 0) topt.proj = AU_TEX_OCT;
      else return fprintf(stderr, "bad --projection\n"), 2;
    } else if (strcmp(s, "--area-tol") == 0 && i + 1 < argc) {
      const char *a = argv[++i];
      char *end;
      topt.area_tol = strcmp(a, "auto") == 0 ? -1 : strtod(a, &end);
      if (strcmp(a, "auto") != 0 && (*end || !(topt.area_tol >= 0))) return fprintf(stderr, "bad --area-tol\n"), 2;
    }
    else if (strcmp(s, "--size") == 0 && i + 1 < argc) {
      if (parse_wh(argv[++i], &W, &H)) return fprintf(stderr, "bad --size\n"), 2;
    } else if (strcmp(s, "--cells") == 0 && i + 1 < argc) {
      if (parse_wh(argv[++i], &CW, &CH)) return fprintf(stderr, "bad --cells\n"), 2;
    } else if (strcmp(s, "--sub") == 0 && i + 1 < argc) sub = atoi(argv[++i]);
    else if (strcmp(s, "--iters") == 0 && i + 1 < argc) iters = atoi(argv[++i]);
    else if (s[0] == '-') return fprintf(stderr, "usage: %s MESH MAP [--projection cea|laea|oct] [--area-tol T|auto] [--patches K] [--size WxH] [--cells WxH] [--sub S] [--iters T]\n", argv[0]), 2;
    else if (!mesh_path) mesh_path = s;
    else if (!map_path) map_path = s;
    else return fprintf(stderr, "extra argument '%s'\n", s), 2;
  }
  if (W == 0) W = 1024, H = topt.proj == AU_TEX_OCT ? 1024 : 512;
  if (!mesh_path || !map_path || K < 2 || sub < 1 || sub > 64 || iters < 0)
    return fprintf(stderr, "usage: %s MESH MAP [--projection cea|laea|oct] [--area-tol T|auto] [--patches K] [--size WxH] [--cells WxH] [--sub S] [--iters T]\n", argv[0]), 2;
  au_msg msg = {{0}};
  au_mesh *m = NULL, *s = NULL;
  au_topo *t = NULL;
  if (au_io_read(mesh_path, &m, &msg) != AU_OK || au_io_read(map_path, &s, &msg) != AU_OK)
    return fprintf(stderr, "cannot read: %s\n", msg.text), 2;
  if (s->nv != m->nv || s->nf != m->nf) return fprintf(stderr, "the map does not match the mesh\n"), 2;
  if (au_mesh_topology(m, &t, &msg) != AU_OK) return fprintf(stderr, "topology: %s\n", msg.text), 2;
  int nf = m->nf;
  if (K > nf) K = nf;
  double *P = s->X;
  for (int i = 0; i < m->nv; i++) {
    double *q = P + 3 * i, r = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    if (r > 0) q[0] /= r, q[1] /= r, q[2] /= r;
  }
  au_metrics met;
  if (au_metrics_compute(m->nv, nf, m->X, P, m->F, AU_DOMAIN_SPHERE, &met, NULL, NULL) != AU_OK)
    return fprintf(stderr, "metrics failed\n"), 1;

  /* Face centroids and areas. */
  double *C = malloc(3 * (size_t)nf * sizeof *C), *A = malloc((size_t)nf * sizeof *A);
  double *dist = malloc((size_t)nf * sizeof *dist), *speed = malloc((size_t)K * sizeof *speed);
  double *parea = calloc((size_t)K, sizeof *parea);
  int *label = malloc((size_t)nf * sizeof *label), *seed = malloc((size_t)K * sizeof *seed);
  heap h = {0};
  if (!C || !A || !dist || !speed || !parea || !label || !seed) return fprintf(stderr, "out of memory\n"), 1;
  double total = 0;
  for (int f = 0; f < nf; f++) {
    const double *a = m->X + 3 * m->F[3 * f], *b = m->X + 3 * m->F[3 * f + 1], *c = m->X + 3 * m->F[3 * f + 2];
    double e1[3], e2[3];
    for (int j = 0; j < 3; j++) C[3 * f + j] = (a[j] + b[j] + c[j]) / 3, e1[j] = b[j] - a[j], e2[j] = c[j] - a[j];
    double n0 = e1[1] * e2[2] - e1[2] * e2[1], n1 = e1[2] * e2[0] - e1[0] * e2[2], n2 = e1[0] * e2[1] - e1[1] * e2[0];
    A[f] = 0.5 * sqrt(n0 * n0 + n1 * n1 + n2 * n2);
    total += A[f];
  }
  /* Seeds: farthest-point sampling on the dual graph. */
  for (int k = 0; k < K; k++) speed[k] = 1;
  seed[0] = 0;
  for (int k = 1; k < K; k++) {
    if (voronoi(t, C, nf, k, seed, speed, dist, label, &h)) return fprintf(stderr, "out of memory\n"), 1;
    int best = 0;
    for (int f = 1; f < nf; f++)
      if (dist[f] > dist[best]) best = f;
    seed[k] = best;
  }
  /* Equalize the patch areas by per-patch speeds: damped, bounded updates, keeping the best
   * partition seen (the iteration can oscillate once patches are boxed in by their neighbours). */
  double target = total / K, best_dev = INFINITY;
  int *best_label = malloc((size_t)nf * sizeof *best_label);
  if (!best_label) return fprintf(stderr, "out of memory\n"), 1;
  for (int it = 0; it <= iters; it++) {
    if (voronoi(t, C, nf, K, seed, speed, dist, label, &h)) return fprintf(stderr, "out of memory\n"), 1;
    memset(parea, 0, (size_t)K * sizeof *parea);
    for (int f = 0; f < nf; f++)
      if (label[f] >= 0) parea[label[f]] += A[f];
    double dev = 0;
    for (int k = 0; k < K; k++) dev = fmax(dev, fabs(parea[k] / target - 1));
    if (dev < best_dev) best_dev = dev, memcpy(best_label, label, (size_t)nf * sizeof *label);
    for (int k = 0; k < K; k++) speed[k] *= fmin(1.25, fmax(0.8, pow(target / fmax(parea[k], 1e-300), 0.3)));
  }
  memcpy(label, best_label, (size_t)nf * sizeof *label);
  free(best_label);
  memset(parea, 0, (size_t)K * sizeof *parea);
  for (int f = 0; f < nf; f++)
    if (label[f] >= 0) parea[label[f]] += A[f];
  double pmean = 0, pvar = 0, pmin = INFINITY, pmax = 0;
  for (int k = 0; k < K; k++) pmean += parea[k] / K;
  for (int k = 0; k < K; k++) pvar += (parea[k] - pmean) * (parea[k] - pmean) / K, pmin = fmin(pmin, parea[k]), pmax = fmax(pmax, parea[k]);

  /* The texture, then the texel shares through its layout. */
  au_tex_mesh *tm = NULL;
  if (au_tex_coords_opts(m, P, &topt, &tm, &msg) != AU_OK) return fprintf(stderr, "texture: %s\n", msg.text), 1;
  au_tex_layout lay = tm->layout;
  au_locator *loc = NULL;
  if (au_locator_build(m->nv, P, nf, m->F, &loc, &msg) != AU_OK) return fprintf(stderr, "locator: %s\n", msg.text), 1;
  int *face = malloc((size_t)W * H * sizeof *face);
  double *cnt = calloc((size_t)K, sizeof *cnt), *vcnt = calloc((size_t)K, sizeof *vcnt);
  if (!face || !cnt || !vcnt) return fprintf(stderr, "out of memory\n"), 1;
  if (au_tex_locate_texels(&lay, loc, W, H, face, NULL, &msg) != AU_OK) return fprintf(stderr, "texels: %s\n", msg.text), 1;
  long miss = 0, nprim = 0;
  for (long i = 0; i < (long)W * H; i++) {
    double u = (i % W + 0.5) / W, v = 1 - (i / W + 0.5) / H;
    if (!primary(&lay, u, v)) continue;
    nprim++;
    if (face[i] < 0) miss++;
    else cnt[label[face[i]]]++;
  }
  double vtotal = count_vt(tm, label, W, H, vcnt);
  /* The patch's exact share of the sphere (spherical triangle areas, Van Oosterom & Strackee):
   * texel share vs sphere share is the sampling error of the measure itself, sphere share vs
   * surface share the map's own area error at the patch scale. */
  double *sph = calloc((size_t)K, sizeof *sph);
  if (!sph) return fprintf(stderr, "out of memory\n"), 1;
  for (int f = 0; f < nf; f++) {
    const double *a = P + 3 * m->F[3 * f], *b = P + 3 * m->F[3 * f + 1], *c = P + 3 * m->F[3 * f + 2];
    double det = a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
    double den = 1 + (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) + (b[0] * c[0] + b[1] * c[1] + b[2] * c[2]) +
                 (c[0] * a[0] + c[1] * a[1] + c[2] * a[2]);
    sph[label[f]] += 2 * atan2(det, den) / (4 * M_PI);
  }
  double emean = 0, emax = 0, smean = 0, smax = 0, vmean = 0, vmax = 0;
  int worst = 0, over10 = 0, vover10 = 0;
  for (int k = 0; k < K; k++) {
    double ts = cnt[k] / (double)(nprim - miss), as = parea[k] / total, e = fabs(ts / as - 1), es = fabs(ts / sph[k] - 1);
    double ev = fabs(vcnt[k] / vtotal / as - 1);
    emean += e / K, smean += es / K, smax = fmax(smax, es);
    vmean += ev / K, vmax = fmax(vmax, ev), vover10 += ev > 0.1;
    over10 += e > 0.1;
    if (e > emax) emax = e, worst = k;
  }
  double wsphere = sph[worst], wc[3] = {C[3 * seed[worst]], C[3 * seed[worst] + 1], C[3 * seed[worst] + 2]};
  free(sph);
  printf("{\"mesh\": \"%s\", \"map\": \"%s\", \"faces\": %d, \"map_r_cv\": %.5g, \"map_upsilon_mean_abs\": %.5g, "
         "\"map_vertex_logr_mean_abs\": %.5g, \"folds\": %d,\n \"projection\": \"%s\", \"area_tol\": %.4g, "
         "\"texture_faces\": %d, \"texture_folds_left\": %d, \"patches\": %d, \"patch_area_cv\": %.4g, "
         "\"patch_area_min_rel\": %.4g, \"patch_area_max_rel\": %.4g, \"texture\": [%d, %d], \"texels_primary\": %ld, \"texels_missed\": %ld, "
         "\"texel_share_rel_err_mean\": %.5g, \"texel_share_rel_err_max\": %.5g, "
         "\"texel_vs_sphere_share_rel_err_mean\": %.3g, \"texel_vs_sphere_share_rel_err_max\": %.3g",
         mesh_path, map_path, nf, met.r_cv, met.upsilon_mean_abs, met.vertex_logr_mean_abs, met.folds, pname,
         tm->area_tol, tm->nf, tm->folds_left, K, sqrt(pvar) / pmean, pmin / pmean, pmax / pmean, W, H, nprim, miss, emean, emax, smean, smax);
  printf(",\n \"vt_texels\": %.0f, \"vt_texel_share_rel_err_mean\": %.5g, \"vt_texel_share_rel_err_max\": %.5g, "
         "\"vt_patches_over_10pct\": %d", vtotal, vmean, vmax, vover10);
  printf(",\n \"patches_over_10pct\": %d, \"worst_patch\": {\"surface_share\": %.4g, \"sphere_share\": %.4g, "
         "\"texel_share\": %.4g, \"seed_centroid\": [%.4g, %.4g, %.4g]}",
         over10, parea[worst] / total, wsphere, cnt[worst] / (double)(nprim - miss), wc[0], wc[1], wc[2]);
  if (CW > 0) {
    double *area = malloc((size_t)CW * CH * sizeof *area);
    if (!area) return fprintf(stderr, "out of memory\n"), 1;
    au_status st = au_tex_cell_areas(m, P, loc, CW, CH, sub, area, &msg);
    if (st != AU_OK) return fprintf(stderr, "cells: %s\n", msg.text), 1;
    long n = (long)CW * CH;
    double mean = 0, var = 0, mn = INFINITY, mx = 0;
    for (long i = 0; i < n; i++) mean += area[i] / n;
    for (long i = 0; i < n; i++) var += (area[i] - mean) * (area[i] - mean) / n, mn = fmin(mn, area[i]), mx = fmax(mx, area[i]);
    printf(",\n \"cells\": [%d, %d], \"cell_sub\": %d, \"cell_area_cv\": %.5g, \"cell_area_min_rel\": %.4g, \"cell_area_max_rel\": %.4g",
           CW, CH, sub, sqrt(var) / mean, mn / mean, mx / mean);
    free(area);
  }
  printf("}\n");
  au_locator_free(&loc);
  au_tex_mesh_free(&tm);
  free(face), free(cnt), free(vcnt), free(C), free(A), free(dist), free(speed), free(parea), free(label), free(seed);
  free(h.key), free(h.node);
  au_topo_free(&t);
  au_mesh_free(&m);
  au_mesh_free(&s);
  return 0;
}
