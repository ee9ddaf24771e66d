/* au_atlas_layout.c - the cut through the cones and a homology basis, the charts laid out in the cone
 * metric, their packing into the unit square, and the seams' rigid motions (au_atlas.h). */
#include "au_atlas.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define AU_PI 3.14159265358979323846

void au_atlas_layout_free(au_atlas_layout *L) {
  if (!L) return;
  free(L->vt), free(L->Ft), free(L->cut), free(L->chart), free(L->seam_rot), free(L->seam_edge);
  memset(L, 0, sizeof *L);
}

static int uf_find(int *p, int x) {
  while (p[x] != x) x = p[x] = p[p[x]];
  return x;
}
static void uf_union(int *p, int a, int b) {
  a = uf_find(p, a), b = uf_find(p, b);
  if (a != b) p[a > b ? a : b] = a < b ? a : b;
}

/* Corner of face f at vertex v. */
static int corner_at(const int *F, int f, int v) {
  return F[3 * f] == v ? 0 : F[3 * f + 1] == v ? 1 : 2;
}

/* The rows of vt the corners get: corners glued across an interior edge that is not cut share one.
 * uf and cls hold 3 nf entries each; on return corner i's row is cls[uf_find(uf, i)], numbered in
 * corner order. Returns the number of rows. */
static int corner_rows(const au_topo *t, const int *F, int nf, const unsigned char *cut, int *uf, int *cls) {
  for (int i = 0; i < 3 * nf; i++) uf[i] = i;
  for (int e = 0; e < t->ne; e++) {
    if (t->EF[2 * e + 1] < 0 || cut[e]) continue;
    int f0 = t->EF[2 * e], f1 = t->EF[2 * e + 1];
    for (int s = 0; s < 2; s++) {
      int v = t->E[2 * e + s];
      uf_union(uf, 3 * f0 + corner_at(F, f0, v), 3 * f1 + corner_at(F, f1, v));
    }
  }
  int nvt = 0;
  for (int i = 0; i < 3 * nf; i++) cls[i] = -1;
  for (int i = 0; i < 3 * nf; i++) {
    int r = uf_find(uf, i);
    if (cls[r] < 0) cls[r] = nvt++;
  }
  return nvt;
}

/* Binary min-heap of (key, vertex) for Dijkstra. */
typedef struct heap {
  int n;
  double *key;
  int *v;
} heap;
static void heap_push(heap *h, double k, int v) {
  int i = h->n++;
  while (i > 0) {
    int p = (i - 1) / 2;
    if (h->key[p] <= k) break;
    h->key[i] = h->key[p], h->v[i] = h->v[p], i = p;
  }
  h->key[i] = k, h->v[i] = v;
}
static void heap_pop(heap *h, double *k, int *v) {
  *k = h->key[0], *v = h->v[0];
  double lk = h->key[--h->n];
  int lv = h->v[h->n], i = 0;
  for (;;) {
    int c = 2 * i + 1;
    if (c >= h->n) break;
    if (c + 1 < h->n && h->key[c + 1] < h->key[c]) c++;
    if (h->key[c] >= lk) break;
    h->key[i] = h->key[c], h->v[i] = h->v[c], i = c;
  }
  h->key[i] = lk, h->v[i] = lv;
}

/* Angle at corner 0 of a triangle with sides b, c at it and a opposite (the metric is Euclidean per face). */
static double corner_angle(double a, double b, double c) {
  double x = (b * b + c * c - a * a) / (2 * b * c);
  return acos(x < -1 ? -1 : x > 1 ? 1 : x);
}

/* The direction of the edge from corner j to corner j+1 of a triangle with side lengths l (l[k] opposite
 * corner k) whose edge 0 -> 1 points along phi: turning left by pi minus each corner's angle on the way. */
static double edge_dir(const double *l, double phi, int j) {
  for (int i = 1; i <= j; i++) phi += AU_PI - corner_angle(l[i], l[(i + 1) % 3], l[(i + 2) % 3]);
  return phi;
}

/* Top-left rule for a pixel centre exactly on an edge: the edge (dx, dy) of a counter-clockwise face owns
 * its points when it is a top edge (horizontal, running left) or a left edge (running down). */
static int owns_edge(double dx, double dy) { return (dy == 0 && dx < 0) || dy < 0; }

long au_atlas_overlap_texels(int nf, const double *vt, const int *Ft, int R, long *covered) {
  unsigned char *cnt = calloc((size_t)R * R, 1);
  if (!cnt) return -1;
  for (int f = 0; f < nf; f++) {
    double x[3], y[3];
    for (int k = 0; k < 3; k++) x[k] = vt[2 * (size_t)Ft[3 * f + k]] * R, y[k] = vt[2 * (size_t)Ft[3 * f + k] + 1] * R;
    double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    if (area == 0) continue;
    if (area < 0) { /* a folded face is counted in the orientation it has */
      double t = x[1];
      x[1] = x[2], x[2] = t;
      t = y[1], y[1] = y[2], y[2] = t;
    }
    double lx = fmin(x[0], fmin(x[1], x[2])), hx = fmax(x[0], fmax(x[1], x[2]));
    double ly = fmin(y[0], fmin(y[1], y[2])), hy = fmax(y[0], fmax(y[1], y[2]));
    int i0 = (int)floor(lx - 0.5), i1 = (int)ceil(hx - 0.5), j0 = (int)floor(ly - 0.5), j1 = (int)ceil(hy - 0.5);
    if (i0 < 0) i0 = 0;
    if (j0 < 0) j0 = 0;
    if (i1 > R - 1) i1 = R - 1;
    if (j1 > R - 1) j1 = R - 1;
    for (int j = j0; j <= j1; j++)
      for (int i = i0; i <= i1; i++) {
        double px = i + 0.5, py = j + 0.5;
        int in = 1;
        for (int k = 0; k < 3 && in; k++) {
          double ax = x[k], ay = y[k], bx = x[(k + 1) % 3], by = y[(k + 1) % 3];
          double w = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
          in = w > 0 || (w == 0 && owns_edge(bx - ax, by - ay));
        }
        if (in && cnt[(size_t)j * R + i] < 255) cnt[(size_t)j * R + i]++;
      }
  }
  long twice = 0, any = 0;
  for (size_t p = 0; p < (size_t)R * R; p++) twice += cnt[p] > 1, any += cnt[p] > 0;
  free(cnt);
  if (covered) *covered = any;
  return twice;
}

/* Shelf packing of n boxes (w, h) at scale s with gap g into the unit square: positions into (x, y) when
 * they are given. Boxes go in the order ord. Returns 1 if they fit. */
static int shelf_pack(int n, const int *ord, const double *w, const double *h, double s, double g, double *x,
                      double *y) {
  double cx = g, cy = g, shelf = 0;
  for (int i = 0; i < n; i++) {
    int c = ord[i];
    double W = w[c] * s, H = h[c] * s;
    if (W + 2 * g > 1) return 0;
    if (cx + W + g > 1) cy += shelf + g, cx = g, shelf = 0;
    if (x) x[c] = cx, y[c] = cy;
    cx += W + g;
    shelf = H > shelf ? H : shelf;
  }
  return cy + shelf + g <= 1;
}

/* A triangle (grid coordinates) and the cell [i, i+1] x [j, j+1] overlap, touching included: no edge of
 * the triangle has the whole cell strictly outside it (the cell's own axes are the caller's bounding box). */
static int tri_cell(const double *x, const double *y, int i, int j) {
  double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  double sg = area < 0 ? -1 : 1;
  for (int k = 0; k < 3; k++) {
    double ax = x[k], ay = y[k], dx = x[(k + 1) % 3] - ax, dy = y[(k + 1) % 3] - ay;
    /* The cell's corner farthest to the left of the edge. */
    double px = i + (sg * dy < 0), py = j + (sg * dx > 0), best = sg * (dx * (py - ay) - dy * (px - ax));
    if (best < -1e-9 * (fabs(dx) + fabs(dy))) return 0;
  }
  return 1;
}

/* One chart's footprint on the packing grid: the cells its faces touch, grown by one cell on every side
 * (the gap), in a w x h bitmap whose cell (i, j) is bit[j * w + i]. */
typedef struct footprint {
  int w, h;
  unsigned char *bit;
} footprint;

/* The footprint turned by k quarter turns counter-clockwise: cell (i, j) of a w x h bitmap goes to
 * (h - 1 - j, i) per turn, the same map as the continuous (u, v) -> (h - v, u). */
