/* au_image.c - pictures of sphere maps: PNG files through libpng's simplified API, colour maps,
 * a small z-buffered triangle rasterizer with a 3x5 bitmap font for labels, the preview of a map
 * coloured by area distortion with the Upsilon/Lambda histograms (the paper's figures: Upsilon dark
 * red, Lambda blue), the same for a torus map tiled 3 x 3 by its lattice, and a render of a textured
 * mesh. */
#include <math.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>

#include "au_io.h"
#include "au_metrics.h"
#include "au_texture.h"

/* ---------------------------------------------------------------- PNG */

au_status au_png_write(const char *path, int W, int H, const unsigned char *rgb, au_msg *msg) {
  if (!path || !rgb || W < 1 || H < 1 || W > 65535 || H > 65535) return au_msg_set(msg, AU_E_ARG, "au_png_write: bad arguments");
  png_image img;
  memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  img.width = (png_uint_32)W;
  img.height = (png_uint_32)H;
  img.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&img, NULL, &size, 0, rgb, 0, NULL))
    return au_msg_set(msg, AU_E_NOMEM, "cannot encode '%s': %s", path, img.message);
  void *buf = malloc(size);
  if (!buf) return au_msg_set(msg, AU_E_NOMEM, "out of memory writing '%s'", path);
  au_status st = AU_OK;
  if (!png_image_write_to_memory(&img, buf, &size, 0, rgb, 0, NULL))
    st = au_msg_set(msg, AU_E_NOMEM, "cannot encode '%s': %s", path, img.message);
  else
    st = au_io_write_text(path, buf, size, msg);
  png_image_free(&img);
  free(buf);
  return st;
}

au_status au_png_read(const char *path, int *W, int *H, unsigned char **rgb, au_msg *msg) {
  if (!path || !W || !H || !rgb) return au_msg_set(msg, AU_E_ARG, "au_png_read: bad arguments");
  *rgb = NULL;
  FILE *fp = fopen(path, "rb");
  if (!fp) return au_msg_set(msg, AU_E_IO, "cannot read '%s'", path);
  fclose(fp);
  png_image img;
  memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path))
    return au_msg_set(msg, AU_E_FORMAT, "'%s' is not a readable PNG: %s", path, img.message);
  img.format = PNG_FORMAT_RGB;
  size_t n = PNG_IMAGE_SIZE(img);
  unsigned char *b = malloc(n);
  if (!b) {
    png_image_free(&img);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
  }
  if (!png_image_finish_read(&img, NULL, b, 0, NULL)) {
    free(b);
    return au_msg_set(msg, AU_E_FORMAT, "cannot decode '%s': %s", path, img.message);
  }
  *W = (int)img.width, *H = (int)img.height, *rgb = b;
  return AU_OK;
}

/* ---------------------------------------------------------------- colour maps */

static void cmap_lerp(const unsigned char (*tab)[3], int n, double t, unsigned char rgb[3]) {
  if (isnan(t)) {
    rgb[0] = rgb[1] = rgb[2] = 128;
    return;
  }
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  double s = t * (n - 1);
  int i = (int)s;
  if (i >= n - 1) i = n - 2;
  double f = s - i;
  for (int k = 0; k < 3; k++) rgb[k] = (unsigned char)lround((1 - f) * tab[i][k] + f * tab[i + 1][k]);
}

void au_cmap_viridis(double t, unsigned char rgb[3]) {
  static const unsigned char tab[9][3] = {{68, 1, 84},    {71, 44, 122},  {59, 81, 139},  {44, 113, 142}, {33, 144, 141},
                                          {39, 173, 129}, {92, 200, 99},  {170, 220, 50}, {253, 231, 37}};
  cmap_lerp(tab, 9, t, rgb);
}

void au_cmap_diverging(double t, unsigned char rgb[3]) {
  static const unsigned char tab[5][3] = {{5, 48, 97}, {67, 147, 195}, {247, 247, 247}, {214, 96, 77}, {103, 0, 31}};
  cmap_lerp(tab, 5, t, rgb);
}

/* ---------------------------------------------------------------- canvas, triangles, text */

