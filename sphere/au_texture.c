/* au_texture.c - equal-area texture layouts of the sphere, per-corner texture coordinates with seam
 * and pole handling, the OBJ writer for them, texel location, baking/sampling helpers, the surface
 * area of equal-area grid cells, and the small file formats (.npy, per-vertex scalars).
 *
 * Projections come from GeographicLib through au_geo.h (Lambert cylindrical and azimuthal
 * equal-area are AlbersEqualArea on the unit sphere with stdlat 0 and +-90). */

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "au_geo.h"
#include "au_io.h"
#include "au_texture.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define DEG (180.0 / M_PI)
#define SQRT2 1.4142135623730951

/* The Lambert charts reach this much past the farthest corner of their faces, so that no corner lies on
 * the chart's edge (where a texel's bilinear lookup would read the next chart). */
#define AU_LAEA_MARGIN 1.02

/* Rounds of splitting flipped faces in the cylindrical layout: each halves the offending arcs, and
 * the shared meshes need at most a few. */
#define AU_FLIP_ROUNDS 8

au_tex_layout au_tex_layout_default(au_tex_proj proj) {
  au_tex_layout l;
  l.proj = proj;
  l.half = proj == AU_TEX_LAEA ? 1.5 : 0.0;
  return l;
}

static int layout_ok(const au_tex_layout *lay) {
  if (!lay) return 0;
  if (lay->proj == AU_TEX_CEA) return 1;
  return lay->proj == AU_TEX_LAEA && lay->half >= SQRT2 - 1e-12 && lay->half <= 2.0 + 1e-12;
}

static void unit_from_latlon(double lat_deg, double lon_deg, double *p) {
  double la = lat_deg / DEG, lo = lon_deg / DEG;
  double c = cos(la);
  p[0] = c * cos(lo);
  p[1] = c * sin(lo);
  p[2] = sin(la);
}

/* lat, lon in degrees of a nonzero vector (normalized first); lon = 0 on the axis. */
static void latlon_of(const double *q, double *lat, double *lon) {
  double r = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  double x = q[0] / r, y = q[1] / r, z = q[2] / r;
  double h = hypot(x, y);
  *lat = atan2(z, h) * DEG;
  *lon = (x == 0 && y == 0) ? 0.0 : atan2(y, x) * DEG;
}

au_status au_tex_lonlat(int n, const double *p, double *lonlat) {
  if (n < 0 || (n > 0 && (!p || !lonlat))) return AU_E_ARG;
  for (int i = 0; i < n; i++) {
    const double *q = p + 3 * (size_t)i;
    if (!(q[0] != 0 || q[1] != 0 || q[2] != 0)) return AU_E_ARG;
    latlon_of(q, &lonlat[2 * i + 1], &lonlat[2 * i]);
  }
  return AU_OK;
}

au_status au_tex_to_sphere(const au_tex_layout *lay, int n, const double *uv, double *p, unsigned char *valid,
                           au_msg *msg) {
  if (!layout_ok(lay) || n < 0 || (n > 0 && (!uv || !p))) return au_msg_set(msg, AU_E_ARG, "au_tex_to_sphere: bad arguments");
  if (n == 0) return AU_OK;
  double *buf = malloc(4 * (size_t)n * sizeof *buf);
  int *idx = malloc((size_t)n * sizeof *idx);
  signed char *chart = malloc((size_t)n);
  if (!buf || !idx || !chart) {
    free(buf), free(idx), free(chart);
    return au_msg_set(msg, AU_E_NOMEM, "au_tex_to_sphere: out of memory");
  }
  double *x = buf, *y = buf + n, *lat = buf + 2 * (size_t)n, *lon = buf + 3 * (size_t)n;
  /* The chart of every point (0: cea or northern, 1: southern, -1: no point) and its projection
   * coordinates. */
  for (int i = 0; i < n; i++) {
    double u = uv[2 * i], v = uv[2 * i + 1];
    chart[i] = -1;
    if (!(isfinite(u) && isfinite(v) && v >= 0 && v <= 1)) continue;
    if (lay->proj == AU_TEX_CEA) {
      u -= floor(u);
      x[i] = 2 * M_PI * u - M_PI, y[i] = 2 * v - 1;
      chart[i] = 0;
    } else if (u >= 0 && u <= 1) {
      int south = u >= 0.5;
      double uu = south ? u - 0.5 : u;
      x[i] = (4 * uu - 1) * lay->half, y[i] = (2 * v - 1) * lay->half;
      if (x[i] * x[i] + y[i] * y[i] <= 4.0) chart[i] = (signed char)south;
    }
  }
  au_status st = AU_OK;
  for (int pass = 0; pass < 2 && st == AU_OK; pass++) {
    int m = 0;
    for (int i = 0; i < n; i++)
      if (chart[i] == pass) idx[m++] = i;
    if (m == 0) continue;
    /* Gather in place: idx is increasing, so slot j <= idx[j] is never read again. */
    for (int j = 0; j < m; j++) x[j] = x[idx[j]], y[j] = y[idx[j]];
    au_geo_aea kind = lay->proj == AU_TEX_CEA ? AU_GEO_CEA : pass == 0 ? AU_GEO_LAEA_NORTH : AU_GEO_LAEA_SOUTH;
    st = au_geo_aea_inverse(kind, m, x, y, lat, lon, msg);
    for (int j = 0; j < m && st == AU_OK; j++) unit_from_latlon(lat[j], lon[j], p + 3 * (size_t)idx[j]);
    if (pass == 0 && st == AU_OK) {
      /* x, y were overwritten by the gather: recompute the southern points' coordinates. */
      for (int i = 0; i < n; i++) {
        if (chart[i] != 1) continue;
        double uu = uv[2 * i] - 0.5, v = uv[2 * i + 1];
        x[i] = (4 * uu - 1) * lay->half, y[i] = (2 * v - 1) * lay->half;
      }
    }
  }
  for (int i = 0; i < n; i++) {
    if (chart[i] < 0) p[3 * i] = p[3 * i + 1] = p[3 * i + 2] = 0;
    if (valid) valid[i] = chart[i] >= 0;
  }
  free(buf), free(idx), free(chart);
  return st;
}