static void turn_footprint(const footprint *a, int k, footprint *b) {
  int w = a->w, h = a->h;
  b->w = k & 1 ? h : w, b->h = k & 1 ? w : h;
  for (int j = 0; j < h; j++)
    for (int i = 0; i < w; i++) {
      int x = k == 0 ? i : k == 1 ? h - 1 - j : k == 2 ? w - 1 - i : j;
      int y = k == 0 ? j : k == 1 ? i : k == 2 ? h - 1 - j : w - 1 - i;
      b->bit[(size_t)y * b->w + x] = a->bit[(size_t)j * w + i];
    }
}

/* A footprint in one quarter turn as runs of cells: row j (of h) holds the runs run[2r], run[2r+1]
 * (first and last cell) for r in rs[j] .. rs[j+1]-1. */
typedef struct runs {
  int w, h;
  int *rs, *run;
  int *longest; /* longest [0..h-1]: the longest run of each row */
} runs;

/* The runs of b (rs: b->h + 1 entries, run: two per run; both large enough). Returns the number of runs. */
static int footprint_runs(const footprint *b, runs *r) {
  int n = 0;
  r->w = b->w, r->h = b->h;
  for (int j = 0; j < b->h; j++) {
    r->rs[j] = n, r->longest[j] = 0;
    const unsigned char *row = b->bit + (size_t)j * b->w;
    for (int i = 0; i < b->w; i++) {
      if (!row[i] || (i > 0 && row[i - 1])) continue;
      int e = i;
      while (e + 1 < b->w && row[e + 1]) e++;
      r->run[2 * n] = i, r->run[2 * n + 1] = e, n++;
      if (e - i + 1 > r->longest[j]) r->longest[j] = e - i + 1;
    }
  }
  r->rs[b->h] = n;
  return n;
}

/* The first occupied cell of an occupancy row (nw words) in [lo, hi], or -1. */
static int first_set(const uint64_t *row, int lo, int hi) {
  for (int q = lo >> 6; q <= hi >> 6; q++) {
    uint64_t wd = row[q];
    if (q == lo >> 6) wd &= ~(uint64_t)0 << (lo & 63);
    if (q == hi >> 6 && (hi & 63) != 63) wd &= ((uint64_t)1 << ((hi & 63) + 1)) - 1;
    if (wd) return 64 * q + __builtin_ctzll(wd);
  }
  return -1;
}

/* Bottom-left packing of the charts' footprints on a G x G grid of occupied cells (occ: G rows of nw
 * 64-bit words), in the order ord: each chart goes, in the quarter turn that leaves its top lowest, to the
 * lowest, then leftmost, cells where its footprint meets no occupied cell, so a chart may nest in the
 * hollows of the ones below it. rt[4 ch + k]: chart ch's footprint in k quarter turns, as runs. A row of
 * the grid is scanned left to right by runs: when a run of the footprint meets an occupied cell p, every
 * position up to the one that puts the run just right of p meets it too, so the scan jumps there. Returns
 * 1 if all fit, with each chart's turn and lower-left cell in (turn, px, py). */
static int grid_pack(int nch, const int *ord, const runs *rt, int G, uint64_t *occ, int *freerun, int *turn, int *px,
                     int *py) {
  const int nw = (G + 63) / 64;
  memset(occ, 0, (size_t)G * nw * sizeof *occ);
  for (int j = 0; j < G; j++) freerun[j] = G;
  for (int n = 0; n < nch; n++) {
    int ch = ord[n], bestk = -1, bestx = 0, besty = 0, besttop = INT_MAX;
    for (int k = 0; k < 4; k++) {
      const runs *b = &rt[4 * ch + k];
      if (b->w > G || b->h > G) continue;
      int found = 0, jhit = 0;
      for (int y = 0; y + b->h <= G && y + b->h < besttop && !found; y++) {
        /* A row of the grid whose longest free run is shorter than the footprint's longest run in that row
         * rules the position out at once. */
        int x = 0, jr = jhit;
        if (freerun[y + jr] < b->longest[jr]) continue;
        for (jr = 0; jr < b->h && freerun[y + jr] >= b->longest[jr]; jr++) {
        }
        if (jr < b->h) {
          jhit = jr;
          continue;
        }
        while (x + b->w <= G) {
          /* The row that stopped the last position first: it is the likeliest to stop this one too. */
          int hit = 0;
          for (int jj = 0; jj < b->h && !hit; jj++) {
            int j = (jj + jhit) % b->h;
            const uint64_t *g = occ + (size_t)(y + j) * nw;
            for (int r = b->rs[j]; r < b->rs[j + 1]; r++) {
              int p = first_set(g, x + b->run[2 * r], x + b->run[2 * r + 1]);
              if (p >= 0) {
                x = p - b->run[2 * r] + 1, hit = 1, jhit = j;
                break;
              }
            }
          }
          if (!hit) {
            found = 1, besttop = y + b->h, bestk = k, bestx = x, besty = y;
            break;
          }
        }
      }
    }
    if (bestk < 0) return 0;
    const runs *b = &rt[4 * ch + bestk];
    for (int j = 0; j < b->h; j++) {
      uint64_t *g = occ + (size_t)(besty + j) * nw;
      for (int r = b->rs[j]; r < b->rs[j + 1]; r++)
        for (int i = bestx + b->run[2 * r]; i <= bestx + b->run[2 * r + 1]; i++) g[i >> 6] |= (uint64_t)1 << (i & 63);
      int longest = 0, len = 0;
      for (int i = 0; i < G; i++) {
        len = g[i >> 6] >> (i & 63) & 1 ? 0 : len + 1;
        if (len > longest) longest = len;
      }
      freerun[besty + j] = longest;
    }
    turn[ch] = bestk, px[ch] = bestx, py[ch] = besty;
  }
  return 1;
}

/* ord [0..n-1] = 0..n-1 sorted by key, largest first, ties by index (a merge sort, stable; tmp holds n
 * entries): no global for a qsort comparator to read. */
static void sort_desc(int *ord, int *tmp, const double *key, int n) {
  for (int i = 0; i < n; i++) ord[i] = i;
  for (int w = 1; w < n; w *= 2) {
    for (int lo = 0; lo < n; lo += 2 * w) {
      int mid = lo + w < n ? lo + w : n, hi = lo + 2 * w < n ? lo + 2 * w : n, i = lo, j = mid, k = lo;
      while (i < mid && j < hi) tmp[k++] = key[ord[j]] > key[ord[i]] ? ord[j++] : ord[i++];
      while (i < mid) tmp[k++] = ord[i++];
      while (j < hi) tmp[k++] = ord[j++];
    }
    memcpy(ord, tmp, (size_t)n * sizeof *ord);
  }
}

/* Packing by the charts' shapes: footprints (the grid cells of side gap that the chart's faces touch at
 * scale s, grown by one cell up and to the right, so footprints that do not share a cell leave at least
 * a cell between the charts) packed bottom-left on a grid (grid_pack), the largest area first; the largest scale that packs, by
 * bisection above the shelves' scale s0. The charts' vt are turned flat and start at (lox, loy) with extent
 * (bw, bh). *s: the scale found (0 when none beats s0), with each chart's quarter turns and lower-left grid
 * cell in turn, px, py. Returns AU_OK, AU_E_NOMEM. */