typedef struct canvas {
  int W, H;
  unsigned char *rgb;
  float *z; /* depth; larger is nearer */
} canvas;

static int canvas_init(canvas *c, int W, int H) {
  c->W = W, c->H = H;
  c->rgb = malloc(3 * (size_t)W * H);
  c->z = malloc((size_t)W * H * sizeof *c->z);
  if (!c->rgb || !c->z) {
    free(c->rgb), free(c->z);
    return -1;
  }
  memset(c->rgb, 255, 3 * (size_t)W * H);
  for (size_t i = 0; i < (size_t)W * H; i++) c->z[i] = -INFINITY;
  return 0;
}

static void canvas_free(canvas *c) {
  free(c->rgb), free(c->z);
  c->rgb = NULL, c->z = NULL;
}

static void put(canvas *c, int x, int y, const unsigned char rgb[3]) {
  if (x < 0 || y < 0 || x >= c->W || y >= c->H) return;
  memcpy(c->rgb + 3 * ((size_t)y * c->W + x), rgb, 3);
}

static void fill_rect(canvas *c, int x0, int y0, int x1, int y1, const unsigned char rgb[3]) {
  for (int y = y0; y < y1; y++)
    for (int x = x0; x < x1; x++) put(c, x, y, rgb);
}

/* A shader gets the face, the screen-space barycentric coordinates (exact object-space ones under
 * an orthographic view) and writes the colour. */
typedef void (*shade_fn)(void *user, int face, const double b[3], unsigned char rgb[3]);

/* Fill the triangle with screen corners (x, y) and depths z, pixel centres at (i + 0.5, j + 0.5),
 * both orientations. */
static void raster_tri(canvas *c, const double *x, const double *y, const double *z, int face, shade_fn shade, void *user) {
  double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  if (!(fabs(area) > 1e-12)) return;
  int x0 = (int)floor(fmin(x[0], fmin(x[1], x[2]))), x1 = (int)ceil(fmax(x[0], fmax(x[1], x[2])));
  int y0 = (int)floor(fmin(y[0], fmin(y[1], y[2]))), y1 = (int)ceil(fmax(y[0], fmax(y[1], y[2])));
  if (x0 < 0) x0 = 0;
  if (y0 < 0) y0 = 0;
  if (x1 > c->W - 1) x1 = c->W - 1;
  if (y1 > c->H - 1) y1 = c->H - 1;
  for (int j = y0; j <= y1; j++)
    for (int i = x0; i <= x1; i++) {
      double px = i + 0.5, py = j + 0.5, b[3];
      b[0] = ((x[1] - px) * (y[2] - py) - (x[2] - px) * (y[1] - py)) / area;
      b[1] = ((x[2] - px) * (y[0] - py) - (x[0] - px) * (y[2] - py)) / area;
      b[2] = 1 - b[0] - b[1];
      if (b[0] < -1e-9 || b[1] < -1e-9 || b[2] < -1e-9) continue;
      float d = (float)(b[0] * z[0] + b[1] * z[1] + b[2] * z[2]);
      size_t k = (size_t)j * c->W + i;
      if (d <= c->z[k]) continue;
      c->z[k] = d;
      shade(user, face, b, c->rgb + 3 * k);
    }
}

/* A 3x5 font: digits, '.', '-', and the letters of the labels. Rows top to bottom, 3 bits each. */
static const char *glyph(char ch) {
  switch (ch) {
    case '0': case 'O': return "111101101101111";
    case '1': return "010110010010111";
    case '2': return "111001111100111";
    case '3': return "111001111001111";
    case '4': return "101101111001001";
    case '5': case 'S': return "111100111001111";
    case '6': return "111100111101111";
    case '7': return "111001001001001";
    case '8': return "111101111101111";
    case '9': return "111101111001111";
    case '.': return "000000000000010";
    case '-': return "000000111000000";
    case '+': return "000010111010000";
    case 'U': return "101101101101111";
    case 'P': return "111101111100100";
    case 'I': return "111010010010111";
    case 'L': return "100100100100111";
    case 'N': return "110101101101101";
    case 'A': return "010101111101101";
    case 'M': return "101111111101101";
    case 'B': return "110101110101110";
    case 'D': return "110101101101110";
    case 'Z': return "111001010100111";
    default: return "000000000000000";
  }
}

