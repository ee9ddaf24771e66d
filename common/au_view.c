/* au_view.c - the `authalic view` page: one self-contained HTML file showing a surface and its map
 * side by side, coloured by the map's per-face distortion (see include/authalic.h, au_view_html).
 *
 * The page itself (HTML, CSS, its JavaScript and three.js) is compiled in: view/embed.mjs makes
 * au_view_page.c at build time, the page cut in two around its data. This file writes the data: a
 * JSON object whose arrays are little-endian binary in base64 (positions quantized to 16 bits over
 * their bounding box, faces as 32-bit indices, per-face log r and Lambda as float32), so a map of a
 * million faces stays a page of tens of megabytes that a browser decodes in a second or two. The
 * per-face figures come from au_metrics_compute (au__metrics_vt for a map by per-corner coordinates),
 * the numbers the report and param-eval give. */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "authalic.h"
#include "au_metrics.h"

extern const unsigned char au__view_head[], au__view_tail[];
extern const unsigned long au__view_head_len, au__view_tail_len;

au_view_input au_view_input_default(void) {
  au_view_input in;
  memset(&in, 0, sizeof in);
  in.steps = -1;
  in.seconds = -1;
  return in;
}

/* ---------------------------------------------------------------- a growing text */

typedef struct vbuf {
  char *s;
  size_t len, cap;
  int bad; /* out of memory: every later append is dropped */
} vbuf;

static char *vb_room(vbuf *b, size_t n) {
  if (b->bad) return NULL;
  if (b->len + n + 1 > b->cap) {
    size_t cap = b->cap ? b->cap : 1 << 16;
    while (b->len + n + 1 > cap) cap *= 2;
    char *s = realloc(b->s, cap);
    if (!s) return b->bad = 1, NULL;
    b->s = s, b->cap = cap;
  }
  return b->s + b->len;
}

static void vb_put(vbuf *b, const void *p, size_t n) {
  char *d = vb_room(b, n);
  if (d) memcpy(d, p, n), b->len += n, b->s[b->len] = '\0';
}

static void vb_printf(vbuf *b, const char *fmt, ...) {
  char tmp[512];
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
  va_end(ap);
  if (n > 0) vb_put(b, tmp, (size_t)n < sizeof tmp ? (size_t)n : sizeof tmp - 1);
}

/* A JSON string; '<' escaped so that no text can close the page's script element. */
static void vb_json_string(vbuf *b, const char *s) {
  vb_put(b, "\"", 1);
  for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
    if (*p == '"' || *p == '\\') vb_printf(b, "\\%c", *p);
    else if (*p < 0x20 || *p == '<' || *p == '>' || *p == '&') vb_printf(b, "\\u%04x", *p);
    else vb_put(b, p, 1);
  }
  vb_put(b, "\"", 1);
}