/* uv of n points (lat, lon in degrees) in chart `kind` of the layout. */
static void chart_uv(const au_tex_layout *lay, au_geo_aea kind, double x, double y, double *uv) {
  if (kind == AU_GEO_CEA) {
    uv[0] = (x + M_PI) / (2 * M_PI);
    uv[1] = (y + 1) / 2;
  } else {
    uv[0] = (x / lay->half + 1) / 4 + (kind == AU_GEO_LAEA_SOUTH ? 0.5 : 0.0);
    uv[1] = (y / lay->half + 1) / 2;
  }
}

au_status au_tex_from_sphere(const au_tex_layout *lay, int n, const double *p, double *uv, au_msg *msg) {
  if (!layout_ok(lay) || n < 0 || (n > 0 && (!uv || !p))) return au_msg_set(msg, AU_E_ARG, "au_tex_from_sphere: bad arguments");
  if (n == 0) return AU_OK;
  double *buf = malloc(4 * (size_t)n * sizeof *buf);
  if (!buf) return au_msg_set(msg, AU_E_NOMEM, "au_tex_from_sphere: out of memory");
  double *lat = buf, *lon = buf + n, *x = buf + 2 * (size_t)n, *y = buf + 3 * (size_t)n;
  au_status st = AU_OK;
  for (int i = 0; i < n && st == AU_OK; i++) {
    const double *q = p + 3 * (size_t)i;
    if (!(isfinite(q[0]) && isfinite(q[1]) && isfinite(q[2])) || (q[0] == 0 && q[1] == 0 && q[2] == 0))
      st = au_msg_set(msg, AU_E_ARG, "au_tex_from_sphere: point %d is zero or not finite", i);
    else
      latlon_of(q, &lat[i], &lon[i]);
  }
  if (st == AU_OK && lay->proj == AU_TEX_CEA) {
    st = au_geo_aea_forward(AU_GEO_CEA, n, lat, lon, x, y, msg);
    for (int i = 0; i < n && st == AU_OK; i++) chart_uv(lay, AU_GEO_CEA, x[i], y[i], uv + 2 * i);
  } else if (st == AU_OK) {
    /* Both charts for every point (two batches), then each point takes its own hemisphere's. */
    double *xs = malloc(2 * (size_t)n * sizeof *xs);
    if (!xs) st = au_msg_set(msg, AU_E_NOMEM, "au_tex_from_sphere: out of memory");
    if (st == AU_OK) st = au_geo_aea_forward(AU_GEO_LAEA_NORTH, n, lat, lon, x, y, msg);
    if (st == AU_OK) st = au_geo_aea_forward(AU_GEO_LAEA_SOUTH, n, lat, lon, xs, xs + n, msg);
    for (int i = 0; i < n && st == AU_OK; i++) {
      if (lat[i] >= 0) chart_uv(lay, AU_GEO_LAEA_NORTH, x[i], y[i], uv + 2 * i);
      else chart_uv(lay, AU_GEO_LAEA_SOUTH, xs[i], xs[n + i], uv + 2 * i);
    }
    free(xs);
  }
  free(buf);
  return st;
}

/* ---------------------------------------------------------------- texture coordinates */

void au_tex_mesh_free(au_tex_mesh **t) {
  if (!t || !*t) return;
  free((*t)->X);
  free((*t)->P);
  free((*t)->F);
  free((*t)->src_face);
  free((*t)->vt);
  free((*t)->Ft);
  free((*t)->lonlat);
  free(*t);
  *t = NULL;
}

/* Split the face containing the pole (0, 0, sz) of the cea layout, unless the pole is one of its
 * corners. Adds a vertex and two faces to t (room reserved by the caller). */