static au_status raster_pack(int nf, const int *Ft, const int *chart, int nch, const double *vt, const double *lox,
                             const double *loy, const double *bw, const double *bh, double gap, double s0, double probe,
                             double *s, int *turn, int *px, int *py) {
  const int G = (int)floor(1 / gap);
  *s = 0;
  if (nch <= 0 || G < 8) return AU_OK;
  int *fstart = calloc((size_t)nch + 1, sizeof *fstart), *flist = malloc((size_t)(nf > 0 ? nf : 1) * sizeof *flist);
  int *ord = malloc(3 * (size_t)nch * sizeof *ord);
  uint64_t *occ = malloc((size_t)G * ((G + 63) / 64) * sizeof *occ);
  double *area = calloc(2 * (size_t)nch, sizeof *area), *key = area ? area + nch : NULL;
  footprint *fp = calloc((size_t)nch, sizeof *fp);
  runs *rt = calloc(4 * (size_t)nch, sizeof *rt);
  int *tturn = malloc(3 * (size_t)nch * sizeof *tturn), *tpx = tturn ? tturn + nch : NULL, *tpy = tturn ? tturn + 2 * nch : NULL;
  int *freerun = malloc((size_t)G * sizeof *freerun);
  au_status st = AU_OK;
  unsigned char *tmp = NULL;
  if (!fstart || !flist || !ord || !occ || !area || !fp || !rt || !tturn || !freerun) {
    st = AU_E_NOMEM;
    goto done;
  }
  double total = 0;
  for (int f = 0; f < nf; f++) {
    fstart[chart[f] + 1]++;
    const double *a = vt + 2 * Ft[3 * f], *b = vt + 2 * Ft[3 * f + 1], *c = vt + 2 * Ft[3 * f + 2];
    double ar = 0.5 * fabs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
    area[chart[f]] += ar, total += ar;
  }
  for (int ch = 0; ch < nch; ch++) fstart[ch + 1] += fstart[ch], ord[ch] = ch;
  {
    int *fill = calloc((size_t)nch, sizeof *fill);
    if (!fill) {
      st = AU_E_NOMEM;
      goto done;
    }
    for (int f = 0; f < nf; f++) flist[fstart[chart[f]] + fill[chart[f]]++] = f;
    free(fill);
  }
  /* Three orders: by area, by longer side, by bounding box, each largest first; a scale packs when one
   * of them packs at it. */
  for (int o = 0; o < 3; o++) {
    int *od = ord + (size_t)o * nch;
    for (int ch = 0; ch < nch; ch++) key[ch] = o == 0 ? area[ch] : o == 1 ? fmax(bw[ch], bh[ch]) : bw[ch] * bh[ch];
    sort_desc(od, tturn, key, nch);
  }
  double lo = s0, hi = 1 / sqrt(total > 0 ? total : 1);
  if (probe > 0) lo = 0; /* one scale only: the one that covers probe of the square */
  for (int it = 0; it < (probe > 0 ? 1 : 14) && hi > lo * (1 + 1e-3); it++) {
    double sc = probe > 0 ? hi * sqrt(probe) : it == 0 ? hi * 0.999 : 0.5 * (lo + hi);
    /* The footprints at scale sc. */
    size_t maxcells = 0;
    int fits = 1;
    for (int ch = 0; ch < nch; ch++) {
      free(fp[ch].bit);
      fp[ch].w = (int)floor(bw[ch] * sc * G) + 2, fp[ch].h = (int)floor(bh[ch] * sc * G) + 2;
      if (fp[ch].w > G + 2 || fp[ch].h > G + 2) fits = 0;
      size_t cells = (size_t)fp[ch].w * fp[ch].h;
      if (cells > maxcells) maxcells = cells;
      if (!(fp[ch].bit = calloc(cells, 1))) {
        st = AU_E_NOMEM;
        goto done;
      }
    }
    if (fits) {
      for (int ch = 0; ch < nch; ch++) {
        footprint *p = &fp[ch];
        for (int n = fstart[ch]; n < fstart[ch + 1]; n++) {
          int f = flist[n];
          double x[3], y[3];
          for (int k = 0; k < 3; k++)
            x[k] = (vt[2 * Ft[3 * f + k]] - lox[ch]) * sc * G, y[k] = (vt[2 * Ft[3 * f + k] + 1] - loy[ch]) * sc * G;
          int i0 = (int)floor(fmin(x[0], fmin(x[1], x[2]))), i1 = (int)floor(fmax(x[0], fmax(x[1], x[2])));
          int j0 = (int)floor(fmin(y[0], fmin(y[1], y[2]))), j1 = (int)floor(fmax(y[0], fmax(y[1], y[2])));
          i0 = i0 < 0 ? 0 : i0, j0 = j0 < 0 ? 0 : j0, i1 = i1 > p->w - 2 ? p->w - 2 : i1, j1 = j1 > p->h - 2 ? p->h - 2 : j1;
          /* A face within one row or column of cells touches every cell of its box (it is connected and
           * spans the box); only a larger box needs the cell test. */
          int thin = i0 == i1 || j0 == j1;
          for (int j = j0; j <= j1; j++)
            for (int i = i0; i <= i1; i++)
              if (!p->bit[(size_t)j * p->w + i] && (thin || tri_cell(x, y, i, j))) p->bit[(size_t)j * p->w + i] = 1;
        }
        /* Grown by one cell up and to the right (top rows first, so a grown cell does not grow again). */
        for (int j = p->h - 1; j >= 0; j--)
          for (int i = p->w - 1; i >= 0; i--)
            if (!p->bit[(size_t)j * p->w + i]) {
              int l = i > 0 && p->bit[(size_t)j * p->w + i - 1] == 1, d = j > 0 && p->bit[(size_t)(j - 1) * p->w + i] == 1;
              int ld = i > 0 && j > 0 && p->bit[(size_t)(j - 1) * p->w + i - 1] == 1;
              if (l || d || ld) p->bit[(size_t)j * p->w + i] = 2;
            }
      }
      /* Each footprint in its four quarter turns, as runs of cells. */
      free(tmp);
      if (!(tmp = malloc(maxcells))) {
        st = AU_E_NOMEM;
        goto done;
      }
      for (int ch = 0; ch < nch && st == AU_OK; ch++)
        for (int k = 0; k < 4; k++) {
          runs *r = &rt[4 * ch + k];
          footprint b = {0, 0, tmp};
          turn_footprint(&fp[ch], k, &b);
          free(r->rs), free(r->run);
          r->rs = malloc((2 * (size_t)b.h + 1) * sizeof *r->rs), r->run = malloc((2 * maxcells + 2) * sizeof *r->run);
          if (!r->rs || !r->run) {
            st = AU_E_NOMEM;
            break;
          }
          r->longest = r->rs + b.h + 1;
          int nr = footprint_runs(&b, r);
          int *shrunk = realloc(r->run, (2 * (size_t)nr + 1) * sizeof *r->run);
          if (shrunk) r->run = shrunk;
        }
      if (st != AU_OK) goto done;
      fits = 0;
      for (int o = 0; o < 3 && !fits; o++) fits = grid_pack(nch, ord + (size_t)o * nch, rt, G, occ, freerun, tturn, tpx, tpy);
    }
    if (fits) {
      memcpy(turn, tturn, (size_t)nch * sizeof *turn), memcpy(px, tpx, (size_t)nch * sizeof *px);
      memcpy(py, tpy, (size_t)nch * sizeof *py);
      lo = sc, *s = sc;
    } else {
      hi = sc;
    }
  }
done:
  if (fp)
    for (int ch = 0; ch < nch; ch++) free(fp[ch].bit);
  if (rt)
    for (int i = 0; i < 4 * nch; i++) free(rt[i].rs), free(rt[i].run);
  free(fstart), free(flist), free(ord), free(occ), free(area), free(fp), free(tmp), free(rt), free(tturn), free(freerun);
  return st;
}