/* n bytes as a quoted base64 string. */
static void vb_base64(vbuf *b, const unsigned char *p, size_t n) {
  static const char A[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  char *d = vb_room(b, 4 * ((n + 2) / 3) + 2);
  if (!d) return;
  *d++ = '"';
  size_t i = 0;
  for (; i + 3 <= n; i += 3) {
    uint32_t v = (uint32_t)p[i] << 16 | (uint32_t)p[i + 1] << 8 | p[i + 2];
    *d++ = A[v >> 18], *d++ = A[v >> 12 & 63], *d++ = A[v >> 6 & 63], *d++ = A[v & 63];
  }
  if (i < n) {
    uint32_t v = (uint32_t)p[i] << 16 | (i + 1 < n ? (uint32_t)p[i + 1] << 8 : 0);
    *d++ = A[v >> 18], *d++ = A[v >> 12 & 63];
    *d++ = i + 1 < n ? A[v >> 6 & 63] : '=';
    *d++ = '=';
  }
  *d++ = '"';
  b->len = (size_t)(d - b->s);
  b->s[b->len] = '\0';
}

/* ---------------------------------------------------------------- binary arrays */

static void put_u16(unsigned char *p, unsigned v) { p[0] = (unsigned char)v, p[1] = (unsigned char)(v >> 8); }
static void put_u32(unsigned char *p, uint32_t v) {
  for (int k = 0; k < 4; k++) p[k] = (unsigned char)(v >> 8 * k);
}
static void put_f32(unsigned char *p, double x) {
  float f = (float)x;
  uint32_t v;
  memcpy(&v, &f, 4);
  put_u32(p, v);
}

/* Rows of dim coordinates (stride apart in A, the first dim of each row taken, each scaled by s) as
 * {"dim":..,"min":[..],"scale":[..],"q":base64 of uint16}: q / 65535 of the box. */
static int vb_positions(vbuf *b, const double *A, int n, int stride, int dim, const double *s) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int i = 0; i < n; i++)
    for (int k = 0; k < dim; k++) {
      double x = A[(size_t)stride * i + k] * (s ? s[i] : 1);
      if (x < lo[k]) lo[k] = x;
      if (x > hi[k]) hi[k] = x;
    }
  unsigned char *q = malloc((size_t)2 * dim * (n > 0 ? n : 1));
  if (!q) return -1;
  double ext[3];
  for (int k = 0; k < dim; k++) ext[k] = hi[k] > lo[k] ? hi[k] - lo[k] : 1;
  for (int i = 0; i < n; i++)
    for (int k = 0; k < dim; k++) {
      double t = (A[(size_t)stride * i + k] * (s ? s[i] : 1) - lo[k]) / ext[k];
      put_u16(q + 2 * ((size_t)dim * i + k), (unsigned)lrint((t < 0 ? 0 : t > 1 ? 1 : t) * 65535));
    }
  vb_printf(b, "{\"dim\":%d,\"min\":[", dim);
  for (int k = 0; k < dim; k++) vb_printf(b, "%s%.9g", k ? "," : "", lo[k]);
  vb_printf(b, "],\"scale\":[");
  for (int k = 0; k < dim; k++) vb_printf(b, "%s%.9g", k ? "," : "", ext[k]);
  vb_printf(b, "],\"q\":");
  vb_base64(b, q, (size_t)2 * dim * n);
  vb_put(b, "}", 1);
  free(q);
  return 0;
}

static int vb_ints(vbuf *b, const int *I, size_t n) {
  unsigned char *q = malloc(4 * (n ? n : 1));
  if (!q) return -1;
  for (size_t i = 0; i < n; i++) put_u32(q + 4 * i, (uint32_t)I[i]);
  vb_base64(b, q, 4 * n);
  free(q);
  return 0;
}

/* n values, each times sign, as float32. */
static int vb_floats(vbuf *b, const double *v, size_t n, double sign) {
  unsigned char *q = malloc(4 * (n ? n : 1));
  if (!q) return -1;
  for (size_t i = 0; i < n; i++) put_f32(q + 4 * i, sign * v[i]);
  vb_base64(b, q, 4 * n);
  free(q);
  return 0;
}

/* ---------------------------------------------------------------- the map's kind */

/* A map by per-corner coordinates tiles the plane (a torus) when the copies of every vertex differ by
 * whole combinations of two independent vectors: the lattice, found as the shortest difference and
 * the shortest one not parallel to it. 1 with L set, 0 if not a torus's map, -1 out of memory. */