/* Draw text with its top-left corner at (x, y), each font pixel a s x s block. Returns the width. */
static int draw_text(canvas *c, int x, int y, int s, const char *txt, const unsigned char rgb[3]) {
  int x0 = x;
  for (const char *p = txt; *p; p++) {
    if (*p != ' ') {
      const char *g = glyph(*p);
      for (int r = 0; r < 5; r++)
        for (int q = 0; q < 3; q++)
          if (g[3 * r + q] == '1') fill_rect(c, x + q * s, y + r * s, x + (q + 1) * s, y + (r + 1) * s, rgb);
    }
    x += 4 * s;
  }
  return x - x0;
}

/* ---------------------------------------------------------------- the preview */

typedef struct preview_ctx {
  const double *ups;
  double range;
} preview_ctx;

static void shade_ups(void *user, int face, const double b[3], unsigned char rgb[3]) {
  (void)b;
  const preview_ctx *p = user;
  double u = p->ups[face];
  au_cmap_diverging(isnan(u) ? NAN : 0.5 + u / (2 * p->range), rgb);
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The histogram of the finite values v [0..n-1] over [lo, hi] in the box (x0, y0, w, h). */
static void draw_hist(canvas *c, int x0, int y0, int w, int h, const double *v, int n, double lo, double hi,
                      const unsigned char col[3], const char *label) {
  enum { NB = 80 };
  double cnt[NB] = {0};
  for (int i = 0; i < n; i++) {
    if (isnan(v[i])) continue;
    int k = (int)floor((v[i] - lo) / (hi - lo) * NB);
    k = k < 0 ? 0 : k >= NB ? NB - 1 : k;
    cnt[k]++;
  }
  double mx = 0;
  for (int k = 0; k < NB; k++) mx = fmax(mx, cnt[k]);
  const unsigned char black[3] = {0, 0, 0}, grey[3] = {150, 150, 150};
  int top = y0 + 24, base = y0 + h - 24, tw = w - 20;
  for (int k = 0; k < NB && mx > 0; k++) {
    int bx0 = x0 + 10 + k * tw / NB, bx1 = x0 + 10 + (k + 1) * tw / NB - 1;
    int bh = (int)lround((base - top) * cnt[k] / mx);
    fill_rect(c, bx0, base - bh, bx1 > bx0 ? bx1 : bx0 + 1, base, col);
  }
  fill_rect(c, x0 + 10, base, x0 + 10 + tw, base + 2, black);
  if (lo < 0 && hi > 0) {
    int zx = x0 + 10 + (int)lround(tw * (0 - lo) / (hi - lo));
    fill_rect(c, zx, top, zx + 1, base, grey);
  }
  char s[32];
  snprintf(s, sizeof s, "%.2f", lo);
  draw_text(c, x0 + 10, base + 6, 2, s, black);
  snprintf(s, sizeof s, "%.2f", hi);
  draw_text(c, x0 + 10 + tw - 8 * (int)strlen(s), base + 6, 2, s, black);
  draw_text(c, x0 + 10, y0 + 6, 2, label, col);
}

/* The p-th percentile (0..100) of the finite values among v [0..n-1] (|v| when absval), or dflt if none;
 * tmp holds n doubles. */
static double finite_percentile(const double *v, int n, int absval, double p, double dflt, double *tmp) {
  int m = 0;
  for (int i = 0; i < n; i++)
    if (!isnan(v[i])) tmp[m++] = absval ? fabs(v[i]) : v[i];
  if (!m) return dflt;
  qsort(tmp, (size_t)m, sizeof *tmp, cmp_double);
  return tmp[(int)(p / 100 * (m - 1))];
}

/* Below a picture whose top part ends at y0 (the canvas W wide): the colour bar of Upsilon over
 * [-range, range] and the Upsilon and Lambda histograms of the faces (hist_h high), each over the
 * data's 99th percentile, so that colours compare between maps and the histograms show the shape. */
static void draw_legend(canvas *c, int y0, int hist_h, const double *ups, const double *lam, int nf, double range,
                        double *tmp) {
  double hrange = fmax(0.05, finite_percentile(ups, nf, 1, 99, 0.05, tmp));
  double lrange = fmax(0.1, finite_percentile(lam, nf, 0, 99, 0.1, tmp));
  const unsigned char black[3] = {0, 0, 0};
  int W = c->W, half = W / 2, by = y0 + 4, bx0 = half / 4, bx1 = W - half / 4;
  for (int x = bx0; x < bx1; x++) {
    unsigned char col[3];
    au_cmap_diverging((x - bx0 + 0.5) / (bx1 - bx0), col);
    fill_rect(c, x, by, x + 1, by + 14, col);
  }
  char s[32];
  snprintf(s, sizeof s, "%.2f", -range);
  draw_text(c, bx0 - 8 * (int)strlen(s) - 6, by, 2, s, black);
  snprintf(s, sizeof s, "+%.2f", range);
  draw_text(c, bx1 + 6, by, 2, s, black);
  draw_text(c, (bx0 + bx1) / 2 - 3, by + 18, 2, "0", black);
  const unsigned char red[3] = {139, 0, 0}, blue[3] = {0, 0, 200};
  draw_hist(c, 0, y0 + 40, half, hist_h, ups, nf, -hrange, hrange, red, "UPSILON");
  draw_hist(c, half, y0 + 40, W - half, hist_h, lam, nf, 0, lrange, blue, "LAMBDA");
}

au_status au_tex_preview(const char *path, const au_mesh *m, const double *P, int size, double range, au_msg *msg) {
  if (!path || !m || !P || size < 200 || size > 8000) return au_msg_set(msg, AU_E_ARG, "au_tex_preview: bad arguments");
  int nf = m->nf;
  double *ups = malloc(3 * (size_t)nf * sizeof *ups);
  if (!ups) return au_msg_set(msg, AU_E_NOMEM, "out of memory drawing '%s'", path);
  double *lam = ups + nf, *tmp = ups + 2 * (size_t)nf;
  au_metrics met;
  au_status st = au_metrics_compute(m->nv, nf, m->X, P, m->F, AU_DOMAIN_SPHERE, &met, ups, lam);
  if (st != AU_OK) {
    free(ups);
    return au_msg_set(msg, st, "cannot measure the map for '%s'", path);
  }
  if (!(range > 0)) range = 0.5;
  int W = size, half = size / 2, H = half + 40 + size / 4;
  canvas c;
  if (canvas_init(&c, W, H)) {
    free(ups);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory drawing '%s'", path);
  }
  preview_ctx pc = {ups, range};
  double R = 0.46 * half;
  for (int view = 0; view < 2; view++) {
    double cx = half * view + half / 2.0, cy = half / 2.0, s = view ? -1.0 : 1.0;
    for (int f = 0; f < nf; f++) {
      double x[3], y[3], z[3];
      for (int k = 0; k < 3; k++) {
        const double *p = P + 3 * (size_t)m->F[3 * f + k];
        x[k] = cx + s * R * p[0], y[k] = cy - R * p[1], z[k] = s * p[2];
      }
      raster_tri(&c, x, y, z, f, shade_ups, &pc);
    }
  }
  const unsigned char black[3] = {0, 0, 0};
  draw_text(&c, 8, 8, 3, "+Z", black);
  draw_text(&c, half + 8, 8, 3, "-Z", black);
  draw_legend(&c, half, size / 4, ups, lam, nf, range, tmp);
  st = au_png_write(path, W, H, c.rgb, msg);
  canvas_free(&c);
  free(ups);
  return st;
}

/* ---------------------------------------------------------------- the torus preview */

/* A straight line of width w pixels from (x0, y0) to (x1, y1). */
static void draw_line(canvas *c, double x0, double y0, double x1, double y1, int w, const unsigned char rgb[3]) {
  int n = (int)ceil(fmax(fabs(x1 - x0), fabs(y1 - y0))) + 1;
  for (int i = 0; i <= n; i++) {
    double t = (double)i / n;
    int x = (int)floor(x0 + t * (x1 - x0)) - w / 2, y = (int)floor(y0 + t * (y1 - y0)) - w / 2;
    fill_rect(c, x, y, x + w, y + w, rgb);
  }
}

au_status au_torus_preview(const char *path, const au_result *r, int size, double range, au_msg *msg) {
  if (!path || !r || !r->vt || !r->Ft || !r->X || !r->F || r->nf < 1 || size < 200 || size > 8000)
    return au_msg_set(msg, AU_E_ARG, "au_torus_preview: bad arguments (a torus result is needed)");
  const double(*L)[2] = r->lattice;
  double det = L[0][0] * L[1][1] - L[0][1] * L[1][0];
  if (!(fabs(det) > 1e-12)) return au_msg_set(msg, AU_E_ARG, "au_torus_preview: the result's lattice is degenerate");
  int nf = r->nf;
  /* Distortion per face of the surface cut along the seams, as the result's metrics measure it:
   * every face by its own lifted triangle. */
  double *ups = malloc(3 * (size_t)nf * sizeof *ups);
  if (!ups) return au_msg_set(msg, AU_E_NOMEM, "out of memory drawing '%s'", path);
  double *lam = ups + nf, *tmp = ups + 2 * (size_t)nf;
  au_metrics met;
  au_status st = au__metrics_vt(r->nv, nf, r->X, r->F, r->nvt, r->vt, r->Ft, &met, ups, lam);
  if (st != AU_OK) {
    free(ups);
    return au_msg_set(msg, st, "cannot measure the map for '%s'", path);
  }
  if (!(range > 0)) range = 0.5;
  /* The 3 x 3 tiles: the parallelogram spanned by 3 a1 and 3 a2 from -a1 - a2, fitted into a square
   * picture with a margin, y upwards. */
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (int i = 0; i < 4; i++) {
    double s = (i & 1) ? 2 : -1, t = (i & 2) ? 2 : -1;
    for (int d = 0; d < 2; d++) {
      double p = s * L[0][d] + t * L[1][d];
      lo[d] = fmin(lo[d], p), hi[d] = fmax(hi[d], p);
    }
  }
  int W = size, top = size, H = top + 40 + size / 4;
  double scale = 0.96 * size / fmax(hi[0] - lo[0], hi[1] - lo[1]);
  double ox = 0.5 * size - scale * 0.5 * (lo[0] + hi[0]), oy = 0.5 * top + scale * 0.5 * (lo[1] + hi[1]);
  canvas c;
  if (canvas_init(&c, W, H)) {
    free(ups);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory drawing '%s'", path);
  }
  preview_ctx pc = {ups, range};
  for (int ti = -1; ti <= 1; ti++)
    for (int tj = -1; tj <= 1; tj++) {
      double sx = ti * L[0][0] + tj * L[1][0], sy = ti * L[0][1] + tj * L[1][1];
      for (int f = 0; f < nf; f++) {
        double x[3], y[3], z[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++) {
          const double *p = r->vt + 2 * (size_t)r->Ft[3 * f + k];
          x[k] = ox + scale * (p[0] + sx), y[k] = oy - scale * (p[1] + sy);
        }
        raster_tri(&c, x, y, z, f, shade_ups, &pc);
      }
    }
  /* The tiles' edges in grey, the fundamental domain {s a1 + t a2 : 0 <= s, t <= 1} in black. */
  const unsigned char black[3] = {0, 0, 0}, grey[3] = {110, 110, 110};
  for (int k = -1; k <= 2; k++) {
    double ax = k * L[0][0], ay = k * L[0][1], bx = k * L[1][0], by = k * L[1][1];
    draw_line(&c, ox + scale * (ax - L[1][0]), oy - scale * (ay - L[1][1]), ox + scale * (ax + 2 * L[1][0]),
              oy - scale * (ay + 2 * L[1][1]), 1, grey);
    draw_line(&c, ox + scale * (bx - L[0][0]), oy - scale * (by - L[0][1]), ox + scale * (bx + 2 * L[0][0]),
              oy - scale * (by + 2 * L[0][1]), 1, grey);
  }
  double cx[5] = {0, L[0][0], L[0][0] + L[1][0], L[1][0], 0}, cy[5] = {0, L[0][1], L[0][1] + L[1][1], L[1][1], 0};
  for (int k = 0; k < 4; k++)
    draw_line(&c, ox + scale * cx[k], oy - scale * cy[k], ox + scale * cx[k + 1], oy - scale * cy[k + 1], 3, black);
  draw_legend(&c, top, size / 4, ups, lam, nf, range, tmp);
  st = au_png_write(path, W, H, c.rgb, msg);
  canvas_free(&c);
  free(ups);
  return st;
}

/* ---------------------------------------------------------------- the textured render */

typedef struct render_ctx {
  const au_tex_mesh *t;
  const unsigned char *img;
  int tw, th, wrap;
  const double *N; /* vertex normals of t */
  double w[3];     /* towards the viewer */
  int mark_seam;   /* tint the faces across the cea seam */
} render_ctx;

static void texel(const render_ctx *r, int i, int j, double out[3]) {
  if (r->wrap) i = ((i % r->tw) + r->tw) % r->tw;
  else i = i < 0 ? 0 : i >= r->tw ? r->tw - 1 : i;
  j = j < 0 ? 0 : j >= r->th ? r->th - 1 : j;
  const unsigned char *p = r->img + 3 * ((size_t)j * r->tw + i);
  out[0] = p[0], out[1] = p[1], out[2] = p[2];
}

static void shade_tex(void *user, int face, const double b[3], unsigned char rgb[3]) {
  const render_ctx *r = user;
  const int *ft = r->t->Ft + 3 * (size_t)face, *fv = r->t->F + 3 * (size_t)face;
  double u = 0, v = 0, n[3] = {0, 0, 0};
  for (int k = 0; k < 3; k++) {
    u += b[k] * r->t->vt[2 * ft[k]];
    v += b[k] * r->t->vt[2 * ft[k] + 1];
    for (int j = 0; j < 3; j++) n[j] += b[k] * r->N[3 * fv[k] + j];
  }
  /* Bilinear lookup; texel centres at ((i + 0.5)/tw, 1 - (j + 0.5)/th). */
  double fx = u * r->tw - 0.5, fy = (1 - v) * r->th - 0.5;
  int i0 = (int)floor(fx), j0 = (int)floor(fy);
  double ax = fx - i0, ay = fy - j0, c00[3], c10[3], c01[3], c11[3];
  texel(r, i0, j0, c00), texel(r, i0 + 1, j0, c10), texel(r, i0, j0 + 1, c01), texel(r, i0 + 1, j0 + 1, c11);
  double tint = 0;
  if (r->mark_seam && r->wrap) {
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < 3; k++) lo = fmin(lo, r->t->vt[2 * ft[k]]), hi = fmax(hi, r->t->vt[2 * ft[k]]);
    tint = (lo < 0 || hi > 1) ? 0.55 : 0;
  }
  double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  double lum = nn > 0 ? fabs(n[0] * r->w[0] + n[1] * r->w[1] + n[2] * r->w[2]) / nn : 1;
  double shade = 0.35 + 0.65 * lum;
  for (int k = 0; k < 3; k++) {
    double col = (1 - ay) * ((1 - ax) * c00[k] + ax * c10[k]) + ay * ((1 - ax) * c01[k] + ax * c11[k]);
    col = (1 - tint) * col + tint * (k == 0 ? 255 : 0);
    col *= shade;
    rgb[k] = (unsigned char)(col < 0 ? 0 : col > 255 ? 255 : lround(col));
  }
}