/* au_atlas_pack, by the charts' shapes too when shapes is 1, on shelves only when 0. */
static au_status pack(int nf, const int *Ft, const int *chart, int nch, int nvt, double *vt, int quarter, double gap,
                      int shapes, double probe, double *scale, au_msg *msg) {
  /* 7. Each chart turned to its smallest bounding box (1 degree steps), lying flat, moved to the origin. */
  double *bw = calloc((size_t)nch, sizeof *bw), *bh = calloc((size_t)nch, sizeof *bh);
  double *bx = calloc((size_t)nch, sizeof *bx), *by = calloc((size_t)nch, sizeof *by);
  double *lox = malloc((size_t)nch * sizeof *lox), *loy = malloc((size_t)nch * sizeof *loy);
  double *hix = malloc((size_t)nch * sizeof *hix), *hiy = malloc((size_t)nch * sizeof *hiy);
  int *vchart = malloc((size_t)nvt * sizeof *vchart), *ord = malloc((size_t)nch * sizeof *ord);
  double *best = malloc((size_t)nch * sizeof *best), *bestang = calloc((size_t)nch, sizeof *bestang);
  if (!bw || !bh || !bx || !by || !lox || !loy || !hix || !hiy || !vchart || !ord || !best || !bestang) {
    free(bw), free(bh), free(bx), free(by), free(lox), free(loy), free(hix), free(hiy), free(vchart), free(ord), free(best),
        free(bestang);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory packing the atlas");
  }
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) vchart[Ft[3 * f + k]] = chart[f];
  for (int ch = 0; ch < nch; ch++) best[ch] = INFINITY;
  for (int deg_ = 0; deg_ < (quarter ? 1 : 90); deg_++) { /* quarter: the common frame is kept */
    double a = deg_ * AU_PI / 180, ca = cos(a), sa = sin(a);
    for (int ch = 0; ch < nch; ch++) lox[ch] = loy[ch] = INFINITY, hix[ch] = hiy[ch] = -INFINITY;
    for (int q = 0; q < nvt; q++) {
      int ch = vchart[q];
      double x = ca * vt[2 * q] - sa * vt[2 * q + 1], y = sa * vt[2 * q] + ca * vt[2 * q + 1];
      if (x < lox[ch]) lox[ch] = x;
      if (x > hix[ch]) hix[ch] = x;
      if (y < loy[ch]) loy[ch] = y;
      if (y > hiy[ch]) hiy[ch] = y;
    }
    for (int ch = 0; ch < nch; ch++) {
      double ar = (hix[ch] - lox[ch]) * (hiy[ch] - loy[ch]);
      if (ar < best[ch]) best[ch] = ar, bestang[ch] = a, bw[ch] = hix[ch] - lox[ch], bh[ch] = hiy[ch] - loy[ch];
    }
  }
  for (int ch = 0; ch < nch; ch++)
    if (bh[ch] > bw[ch]) bestang[ch] += AU_PI / 2; /* lying flat packs better on shelves */
  for (int ch = 0; ch < nch; ch++) lox[ch] = loy[ch] = INFINITY, hix[ch] = hiy[ch] = -INFINITY;
  for (int q = 0; q < nvt; q++) {
    int ch = vchart[q];
    double ca = cos(bestang[ch]), sa = sin(bestang[ch]);
    double x = ca * vt[2 * q] - sa * vt[2 * q + 1], y = sa * vt[2 * q] + ca * vt[2 * q + 1];
    vt[2 * q] = x, vt[2 * q + 1] = y;
    lox[ch] = fmin(lox[ch], x), hix[ch] = fmax(hix[ch], x), loy[ch] = fmin(loy[ch], y), hiy[ch] = fmax(hiy[ch], y);
  }
  double maxside = 0;
  for (int ch = 0; ch < nch; ch++) {
    bw[ch] = hix[ch] - lox[ch], bh[ch] = hiy[ch] - loy[ch], ord[ch] = ch;
    maxside = fmax(maxside, fmax(bw[ch], bh[ch]));
  }
  {
    int *tmp = malloc((size_t)(nch > 0 ? nch : 1) * sizeof *tmp);
    if (!tmp) {
      free(bw), free(bh), free(bx), free(by), free(lox), free(loy), free(hix), free(hiy), free(vchart), free(ord), free(best),
          free(bestang);
      return au_msg_set(msg, AU_E_NOMEM, "out of memory packing the atlas");
    }
    sort_desc(ord, tmp, bh, nch);
    free(tmp);
  }
  /* 8. The largest scale at which the shelves fit, by bisection. */
  double lo = 0, hi = (1 - 2 * gap) / maxside;
  for (int it = 0; it < 60; it++) {
    double mid = 0.5 * (lo + hi);
    if (shelf_pack(nch, ord, bw, bh, mid, gap, NULL, NULL)) lo = mid;
    else hi = mid;
  }
  shelf_pack(nch, ord, bw, bh, lo, gap, bx, by);
  /* 8b. The same by the charts' shapes (raster_pack); kept when it packs at a larger scale. */
  double rs = 0;
  int *turn = malloc((size_t)(nch > 0 ? nch : 1) * sizeof *turn);
  int *px = malloc((size_t)(nch > 0 ? nch : 1) * sizeof *px), *py = malloc((size_t)(nch > 0 ? nch : 1) * sizeof *py);
  au_status st = AU_OK;
  if (!turn || !px || !py) st = AU_E_NOMEM;
  else if (shapes) st = raster_pack(nf, Ft, chart, nch, vt, lox, loy, bw, bh, gap, lo, probe, &rs, turn, px, py);
  if (st != AU_OK) {
    free(bw), free(bh), free(bx), free(by), free(lox), free(loy), free(hix), free(hiy), free(vchart), free(ord), free(best),
        free(bestang), free(turn), free(px), free(py);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory packing the atlas");
  }
  const int G = (int)floor(1 / gap);
  if (scale) *scale = rs > lo ? rs : lo;
  for (int q = 0; q < nvt; q++) {
    int ch = vchart[q];
    if (rs > lo) {
      double u = (vt[2 * q] - lox[ch]) * rs * G, v = (vt[2 * q + 1] - loy[ch]) * rs * G;
      int w = (int)floor(bw[ch] * rs * G) + 2, h = (int)floor(bh[ch] * rs * G) + 2;
      for (int k = 0; k < turn[ch]; k++) {
        double nu = h - v;
        v = u, u = nu;
        int tw = w;
        w = h, h = tw;
      }
      vt[2 * q] = (px[ch] + u) / G, vt[2 * q + 1] = (py[ch] + v) / G;
    } else {
      vt[2 * q] = bx[ch] + lo * (vt[2 * q] - lox[ch]);
      vt[2 * q + 1] = by[ch] + lo * (vt[2 * q + 1] - loy[ch]);
    }
    vt[2 * q] = fmin(1, fmax(0, vt[2 * q])), vt[2 * q + 1] = fmin(1, fmax(0, vt[2 * q + 1]));
  }
  free(turn), free(px), free(py);
  free(bw), free(bh), free(bx), free(by), free(lox), free(loy), free(hix), free(hiy), free(vchart), free(ord), free(best),
      free(bestang);

  return AU_OK;
}

au_status au_atlas_pack(int nf, const int *Ft, const int *chart, int nch, int nvt, double *vt, int quarter, double gap,
                        double *scale, au_msg *msg) {
  return pack(nf, Ft, chart, nch, nvt, vt, quarter, gap, 1, 0, scale, msg);
}

/* Steps 5 to 8 for the cut as it stands: texture coordinates shared across uncut edges, the charts laid
 * out in the metric (flen: the metric's length of the edge opposite each corner), turned and packed. */
static au_status lay_out(const au_mesh *m, const au_topo *t, const unsigned char *cut, const double *flen,
                         const double *frame, int quarter, double gap, int *uf, int *cls, int *queue,
                         au_atlas_layout *L, au_msg *msg) {
  const int nf = m->nf, *F = m->F;
  free(L->vt);
  L->vt = NULL;
  /* 5. Corners glued across uncut interior edges share a texture coordinate. */
  int nvt = corner_rows(t, F, nf, cut, uf, cls);
  for (int i = 0; i < 3 * nf; i++) L->Ft[i] = cls[uf_find(uf, i)];
  L->nvt = nvt;
  L->vt = calloc(2 * (size_t)nvt, sizeof *L->vt);
  unsigned char *placed = calloc((size_t)nvt, 1);
  if (!L->vt || !placed) {
    free(placed);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory laying out the atlas");
  }
  double *vt = L->vt;
  const int *Ft = L->Ft;

  /* 6. Charts: faces joined across uncut edges, laid out face by face in the metric. */
  for (int f = 0; f < nf; f++) L->chart[f] = -1;
  int nch = 0;
  for (int f0 = 0; f0 < nf; f0++) {
    if (L->chart[f0] >= 0) continue;
    const double *l = flen + 3 * f0;
    double a0 = corner_angle(l[0], l[1], l[2]);
    double *p0 = vt + 2 * Ft[3 * f0], *p1 = vt + 2 * Ft[3 * f0 + 1], *p2 = vt + 2 * Ft[3 * f0 + 2];
    double phi = frame[f0];
    p0[0] = 0, p0[1] = 0, p1[0] = l[2] * cos(phi), p1[1] = l[2] * sin(phi);
    p2[0] = l[1] * cos(phi + a0), p2[1] = l[1] * sin(phi + a0);
    placed[Ft[3 * f0]] = placed[Ft[3 * f0 + 1]] = placed[Ft[3 * f0 + 2]] = 1;
    int head = 0, tail = 0;
    queue[tail++] = f0, L->chart[f0] = nch;
    while (head < tail) {
      int f = queue[head++];
      for (int k = 0; k < 3; k++) {
        int e = t->FE[3 * f + k];
        if (t->EF[2 * e + 1] < 0 || cut[e]) continue;
        int g = t->EF[2 * e] == f ? t->EF[2 * e + 1] : t->EF[2 * e];
        if (L->chart[g] >= 0) continue;
        L->chart[g] = nch, queue[tail++] = g;
        /* The corner of g off the shared edge, from the shared edge's two (placed) corners. */
        int kg = t->EF[2 * e] == g ? t->EC[2 * e] : t->EC[2 * e + 1];
        int q = Ft[3 * g + kg];
        if (placed[q]) continue;
        int ka = (kg + 1) % 3, kb = (kg + 2) % 3;
        const double *lg = flen + 3 * g, *pa = vt + 2 * Ft[3 * g + ka], *pb = vt + 2 * Ft[3 * g + kb];
        double alpha = corner_angle(lg[ka], lg[kb], lg[kg]);
        double dx = pb[0] - pa[0], dy = pb[1] - pa[1], dl = sqrt(dx * dx + dy * dy);
        double ux = dx / dl, uy = dy / dl, cs = cos(alpha), sn = sin(alpha);
        vt[2 * q] = pa[0] + lg[kb] * (cs * ux - sn * uy);
        vt[2 * q + 1] = pa[1] + lg[kb] * (sn * ux + cs * uy);
        placed[q] = 1;
      }
    }
    nch++;
  }
  L->ncharts = nch;

  au_status st = pack(nf, Ft, L->chart, nch, nvt, vt, quarter, gap, 0, 0, &L->scale, msg);
  free(placed);
  return st;
}