static au_status split_pole(au_tex_mesh *t, const au_locator *loc, double sz, unsigned char *is_pole, au_msg *msg) {
  double pole[3] = {0, 0, sz}, b[3];
  int f = au_locator_find(loc, pole, NULL, b);
  if (f < 0) return au_msg_set(msg, AU_E_FOLD, "the %s pole lies in no triangle of the map (the map does not cover the sphere)",
                               sz > 0 ? "north" : "south");
  int *c = t->F + 3 * (size_t)f;
  for (int k = 0; k < 3; k++) {
    double *q = t->P + 3 * (size_t)c[k];
    /* A corner on the pole, or within 1e-9 of it (snapped there: splitting would leave a sliver
     * whose coordinates are all rounding). */
    if ((q[0] == 0 && q[1] == 0) || b[k] > 1 - 1e-9) {
      q[0] = 0, q[1] = 0, q[2] = sz;
      is_pole[c[k]] = 1;
      return AU_OK;
    }
  }
  int v = t->nv++;
  for (int j = 0; j < 3; j++) {
    t->X[3 * v + j] = b[0] * t->X[3 * c[0] + j] + b[1] * t->X[3 * c[1] + j] + b[2] * t->X[3 * c[2] + j];
    t->P[3 * v + j] = pole[j];
  }
  is_pole[v] = 1;
  int a0 = c[0], a1 = c[1], a2 = c[2];
  int g1 = t->nf++, g2 = t->nf++;
  c[0] = a0, c[1] = a1, c[2] = v;
  t->F[3 * g1] = a1, t->F[3 * g1 + 1] = a2, t->F[3 * g1 + 2] = v;
  t->F[3 * g2] = a2, t->F[3 * g2 + 1] = a0, t->F[3 * g2 + 2] = v;
  t->src_face[g1] = t->src_face[g2] = t->src_face[f];
  t->pole_splits++;
  return AU_OK;
}

/* (u, v) of the cea layout up to its affine chart, straight from the unit vector p: u follows the
 * longitude, v = (1 + z) / 2. Enough for orientation tests (the chart scales both positively). */
static void cea_raw(const double *p, double *u, double *v) {
  *u = atan2(p[1], p[0]) / (2 * M_PI);
  *v = 0.5 * (1 + p[2]);
}

/* 1 if face f, drawn with straight edges in the cea layout (longitudes unwrapped around its first
 * corner), is not positively oriented. Faces with a pole corner are drawn differently (the pole
 * takes the middle of the others' u) and are left alone. */
static int cea_flipped(const au_tex_mesh *t, const unsigned char *is_pole, int f) {
  const int *c = t->F + 3 * (size_t)f;
  double u[3], v[3];
  for (int k = 0; k < 3; k++) {
    if (is_pole[c[k]]) return 0;
    cea_raw(t->P + 3 * (size_t)c[k], &u[k], &v[k]);
    if (k > 0) u[k] = u[0] + (u[k] - u[0] - nearbyint(u[k] - u[0]));
  }
  return (u[1] - u[0]) * (v[2] - v[0]) - (u[2] - u[0]) * (v[1] - v[0]) <= 0;
}

/* Room for at least nv vertices and nf faces in the arrays the splits grow. */
static int tex_reserve(au_tex_mesh *t, unsigned char **is_pole, int *nvcap, int *nfcap, int nv, int nf) {
  if (nv > *nvcap) {
    int cap = nv + nv / 2 + 16;
    double *X = realloc(t->X, 3 * (size_t)cap * sizeof *X);
    if (X) t->X = X;
    double *P = realloc(t->P, 3 * (size_t)cap * sizeof *P);
    if (P) t->P = P;
    unsigned char *ip = realloc(*is_pole, (size_t)cap);
    if (ip) *is_pole = ip;
    if (!X || !P || !ip) return 0;
    memset(*is_pole + *nvcap, 0, (size_t)(cap - *nvcap));
    *nvcap = cap;
  }
  if (nf > *nfcap) {
    int cap = nf + nf / 2 + 16;
    int *F = realloc(t->F, 3 * (size_t)cap * sizeof *F);
    if (F) t->F = F;
    int *src = realloc(t->src_face, (size_t)cap * sizeof *src);
    if (src) t->src_face = src;
    if (!F || !src) return 0;
    *nfcap = cap;
  }
  return 1;
}

/* Split the edge (a, b) at its midpoint (on the surface: the middle of the straight edge; on the
 * sphere: the normalized middle of the chord, which is where the map sends that surface point),
 * and each face on it into two with the same orientation. Room for one vertex and two faces must
 * be reserved. Returns 0 if the edge is not in the mesh. */
static int split_edge(au_tex_mesh *t, int a, int b) {
  int m = t->nv, found = 0;
  for (int f = 0, nf = t->nf; f < nf; f++) {
    int *c = t->F + 3 * (size_t)f;
    for (int k = 0; k < 3; k++) {
      int p = c[k], q = c[(k + 1) % 3], r = c[(k + 2) % 3];
      if (!((p == a && q == b) || (p == b && q == a))) continue;
      if (!found) {
        double s = 0, *P = t->P + 3 * (size_t)m;
        for (int j = 0; j < 3; j++) {
          t->X[3 * (size_t)m + j] = 0.5 * (t->X[3 * (size_t)a + j] + t->X[3 * (size_t)b + j]);
          P[j] = t->P[3 * (size_t)a + j] + t->P[3 * (size_t)b + j];
          s += P[j] * P[j];
        }
        s = sqrt(s);
        if (!(s > 0)) return 0;
        for (int j = 0; j < 3; j++) P[j] /= s;
        t->nv++;
        found = 1;
      }
      int g = t->nf++;
      c[0] = p, c[1] = m, c[2] = r;
      t->F[3 * (size_t)g] = m, t->F[3 * (size_t)g + 1] = q, t->F[3 * (size_t)g + 2] = r;
      t->src_face[g] = t->src_face[f];
      break;
    }
  }
  return found;
}