static int find_lattice(int nv, int nf, const int *F, int nvt, const double *vt, const int *Ft, double L[2][2]) {
  int *first = malloc((size_t)nv * sizeof *first);
  if (!first) return -1;
  double best[2][2] = {{0, 0}, {0, 0}}, len[2] = {INFINITY, INFINITY}, scale = 0;
  for (size_t i = 0; i < 2 * (size_t)nvt; i++) scale = fmax(scale, fabs(vt[i]));
  const double tiny = 1e-9 * (scale > 0 ? scale : 1);
  for (int pass = 0; pass < 3; pass++) {
    for (int i = 0; i < nv; i++) first[i] = -1;
    for (size_t c = 0; c < 3 * (size_t)nf; c++) {
      int v = F[c], t = Ft[c];
      if (first[v] < 0) {
        first[v] = t;
        continue;
      }
      double d[2] = {vt[2 * (size_t)t] - vt[2 * (size_t)first[v]], vt[2 * (size_t)t + 1] - vt[2 * (size_t)first[v] + 1]};
      double n = hypot(d[0], d[1]);
      if (n <= tiny) continue;
      if (pass == 0 && n < len[0]) len[0] = n, best[0][0] = d[0], best[0][1] = d[1];
      if (pass == 1 && n < len[1] && fabs(d[0] * best[0][1] - d[1] * best[0][0]) > 1e-3 * n * len[0])
        len[1] = n, best[1][0] = d[0], best[1][1] = d[1];
      if (pass == 2) { /* d = a L0 + b L1 with a, b whole */
        double det = best[0][0] * best[1][1] - best[0][1] * best[1][0];
        double a = (d[0] * best[1][1] - d[1] * best[1][0]) / det, b = (best[0][0] * d[1] - best[0][1] * d[0]) / det;
        if (fabs(a - rint(a)) > 1e-4 || fabs(b - rint(b)) > 1e-4) {
          free(first);
          return 0;
        }
      }
    }
    if (!isfinite(len[pass < 2 ? pass : 1])) {
      free(first);
      return 0;
    }
  }
  free(first);
  memcpy(L, best, sizeof best);
  return 1;
}

/* ---------------------------------------------------------------- the page */