static int race_cut(const au_topo *t, int nf, unsigned char *cut, const au_atlas_layout *L, int ch, int fa, int fb,
                    int *lab);

/* Rasterize the atlas at 1024 x 1024 with the face that first covers each pixel centre; for every chart
 * with pixels covered twice by two of its faces, race a breadth-first search from both faces over the
 * chart's uncut edges and cut the edges between the two territories, for up to AU_ATLAS_PAIRS distinct
 * pairs of faces per chart in one round (a pair that an earlier race of the round already separated adds
 * no cut; one that it did not still overlaps and needs its own). *nsplit: the charts split. */
#define AU_ATLAS_PAIRS 8
static au_status split_overlaps(const au_mesh *m, const au_topo *t, unsigned char *cut, au_atlas_layout *L, int *nsplit,
                                au_msg *msg) {
  const int R = 1024, nf = m->nf, nch = L->ncharts, K = AU_ATLAS_PAIRS;
  int *owner = malloc((size_t)R * R * sizeof *owner), *pairs = malloc(2 * (size_t)K * nch * sizeof *pairs);
  int *np = calloc((size_t)nch, sizeof *np), *lab = malloc((size_t)nf * sizeof *lab);
  if (!owner || !pairs || !np || !lab) {
    free(owner), free(pairs), free(np), free(lab);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory checking the atlas for overlaps");
  }
  for (size_t i = 0; i < (size_t)R * R; i++) owner[i] = -1;
  const double *vt = L->vt;
  for (int f = 0; f < nf; f++) {
    double x[3], y[3];
    for (int k = 0; k < 3; k++) x[k] = vt[2 * (size_t)L->Ft[3 * f + k]] * R, y[k] = vt[2 * (size_t)L->Ft[3 * f + k] + 1] * R;
    double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    if (area == 0) continue;
    if (area < 0) {
      double tt = x[1];
      x[1] = x[2], x[2] = tt;
      tt = y[1], y[1] = y[2], y[2] = tt;
    }
    int i0 = (int)floor(fmin(x[0], fmin(x[1], x[2])) - 0.5), i1 = (int)ceil(fmax(x[0], fmax(x[1], x[2])) - 0.5);
    int j0 = (int)floor(fmin(y[0], fmin(y[1], y[2])) - 0.5), j1 = (int)ceil(fmax(y[0], fmax(y[1], y[2])) - 0.5);
    i0 = i0 < 0 ? 0 : i0, j0 = j0 < 0 ? 0 : j0, i1 = i1 > R - 1 ? R - 1 : i1, j1 = j1 > R - 1 ? R - 1 : j1;
    for (int j = j0; j <= j1; j++)
      for (int i = i0; i <= i1; i++) {
        double px = i + 0.5, py = j + 0.5;
        int in = 1;
        for (int k = 0; k < 3 && in; k++) {
          double ax = x[k], ay = y[k], bx = x[(k + 1) % 3], by = y[(k + 1) % 3];
          double w = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
          in = w > 0 || (w == 0 && owns_edge(bx - ax, by - ay));
        }
        if (!in) continue;
        int *o = owner + (size_t)j * R + i;
        if (*o < 0) {
          *o = f;
        } else {
          int ch = L->chart[f], *pr = pairs + 2 * (size_t)K * ch, known = 0;
          if (L->chart[*o] != ch || np[ch] == K) continue;
          for (int k = 0; k < np[ch] && !known; k++) known = pr[2 * k] == *o && pr[2 * k + 1] == f;
          if (!known) pr[2 * np[ch]] = *o, pr[2 * np[ch] + 1] = f, np[ch]++;
        }
      }
  }
  int n = 0, bad = 0;
  for (int ch = 0; ch < nch; ch++) {
    for (int k = 0; k < np[ch] && !bad; k++)
      bad = race_cut(t, nf, cut, L, ch, pairs[2 * ((size_t)K * ch + k)], pairs[2 * ((size_t)K * ch + k) + 1], lab);
    n += np[ch] > 0;
  }
  free(owner), free(pairs), free(np), free(lab);
  if (bad) return au_msg_set(msg, AU_E_NOMEM, "out of memory checking the atlas for overlaps");
  *nsplit = n;
  return AU_OK;
}

/* Cut chart ch of L between faces fa and fb: a race from both over the chart's uncut edges, by the
 * distance between face centroids in vt (Dijkstra on the dual graph; the chart is flat, so this follows
 * the metric, and the two territories meet near the straight bisector of a convex stretch, where a race by
 * steps follows the triangulation's zigzags), and the edges between the two territories cut. Each
 * territory is connected (a shortest-path tree). lab [0..nf-1]: scratch. Returns 0, -1 when out of memory. */
static int race_cut(const au_topo *t, int nf, unsigned char *cut, const au_atlas_layout *L, int ch, int fa, int fb,
                    int *lab) {
  double *dist = malloc((size_t)nf * sizeof *dist);
  heap h = {0, malloc((3 * (size_t)nf + 2) * sizeof(double)), malloc((3 * (size_t)nf + 2) * sizeof(int))};
  if (!dist || !h.key || !h.v) {
    free(dist), free(h.key), free(h.v);
    return -1;
  }
  for (int f = 0; f < nf; f++) lab[f] = -1, dist[f] = INFINITY;
  lab[fa] = 0, lab[fb] = 1, dist[fa] = dist[fb] = 0;
  heap_push(&h, 0, fa), heap_push(&h, 0, fb);
  while (h.n > 0) {
    double d;
    int f;
    heap_pop(&h, &d, &f);
    if (d > dist[f]) continue;
    const double *a = L->vt + 2 * L->Ft[3 * f], *b = L->vt + 2 * L->Ft[3 * f + 1], *c = L->vt + 2 * L->Ft[3 * f + 2];
    double cx = (a[0] + b[0] + c[0]) / 3, cy = (a[1] + b[1] + c[1]) / 3;
    for (int k = 0; k < 3; k++) {
      int e = t->FE[3 * f + k];
      if (t->EF[2 * e + 1] < 0 || cut[e]) continue;
      int g = t->EF[2 * e] == f ? t->EF[2 * e + 1] : t->EF[2 * e];
      const double *p = L->vt + 2 * L->Ft[3 * g], *q = L->vt + 2 * L->Ft[3 * g + 1], *r = L->vt + 2 * L->Ft[3 * g + 2];
      double dg = d + hypot((p[0] + q[0] + r[0]) / 3 - cx, (p[1] + q[1] + r[1]) / 3 - cy);
      if (dg < dist[g]) dist[g] = dg, lab[g] = lab[f], heap_push(&h, dg, g);
    }
  }
  for (int e = 0; e < t->ne; e++) {
    if (t->EF[2 * e + 1] < 0 || cut[e]) continue;
    int f0 = t->EF[2 * e], f1 = t->EF[2 * e + 1];
    if (L->chart[f0] == ch && lab[f0] >= 0 && lab[f1] >= 0 && lab[f0] != lab[f1]) cut[e] = 1;
  }
  free(dist), free(h.key), free(h.v);
  return 0;
}

/* The factors of the square root of the atlas's area above which charts are cut for length, in turn (0:
 * none), until the packed charts cover AU_ATLAS_COVER of the square (au_atlas_separate). */
#define AU_ATLAS_LONG {0, 1.0, 0.8, 0.65, 0.5}
#define AU_ATLAS_COVER 0.55

/* The area of L's charts in vt (their coverage of the unit square). */
static double atlas_area(int nf, const au_atlas_layout *L) {
  double a = 0;
  for (int f = 0; f < nf; f++) {
    const double *p = L->vt + 2 * L->Ft[3 * f], *q = L->vt + 2 * L->Ft[3 * f + 1], *r = L->vt + 2 * L->Ft[3 * f + 2];
    a += 0.5 * ((q[0] - p[0]) * (r[1] - p[1]) - (r[0] - p[0]) * (q[1] - p[1]));
  }
  return a;
}

/* Every chart whose longer side exceeds factor times the square root of the atlas's area (at the scale
 * that covers half of the square, factor 0.5 is a side of more than 0.35 of the square's: long ragged
 * charts leave space that no other chart fills) is cut in two between the faces at the two ends of that
 * side (race_cut), the longest first, at most maxn of them. A chart's cut depends on that chart alone, so
 * cutting them all in one round cuts the same edges as one at a time, in fewer rounds of packing. Returns
 * the number of charts cut, -1 when out of memory. */