/* Split until no face is flipped in the cea layout, at most `rounds` times: each flipped face's
 * longest edge (on the sphere) is split with its neighbour, so every arc of the face gets shorter
 * and bends less in the projection. A flip happens where a triangle's middle corner lies between a
 * long edge's great circle and the straight line of its image: slivers, and ordinary triangles
 * near a pole. */
static au_status split_flipped(au_tex_mesh *t, unsigned char **is_pole, int *nvcap, int *nfcap, int rounds,
                               au_msg *msg) {
  int *edges = NULL, ne = 0, cap = 0;
  au_status st = AU_OK;
  for (int round = 0; round < rounds; round++) {
    ne = 0;
    for (int f = 0; f < t->nf; f++) {
      if (!cea_flipped(t, *is_pole, f)) continue;
      const int *c = t->F + 3 * (size_t)f;
      int best = 0;
      double lmax = -1;
      for (int k = 0; k < 3; k++) {
        const double *p = t->P + 3 * (size_t)c[k], *q = t->P + 3 * (size_t)c[(k + 1) % 3];
        double l = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
        if (l > lmax) lmax = l, best = k;
      }
      if (ne == cap) {
        cap = 2 * cap + 16;
        int *e = realloc(edges, 2 * (size_t)cap * sizeof *e);
        if (!e) {
          st = au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
          goto done;
        }
        edges = e;
      }
      edges[2 * ne] = c[best], edges[2 * ne + 1] = c[(best + 1) % 3];
      ne++;
    }
    if (ne == 0) break;
    for (int i = 0; i < ne; i++) {
      if (!tex_reserve(t, is_pole, nvcap, nfcap, t->nv + 1, t->nf + 2)) {
        st = au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
        goto done;
      }
      /* An edge named twice (both its faces flipped) is split once: the second time it is gone. */
      t->edge_splits += split_edge(t, edges[2 * i], edges[2 * i + 1]);
    }
  }
done:
  free(edges);
  return st;
}

/* Cylindrical equal-area texture coordinates of t's faces from the projected x, y [0..nv-1]: each face's
 * longitudes unwrapped around its first non-pole corner, one copy of a corner per side of the seam (key
 * [0..3nv-1], -1 on entry), a copy of its own per face at a pole. Returns AU_OK or AU_E_NUMERIC. */
static au_status cea_faces(au_tex_mesh *t, const unsigned char *is_pole, const double *x, const double *y, int *key,
                           au_msg *msg) {
  for (int f = 0; f < t->nf; f++) {
    const int *c = t->F + 3 * (size_t)f;
    double u[3], v[3], uraw[3];
    int ref = -1;
    for (int k = 0; k < 3; k++) {
      double uv[2];
      chart_uv(&t->layout, AU_GEO_CEA, x[c[k]], y[c[k]], uv);
      uraw[k] = u[k] = uv[0], v[k] = uv[1];
      if (!is_pole[c[k]] && ref < 0) ref = k;
    }
    /* Unwrap the longitudes of the corners around the first non-pole corner, so the face's
     * corners are within half a turn of each other; pole corners take the middle of the others. */
    double usum = 0;
    int nreg = 0;
    for (int k = 0; k < 3; k++) {
      if (is_pole[c[k]]) continue;
      double d = u[k] - u[ref];
      u[k] = u[ref] + (d - nearbyint(d));
      usum += u[k], nreg++;
    }
    double umid = nreg ? usum / nreg : 0.5;
    for (int k = 0; k < 3; k++)
      if (is_pole[c[k]]) u[k] = umid, v[k] = t->P[3 * c[k] + 2] > 0 ? 1.0 : 0.0;
    double shift = floor((u[0] + u[1] + u[2]) / 3);
    int seam = 0;
    for (int k = 0; k < 3; k++) {
      u[k] -= shift;
      int vt;
      if (is_pole[c[k]]) {
        vt = t->nvt++;
      } else {
        int s = (int)nearbyint(u[k] - uraw[k]);
        if (s != 0) seam = 1;
        if (s < -1 || s > 1) return au_msg_set(msg, AU_E_NUMERIC, "au_tex_coords: face %d spans more than a turn", f);
        int *slot = &key[3 * (size_t)c[k] + (s + 1)];
        if (*slot < 0) *slot = t->nvt++;
        vt = *slot;
      }
      t->vt[2 * vt] = u[k], t->vt[2 * vt + 1] = v[k];
      t->Ft[3 * f + k] = vt;
    }
    t->seam_faces += seam;
  }
  return AU_OK;
}

/* Lambert azimuthal equal-area texture coordinates: each face in the chart of the hemisphere holding
 * the sum of its corners, one copy of a corner per chart (key [0..3nv-1], -1 on entry); lat, lon
 * [0..nv-1], x, y scratch [0..nv-1]. Returns AU_OK, AU_E_NOMEM or a projection's error. */
