/* au_io_freesurfer.c - FreeSurfer binary triangle surfaces and curv files (big-endian), read and written.
 *
 * The triangle surface (FreeSurfer's `lh.white`, `rh.sphere`, ...; FreeSurfer's mrisReadTriangleFile
 * and nibabel's freesurfer.io describe the same layout):
 *   3 bytes   magic 0xFFFFFE
 *   text      "created by USER on DATE\n\n": a line, then an empty line
 *   int32     number of vertices nv, number of faces nf
 *   float32   nv x 3 coordinates
 *   int32     nf x 3 vertex indices, counted from 0
 *   bytes     optional: the volume geometry footer (tag 20, or 2 0 20, then `valid = 1` ... `cras =`
 *             lines) and further tags (the command lines that made the file)
 * All numbers are big-endian. The footer is kept as raw bytes and written back unchanged: it says
 * which volume the surface belongs to, and nothing we do to the positions changes that.
 *
 * The curv file (per-vertex values: curv, sulc, thickness, ...), the "new" format:
 *   3 bytes   magic 0xFFFFFF
 *   int32     number of vertices, number of faces, values per vertex (1)
 *   float32   one value per vertex
 * The old format (3-byte counts, int16 values / 100) predates 2000 and is not read. */
#define _POSIX_C_SOURCE 200809L

#include "au_io_internal.h"

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#ifndef AU_VERSION
#define AU_VERSION "unknown"
#endif

#define FS_TRIANGLE_MAGIC 0xFFFFFEu
#define FS_CURV_MAGIC 0xFFFFFFu

static uint32_t be32(const unsigned char *p) {
  return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | (uint32_t)p[3];
}

static int32_t be_int(const unsigned char *p) {
  uint32_t u = be32(p);
  int32_t i;
  memcpy(&i, &u, sizeof i);
  return i;
}

static double be_float(const unsigned char *p) {
  uint32_t u = be32(p);
  float f;
  memcpy(&f, &u, sizeof f);
  return (double)f;
}

static void put32(unsigned char *p, uint32_t u) {
  p[0] = (unsigned char)(u >> 24), p[1] = (unsigned char)(u >> 16), p[2] = (unsigned char)(u >> 8),
  p[3] = (unsigned char)u;
}

static void put_float(unsigned char *p, double x) {
  float f = (float)x;
  uint32_t u;
  memcpy(&u, &f, sizeof u);
  put32(p, u);
}

int au_io__fits_float(double x) { return isfinite(x) && fabs(x) <= FLT_MAX; }

/* The created-by line after the magic: [3, *end) holds it, *data is where the counts start. nibabel
 * and FreeSurfer read it as one line and then one more (empty) line. */
static au_status fs_header(const char *path, const unsigned char *buf, size_t len, size_t *end, size_t *data,
                           au_msg *msg) {
  const unsigned char *nl = len > 3 ? memchr(buf + 3, '\n', len - 3) : NULL;
  if (!nl)
    return au_msg_set(msg, AU_E_FORMAT, "%s: FreeSurfer surface without its created-by line (no line end in its "
                      "%zu bytes)", path, len);
  for (const unsigned char *c = buf + 3; c < nl; c++)
    if ((*c < 0x20 && *c != '\t' && *c != '\r') || *c == 0x7f)
      return au_msg_set(msg, AU_E_FORMAT, "%s: FreeSurfer surface: binary data in the created-by line (byte %td)",
                        path, c - buf);
  size_t e = (size_t)(nl - buf);
  if (e + 1 >= len || buf[e + 1] != '\n')
    return au_msg_set(msg, AU_E_FORMAT, "%s: FreeSurfer surface: no empty line after the created-by line", path);
  *end = e, *data = e + 2;
  return AU_OK;
}

au_status au_io__check_float32(const char *path, int nv, const double *P, const char *container, au_msg *msg) {
  for (size_t i = 0; i < 3 * (size_t)nv; i++)
    if (!au_io__fits_float(P[i]))
      return au_msg_set(msg, AU_E_FORMAT, "%s: vertex %zu has coordinate %g, which %s (float32) cannot hold", path, i / 3,
                        P[i], container);
  return AU_OK;
}