static int split_long(const au_topo *t, int nf, unsigned char *cut, const au_atlas_layout *L, double factor, int maxn) {
  const int nch = L->ncharts;
  double cover = 0, *box = malloc(4 * (size_t)(nch > 0 ? nch : 1) * sizeof *box);
  int *lab = malloc((size_t)(nf > 0 ? nf : 1) * sizeof *lab), *fa = malloc(3 * (size_t)(nch > 0 ? nch : 1) * sizeof *fa);
  double *span = malloc((size_t)(nch > 0 ? nch : 1) * sizeof *span), *lo = malloc(2 * (size_t)(nch > 0 ? nch : 1) * sizeof *lo);
  if (!box || !lab || !fa || !span || !lo) {
    free(box), free(lab), free(fa), free(span), free(lo);
    return -1;
  }
  int *fb = fa + nch, *axis = fa + 2 * nch;
  double *hi = lo + nch;
  for (int ch = 0; ch < nch; ch++) box[4 * ch] = box[4 * ch + 1] = INFINITY, box[4 * ch + 2] = box[4 * ch + 3] = -INFINITY;
  for (int f = 0; f < nf; f++) {
    const double *a = L->vt + 2 * L->Ft[3 * f], *b = L->vt + 2 * L->Ft[3 * f + 1], *c = L->vt + 2 * L->Ft[3 * f + 2];
    cover += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
    double *bx = box + 4 * L->chart[f];
    for (int k = 0; k < 3; k++) {
      const double *p = L->vt + 2 * L->Ft[3 * f + k];
      bx[0] = fmin(bx[0], p[0]), bx[1] = fmin(bx[1], p[1]), bx[2] = fmax(bx[2], p[0]), bx[3] = fmax(bx[3], p[1]);
    }
  }
  const double limit = factor * sqrt(cover > 0 ? cover : 0);
  for (int ch = 0; ch < nch; ch++) {
    span[ch] = 0, axis[ch] = 0, fa[ch] = fb[ch] = -1, lo[ch] = INFINITY, hi[ch] = -INFINITY;
    for (int d = 0; d < 2; d++)
      if (box[4 * ch + 2 + d] - box[4 * ch + d] > span[ch]) span[ch] = box[4 * ch + 2 + d] - box[4 * ch + d], axis[ch] = d;
  }
  for (int f = 0; f < nf; f++) {
    int ch = L->chart[f], d = axis[ch];
    if (!(span[ch] > limit)) continue;
    double c = (L->vt[2 * L->Ft[3 * f] + d] + L->vt[2 * L->Ft[3 * f + 1] + d] + L->vt[2 * L->Ft[3 * f + 2] + d]) / 3;
    if (c < lo[ch]) lo[ch] = c, fa[ch] = f;
    if (c > hi[ch]) hi[ch] = c, fb[ch] = f;
  }
  int done = 0;
  while (done < maxn) {
    int best = -1;
    for (int ch = 0; ch < nch; ch++)
      if (span[ch] > limit && fa[ch] >= 0 && fb[ch] >= 0 && fa[ch] != fb[ch] && (best < 0 || span[ch] > span[best])) best = ch;
    if (best < 0) break;
    if (race_cut(t, nf, cut, L, best, fa[best], fb[best], lab)) {
      done = -1;
      break;
    }
    span[best] = 0, done++;
  }
  free(box), free(lab), free(fa), free(span), free(lo);
  return done;
}

au_status au_atlas_separate(const au_mesh *m, const au_topo *t, au_atlas_layout *L, int quarter, double gap, int *nsplit,
                            au_msg *msg) {
  const int nf = m->nf, ne = t->ne, *F = m->F;
  int nq = nf > ne ? nf : ne;
  int *queue = malloc((size_t)nq * sizeof *queue), *uf = malloc(3 * (size_t)nf * sizeof *uf);
  int *cls = malloc(3 * (size_t)nf * sizeof *cls);
  au_status st = AU_OK;
  if (nsplit) *nsplit = 0;
  if (!queue || !uf || !cls) {
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory separating the charts");
    goto done;
  }
  /* Long charts are cut only as far as the packing needs: with no cut first, then above each of the
   * factors of AU_ATLAS_LONG in turn, until the charts, packed by their shapes, cover AU_ATLAS_COVER of
   * the square. */
  static const double longf[] = AU_ATLAS_LONG;
  const int nlevels = (int)(sizeof longf / sizeof longf[0]);
  int nlong = 0;
  for (int level = 0; level < nlevels && st == AU_OK; level++) {
    int nlevel = 0; /* splits at this level */
    for (int round = 0;; round++) {
      /* Shelves while charts are split (where they overlap themselves or are too long), then the shapes. */
      if ((st = pack(nf, L->Ft, L->chart, L->ncharts, L->nvt, L->vt, quarter, gap, 0, 0, &L->scale, msg)) != AU_OK) goto done;
      int split = 0;
      if (round == 40 || (st = split_overlaps(m, t, L->cut, L, &split, msg)) != AU_OK) break;
      if (!split && nlong < 32 && longf[level] > 0) {
        if ((split = split_long(t, nf, L->cut, L, longf[level], 32 - nlong)) < 0) {
          st = au_msg_set(msg, AU_E_NOMEM, "out of memory separating the charts");
          goto done;
        }
        nlong += split;
      }
      if (!split) break;
      if (nsplit) *nsplit += split;
      nlevel += split;
      /* The corners separated by the new cut edges get their own rows of vt, where they were. */
      int nvt = corner_rows(t, F, nf, L->cut, uf, cls);
      double *vt = malloc(2 * (size_t)nvt * sizeof *vt);
      if (!vt) {
        st = au_msg_set(msg, AU_E_NOMEM, "out of memory separating the charts");
        goto done;
      }
      for (int i = 0; i < 3 * nf; i++) {
        int q = cls[uf_find(uf, i)];
        vt[2 * q] = L->vt[2 * L->Ft[i]], vt[2 * q + 1] = L->vt[2 * L->Ft[i] + 1];
      }
      for (int i = 0; i < 3 * nf; i++) L->Ft[i] = cls[uf_find(uf, i)];
      free(L->vt);
      L->vt = vt, L->nvt = nvt;
      int nch = 0;
      for (int f = 0; f < nf; f++) L->chart[f] = -1;
      for (int f0 = 0; f0 < nf; f0++) {
        if (L->chart[f0] >= 0) continue;
        int head = 0, tail = 0;
        queue[tail++] = f0, L->chart[f0] = nch;
        while (head < tail) {
          int f = queue[head++];
          for (int k = 0; k < 3; k++) {
            int e = t->FE[3 * f + k];
            if (t->EF[2 * e + 1] < 0 || L->cut[e]) continue;
            int g = t->EF[2 * e] == f ? t->EF[2 * e + 1] : t->EF[2 * e];
            if (L->chart[g] < 0) L->chart[g] = nch, queue[tail++] = g;
          }
        }
        nch++;
      }
      L->ncharts = nch;
    }
    if (st != AU_OK) break;
    /* Before the last level, one packing at the scale that covers AU_ATLAS_COVER tells whether the charts
     * as they are reach it (a level that cut nothing packs as the one before it did); then the largest
     * scale, by bisection. */
    if (level < nlevels - 1) {
      if (level > 0 && nlevel == 0) continue;
      if ((st = pack(nf, L->Ft, L->chart, L->ncharts, L->nvt, L->vt, quarter, gap, 1, AU_ATLAS_COVER, &L->scale, msg)) !=
          AU_OK)
        break;
      if (atlas_area(nf, L) < AU_ATLAS_COVER * (1 - 1e-9)) continue;
    }
    st = pack(nf, L->Ft, L->chart, L->ncharts, L->nvt, L->vt, quarter, gap, 1, 0, &L->scale, msg);
    break;
  }
done:
  free(queue), free(uf), free(cls);
  return st;
}