static au_status laea_faces(au_tex_mesh *t, const double *lat, const double *lon, double *x, double *y, int *key,
                            au_msg *msg) {
  const int NV = t->nv;
  au_status st = AU_OK;
  unsigned char *hemi = malloc((size_t)t->nf);
  double *xs = malloc(2 * (size_t)NV * sizeof *xs);
  if (!hemi || !xs) {
    free(hemi), free(xs);
    return au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
  }
  double *ys = xs + NV;
  st = au_geo_aea_forward(AU_GEO_LAEA_NORTH, NV, lat, lon, x, y, msg);
  if (st == AU_OK) st = au_geo_aea_forward(AU_GEO_LAEA_SOUTH, NV, lat, lon, xs, ys, msg);
  double need = SQRT2;
  for (int f = 0; f < t->nf && st == AU_OK; f++) {
    const int *c = t->F + 3 * (size_t)f;
    double zs = t->P[3 * c[0] + 2] + t->P[3 * c[1] + 2] + t->P[3 * c[2] + 2];
    hemi[f] = zs < 0;
    for (int k = 0; k < 3; k++) {
      double xx = hemi[f] ? xs[c[k]] : x[c[k]], yy = hemi[f] ? ys[c[k]] : y[c[k]];
      need = fmax(need, fmax(fabs(xx), fabs(yy)));
    }
  }
  t->layout.half = fmin(2.0, need * AU_LAEA_MARGIN);
  for (int f = 0; f < t->nf && st == AU_OK; f++) {
    const int *c = t->F + 3 * (size_t)f;
    for (int k = 0; k < 3; k++) {
      int *slot = &key[3 * (size_t)c[k] + hemi[f]];
      if (*slot < 0) {
        *slot = t->nvt++;
        au_geo_aea kind = hemi[f] ? AU_GEO_LAEA_SOUTH : AU_GEO_LAEA_NORTH;
        chart_uv(&t->layout, kind, hemi[f] ? xs[c[k]] : x[c[k]], hemi[f] ? ys[c[k]] : y[c[k]], t->vt + 2 * (size_t)*slot);
      }
      t->Ft[3 * f + k] = *slot;
    }
    if (hemi[f]) t->seam_faces++;
  }
  /* For laea seam_faces counts the faces in the southern chart; report the ones whose corners
   * straddle the equator instead, which is what the name promises. */
  int straddle = 0;
  for (int f = 0; f < t->nf; f++) {
    const int *c = t->F + 3 * (size_t)f;
    int np = 0;
    for (int k = 0; k < 3; k++) np += t->P[3 * c[k] + 2] >= 0;
    straddle += np > 0 && np < 3;
  }
  t->seam_faces = straddle;
  free(hemi), free(xs);
  return st;
}