/* Copy [s, e) into a new NUL-terminated string; NULL when out of memory. */
static char *dup_range(const unsigned char *s, const unsigned char *e) {
  char *t = malloc((size_t)(e - s) + 1);
  if (t) {
    memcpy(t, s, (size_t)(e - s));
    t[e - s] = '\0';
  }
  return t;
}

au_status au_io__fs_read_surface(const char *path, const unsigned char *buf, size_t len, au_mesh **out,
                                 au_io_meta *meta, au_msg *msg) {
  size_t end = 0, at = 0;
  au_status st = fs_header(path, buf, len, &end, &at, msg);
  if (st != AU_OK) return st;
  if (len - at < 8)
    return au_msg_set(msg, AU_E_FORMAT, "%s: FreeSurfer surface ends before its vertex and face counts", path);
  long long nv = be_int(buf + at), nf = be_int(buf + at + 4);
  at += 8;
  if (nv <= 0 || nf <= 0)
    return au_msg_set(msg, AU_E_EMPTY, "%s: FreeSurfer surface of %lld vertices and %lld faces; a mesh needs both",
                      path, nv, nf);
  unsigned long long need = 12ull * (unsigned long long)nv + 12ull * (unsigned long long)nf;
  if (need > len - at)
    return au_msg_set(msg, AU_E_FORMAT, "%s: FreeSurfer surface announces %lld vertices and %lld faces (%llu bytes) "
                      "but %zu bytes follow its header (truncated?)", path, nv, nf, need, len - at);
  st = au_io__mesh_new(path, nv, nf, out, msg);
  if (st != AU_OK) return st;
  au_mesh *m = *out;
  for (long long i = 0; i < 3 * nv; i++, at += 4) m->X[i] = be_float(buf + at);
  for (long long j = 0; j < 3 * nf; j++, at += 4) {
    int32_t v = be_int(buf + at);
    if (v < 0 || v >= nv) {
      au_mesh_free(out);
      return au_msg_set(msg, AU_E_INDEX, "%s: face %lld: index %d is out of range (%lld vertices, counted from 0)",
                        path, j / 3, (int)v, nv);
    }
    m->F[j] = v;
  }
  if (meta) {
    meta->fs_stamp = dup_range(buf + 3, buf + end);
    if (len > at) {
      meta->fs_footer = malloc(len - at);
      if (meta->fs_footer) memcpy(meta->fs_footer, buf + at, len - at), meta->fs_footer_len = len - at;
    }
    if (!meta->fs_stamp || (len > at && !meta->fs_footer)) {
      au_mesh_free(out);
      return au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
    }
  }
  return AU_OK;
}

/* ---------- writing the surface ---------- */

typedef struct fs_out {
  const au_mesh *m;
  const double *P;
  const au_io_meta *meta;
} fs_out;

/* Writes in blocks of this many bytes, so a large surface needs no second copy in memory. */
#define FS_BLOCK 65536

static int emit_surface(FILE *fp, const void *ctx) {
  const fs_out *o = ctx;
  const au_mesh *m = o->m;
  unsigned char b[FS_BLOCK];
  size_t n = 0;
  errno = 0;
  int bad = fputs("\xff\xff\xfe" "created by authalic " AU_VERSION "\n\n", fp) < 0;
  put32(b, (uint32_t)m->nv), put32(b + 4, (uint32_t)m->nf), n = 8;
  for (size_t i = 0; i < 3 * (size_t)m->nv && !bad; i++) {
    put_float(b + n, o->P[i]), n += 4;
    if (n == FS_BLOCK) bad |= fwrite(b, 1, n, fp) != n, n = 0;
  }
  for (size_t j = 0; j < 3 * (size_t)m->nf && !bad; j++) {
    put32(b + n, (uint32_t)m->F[j]), n += 4;
    if (n == FS_BLOCK) bad |= fwrite(b, 1, n, fp) != n, n = 0;
  }
  if (n && !bad) bad |= fwrite(b, 1, n, fp) != n;
  const au_io_meta *meta = o->meta;
  if (!bad && meta && meta->format == AU_IO_FORMAT_FREESURFER && meta->fs_footer_len)
    bad |= fwrite(meta->fs_footer, 1, meta->fs_footer_len, fp) != meta->fs_footer_len;
  return bad;
}