au_status au_tex_render(const char *path, const au_tex_mesh *t, const unsigned char *img, int tw, int th,
                        const double view[3], int size, int mark_seam, au_msg *msg) {
  if (!path || !t || !img || tw < 1 || th < 1 || !view || size < 64 || size > 8000)
    return au_msg_set(msg, AU_E_ARG, "au_tex_render: bad arguments");
  double vn = sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
  if (!(vn > 0)) return au_msg_set(msg, AU_E_ARG, "au_tex_render: zero view direction");
  au_mesh mm = {t->nv, t->nf, t->X, t->F};
  double *N = malloc(3 * (size_t)t->nv * sizeof *N);
  canvas c;
  if (!N || canvas_init(&c, 2 * size, size)) {
    free(N);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory drawing '%s'", path);
  }
  au_tex_vertex_normals(&mm, N);
  /* Framed by the input's vertices: the ones the splits add lie on its surface and must not move
   * the camera (a render of the same mesh in either projection frames it the same way). */
  double ctr[3] = {0, 0, 0}, rad = 0;
  int nin = t->nv_in > 0 ? t->nv_in : t->nv;
  for (int i = 0; i < nin; i++)
    for (int j = 0; j < 3; j++) ctr[j] += t->X[3 * i + j] / nin;
  for (int i = 0; i < nin; i++) {
    double d[3] = {t->X[3 * i] - ctr[0], t->X[3 * i + 1] - ctr[1], t->X[3 * i + 2] - ctr[2]};
    rad = fmax(rad, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
  }
  if (!(rad > 0)) rad = 1;
  render_ctx r = {t, img, tw, th, t->layout.proj == AU_TEX_CEA, N, {0, 0, 0}, mark_seam};
  for (int view_i = 0; view_i < 2; view_i++) {
    double w[3];
    for (int j = 0; j < 3; j++) w[j] = (view_i ? -1 : 1) * view[j] / vn;
    /* Screen up: the world axis least aligned with w, made orthogonal to it. */
    double up[3] = {0, 0, 0};
    int ax = fabs(w[1]) < 0.9 ? 1 : 2;
    up[ax] = 1;
    double d = up[0] * w[0] + up[1] * w[1] + up[2] * w[2];
    for (int j = 0; j < 3; j++) up[j] -= d * w[j];
    double un = sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
    for (int j = 0; j < 3; j++) up[j] /= un;
    double right[3] = {up[1] * w[2] - up[2] * w[1], up[2] * w[0] - up[0] * w[2], up[0] * w[1] - up[1] * w[0]};
    memcpy(r.w, w, sizeof w);
    double s = 0.47 * size / rad, cx = size * view_i + size / 2.0, cy = size / 2.0;
    for (int f = 0; f < t->nf; f++) {
      double x[3], y[3], z[3];
      for (int k = 0; k < 3; k++) {
        const double *p = t->X + 3 * (size_t)t->F[3 * f + k];
        double q[3] = {p[0] - ctr[0], p[1] - ctr[1], p[2] - ctr[2]};
        x[k] = cx + s * (q[0] * right[0] + q[1] * right[1] + q[2] * right[2]);
        y[k] = cy - s * (q[0] * up[0] + q[1] * up[1] + q[2] * up[2]);
        z[k] = q[0] * w[0] + q[1] * w[1] + q[2] * w[2];
      }
      raster_tri(&c, x, y, z, f, shade_tex, &r);
    }
  }
  au_status st = au_png_write(path, 2 * size, size, c.rgb, msg);
  canvas_free(&c);
  free(N);
  return st;
}

au_status au_tex_seam_view(const au_tex_mesh *t, double view[3]) {
  if (!t || !view || t->nv < 1) return AU_E_ARG;
  double ctr[3] = {0, 0, 0}, s[3] = {0, 0, 0};
  int n = 0;
  int nin = t->nv_in > 0 ? t->nv_in : t->nv;
  for (int i = 0; i < nin; i++)
    for (int j = 0; j < 3; j++) ctr[j] += t->X[3 * i + j] / nin;
  /* The vertices within 10 degrees of longitude of the seam, above the equator's latitude band
   * midpoint so the direction does not cancel out between the hemispheres. */
  for (int i = 0; i < nin; i++) {
    double lon = t->lonlat[2 * i], lat = t->lonlat[2 * i + 1];
    if (fabs(lon) > 170 && fabs(lat) < 60) {
      for (int j = 0; j < 3; j++) s[j] += t->X[3 * i + j] - ctr[j];
      n++;
    }
  }
  double r = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  if (n == 0 || !(r > 0)) {
    view[0] = -1, view[1] = 0, view[2] = 0;
    return AU_OK;
  }
  for (int j = 0; j < 3; j++) view[j] = s[j] / r;
  return AU_OK;
}