au_status au_tex_coords(const au_mesh *m, const double *P, au_tex_proj proj, au_tex_mesh **out, au_msg *msg) {
  if (!out) return au_msg_set(msg, AU_E_ARG, "au_tex_coords: out is NULL");
  *out = NULL;
  if (!m || !P || m->nv < 3 || m->nf < 1 || !m->X || !m->F || (proj != AU_TEX_CEA && proj != AU_TEX_LAEA))
    return au_msg_set(msg, AU_E_ARG, "au_tex_coords: bad arguments");
  int nv = m->nv, nf = m->nf;
  for (long i = 0; i < 3L * nf; i++)
    if (m->F[i] < 0 || m->F[i] >= nv) return au_msg_set(msg, AU_E_ARG, "au_tex_coords: face index out of range");
  au_status st = AU_OK;
  au_tex_mesh *t = calloc(1, sizeof *t);
  au_locator *loc = NULL;
  unsigned char *is_pole = NULL;
  int *key = NULL;
  double *buf = NULL;
  if (!t) return au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
  /* Room for the pole splits; the flip splits grow it (tex_reserve). */
  int nvmax = nv + 2, nfmax = nf + 4;
  t->X = malloc(3 * (size_t)nvmax * sizeof *t->X);
  t->P = malloc(3 * (size_t)nvmax * sizeof *t->P);
  t->F = malloc(3 * (size_t)nfmax * sizeof *t->F);
  t->src_face = malloc((size_t)nfmax * sizeof *t->src_face);
  is_pole = calloc((size_t)nvmax, 1);
  if (!t->X || !t->P || !t->F || !t->src_face || !is_pole) {
    st = au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
    goto done;
  }
  t->nv = t->nv_in = nv, t->nf = t->nf_in = nf;
  memcpy(t->X, m->X, 3 * (size_t)nv * sizeof *t->X);
  memcpy(t->F, m->F, 3 * (size_t)nf * sizeof *t->F);
  for (int f = 0; f < nf; f++) t->src_face[f] = f;
  for (int i = 0; i < nv; i++) {
    const double *q = P + 3 * (size_t)i;
    double r = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    if (!(r > 0) || !isfinite(r)) {
      st = au_msg_set(msg, AU_E_ARG, "vertex %d of the sphere map is zero or not finite", i);
      goto done;
    }
    for (int j = 0; j < 3; j++) t->P[3 * i + j] = q[j] / r;
  }
  t->layout = au_tex_layout_default(proj);

  if (proj == AU_TEX_CEA) {
    /* Poles: locate both before splitting either (the locator holds the input faces). */
    st = au_locator_build(nv, t->P, nf, t->F, &loc, msg);
    if (st != AU_OK) goto done;
    for (int i = 0; i < nv; i++)
      if (t->P[3 * i] == 0 && t->P[3 * i + 1] == 0) is_pole[i] = 1;
    st = split_pole(t, loc, 1.0, is_pole, msg);
    if (st == AU_OK) st = split_pole(t, loc, -1.0, is_pole, msg);
    if (st != AU_OK) goto done;
    t->pole_vertices = 0;
    for (int i = 0; i < t->nv_in; i++) t->pole_vertices += is_pole[i];
    st = split_flipped(t, &is_pole, &nvmax, &nfmax, AU_FLIP_ROUNDS, msg);
    if (st != AU_OK) goto done;
  }
  int NV = t->nv;
  t->Ft = malloc(3 * (size_t)t->nf * sizeof *t->Ft);
  t->vt = malloc(2 * (3 * (size_t)t->nf) * sizeof *t->vt);
  t->lonlat = malloc(2 * (size_t)NV * sizeof *t->lonlat);
  key = malloc(3 * (size_t)NV * sizeof *key);
  buf = malloc(4 * (size_t)NV * sizeof *buf);
  if (!t->Ft || !t->vt || !t->lonlat || !key || !buf) {
    st = au_msg_set(msg, AU_E_NOMEM, "au_tex_coords: out of memory");
    goto done;
  }
  st = au_tex_lonlat(NV, t->P, t->lonlat);
  if (st != AU_OK) {
    au_msg_set(msg, st, "au_tex_coords: bad sphere positions");
    goto done;
  }
  double *lat = buf, *lon = buf + NV, *x = buf + 2 * (size_t)NV, *y = buf + 3 * (size_t)NV;
  for (int i = 0; i < NV; i++) lon[i] = t->lonlat[2 * i], lat[i] = t->lonlat[2 * i + 1];
  for (int i = 0; i < 3 * NV; i++) key[i] = -1;
  t->nvt = 0;

  if (proj == AU_TEX_CEA) {
    st = au_geo_aea_forward(AU_GEO_CEA, NV, lat, lon, x, y, msg);
    if (st != AU_OK) goto done;
    st = cea_faces(t, is_pole, x, y, key, msg);
    if (st != AU_OK) goto done;
  } else {
    /* Each face goes to the chart of the hemisphere holding the sum of its corners; the charts
     * reach past the equator far enough for every face. */
    st = laea_faces(t, lat, lon, x, y, key, msg);
    if (st != AU_OK) goto done;
  }
  *out = t;
  t = NULL;
done:
  au_tex_mesh_free(&t);
  au_locator_free(&loc);
  free(is_pole);
  free(key);
  free(buf);
  return st;
}

au_status au_tex_write_obj(const char *path, const au_tex_mesh *t, const char *mtl_name, au_msg *msg) {
  if (!path || !t || !t->X || !t->F || !t->vt || !t->Ft) return au_msg_set(msg, AU_E_ARG, "au_tex_write_obj: bad arguments");
  au_textbuf b = {0};
  if (t->layout.proj == AU_TEX_CEA)
    au_textbuf_printf(&b, "# authalic texture: Lambert cylindrical equal-area (cea) coordinates of a sphere map\n"
                  "# u = (lon + pi)/(2 pi), v = (sin lat + 1)/2; %d faces across the seam have u outside [0, 1]:\n"
                  "# sample the texture with u wrapped (repeat). %d face(s) split at a pole, %d edge(s) split where\n"
                  "# a face would flip in (u, v): vertices %d.. and faces %d.. added.\n",
              t->seam_faces, t->pole_splits, t->edge_splits, t->nv_in + 1, t->nf_in + 1);
  else
    au_textbuf_printf(&b, "# authalic texture: Lambert azimuthal equal-area (laea) coordinates of a sphere map\n"
                  "# northern hemisphere in the left half, southern in the right half, chart half side %.17g\n",
              t->layout.half);
  if (mtl_name) au_textbuf_printf(&b, "mtllib %s\n", mtl_name);
  for (int i = 0; i < t->nv; i++) au_textbuf_printf(&b, "v %.17g %.17g %.17g\n", t->X[3 * i], t->X[3 * i + 1], t->X[3 * i + 2]);
  for (int i = 0; i < t->nvt; i++) au_textbuf_printf(&b, "vt %.17g %.17g\n", t->vt[2 * i], t->vt[2 * i + 1]);
  if (mtl_name) au_textbuf_printf(&b, "usemtl authalic\n");
  for (int f = 0; f < t->nf; f++)
    au_textbuf_printf(&b, "f %d/%d %d/%d %d/%d\n", t->F[3 * f] + 1, t->Ft[3 * f] + 1, t->F[3 * f + 1] + 1, t->Ft[3 * f + 1] + 1,
              t->F[3 * f + 2] + 1, t->Ft[3 * f + 2] + 1);
  au_status st = b.bad ? au_msg_set(msg, AU_E_NOMEM, "out of memory writing '%s'", path)
                       : au_io_write_text(path, b.s, b.len, msg);
  au_textbuf_free(&b);
  return st;
}