au_status au_io__fs_write_surface(const char *path, const au_mesh *m, const double *P, const au_io_meta *meta,
                                  au_msg *msg) {
  au_status st = au_io__check_float32(path, m->nv, P, "a FreeSurfer surface", msg);
  if (st != AU_OK) return st;
  fs_out o = {m, P, meta};
  return au_io__write_atomic(path, emit_surface, &o, msg);
}

/* ---------- curv ---------- */

au_status au_io__fs_read_curv(const char *path, const unsigned char *buf, size_t len, int n, double **out, int *count,
                              au_msg *msg) {
  if (len < 15)
    return au_msg_set(msg, AU_E_FORMAT, "%s: FreeSurfer curv file ends inside its header (%zu bytes)", path, len);
  long long vnum = be_int(buf + 3), fnum = be_int(buf + 7), per = be_int(buf + 11);
  if (per != 1)
    return au_msg_set(msg, AU_E_FORMAT, "%s: FreeSurfer curv file with %lld values per vertex (1 expected)", path, per);
  if (vnum <= 0 || fnum < 0)
    return au_msg_set(msg, AU_E_FORMAT, "%s: FreeSurfer curv file announces %lld vertices and %lld faces", path, vnum,
                      fnum);
  unsigned long long need = 4ull * (unsigned long long)vnum;
  if (need != len - 15)
    return au_msg_set(msg, AU_E_FORMAT, "%s: FreeSurfer curv file announces %lld values (%llu bytes) but %zu bytes "
                      "follow its header%s", path, vnum, need, len - 15, need > len - 15 ? " (truncated?)" : "");
  if (n > 0 && vnum != n)
    return au_msg_set(msg, AU_E_FORMAT, "%s: %lld values for %d vertices (one value a vertex expected)", path, vnum, n);
  double *v = malloc((size_t)vnum * sizeof *v);
  if (!v) return au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
  for (long long i = 0; i < vnum; i++) {
    v[i] = be_float(buf + 15 + 4 * i);
    if (!isfinite(v[i])) {
      free(v);
      return au_msg_set(msg, AU_E_FORMAT, "%s: value %lld is not finite", path, i + 1);
    }
  }
  *out = v;
  if (count) *count = (int)vnum;
  return AU_OK;
}

typedef struct curv_out {
  int n, nfaces;
  const double *v;
} curv_out;

static int emit_curv(FILE *fp, const void *ctx) {
  const curv_out *o = ctx;
  unsigned char b[FS_BLOCK];
  errno = 0;
  b[0] = b[1] = b[2] = 0xff;
  put32(b + 3, (uint32_t)o->n), put32(b + 7, (uint32_t)o->nfaces), put32(b + 11, 1u);
  size_t n = 15;
  int bad = 0;
  for (int i = 0; i < o->n && !bad; i++) {
    put_float(b + n, o->v[i]), n += 4;
    if (n + 4 > FS_BLOCK) bad |= fwrite(b, 1, n, fp) != n, n = 0;
  }
  if (n && !bad) bad |= fwrite(b, 1, n, fp) != n;
  return bad;
}

au_status au_io__fs_write_curv(const char *path, int n, const double *values, int nfaces, au_msg *msg) {
  for (int i = 0; i < n; i++)
    if (!au_io__fits_float(values[i]))
      return au_msg_set(msg, AU_E_FORMAT, "%s: value %d (%g) does not fit a curv file's float32", path, i + 1,
                        values[i]);
  curv_out o = {n, nfaces < 0 ? 0 : nfaces, values};
  return au_io__write_atomic(path, emit_curv, &o, msg);
}