au_status au_view_html(const au_view_input *in, char **html, size_t *len, au_msg *msg) {
  if (!in || !html) return au_msg_set(msg, AU_E_ARG, "au_view_html: NULL argument");
  *html = NULL;
  if (len) *len = 0;
  const int nv = in->nv, nf = in->nf;
  if (nv <= 0 || nf <= 0 || !in->X || !in->F || (!in->P) == (!in->vt) || (in->vt && (!in->Ft || in->nvt <= 0)))
    return au_msg_set(msg, AU_E_ARG, "au_view_html: needs a surface (nv, nf, X, F) and exactly one map: P, or vt with Ft and nvt");
  const int nm = in->vt ? in->nvt : nv;
  for (size_t c = 0; c < 3 * (size_t)nf; c++) {
    if (in->F[c] < 0 || in->F[c] >= nv) return au_msg_set(msg, AU_E_ARG, "au_view_html: face %zu has vertex %d, outside 0..%d", c / 3, in->F[c], nv - 1);
    if (in->vt && (in->Ft[c] < 0 || in->Ft[c] >= nm))
      return au_msg_set(msg, AU_E_ARG, "au_view_html: face %zu has vt row %d, outside 0..%d", c / 3, in->Ft[c], nm - 1);
  }
  /* A map at the vertices is planar when every z is 0, else on a sphere (of any radius: drawn unit). */
  int sphere = 0;
  double *unit = NULL;
  if (in->P)
    for (int i = 0; i < nv && !sphere; i++) sphere = in->P[3 * (size_t)i + 2] != 0;
  double L[2][2];
  int torus = in->vt ? find_lattice(nv, nf, in->F, in->nvt, in->vt, in->Ft, L) : 0;
  double *ups = malloc((size_t)nf * sizeof *ups), *lam = malloc((size_t)nf * sizeof *lam);
  if (sphere && (unit = malloc((size_t)nv * sizeof *unit)))
    for (int i = 0; i < nv; i++) {
      const double *p = in->P + 3 * (size_t)i;
      double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      unit[i] = r > 0 ? 1 / r : 0;
    }
  vbuf b = {NULL, 0, 0, 0};
  au_status st = AU_OK;
  if (torus < 0 || !ups || !lam || (sphere && !unit)) {
    st = au_msg_set(msg, AU_E_NOMEM, "au_view_html: out of memory");
    goto done;
  }
  au_metrics m;
  if (in->vt) {
    st = au__metrics_vt(nv, nf, in->X, in->F, in->nvt, in->vt, in->Ft, &m, ups, lam);
  } else {
    double *Pu = malloc((size_t)3 * nv * sizeof *Pu);
    if (!Pu) {
      st = au_msg_set(msg, AU_E_NOMEM, "au_view_html: out of memory");
      goto done;
    }
    for (size_t i = 0; i < 3 * (size_t)nv; i++) Pu[i] = in->P[i] * (sphere ? unit[i / 3] : 1);
    st = au_metrics_compute(nv, nf, in->X, Pu, in->F, sphere ? AU_DOMAIN_SPHERE : AU_DOMAIN_PLANE, &m, ups, lam);
    free(Pu);
  }
  if (st != AU_OK) {
    au_msg_set(msg, st, "au_view_html: the map's distortion cannot be measured (%s)", au_status_str(st));
    goto done;
  }
  vb_put(&b, au__view_head, au__view_head_len);
  vb_printf(&b, "{\"v\":1,\"title\":");
  vb_json_string(&b, in->title ? in->title : "");
  vb_printf(&b, ",\"nv\":%d,\"nf\":%d,\"kind\":\"%s\",\"lattice\":", nv, nf, sphere ? "sphere" : torus ? "torus" : "plane");
  if (torus) vb_printf(&b, "[[%.17g,%.17g],[%.17g,%.17g]]", L[0][0], L[0][1], L[1][0], L[1][1]);
  else vb_printf(&b, "null");
  vb_printf(&b, ",\n\"stats\":{\"folds\":%d,\"per_face\":%.17g,\"vertex\":%.17g,\"excluded\":%d,\"steps\":%d,\"seconds\":%.6g},",
            m.folds, m.r_mean_abs_dev, m.vertex_logr_mean_abs, m.excluded, in->steps, in->seconds);
  vb_printf(&b, "\n\"X\":");
  int bad = vb_positions(&b, in->X, nv, 3, 3, NULL);
  vb_printf(&b, ",\n\"M\":");
  if (!bad) bad = in->vt ? vb_positions(&b, in->vt, nm, 2, 2, NULL) : vb_positions(&b, in->P, nv, 3, sphere ? 3 : 2, unit);
  vb_printf(&b, ",\n\"F\":");
  if (!bad) bad = vb_ints(&b, in->F, 3 * (size_t)nf);
  vb_printf(&b, ",\n\"Ft\":");
  if (!bad && in->vt) bad = vb_ints(&b, in->Ft, 3 * (size_t)nf);
  else vb_printf(&b, "null");
  /* log r = ln(domain share / surface share) = -Upsilon: negative where the map squeezes. */
  vb_printf(&b, ",\n\"logr\":");
  if (!bad) bad = vb_floats(&b, ups, (size_t)nf, -1);
  vb_printf(&b, ",\n\"lam\":");
  if (!bad) bad = vb_floats(&b, lam, (size_t)nf, 1);
  vb_printf(&b, ",\n\"attr\":");
  if (in->attr) {
    vb_printf(&b, "{\"name\":");
    vb_json_string(&b, in->attr_name ? in->attr_name : "attribute");
    vb_printf(&b, ",\"v\":");
    if (!bad) bad = vb_floats(&b, in->attr, (size_t)nv, 1);
    vb_printf(&b, "}");
  } else {
    vb_printf(&b, "null");
  }
  vb_printf(&b, "}");
  vb_put(&b, au__view_tail, au__view_tail_len);
  if (bad || b.bad) {
    st = au_msg_set(msg, AU_E_NOMEM, "au_view_html: out of memory");
    goto done;
  }
  *html = b.s, b.s = NULL;
  if (len) *len = b.len;
done:
  free(b.s), free(ups), free(lam), free(unit);
  return st;
}

au_status au_view_write(const char *path, const au_view_input *in, au_msg *msg) {
  if (!path) return au_msg_set(msg, AU_E_ARG, "au_view_write: NULL path");
  char *html = NULL;
  size_t n = 0;
  au_status st = au_view_html(in, &html, &n, msg);
  if (st == AU_OK) st = au_write_text(path, html, n, msg);
  free(html);
  return st;
}