/* ---------------------------------------------------------------- texels, interpolation */

au_status au_tex_locate_texels(const au_tex_layout *lay, const au_locator *loc, int W, int H, int *face,
                               double *bary, au_msg *msg) {
  if (!layout_ok(lay) || !loc || W < 1 || H < 1 || !face || (long)W * H > 400000000L)
    return au_msg_set(msg, AU_E_ARG, "au_tex_locate_texels: bad arguments");
  double *uv = malloc(2 * (size_t)W * sizeof *uv), *p = malloc(3 * (size_t)W * sizeof *p);
  unsigned char *valid = malloc((size_t)W);
  if (!uv || !p || !valid) {
    free(uv), free(p), free(valid);
    return au_msg_set(msg, AU_E_NOMEM, "au_tex_locate_texels: out of memory");
  }
  au_status st = AU_OK;
  int hint = -1;
  for (int r = 0; r < H && st == AU_OK; r++) {
    for (int c = 0; c < W; c++) uv[2 * c] = (c + 0.5) / W, uv[2 * c + 1] = 1 - (r + 0.5) / H;
    st = au_tex_to_sphere(lay, W, uv, p, valid, msg);
    for (int c = 0; c < W && st == AU_OK; c++) {
      size_t i = (size_t)r * W + c;
      double b[3] = {0, 0, 0};
      face[i] = valid[c] ? au_locator_find(loc, p + 3 * c, &hint, b) : -1;
      if (bary) bary[3 * i] = b[0], bary[3 * i + 1] = b[1], bary[3 * i + 2] = b[2];
    }
  }
  free(uv), free(p), free(valid);
  return st;
}

au_status au_tex_interpolate(int n, const int *face, const double *bary, const int *F, int k, const double *A,
                             double *out) {
  if (n < 0 || k < 1 || (n > 0 && (!face || !bary || !F || !A || !out))) return AU_E_ARG;
  for (int i = 0; i < n; i++) {
    double *o = out + (size_t)i * k;
    if (face[i] < 0) {
      for (int j = 0; j < k; j++) o[j] = NAN;
      continue;
    }
    const int *c = F + 3 * (size_t)face[i];
    const double *b = bary + 3 * (size_t)i;
    for (int j = 0; j < k; j++)
      o[j] = b[0] * A[(size_t)c[0] * k + j] + b[1] * A[(size_t)c[1] * k + j] + b[2] * A[(size_t)c[2] * k + j];
  }
  return AU_OK;
}

au_status au_tex_vertex_normals(const au_mesh *m, double *N) {
  if (!m || !N || !m->X || !m->F || m->nv < 1) return AU_E_ARG;
  memset(N, 0, 3 * (size_t)m->nv * sizeof *N);
  for (int f = 0; f < m->nf; f++) {
    const int *c = m->F + 3 * (size_t)f;
    const double *a = m->X + 3 * c[0], *b = m->X + 3 * c[1], *d = m->X + 3 * c[2];
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    for (int k = 0; k < 3; k++)
      for (int j = 0; j < 3; j++) N[3 * c[k] + j] += n[j];
  }
  for (int i = 0; i < m->nv; i++) {
    double *n = N + 3 * (size_t)i;
    double r = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (r > 0) n[0] /= r, n[1] /= r, n[2] /= r;
  }
  return AU_OK;
}