au_status au_atlas_measure(const au_mesh *m, const au_topo *t, const au_atlas_cones *c, au_atlas_layout *L,
                           au_msg *msg) {
  const int nv = m->nv, nf = m->nf, ne = t->ne, *F = m->F, nc = c ? c->n : 0, *Ft = L->Ft;
  const unsigned char *cut = L->cut;
  const double *vt = L->vt;
  int *deg = calloc((size_t)nv, sizeof *deg), *vstart = calloc((size_t)nv + 1, sizeof *vstart);
  int *vadj = malloc(2 * (size_t)ne * sizeof *vadj), *queue = malloc((size_t)ne * sizeof *queue);
  unsigned char *iscone = calloc((size_t)nv, 1);
  if (!deg || !vstart || !vadj || !queue || !iscone) {
    free(deg), free(vstart), free(vadj), free(queue), free(iscone);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory measuring the seams");
  }
  for (int i = 0; i < nc; i++) iscone[c->v[i]] = 1;
  L->ncut = 0;
  for (int e = 0; e < ne; e++) {
    vstart[t->E[2 * e] + 1]++, vstart[t->E[2 * e + 1] + 1]++;
    if (cut[e]) deg[t->E[2 * e]]++, deg[t->E[2 * e + 1]]++, L->ncut++;
  }
  for (int v = 0; v < nv; v++) vstart[v + 1] += vstart[v];
  {
    int *fill = calloc((size_t)nv, sizeof *fill);
    if (!fill) {
      free(deg), free(vstart), free(vadj), free(queue), free(iscone);
      return au_msg_set(msg, AU_E_NOMEM, "out of memory measuring the seams");
    }
    for (int e = 0; e < ne; e++)
      for (int s = 0; s < 2; s++) {
        int v = t->E[2 * e + s];
        vadj[vstart[v] + fill[v]++] = e;
      }
    free(fill);
  }
  int head, tail;
  L->folds = 0, L->seam_len_dev = L->seam_rot_dev = 0;
  free(L->seam_rot);
  L->seam_rot = NULL;
  /* 9. Folds and coverage. */
  double cover = 0;
  for (int f = 0; f < nf; f++) {
    const double *a = vt + 2 * Ft[3 * f], *b = vt + 2 * Ft[3 * f + 1], *q = vt + 2 * Ft[3 * f + 2];
    double ar = 0.5 * ((b[0] - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (b[1] - a[1]));
    L->folds += !(ar > 0);
    cover += ar;
  }
  L->coverage = cover;

  /* 10. Seams: chains of cut edges through interior vertices on exactly two cut edges that are not cones.
   * Each chain is walked with its edges directed one after the other, so that the face on the left of every
   * edge lies on the same side; the rotation takes the right side's copy of an edge onto the left side's. */
  for (int e = 0; e < ne; e++) L->seam_edge[e] = -1;
  int nseams = 0;
  double *rot = malloc((size_t)ne * sizeof *rot);
  int *dir = malloc((size_t)ne * sizeof *dir);
  if (!rot || !dir) {
    free(rot), free(dir);
    free(deg), free(vstart), free(vadj), free(queue), free(iscone);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory measuring the seams");
  }
  for (int e0 = 0; e0 < ne; e0++) {
    if (!cut[e0] || L->seam_edge[e0] >= 0) continue;
    head = tail = 0;
    queue[tail++] = e0, L->seam_edge[e0] = nseams, dir[e0] = 0; /* dir 0: E[2e] -> E[2e+1] */
    while (head < tail) {
      int e = queue[head++];
      for (int s = 0; s < 2; s++) {
        int v = t->E[2 * e + s];
        if (t->vb[v] || iscone[v] || deg[v] != 2) continue;
        for (int j = vstart[v]; j < vstart[v + 1]; j++) {
          int e2 = vadj[j];
          if (e2 == e || !cut[e2] || L->seam_edge[e2] >= 0) continue;
          /* e ends at v (its head when s is its end in its direction) iff e2 starts there, and vice versa. */
          int v_is_head_of_e = (s == 1) == (dir[e] == 0);
          int v_is_first_of_e2 = t->E[2 * e2] == v;
          dir[e2] = v_is_head_of_e == v_is_first_of_e2 ? 0 : 1;
          L->seam_edge[e2] = nseams, queue[tail++] = e2;
        }
      }
    }
    nseams++;
  }
  L->nseams = nseams;
  L->seam_rot = calloc((size_t)(nseams > 0 ? nseams : 1), sizeof *L->seam_rot);
  int *seen = calloc((size_t)(nseams > 0 ? nseams : 1), sizeof *seen);
  if (!L->seam_rot || !seen) {
    free(rot), free(dir), free(seen);
    free(deg), free(vstart), free(vadj), free(queue), free(iscone);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory measuring the seams");
  }
  for (int e = 0; e < ne; e++) {
    if (!cut[e]) continue;
    int a = t->E[2 * e + dir[e]], b = t->E[2 * e + 1 - dir[e]];
    double d[2][2];
    int left = -1;
    for (int s = 0; s < 2; s++) {
      int f = t->EF[2 * e + s];
      int ka = corner_at(F, f, a), kb = corner_at(F, f, b);
      if ((ka + 1) % 3 == kb) left = s; /* f runs a -> b: it lies to the left of a -> b */
      d[s][0] = vt[2 * Ft[3 * f + kb]] - vt[2 * Ft[3 * f + ka]];
      d[s][1] = vt[2 * Ft[3 * f + kb] + 1] - vt[2 * Ft[3 * f + ka] + 1];
    }
    const double *dl = d[left], *dr = d[1 - left];
    rot[e] = atan2(dr[0] * dl[1] - dr[1] * dl[0], dr[0] * dl[0] + dr[1] * dl[1]);
    L->seam_len_dev = fmax(L->seam_len_dev, fabs(hypot(dl[0], dl[1]) - hypot(dr[0], dr[1])));
    int sm = L->seam_edge[e];
    if (!seen[sm]) seen[sm] = 1, L->seam_rot[sm] = rot[e];
  }
  for (int e = 0; e < ne; e++) {
    if (!cut[e]) continue;
    double dd = fabs(remainder(rot[e] - L->seam_rot[L->seam_edge[e]], 2 * AU_PI));
    L->seam_rot_dev = fmax(L->seam_rot_dev, dd);
  }
  free(rot), free(dir), free(seen);
  free(deg), free(vstart), free(vadj), free(queue), free(iscone);
  return AU_OK;
}

au_status au_atlas_layout_make(const au_mesh *m, const au_topo *t, const au_atlas_cones *c, const double *len,
                               double gap, int quarter, int shapes, au_atlas_layout *L, au_msg *msg) {
  if (!m || !t || !len || !L || t->nv != m->nv || t->nf != m->nf || !(gap >= 0) || gap >= 0.25)
    return au_msg_set(msg, AU_E_ARG, "au_atlas_layout_make: bad arguments");
  memset(L, 0, sizeof *L);
  for (int e = 0; e < t->ne; e++)
    if (!(len[e] > 0) || !isfinite(len[e]))
      return au_msg_set(msg, AU_E_ARG, "au_atlas_layout_make: edge %d (%d, %d) has length %g: expected a finite length > 0", e,
                        t->E[2 * e], t->E[2 * e + 1], len[e]);
  const int nv = m->nv, nf = m->nf, ne = t->ne, *F = m->F, nc = c ? c->n : 0;
  au_status st = AU_OK;
  double *elen = malloc((size_t)ne * sizeof *elen), *dist = malloc((size_t)nv * sizeof *dist);
  int *vstart = calloc((size_t)nv + 1, sizeof *vstart), *vadj = malloc(2 * (size_t)ne * sizeof *vadj);
  const int nq = nf > nv ? (nf > ne ? nf : ne) : (nv > ne ? nv : ne);
  int *pedge = malloc((size_t)nv * sizeof *pedge), *queue = malloc((size_t)nq * sizeof *queue);
  int *deg = calloc((size_t)nv, sizeof *deg), *uf = malloc(3 * (size_t)nf * sizeof *uf);
  int *cls = malloc(3 * (size_t)nf * sizeof *cls), *fseen = malloc((size_t)nf * sizeof *fseen);
  unsigned char *incot = calloc((size_t)ne, 1), *iscone = calloc((size_t)nv, 1);
  /* Every vertex may be pushed once as a root and once per improvement along each edge end. */
  const size_t hcap = 2 * (size_t)ne + (size_t)nv + 1;
  heap h = {0, malloc(hcap * sizeof(double)), malloc(hcap * sizeof(int))};
  double *flen = malloc(3 * (size_t)nf * sizeof *flen), *frame = NULL;
  L->cut = calloc((size_t)ne, 1);
  L->chart = malloc((size_t)nf * sizeof *L->chart);
  L->Ft = malloc(3 * (size_t)nf * sizeof *L->Ft);
  L->seam_edge = malloc((size_t)ne * sizeof *L->seam_edge);
  if (!elen || !dist || !vstart || !vadj || !pedge || !queue || !deg || !uf || !cls || !fseen || !incot || !iscone ||
      !h.key || !h.v || !flen || !L->cut || !L->chart || !L->Ft || !L->seam_edge) {
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory laying out the atlas");
    goto done;
  }
  unsigned char *cut = L->cut;
  for (int i = 0; i < nc; i++) iscone[c->v[i]] = 1;
  for (int e = 0; e < ne; e++) {
    elen[e] = len[e];
    vstart[t->E[2 * e] + 1]++, vstart[t->E[2 * e + 1] + 1]++;
  }
  for (int v = 0; v < nv; v++) vstart[v + 1] += vstart[v];
  {
    int *fill = deg; /* borrowed, zeroed again below */
    for (int e = 0; e < ne; e++)
      for (int s = 0; s < 2; s++) {
        int v = t->E[2 * e + s];
        vadj[vstart[v] + fill[v]++] = e;
      }
    memset(deg, 0, (size_t)nv * sizeof *deg);
  }
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) flen[3 * f + k] = elen[t->FE[3 * f + k]];

  /* 1. A shortest-path tree in the metric: from the boundary when there is one (every boundary vertex a
   * root), else from the first cone (or vertex 0). */
  for (int v = 0; v < nv; v++) dist[v] = INFINITY, pedge[v] = -1;
  if (t->nloops > 0) {
    for (int v = 0; v < nv; v++)
      if (t->vb[v]) dist[v] = 0, heap_push(&h, 0, v);
  } else {
    int root = nc > 0 ? c->v[0] : 0;
    while (!t->vused[root]) root++;
    dist[root] = 0, heap_push(&h, 0, root);
  }
  while (h.n > 0) {
    double d;
    int v;
    heap_pop(&h, &d, &v);
    if (d > dist[v]) continue;
    for (int i = vstart[v]; i < vstart[v + 1]; i++) {
      int e = vadj[i], w = t->E[2 * e] == v ? t->E[2 * e + 1] : t->E[2 * e];
      if (t->vb[w] && t->nloops > 0) continue;
      if (d + elen[e] < dist[w]) dist[w] = d + elen[e], pedge[w] = e, heap_push(&h, dist[w], w);
    }
  }
  /* 2. A dual spanning tree across interior edges off the tree (incot 2 marks a tree edge, 1 a crossed
   * one); the interior edges it does not cross are the cut (cutting along them leaves one disk). */
  for (int v = 0; v < nv; v++)
    if (pedge[v] >= 0) incot[pedge[v]] = 2;
  for (int f = 0; f < nf; f++) fseen[f] = 0;
  int head = 0, tail = 0, reached = 0;
  for (int pass = 0; pass < 2 && reached < nf; pass++) {
    /* Pass 0 avoids the tree; pass 1 (never needed when the tree is as built) may cross it. */
    head = tail = 0;
    if (pass == 0) fseen[0] = 1, queue[tail++] = 0, reached = 1;
    else
      for (int f = 0; f < nf; f++)
        if (fseen[f]) queue[tail++] = f;
    while (head < tail) {
      int f = queue[head++];
      for (int k = 0; k < 3; k++) {
        int e = t->FE[3 * f + k];
        if (t->EF[2 * e + 1] < 0 || (incot[e] == 2 && pass == 0)) continue;
        int g = t->EF[2 * e] == f ? t->EF[2 * e + 1] : t->EF[2 * e];
        if (fseen[g]) continue;
        fseen[g] = 1, incot[e] = 1, queue[tail++] = g, reached++;
      }
    }
  }
  if (reached < nf) {
    st = au_msg_set(msg, AU_E_INTERNAL, "the dual tree reaches %d of %d faces", reached, nf);
    goto done;
  }
  for (int e = 0; e < ne; e++) {
    cut[e] = t->EF[2 * e + 1] >= 0 && incot[e] != 1;
    if (cut[e]) deg[t->E[2 * e]]++, deg[t->E[2 * e + 1]]++;
  }
  /* 3. Prune the branches that end at an ordinary interior vertex. */
  head = tail = 0;
  for (int v = 0; v < nv; v++)
    if (deg[v] == 1 && !t->vb[v] && !iscone[v]) queue[tail++] = v;
  while (head < tail) {
    int v = queue[head++];
    if (deg[v] != 1) continue;
    for (int i = vstart[v]; i < vstart[v + 1]; i++) {
      int e = vadj[i];
      if (!cut[e]) continue;
      cut[e] = 0, deg[v]--;
      int w = t->E[2 * e] == v ? t->E[2 * e + 1] : t->E[2 * e];
      deg[w]--;
      if (deg[w] == 1 && !t->vb[w] && !iscone[w] && tail < nv) queue[tail++] = w;
      break;
    }
  }
  /* 4. A cone of angle > 2 pi at the end of a branch would overlap itself around its single cut: a second
   * cut from it, by breadth first over uncut edges to the nearest vertex on the cut or the boundary. */
  for (int i = 0; i < nc; i++) {
    int s = c->v[i];
    if (c->angle[i] <= 2 * AU_PI || deg[s] >= 2) continue;
    for (int v = 0; v < nv; v++) pedge[v] = -2;
    head = tail = 0;
    queue[tail++] = s, pedge[s] = -1;
    int hit = -1;
    while (head < tail && hit < 0) {
      int v = queue[head++];
      for (int j = vstart[v]; j < vstart[v + 1] && hit < 0; j++) {
        int e = vadj[j], w = t->E[2 * e] == v ? t->E[2 * e + 1] : t->E[2 * e];
        if (cut[e] || t->EF[2 * e + 1] < 0 || pedge[w] != -2) continue;
        pedge[w] = e, queue[tail++] = w;
        if (deg[w] > 0 || t->vb[w]) hit = w;
      }
    }
    for (int v = hit; v >= 0 && v != s;) {
      int e = pedge[v];
      cut[e] = 1, deg[t->E[2 * e]]++, deg[t->E[2 * e + 1]]++;
      v = t->E[2 * e] == v ? t->E[2 * e + 1] : t->E[2 * e];
    }
  }

  /* A common frame: the direction of every face's edge from corner 0 to corner 1 when the surface is
   * developed across all interior edges along a dual tree from face 0. Each chart starts in it, so that two
   * charts meet at the rotation of the metric's holonomy (a multiple of pi/2 around quarter cones). */
  frame = malloc((size_t)nf * sizeof *frame);
  if (!frame) {
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory laying out the atlas");
    goto done;
  }
  for (int f = 0; f < nf; f++) fseen[f] = 0;
  frame[0] = 0, fseen[0] = 1;
  head = tail = 0;
  queue[tail++] = 0;
  while (head < tail) {
    int f = queue[head++];
    for (int k = 0; k < 3; k++) {
      int e = t->FE[3 * f + k];
      if (t->EF[2 * e + 1] < 0) continue;
      int g = t->EF[2 * e] == f ? t->EF[2 * e + 1] : t->EF[2 * e];
      if (fseen[g]) continue;
      fseen[g] = 1, queue[tail++] = g;
      /* The shared edge runs from corner k+1 (at a) to k+2 (at b) in f; g runs it from b to a, from its
       * corner gb. */
      int ka = (k + 1) % 3, b = F[3 * f + (k + 2) % 3], gb = corner_at(F, g, b);
      double d = edge_dir(flen + 3 * f, frame[f], ka) + AU_PI;
      d -= edge_dir(flen + 3 * g, 0, gb);
      frame[g] = remainder(d, 2 * AU_PI);
    }
  }
  /* 5.-8. Lay out and pack; where a chart covers a texel of the 1024 x 1024 raster twice (it overlaps
   * itself in the plane: a cone of large angle, a long arm that comes round), the chart is split between
   * the two faces found there, by a race from both (race_cut), and the whole is packed again. */
  for (int round = 0;; round++) {
    if ((st = lay_out(m, t, cut, flen, frame, quarter, gap, uf, cls, queue, L, msg)) != AU_OK) goto done;
    int split = 0;
    if ((st = split_overlaps(m, t, cut, L, &split, msg)) != AU_OK) goto done;
    if (!split || round == 40) break;
  }
  /* On shelves while splitting, by the charts' shapes at the end (when asked: a layout that the flow
   * moves is packed again after it). */
  if (shapes && (st = pack(nf, L->Ft, L->chart, L->ncharts, L->nvt, L->vt, quarter, gap, 1, 0, &L->scale, msg)) != AU_OK)
    goto done;
  /* 9., 10. Folds, coverage and the seams (splits added cut edges). */
  st = au_atlas_measure(m, t, c, L, msg);

done:
  free(elen), free(dist), free(vstart), free(vadj), free(pedge), free(queue), free(deg), free(uf), free(cls),
      free(fseen), free(incot), free(iscone), free(frame), free(h.key), free(h.v), free(flen);
  if (st != AU_OK) au_atlas_layout_free(L);
  return st;
}