au_status au_tex_cell_areas(const au_mesh *m, const double *P, const au_locator *loc, int W, int H, int sub,
                            double *area, au_msg *msg) {
  if (!m || !P || !loc || !area || W < 1 || H < 1 || sub < 1 || sub > 64 || (long)W * sub > 100000000L)
    return au_msg_set(msg, AU_E_ARG, "au_tex_cell_areas: bad arguments");
  int nf = m->nf;
  double *dens = malloc(5 * (size_t)nf * sizeof *dens); /* per face: density factor, normal (3), h */
  double *uv = malloc(2 * (size_t)W * sub * sizeof *uv), *p = malloc(3 * (size_t)W * sub * sizeof *p);
  if (!dens || !uv || !p) {
    free(dens), free(uv), free(p);
    return au_msg_set(msg, AU_E_NOMEM, "au_tex_cell_areas: out of memory");
  }
  double total = 0;
  for (int f = 0; f < nf; f++) {
    const int *c = m->F + 3 * (size_t)f;
    const double *a = m->X + 3 * c[0], *b = m->X + 3 * c[1], *d = m->X + 3 * c[2];
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double As = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    total += As;
    const double *pa = P + 3 * c[0], *pb = P + 3 * c[1], *pd = P + 3 * c[2];
    double g1[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]}, g2[3] = {pd[0] - pa[0], pd[1] - pa[1], pd[2] - pa[2]};
    double q[3] = {g1[1] * g2[2] - g1[2] * g2[1], g1[2] * g2[0] - g1[0] * g2[2], g1[0] * g2[1] - g1[1] * g2[0]};
    double qn = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    double *D = dens + 5 * (size_t)f;
    if (qn > 0) {
      D[0] = As / (0.5 * qn);
      D[1] = q[0] / qn, D[2] = q[1] / qn, D[3] = q[2] / qn;
      D[4] = D[1] * pa[0] + D[2] * pa[1] + D[3] * pa[2];
      if (D[4] < 0) /* a reversed triangle (inward mesh or mirrored map): face the normal outwards */
        D[1] = -D[1], D[2] = -D[2], D[3] = -D[3], D[4] = -D[4];
    } else {
      D[0] = 0, D[1] = D[2] = D[3] = 0, D[4] = 0;
    }
  }
  if (!(total > 0)) {
    free(dens), free(uv), free(p);
    return au_msg_set(msg, AU_E_ARG, "au_tex_cell_areas: the surface has no area");
  }
  double scale = 4 * M_PI / total, dA = 4 * M_PI / ((double)W * H * sub * sub);
  au_tex_layout lay = au_tex_layout_default(AU_TEX_CEA);
  au_status st = AU_OK;
  int hint = -1, missed = 0;
  memset(area, 0, (size_t)W * H * sizeof *area);
  int Ws = W * sub;
  for (int r = 0; r < H && st == AU_OK; r++)
    for (int si = 0; si < sub && st == AU_OK; si++) {
      for (int c = 0; c < Ws; c++) uv[2 * c] = (c + 0.5) / Ws, uv[2 * c + 1] = 1 - (r + (si + 0.5) / sub) / H;
      st = au_tex_to_sphere(&lay, Ws, uv, p, NULL, msg);
      for (int c = 0; c < Ws && st == AU_OK; c++) {
        const double *q = p + 3 * (size_t)c;
        int f = au_locator_find(loc, q, &hint, NULL);
        if (f < 0) {
          missed++;
          continue;
        }
        const double *D = dens + 5 * (size_t)f;
        double np = D[1] * q[0] + D[2] * q[1] + D[3] * q[2];
        /* dA_flat / dA_sphere = h^2/(n.p)^3 for the central projection onto the face's plane. */
        double jac = np > 0 ? D[4] * D[4] / (np * np * np) : 0;
        area[(size_t)r * W + c / sub] += scale * D[0] * jac * dA;
      }
    }
  free(dens), free(uv), free(p);
  if (st == AU_OK && missed)
    st = au_msg_set(msg, AU_E_FOLD, "%d sample points of the sphere lie in no triangle of the map", missed);
  return st;
}

/* ---------------------------------------------------------------- small files */

au_status au_npy_write(const char *path, int ndim, const long *shape, const double *data, au_msg *msg) {
  if (!path || ndim < 1 || ndim > 4 || !shape) return au_msg_set(msg, AU_E_ARG, "au_npy_write: bad arguments");
  size_t count = 1;
  char dims[128] = "";
  for (int i = 0; i < ndim; i++) {
    if (shape[i] < 0) return au_msg_set(msg, AU_E_ARG, "au_npy_write: negative dimension");
    count *= (size_t)shape[i];
    size_t l = strlen(dims);
    snprintf(dims + l, sizeof dims - l, "%ld,%s", shape[i], (ndim > 1 && i < ndim - 1) ? " " : "");
  }
  if (ndim > 1) dims[strlen(dims) - 1] = '\0'; /* (a, b) not (a, b,); a 1-d shape keeps "(a,)" */
  if (count > 0 && !data) return au_msg_set(msg, AU_E_ARG, "au_npy_write: no data");
  char head[256];
  int hl = snprintf(head, sizeof head, "{'descr': '<f8', 'fortran_order': False, 'shape': (%s), }", dims);
  /* Magic (6) + version (2) + length (2) + header, padded with spaces and a newline to a multiple of 64. */
  size_t total_head = 10 + (size_t)hl + 1;
  size_t pad = (64 - total_head % 64) % 64;
  size_t hlen = (size_t)hl + pad + 1, len = 10 + hlen + 8 * count;
  unsigned char *b = malloc(len);
  if (!b) return au_msg_set(msg, AU_E_NOMEM, "out of memory writing '%s'", path);
  memcpy(b, "\x93NUMPY\x01\x00", 8);
  b[8] = (unsigned char)(hlen & 0xff), b[9] = (unsigned char)(hlen >> 8);
  memcpy(b + 10, head, (size_t)hl);
  memset(b + 10 + hl, ' ', pad);
  b[10 + hlen - 1] = '\n';
  unsigned char *d = b + 10 + hlen;
  for (size_t i = 0; i < count; i++) {
    uint64_t u;
    memcpy(&u, &data[i], 8);
    for (int k = 0; k < 8; k++) d[8 * i + k] = (unsigned char)(u >> (8 * k)); /* little-endian on any host */
  }
  au_status st = au_io_write_text(path, (const char *)b, len, msg);
  free(b);
  return st;
}

au_status au_read_scalars(const char *path, int n, double *vals, au_msg *msg) {
  if (!path || n < 1 || !vals) return au_msg_set(msg, AU_E_ARG, "au_read_scalars: bad arguments");
  /* au_io_read_scalars reads the text format, FreeSurfer curv files and GIfTI values alike. */
  double *v = NULL;
  au_status st = au_io_read_scalars(path, n, &v, NULL, msg);
  if (st != AU_OK) return st;
  memcpy(vals, v, (size_t)n * sizeof *vals);
  free(v);
  return AU_OK;
}
