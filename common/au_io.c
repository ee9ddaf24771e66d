/* au_io.c - mesh files: OBJ, OFF and PLY parsed here, STL through the OpenMesh bridge; atomic writers. */
#define _POSIX_C_SOURCE 200809L

#include "au_io.h"
#include "au_io_internal.h"
#include "au_par.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <limits.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

/* Why OBJ, OFF and PLY are parsed here and not by OpenMesh: OpenMesh's importer silently repairs
 * what it cannot represent (it drops faces with a repeated corner or a bad index, and splits the
 * vertices of faces that would make an edge non-manifold), and its PLY reader rounds every
 * coordinate to float. Users need the file's vertices and faces exactly, and a broken mesh must
 * reach au_mesh_validate, which names the broken edge. STL stores float positions and no shared
 * vertices anyway, so OpenMesh reads it (merging equal positions, which is what STL means), and
 * we check that it kept every facet. */

typedef au_io_format au_fmt;
#define AU_FMT_NONE AU_IO_FORMAT_AUTO
#define AU_FMT_OBJ AU_IO_FORMAT_OBJ
#define AU_FMT_OFF AU_IO_FORMAT_OFF
#define AU_FMT_PLY AU_IO_FORMAT_PLY
#define AU_FMT_STL AU_IO_FORMAT_STL

static au_fmt fmt_of(const char *path) {
  if (au_io__gii_name(path)) return AU_IO_FORMAT_GIFTI;
  const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
  if (!dot || (slash && dot < slash)) return AU_FMT_NONE;
  if (!strcasecmp(dot, ".obj")) return AU_FMT_OBJ;
  if (!strcasecmp(dot, ".off")) return AU_FMT_OFF;
  if (!strcasecmp(dot, ".ply")) return AU_FMT_PLY;
  if (!strcasecmp(dot, ".stl")) return AU_FMT_STL;
  return AU_FMT_NONE;
}

au_io_format au_io_format_of_name(const char *path) { return path ? fmt_of(path) : AU_IO_FORMAT_AUTO; }

static const char *const format_names[] = {"auto", "obj", "off", "ply", "stl", "freesurfer", "gifti"};

au_io_format au_io_format_parse(const char *word) {
  if (!word) return AU_IO_FORMAT_AUTO;
  for (int f = AU_IO_FORMAT_OBJ; f <= AU_IO_FORMAT_GIFTI; f++)
    if (f != AU_IO_FORMAT_STL && strcmp(word, format_names[f]) == 0) return (au_io_format)f;
  return AU_IO_FORMAT_AUTO;
}

const char *au_io_format_name(au_io_format f) {
  return f >= AU_IO_FORMAT_AUTO && f <= AU_IO_FORMAT_GIFTI ? format_names[f] : "auto";
}

au_io_format au_io_meta_format(const au_io_meta *meta) { return meta ? meta->format : AU_IO_FORMAT_AUTO; }

const char *au_io_meta_get(const au_io_meta *meta, const char *name) {
  if (!meta || !name) return NULL;
  if (meta->format == AU_IO_FORMAT_FREESURFER) return strcmp(name, "created_by") == 0 ? meta->fs_stamp : NULL;
  return meta->gii ? au_io__gii_meta_get(meta->gii, name) : NULL;
}

void au_io_meta_free(au_io_meta **meta) {
  if (!meta || !*meta) return;
  free((*meta)->fs_stamp);
  free((*meta)->fs_footer);
  au_io__gii_free((*meta)->gii);
  free(*meta);
  *meta = NULL;
}

/* The format of a file as its first bytes say, for the formats that have a signature: FreeSurfer's
 * magic numbers (0xFFFFFE a triangle surface, 0xFFFFFF a curv file or an old quad surface, 0xFFFFFD
 * a quad surface) and GIfTI's XML ('<?xml' or '<GIFTI', after an optional byte-order mark; gzip only
 * under a .gii.gz name). *magic gets the FreeSurfer magic number read, 0 if none. */
static au_fmt fmt_of_content(const char *path, const char *buf, size_t len, unsigned *magic) {
  const unsigned char *u = (const unsigned char *)buf;
  *magic = 0;
  if (len >= 3 && u[0] == 0xff && u[1] == 0xff && u[2] >= 0xfd) {
    *magic = 0xFFFF00u | u[2];
    return AU_IO_FORMAT_FREESURFER;
  }
  size_t skip = len >= 3 && !memcmp(buf, "\xEF\xBB\xBF", 3) ? 3 : 0;
  if ((len - skip >= 5 && !memcmp(buf + skip, "<?xml", 5)) || (len - skip >= 6 && !memcmp(buf + skip, "<GIFTI", 6)))
    return AU_IO_FORMAT_GIFTI;
  return fmt_of(path);
}

/* ---------- reading the whole file ---------- */

/* Read path into a NUL-terminated buffer (*out, *len bytes before the NUL); the caller frees *out. */
au_status au_io__slurp(const char *path, char **out, size_t *len, au_msg *msg) {
  *out = NULL;
  *len = 0;
  FILE *fp = fopen(path, "rb");
  if (!fp) return au_msg_set(msg, AU_E_IO, "cannot open '%s': %s", path, strerror(errno));
  struct stat st;
  if (fstat(fileno(fp), &st) != 0) {
    int err = errno;
    fclose(fp);
    return au_msg_set(msg, AU_E_IO, "cannot read '%s': %s", path, strerror(err));
  }
  if (S_ISDIR(st.st_mode)) {
    fclose(fp);
    return au_msg_set(msg, AU_E_IO, "'%s' is a directory, not a mesh file", path);
  }
  size_t cap = S_ISREG(st.st_mode) && st.st_size > 0 ? (size_t)st.st_size + 1 : 65536, n = 0;
  char *buf = malloc(cap);
  while (buf) {
    n += fread(buf + n, 1, cap - 1 - n, fp);
    if (n < cap - 1) break;
    /* Full: grow only if there is more to read, so a regular file is read into one exact buffer. */
    int c = fgetc(fp);
    if (c == EOF) break;
    char *grown = realloc(buf, 2 * cap);
    if (!grown) {
      free(buf);
      buf = NULL;
    } else {
      buf = grown;
      cap *= 2;
      buf[n++] = (char)c;
    }
  }
  if (!buf) {
    fclose(fp);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
  }
  if (ferror(fp)) {
    int err = errno;
    fclose(fp);
    free(buf);
    return au_msg_set(msg, AU_E_IO, "cannot read '%s': %s", path, strerror(err));
  }
  fclose(fp);
  buf[n] = '\0';
  *out = buf;
  *len = n;
  return AU_OK;
}

/* ---------- text lines and tokens ---------- */

typedef struct au_text {
  const char *p, *end; /* the unread part of the buffer */
  int line;            /* 1-based number of the line last returned */
} au_text;

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

/* The next line that has content, as [*s, *e): leading blanks skipped, a '#' comment and trailing
 * blanks cut. Returns 1, 0 at the end of the buffer, or -1 if the line holds bytes no text file
 * has (NUL or control characters), which is how binary garbage under a text extension is caught. */
static int text_next(au_text *t, const char **s, const char **e) {
  while (t->p < t->end) {
    const char *a = t->p, *b = memchr(a, '\n', (size_t)(t->end - a));
    if (!b) b = t->end;
    t->p = b < t->end ? b + 1 : b;
    t->line++;
    for (const char *c = a; c < b; c++) {
      unsigned char u = (unsigned char)*c;
      if (u == 0 || (u < 0x20 && !is_space(*c)) || u == 0x7f) return -1;
    }
    const char *h = memchr(a, '#', (size_t)(b - a));
    if (h) b = h;
    while (a < b && is_space(*a)) a++;
    while (b > a && is_space(b[-1])) b--;
    if (a < b) {
      *s = a;
      *e = b;
      return 1;
    }
  }
  return 0;
}

/* The next blank-separated token of [*p, e) as [*ts, *te); 0 when none is left. */
static int tok_next(const char **p, const char *e, const char **ts, const char **te) {
  const char *a = *p;
  while (a < e && is_space(*a)) a++;
  if (a >= e) return 0;
  const char *b = a;
  while (b < e && !is_space(*b)) b++;
  *ts = a;
  *te = b;
  *p = b;
  return 1;
}

static int tok_is(const char *s, const char *e, const char *word) {
  size_t n = strlen(word);
  return (size_t)(e - s) == n && memcmp(s, word, n) == 0;
}

/* A whole token as a double. strtod also accepts "nan", "inf" and "infinity": non-finite
 * coordinates are read here so that validation can name the vertex. The character after a
 * token is a blank, '#', or the buffer's NUL, none of which strtod would take into a number. */
static int tok_double(const char *s, const char *e, double *v) {
  char *end;
  *v = strtod(s, &end);
  return e > s && end == e;
}

/* A whole token as an integer in [lo, hi]. */
static int tok_int(const char *s, const char *e, long long lo, long long hi, long long *v) {
  /* Plain decimals of up to 18 digits (every index and count in practice) are read here: strtoll's
   * locale and sign handling was most of the time of reading a face. The value is strtoll's, and
   * anything else goes to strtoll. */
  const char *d = s < e && *s == '-' ? s + 1 : s;
  if (e > d && e - d <= 18) {
    long long x = 0;
    const char *c = d;
    while (c < e && *c >= '0' && *c <= '9') x = 10 * x + (*c++ - '0');
    if (c == e) {
      if (d > s) x = -x;
      if (x < lo || x > hi) return 0;
      *v = x;
      return 1;
    }
  }
  char *end;
  errno = 0;
  long long x = strtoll(s, &end, 10);
  if (e == s || end != e || errno == ERANGE || x < lo || x > hi) return 0;
  *v = x;
  return 1;
}

/* Remaining tokens of a record must be numbers (OBJ's w, OFF's colours); anything else is garbage. */
static int rest_numeric(const char *p, const char *e) {
  const char *ts, *te;
  double d;
  while (tok_next(&p, e, &ts, &te))
    if (!tok_double(ts, te, &d)) return 0;
  return 1;
}

au_status au_io__mesh_new(const char *path, long long nv, long long nf, au_mesh **out, au_msg *msg) {
  if (nv <= 0 || nf <= 0)
    return au_msg_set(msg, AU_E_EMPTY, "%s: %lld vertices and %lld faces; a mesh needs both", path, nv, nf);
  if (nv > INT_MAX / 3 || nf > INT_MAX / 3)
    return au_msg_set(msg, AU_E_FORMAT, "%s: too many vertices or faces (%lld, %lld)", path, nv, nf);
  au_status s = au_mesh_alloc((int)nv, (int)nf, out);
  if (s != AU_OK) return au_msg_set(msg, s, "%s: cannot allocate %lld vertices and %lld faces", path, nv, nf);
  return AU_OK;
}

/* ---------- OBJ ---------- */

/* One corner token of an OBJ face ("7", "7/2", "7//3", "-1/-1/-1"): the vertex index as written. */
static int obj_corner(const char *s, const char *e, long long *v) {
  const char *slash = memchr(s, '/', (size_t)(e - s));
  if (!slash) slash = e;
  if (!tok_int(s, slash, LLONG_MIN, LLONG_MAX, v)) return 0;
  for (const char *c = slash; c < e; c++)
    if (*c != '/' && *c != '-' && (*c < '0' || *c > '9')) return 0;
  return 1;
}

static au_status read_obj(const char *path, const char *buf, size_t len, au_mesh **out, au_msg *msg) {
  /* First pass: count the records, so that positive indices may refer forward and the arrays are
   * allocated once. */
  long long nv = 0, nf = 0;
  au_text t = {buf, buf + len, 0};
  const char *s, *e, *ts, *te;
  int r;
  while ((r = text_next(&t, &s, &e)) != 0) {
    if (r < 0) return au_msg_set(msg, AU_E_FORMAT, "%s:%d: binary data in an OBJ file", path, t.line);
    const char *p = s;
    tok_next(&p, e, &ts, &te);
    if (tok_is(ts, te, "v")) nv++;
    if (tok_is(ts, te, "f")) nf++;
  }
  au_status st = au_io__mesh_new(path, nv, nf, out, msg);
  if (st != AU_OK) return st;
  au_mesh *m = *out;
  int iv = 0, jf = 0;
  t = (au_text){buf, buf + len, 0};
  while (text_next(&t, &s, &e) > 0) {
    const char *p = s;
    tok_next(&p, e, &ts, &te);
    if (tok_is(ts, te, "v")) {
      for (int k = 0; k < 3; k++) {
        if (!tok_next(&p, e, &ts, &te) || !tok_double(ts, te, &m->X[3 * iv + k])) {
          st = au_msg_set(msg, AU_E_FORMAT, "%s:%d: vertex %d: expected three numbers after 'v'", path, t.line, iv);
          goto fail;
        }
      }
      if (!rest_numeric(p, e)) {
        st = au_msg_set(msg, AU_E_FORMAT, "%s:%d: vertex %d: unexpected text after the coordinates", path, t.line, iv);
        goto fail;
      }
      iv++;
    } else if (tok_is(ts, te, "f")) {
      long long idx[3];
      int n = 0;
      while (tok_next(&p, e, &ts, &te)) {
        long long v;
        if (!obj_corner(ts, te, &v)) {
          st = au_msg_set(msg, AU_E_FORMAT, "%s:%d: face %d: bad corner '%.*s'", path, t.line, jf, (int)(te - ts), ts);
          goto fail;
        }
        if (n < 3) idx[n] = v;
        n++;
      }
      if (n != 3) {
        st = au_msg_set(msg, AU_E_FACE, "%s:%d: face %d has %d corners; only triangles are supported (triangulate first)",
                        path, t.line, jf, n);
        goto fail;
      }
      for (int k = 0; k < 3; k++) {
        /* OBJ counts from 1; a negative index counts back from the last vertex defined so far. */
        long long v = idx[k] > 0 ? idx[k] - 1 : idx[k] < 0 ? iv + idx[k] : -1;
        if (v < 0 || v >= nv) {
          st = au_msg_set(msg, AU_E_INDEX, "%s:%d: face %d: index %lld is out of range (%lld vertices%s)", path,
                          t.line, jf, idx[k], idx[k] < 0 ? (long long)iv : nv, idx[k] < 0 ? " defined before it" : "");
          goto fail;
        }
        m->F[3 * jf + k] = (int)v;
      }
      jf++;
    }
  }
  return AU_OK;
fail:
  au_mesh_free(out);
  return st;
}

/* ---------- OFF ---------- */

static au_status read_off(const char *path, const char *buf, size_t len, au_mesh **out, au_msg *msg) {
  au_text t = {buf, buf + len, 0};
  const char *s, *e, *ts, *te, *p;
  int r = text_next(&t, &s, &e);
  if (r < 0) return au_msg_set(msg, AU_E_FORMAT, "%s:%d: binary data in an OFF file", path, t.line);
  if (r == 0) return au_msg_set(msg, AU_E_EMPTY, "%s: no OFF header", path);
  p = s;
  tok_next(&p, e, &ts, &te);
  /* The keyword may carry the prefixes ST (texture), C (colour), N (normal): those add values to
   * each vertex line, which we skip. 4OFF/nOFF (other dimensions) and binary OFF are not meshes we read. */
  const char *k = ts;
  if (te - k >= 2 && k[0] == 'S' && k[1] == 'T') k += 2;
  if (k < te && *k == 'C') k++;
  if (k < te && *k == 'N') k++;
  if (!tok_is(k, te, "OFF"))
    return au_msg_set(msg, AU_E_FORMAT, "%s:%d: not an OFF file (header '%.*s', expected OFF)", path, t.line,
                      (int)(te - ts), ts);
  long long cnt[3] = {0, 0, 0};
  int nc = 0, hline = t.line;
  const char *q = p;
  if (!tok_next(&q, e, &ts, &te)) { /* the counts are on the next line, as usual */
    r = text_next(&t, &s, &e);
    if (r <= 0) return au_msg_set(msg, AU_E_FORMAT, "%s:%d: the OFF header has no counts", path, t.line);
    p = s;
    hline = t.line;
  }
  while (tok_next(&p, e, &ts, &te)) {
    if (nc == 3 || !tok_int(ts, te, 0, LLONG_MAX, &cnt[nc]))
      return au_msg_set(msg, AU_E_FORMAT, "%s:%d: bad OFF counts (expected: vertices faces [edges])", path, hline);
    nc++;
  }
  if (nc < 2) return au_msg_set(msg, AU_E_FORMAT, "%s:%d: bad OFF counts (expected: vertices faces [edges])", path, hline);
  long long nv = cnt[0], nf = cnt[1];
  /* Each record takes a few bytes, so counts far beyond the file's size are a broken header, not
   * a reason to allocate gigabytes. */
  if ((unsigned long long)nv > len / 4 + 1 || (unsigned long long)nf > len / 6 + 1)
    return au_msg_set(msg, AU_E_FORMAT, "%s:%d: the header says %lld vertices and %lld faces, more than a %zu-byte file holds",
                      path, hline, nv, nf, len);
  au_status st = au_io__mesh_new(path, nv, nf, out, msg);
  if (st != AU_OK) return st;
  au_mesh *m = *out;
  for (int i = 0; i < (int)nv; i++) {
    r = text_next(&t, &s, &e);
    if (r <= 0) {
      st = r < 0 ? au_msg_set(msg, AU_E_FORMAT, "%s:%d: binary data in an OFF file", path, t.line)
                 : au_msg_set(msg, AU_E_FORMAT, "%s: the file ends after %d of %lld vertices (header, line %d)", path, i, nv, hline);
      goto fail;
    }
    p = s;
    for (int c = 0; c < 3; c++) {
      if (!tok_next(&p, e, &ts, &te) || !tok_double(ts, te, &m->X[3 * i + c])) {
        st = au_msg_set(msg, AU_E_FORMAT, "%s:%d: vertex %d: expected three numbers (header counts wrong?)", path, t.line, i);
        goto fail;
      }
    }
    if (!rest_numeric(p, e)) {
      st = au_msg_set(msg, AU_E_FORMAT, "%s:%d: vertex %d: unexpected text after the coordinates", path, t.line, i);
      goto fail;
    }
  }
  for (int f = 0; f < (int)nf; f++) {
    r = text_next(&t, &s, &e);
    if (r <= 0) {
      st = r < 0 ? au_msg_set(msg, AU_E_FORMAT, "%s:%d: binary data in an OFF file", path, t.line)
                 : au_msg_set(msg, AU_E_FORMAT, "%s: the file ends after %d of %lld faces (header, line %d)", path, f, nf, hline);
      goto fail;
    }
    p = s;
    long long n, v[3];
    if (!tok_next(&p, e, &ts, &te) || !tok_int(ts, te, 0, INT_MAX, &n)) {
      st = au_msg_set(msg, AU_E_FORMAT, "%s:%d: face %d: expected a corner count (header counts wrong?)", path, t.line, f);
      goto fail;
    }
    if (n != 3) {
      /* Fewer than three corners, or fewer indices than announced, is no polygon at all: most likely
       * the header's counts are wrong and this line is something else. */
      const char *q = p;
      long long have = 0;
      while (have < n && tok_next(&q, e, &ts, &te)) have++;
      if (n < 3 || have < n)
        st = au_msg_set(msg, AU_E_FORMAT, "%s:%d: face %d: not a polygon (header counts wrong?)", path, t.line, f);
      else
        st = au_msg_set(msg, AU_E_FACE, "%s:%d: face %d has %lld corners; only triangles are supported (triangulate first)",
                        path, t.line, f, n);
      goto fail;
    }
    for (int c = 0; c < 3; c++) {
      if (!tok_next(&p, e, &ts, &te) || !tok_int(ts, te, LLONG_MIN, LLONG_MAX, &v[c])) {
        st = au_msg_set(msg, AU_E_FORMAT, "%s:%d: face %d: expected three vertex indices", path, t.line, f);
        goto fail;
      }
    }
    if (!rest_numeric(p, e)) {
      st = au_msg_set(msg, AU_E_FORMAT, "%s:%d: face %d: unexpected text after the indices", path, t.line, f);
      goto fail;
    }
    for (int c = 0; c < 3; c++) {
      if (v[c] < 0 || v[c] >= nv) {
        st = au_msg_set(msg, AU_E_INDEX, "%s:%d: face %d: index %lld is out of range (%lld vertices, counted from 0)",
                        path, t.line, f, v[c], nv);
        goto fail;
      }
      m->F[3 * f + c] = (int)v[c];
    }
  }
  r = text_next(&t, &s, &e);
  if (r != 0) {
    st = au_msg_set(msg, AU_E_FORMAT, "%s:%d: data after the last of the %lld faces the header (line %d) announced",
                    path, t.line, nf, hline);
    goto fail;
  }
  return AU_OK;
fail:
  au_mesh_free(out);
  return st;
}

/* ---------- PLY ---------- */

typedef enum ply_type { PT_NONE, PT_I8, PT_U8, PT_I16, PT_U16, PT_I32, PT_U32, PT_F32, PT_F64 } ply_type;

#define PLY_MAX_PROPS 64
#define PLY_MAX_ELEMS 16

typedef struct ply_prop {
  ply_type type;  /* scalar type, or the item type of a list */
  ply_type count; /* PT_NONE for a scalar, else the type of the list's length */
  char name[40];
} ply_prop;

typedef struct ply_elem {
  char name[40];
  long long n;
  int nprops;
  ply_prop props[PLY_MAX_PROPS];
} ply_elem;

typedef struct ply_in {
  int ascii, swap;                  /* ascii body; binary with the other byte order than this machine */
  const unsigned char *p, *end;     /* unread part of the body */
  int line;                         /* current line of an ascii body */
} ply_in;

static ply_type ply_type_of(const char *s, const char *e) {
  static const struct { const char *name; ply_type t; } names[] = {
      {"char", PT_I8},    {"int8", PT_I8},     {"uchar", PT_U8},   {"uint8", PT_U8},     {"short", PT_I16},
      {"int16", PT_I16},  {"ushort", PT_U16},  {"uint16", PT_U16}, {"int", PT_I32},      {"int32", PT_I32},
      {"uint", PT_U32},   {"uint32", PT_U32},  {"float", PT_F32},  {"float32", PT_F32},  {"double", PT_F64},
      {"float64", PT_F64}};
  for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
    if (tok_is(s, e, names[i].name)) return names[i].t;
  return PT_NONE;
}

static int ply_size(ply_type t) {
  switch (t) {
    case PT_I8: case PT_U8: return 1;
    case PT_I16: case PT_U16: return 2;
    case PT_I32: case PT_U32: case PT_F32: return 4;
    case PT_F64: return 8;
    default: return 0;
  }
}

/* Read one value of type ty into *d (and, exactly, into *i for integer types). 0 on truncation
 * or a malformed token. */
static int ply_value(ply_in *in, ply_type ty, double *d, long long *i) {
  int isint = ty != PT_F32 && ty != PT_F64;
  if (in->ascii) {
    while (in->p < in->end && (is_space((char)*in->p) || *in->p == '\n')) {
      if (*in->p == '\n') in->line++;
      in->p++;
    }
    const char *s = (const char *)in->p, *e = s;
    while ((const unsigned char *)e < in->end && !is_space(*e) && *e != '\n') e++;
    in->p = (const unsigned char *)e;
    if (isint) {
      if (!tok_int(s, e, LLONG_MIN, LLONG_MAX, i)) return 0;
      *d = (double)*i;
      return 1;
    }
    return tok_double(s, e, d);
  }
  int n = ply_size(ty);
  unsigned char b[8];
  if (in->end - in->p < n) return 0;
  for (int k = 0; k < n; k++) b[k] = in->p[in->swap ? n - 1 - k : k];
  in->p += n;
  switch (ty) {
    case PT_I8: { int8_t v; memcpy(&v, b, 1); *i = v; break; }
    case PT_U8: *i = b[0]; break;
    case PT_I16: { int16_t v; memcpy(&v, b, 2); *i = v; break; }
    case PT_U16: { uint16_t v; memcpy(&v, b, 2); *i = v; break; }
    case PT_I32: { int32_t v; memcpy(&v, b, 4); *i = v; break; }
    case PT_U32: { uint32_t v; memcpy(&v, b, 4); *i = v; break; }
    case PT_F32: { float v; memcpy(&v, b, 4); *d = v; return 1; }
    case PT_F64: { double v; memcpy(&v, b, 8); *d = v; return 1; }
    default: return 0;
  }
  *d = (double)*i;
  return 1;
}

/* Parse the header into elems (at most PLY_MAX_ELEMS); in receives the format and where the data starts. */
static au_status ply_header(const char *path, const char *buf, size_t len, ply_elem *elems, int *nelems, ply_in *in,
                            au_msg *msg) {
  au_text t = {buf, buf + len, 0};
  const char *s, *e, *ts, *te, *p;
  int r, fmt_seen = 0;
  *nelems = 0;
  r = text_next(&t, &s, &e);
  if (r <= 0 || t.line != 1 || !tok_is(s, e, "ply")) return au_msg_set(msg, AU_E_FORMAT, "%s:1: not a PLY file (no 'ply' line)", path);
  for (;;) {
    /* text_next cuts at '#', which PLY does not treat as a comment; that is harmless because no
     * header keyword or name contains '#', and its binary check and blank skipping are wanted. */
    r = text_next(&t, &s, &e);
    if (r < 0) return au_msg_set(msg, AU_E_FORMAT, "%s:%d: binary data in the PLY header", path, t.line);
    if (r == 0) return au_msg_set(msg, AU_E_FORMAT, "%s: the PLY header has no end_header", path);
    p = s;
    tok_next(&p, e, &ts, &te);
    if (tok_is(ts, te, "end_header")) break;
    if (tok_is(ts, te, "comment") || tok_is(ts, te, "obj_info")) continue;
    if (tok_is(ts, te, "format")) {
      const char *fs, *fe;
      if (!tok_next(&p, e, &fs, &fe)) break;
      if (tok_is(fs, fe, "ascii")) {
        in->ascii = 1;
      } else {
        const uint16_t one = 1;
        int little = *(const unsigned char *)&one == 1;
        if (tok_is(fs, fe, "binary_little_endian")) in->swap = !little;
        else if (tok_is(fs, fe, "binary_big_endian")) in->swap = little;
        else return au_msg_set(msg, AU_E_FORMAT, "%s:%d: unknown PLY format '%.*s'", path, t.line, (int)(fe - fs), fs);
      }
      fmt_seen = 1;
    } else if (tok_is(ts, te, "element")) {
      const char *ns, *ne, *cs, *ce;
      long long n;
      if (*nelems == PLY_MAX_ELEMS) return au_msg_set(msg, AU_E_FORMAT, "%s:%d: too many PLY elements", path, t.line);
      if (!tok_next(&p, e, &ns, &ne) || !tok_next(&p, e, &cs, &ce) || !tok_int(cs, ce, 0, LLONG_MAX, &n))
        return au_msg_set(msg, AU_E_FORMAT, "%s:%d: bad PLY element line", path, t.line);
      ply_elem *el = &elems[(*nelems)++];
      snprintf(el->name, sizeof el->name, "%.*s", (int)(ne - ns), ns);
      el->n = n;
      el->nprops = 0;
    } else if (tok_is(ts, te, "property")) {
      if (*nelems == 0) return au_msg_set(msg, AU_E_FORMAT, "%s:%d: PLY property before any element", path, t.line);
      ply_elem *el = &elems[*nelems - 1];
      if (el->nprops == PLY_MAX_PROPS) return au_msg_set(msg, AU_E_FORMAT, "%s:%d: too many PLY properties", path, t.line);
      ply_prop *pr = &el->props[el->nprops];
      const char *a, *b;
      pr->count = PT_NONE;
      if (!tok_next(&p, e, &a, &b)) return au_msg_set(msg, AU_E_FORMAT, "%s:%d: bad PLY property line", path, t.line);
      if (tok_is(a, b, "list")) {
        if (!tok_next(&p, e, &a, &b) || (pr->count = ply_type_of(a, b)) == PT_NONE || pr->count == PT_F32 ||
            pr->count == PT_F64 || !tok_next(&p, e, &a, &b))
          return au_msg_set(msg, AU_E_FORMAT, "%s:%d: bad PLY list property", path, t.line);
      }
      if ((pr->type = ply_type_of(a, b)) == PT_NONE || !tok_next(&p, e, &a, &b))
        return au_msg_set(msg, AU_E_FORMAT, "%s:%d: bad PLY property type '%.*s'", path, t.line, (int)(b - a), a);
      snprintf(pr->name, sizeof pr->name, "%.*s", (int)(b - a), a);
      el->nprops++;
    } else {
      if (ts < te && ((*ts >= '0' && *ts <= '9') || *ts == '-' || *ts == '.') && *nelems > 0)
        return au_msg_set(msg, AU_E_FORMAT, "%s:%d: data line '%.*s' before end_header (the PLY header has no end_header)",
                          path, t.line, (int)(te - ts), ts);
      return au_msg_set(msg, AU_E_FORMAT, "%s:%d: unknown PLY header line '%.*s'", path, t.line, (int)(te - ts), ts);
    }
  }
  if (!fmt_seen) return au_msg_set(msg, AU_E_FORMAT, "%s: the PLY header has no valid format line", path);
  in->p = (const unsigned char *)t.p;
  in->end = (const unsigned char *)buf + len;
  in->line = t.line + 1;
  return AU_OK;
}

static int ply_find(const ply_elem *el, const char *name) {
  for (int k = 0; k < el->nprops; k++)
    if (!strcmp(el->props[k].name, name)) return k;
  return -1;
}

static au_status ply_body(const char *path, const ply_elem *elems, int nelems, ply_in *in, au_mesh **out, au_msg *msg) {
  const ply_elem *ve = NULL, *fe = NULL;
  for (int i = 0; i < nelems; i++) {
    if (!strcmp(elems[i].name, "vertex") && !ve) ve = &elems[i];
    if (!strcmp(elems[i].name, "face") && !fe) fe = &elems[i];
  }
  if (!ve || !fe || ve->n == 0 || fe->n == 0)
    return au_msg_set(msg, AU_E_EMPTY, "%s: %lld vertices and %lld faces; a mesh needs both", path, ve ? ve->n : 0,
                      fe ? fe->n : 0);
  int ix[3] = {ply_find(ve, "x"), ply_find(ve, "y"), ply_find(ve, "z")};
  int fl = ply_find(fe, "vertex_indices");
  if (fl < 0) fl = ply_find(fe, "vertex_index");
  if (ix[0] < 0 || ix[1] < 0 || ix[2] < 0 || ve->props[ix[0]].count || ve->props[ix[1]].count || ve->props[ix[2]].count)
    return au_msg_set(msg, AU_E_FORMAT, "%s: the PLY vertex element lacks scalar x, y, z properties", path);
  if (fl < 0 || !fe->props[fl].count)
    return au_msg_set(msg, AU_E_FORMAT, "%s: the PLY face element lacks a vertex_indices list", path);
  /* Every record takes at least a byte per property, so counts beyond the body's size are a broken
   * header, not a reason to allocate gigabytes. */
  size_t body = (size_t)(in->end - in->p);
  /* A record without properties takes no bytes, so its count cannot be checked against the body:
   * refuse it rather than loop over billions of empty records. */
  for (int i = 0; i < nelems; i++)
    if (elems[i].nprops == 0 && elems[i].n > 0)
      return au_msg_set(msg, AU_E_FORMAT, "%s: PLY element '%s' has %lld records but no properties", path,
                        elems[i].name, elems[i].n);
  for (int i = 0; i < nelems; i++)
    if (elems[i].nprops > 0 && (unsigned long long)elems[i].n > body / (size_t)elems[i].nprops)
      return au_msg_set(msg, AU_E_FORMAT, "%s: the PLY header says %lld %s records, more than the file holds", path,
                        elems[i].n, elems[i].name);
  au_status st = au_io__mesh_new(path, ve->n, fe->n, out, msg);
  if (st != AU_OK) return st;
  au_mesh *m = *out;
  for (int i = 0; i < nelems; i++) {
    const ply_elem *el = &elems[i];
    for (long long r = 0; r < el->n; r++) {
      for (int k = 0; k < el->nprops; k++) {
        const ply_prop *pr = &el->props[k];
        double d;
        long long v, len = 1;
        if (pr->count && (!ply_value(in, pr->count, &d, &len) || len < 0)) goto bad;
        if (el == fe && k == fl && len != 3) {
          st = au_msg_set(msg, AU_E_FACE, "%s: face %lld has %lld corners; only triangles are supported (triangulate first)",
                          path, r, len);
          goto fail;
        }
        for (long long j = 0; j < len; j++) {
          if (!ply_value(in, pr->type, &d, &v)) goto bad;
          if (el == ve && (k == ix[0] || k == ix[1] || k == ix[2])) {
            m->X[3 * r + (k == ix[0] ? 0 : k == ix[1] ? 1 : 2)] = d;
          } else if (el == fe && k == fl) {
            if (pr->type == PT_F32 || pr->type == PT_F64 || v < 0 || v >= ve->n) {
              st = au_msg_set(msg, AU_E_INDEX, "%s: face %lld: index %.17g is out of range (%lld vertices, counted from 0)",
                              path, r, d, ve->n);
              goto fail;
            }
            m->F[3 * r + j] = (int)v;
          }
        }
      }
      continue;
    bad:
      if (in->ascii)
        st = au_msg_set(msg, AU_E_FORMAT, "%s:%d: %s %lld: malformed or missing value (truncated file?)", path, in->line,
                        el->name, r);
      else
        st = au_msg_set(msg, AU_E_FORMAT, "%s: %s %lld: the file ends early (truncated?)", path, el->name, r);
      goto fail;
    }
  }
  /* Data left over means the header's counts are wrong; trailing blanks are harmless. */
  if (in->ascii)
    while (in->p < in->end && (is_space((char)*in->p) || *in->p == '\n')) in->p++;
  if (in->p < in->end) {
    st = au_msg_set(msg, AU_E_FORMAT, "%s: %zu bytes of data after the last record the header announced", path,
                    (size_t)(in->end - in->p));
    goto fail;
  }
  return AU_OK;
fail:
  au_mesh_free(out);
  return st;
}

static au_status read_ply(const char *path, const char *buf, size_t len, au_mesh **out, au_msg *msg) {
  ply_elem *elems = calloc(PLY_MAX_ELEMS, sizeof *elems);
  if (!elems) return au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
  int nelems;
  ply_in in = {0, 0, NULL, NULL, 0};
  au_status st = ply_header(path, buf, len, elems, &nelems, &in, msg);
  if (st == AU_OK) st = ply_body(path, elems, nelems, &in, out, msg);
  free(elems);
  return st;
}

/* ---------- STL (through OpenMesh) ---------- */

/* The number of facets the file holds, counted the way STL defines them: a binary file is an
 * 80-byte header, a 32-bit little-endian count and 50 bytes per facet; otherwise it must be
 * ASCII ("solid ... facet ... endsolid"). */
static au_status stl_facets(const char *path, const char *buf, size_t len, long long *n, au_msg *msg) {
  unsigned long long cnt = 0; /* the binary header's facet count */
  if (len >= 84) {
    const unsigned char *c = (const unsigned char *)buf + 80;
    cnt = c[0] | (unsigned long long)c[1] << 8 | (unsigned long long)c[2] << 16 | (unsigned long long)c[3] << 24;
    if (84 + 50 * cnt == len) {
      *n = (long long)cnt;
      return AU_OK;
    }
  }
  au_text t = {buf, buf + len, 0};
  const char *s, *e, *ts, *te;
  int r = text_next(&t, &s, &e), first = 1;
  *n = 0;
  for (; r > 0; r = text_next(&t, &s, &e), first = 0) {
    const char *p = s;
    tok_next(&p, e, &ts, &te);
    if (first && !tok_is(ts, te, "solid")) break;
    if (tok_is(ts, te, "facet")) (*n)++;
  }
  if (r < 0 || (first && len > 0)) {
    if (len < 84)
      return au_msg_set(msg, AU_E_FORMAT, "%s: neither an ASCII STL nor a binary STL (%zu bytes, shorter than the 84-byte header)",
                        path, len);
    return au_msg_set(msg, AU_E_FORMAT,
                      "%s: not an ASCII STL, and as a binary STL its header announces %llu facets (%llu bytes) but "
                      "the file has %zu bytes (%s?)",
                      path, cnt, 84 + 50 * cnt, len, 84 + 50 * cnt > len ? "truncated" : "trailing data or not an STL");
  }
  return AU_OK;
}

/* Positions compared by their bits: a total order that also holds for NaN. */
typedef struct stl_key {
  uint64_t b[3];
  int i;
} stl_key;

static int stl_cmp(const void *pa, const void *pb) {
  const stl_key *a = pa, *b = pb;
  for (int k = 0; k < 3; k++)
    if (a->b[k] != b->b[k]) return a->b[k] < b->b[k] ? -1 : 1;
  return (a->i > b->i) - (a->i < b->i);
}

static au_status read_stl(const char *path, const char *buf, size_t len, au_mesh **out, au_msg *msg) {
  long long facets;
  au_status st = stl_facets(path, buf, len, &facets, msg);
  if (st != AU_OK) return st;
  if (facets == 0) return au_msg_set(msg, AU_E_EMPTY, "%s: the STL file has no facets", path);
  int nv, nf;
  double *X;
  int *F;
  st = au_io__openmesh_read(path, &nv, &nf, &X, &F, msg);
  if (st != AU_OK) return st;
  if (nf != facets) {
    free(X);
    free(F);
    return au_msg_set(msg, AU_E_FORMAT, "%s: the file has %lld facets but OpenMesh kept %d (it drops facets whose corners "
                      "coincide)", path, facets, nf);
  }
  /* OpenMesh merges equal positions, and gives the corners of a facet that would make an edge
   * non-manifold fresh copies of their vertices. Merging equal positions again (keeping the first)
   * undoes that, so a non-manifold STL reaches validation, which names the edge. */
  stl_key *key = malloc(sizeof *key * (size_t)(nv > 0 ? nv : 1));
  int *map = malloc(sizeof *map * (size_t)(nv > 0 ? nv : 1));
  if (!key || !map) {
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
    goto done;
  }
  for (int i = 0; i < nv; i++) {
    memcpy(key[i].b, &X[3 * i], sizeof key[i].b);
    key[i].i = i;
  }
  qsort(key, (size_t)nv, sizeof *key, stl_cmp);
  for (int i = 0, first = 0; i < nv; i++) {
    if (i > 0 && memcmp(key[i].b, key[i - 1].b, sizeof key[i].b) != 0) first = i;
    map[key[i].i] = key[first].i;
  }
  int n = 0;
  for (int i = 0; i < nv; i++) map[i] = map[i] == i ? n++ : -1 - map[i];
  for (int i = 0; i < nv; i++)
    if (map[i] < 0) map[i] = map[-1 - map[i]];
  st = au_io__mesh_new(path, n, nf, out, msg);
  if (st != AU_OK) goto done;
  for (int i = 0; i < nv; i++) memcpy(&(*out)->X[3 * map[i]], &X[3 * i], 3 * sizeof(double));
  for (int j = 0; j < 3 * nf; j++) (*out)->F[j] = map[F[j]];
done:
  free(key);
  free(map);
  free(X);
  free(F);
  return st;
}

/* A FreeSurfer magic number that is not a triangle surface's, said in words. */
static au_status fs_not_triangles(const char *path, unsigned magic, au_msg *msg) {
  return au_msg_set(msg, AU_E_FORMAT, "%s: FreeSurfer magic number 0x%06X: %s, not a triangle surface (0xFFFFFE)", path,
                    magic, magic == 0xFFFFFFu ? "a curv file (per-vertex values) or a quad surface" : "a quad surface");
}

au_status au_io_read(const char *path, au_mesh **out, au_msg *msg) { return au_io_read_meta(path, out, NULL, msg); }

au_status au_io_read_meta(const char *path, au_mesh **out, au_io_meta **meta, au_msg *msg) {
  if (msg) msg->text[0] = '\0';
  if (meta) *meta = NULL;
  if (!path || !out) return au_msg_set(msg, AU_E_ARG, "au_io_read: path and out must not be NULL");
  *out = NULL;
  char *buf;
  size_t len;
  au_status st = au_io__slurp(path, &buf, &len, msg);
  if (st != AU_OK) return st;
  unsigned magic;
  au_fmt fmt = fmt_of_content(path, buf, len, &magic);
  au_io_meta *md = calloc(1, sizeof *md);
  if (!md) {
    free(buf);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
  }
  md->format = fmt;
  /* Editors on some systems start text files with a UTF-8 byte-order mark; it is not part of the
   * first record. */
  const char *text = buf;
  if ((fmt == AU_FMT_OBJ || fmt == AU_FMT_OFF) && len >= 3 && !memcmp(buf, "\xEF\xBB\xBF", 3)) {
    text += 3;
    len -= 3;
  }
  const unsigned char *bytes = (const unsigned char *)buf;
  if (fmt == AU_FMT_NONE)
    st = au_msg_set(msg, AU_E_FORMAT, "%s: unknown mesh file extension (expected .obj, .off, .ply, .stl, .gii, "
                    ".gii.gz, or a FreeSurfer surface)", path);
  else if (len == 0)
    st = au_msg_set(msg, AU_E_EMPTY, "%s: the file is empty", path);
  else if (fmt == AU_IO_FORMAT_FREESURFER)
    st = magic == 0xFFFFFEu ? au_io__fs_read_surface(path, bytes, len, out, md, msg) : fs_not_triangles(path, magic, msg);
  else if (fmt == AU_IO_FORMAT_GIFTI)
    st = au_io__gii_read_surface(path, bytes, len, out, md, msg);
  else if (fmt == AU_FMT_OBJ)
    st = read_obj(path, text, len, out, msg);
  else if (fmt == AU_FMT_OFF)
    st = read_off(path, text, len, out, msg);
  else if (fmt == AU_FMT_PLY)
    st = read_ply(path, buf, len, out, msg);
  else
    st = read_stl(path, buf, len, out, msg);
  free(buf);
  if (st == AU_OK && meta) *meta = md;
  else au_io_meta_free(&md);
  if (st != AU_OK) au_mesh_free(out);
  return st;
}

/* ---------- writing ---------- */

/* The mode a new file gets from open(..., 0666): 0666 without the process's umask. The umask is
 * read from /proc, because umask() can only read it by changing it. */
static mode_t new_file_mode(void) {
  mode_t mask = 022;
  FILE *fp = fopen("/proc/self/status", "r");
  if (fp) {
    char line[256];
    unsigned int u;
    while (fgets(line, sizeof line, fp))
      if (sscanf(line, "Umask: %o", &u) == 1) mask = (mode_t)u;
    fclose(fp);
  }
  return 0666 & ~mask;
}


/* The file a write to path replaces: for a symbolic link, the file it names (into *out, malloc'ed, the
 * caller frees it; followed through further links, and also when that file does not exist yet), so the
 * link stays; otherwise *out = NULL, and path itself is replaced. Returns 0, or -1 (errno set) for a
 * link that cannot be followed: a loop (ELOOP), an unreadable link, a name too long, no memory. */
static int link_target(const char *path, char **out) {
  char cur[PATH_MAX], next[PATH_MAX];
  *out = NULL;
  if (snprintf(cur, sizeof cur, "%s", path) >= (int)sizeof cur) return errno = ENAMETOOLONG, -1;
  int links = 0;
  struct stat ls;
  for (; lstat(cur, &ls) == 0 && S_ISLNK(ls.st_mode); links++) {
    if (links == 40) return errno = ELOOP, -1;
    ssize_t n = readlink(cur, next, sizeof next - 1);
    if (n < 0) return -1;
    next[n] = '\0';
    const char *slash = strrchr(cur, '/');
    /* A relative target is relative to the link's directory. */
    int dirlen = next[0] == '/' || !slash ? 0 : (int)(slash - cur + 1);
    if (snprintf(cur + dirlen, sizeof cur - (size_t)dirlen, "%s", next) >= (int)(sizeof cur - (size_t)dirlen))
      return errno = ENAMETOOLONG, -1;
  }
  if (links == 0) return 0;
  size_t n = strlen(cur) + 1;
  if (!(*out = malloc(n))) return errno = ENOMEM, -1;
  memcpy(*out, cur, n);
  return 0;
}

char *au_output_target(const char *path) {
  char *real = NULL;
  if (!path) return NULL;
  /* A link that cannot be followed stays the name: writing through it fails with the reason. */
  if (link_target(path, &real) == 0 && real) return real;
  size_t n = strlen(path) + 1;
  real = malloc(n);
  if (real) memcpy(real, path, n);
  return real;
}

au_status au_temp_path(const char *path, char *buf, size_t len) {
  if (!path || !buf) return AU_E_ARG;
  char *real = NULL;
  link_target(path, &real);
  int n = snprintf(buf, len, "%s.tmp%ld", real ? real : path, (long)getpid());
  free(real);
  return n >= 0 && (size_t)n < len ? AU_OK : AU_E_ARG;
}

/* Write through emit into the temporary au_temp_path(path) beside path, then rename it over path (over
 * the file a symbolic link names, which keeps the link; a path that is not a regular file is refused). On
 * any failure the temporary is removed and an existing path is left as it was. The name is fixed for
 * the process, so that a program can remove it from a signal handler without the library keeping a
 * list; a file of that name is left only by a process of the same pid that died, so it is replaced. */
au_status au_io__write_atomic(const char *path, au_io__emit_fn emit, const void *ctx, au_msg *msg) {
  /* A device, a FIFO or a socket would be replaced by a plain file (as root, /dev/null itself). */
  struct stat st0;
  if (stat(path, &st0) == 0 && !S_ISREG(st0.st_mode))
    return au_msg_set(msg, AU_E_IO, "cannot write '%s': not a regular file (a device, FIFO, socket or directory)", path);
  char *real = NULL;
  if (link_target(path, &real) != 0)
    return au_msg_set(msg, errno == ENOMEM ? AU_E_NOMEM : AU_E_IO, "cannot write '%s': %s", path, strerror(errno));
  const char *dest = real ? real : path;
  size_t n = strlen(dest) + 32;
  char *tmp = malloc(n);
  if (!tmp) {
    free(real);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory writing '%s'", path);
  }
  /* au_temp_path(path)'s name, made from the target resolved once here. */
  snprintf(tmp, n, "%s.tmp%ld", dest, (long)getpid());
  int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0 && errno == EEXIST && unlink(tmp) == 0) fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) {
    int err = errno;
    free(tmp), free(real);
    return au_msg_set(msg, AU_E_IO, "cannot create '%s': %s", path, strerror(err));
  }
  /* The file is made private (0600); the result should have the mode a plain fopen would give it, or
   * keep the mode of the file it replaces. */
  struct stat st;
  mode_t mode = stat(dest, &st) == 0 && S_ISREG(st.st_mode) ? (st.st_mode & 07777) : new_file_mode();
  FILE *fp = fchmod(fd, mode) == 0 ? fdopen(fd, "w") : NULL;
  int err = 0;
  const char *what = "write";
  if (!fp) {
    err = errno;
    close(fd);
  } else {
    if (emit(fp, ctx) != 0 || fflush(fp) != 0 || ferror(fp) || fsync(fileno(fp)) != 0) err = errno ? errno : EIO;
    if (fclose(fp) != 0 && !err) err = errno ? errno : EIO;
  }
  if (!err && rename(tmp, dest) != 0) {
    err = errno;
    what = "replace";
  }
  if (err) {
    /* Best effort: the error being reported is the write's, and the name is ours alone. */
    unlink(tmp);
    free(tmp), free(real);
    return au_msg_set(msg, AU_E_IO, "cannot %s '%s': %s", what, path, strerror(err));
  }
  free(tmp), free(real);
  return AU_OK;
}

void au_textbuf_printf(au_textbuf *b, const char *fmt, ...) {
  if (b->bad) return;
  for (;;) {
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(b->s ? b->s + b->len : NULL, b->s ? b->cap - b->len : 0, fmt, ap);
    va_end(ap);
    if (n < 0) {
      b->bad = 1;
      return;
    }
    if (b->s && (size_t)n < b->cap - b->len) {
      b->len += (size_t)n;
      return;
    }
    size_t cap = b->cap ? 2 * b->cap : 1 << 16;
    while (cap < b->len + (size_t)n + 1) cap *= 2;
    char *q = realloc(b->s, cap);
    if (!q) {
      b->bad = 1;
      return;
    }
    b->s = q, b->cap = cap;
  }
}

void au_textbuf_free(au_textbuf *b) {
  free(b->s);
  memset(b, 0, sizeof *b);
}

typedef struct au_mesh_out {
  au_fmt fmt;
  const au_mesh *m;
  const double *P, *uv;
  int prec;
  int nvt;
  const double *vt;
  const int *Ft;
} au_mesh_out;

/* The lines of one part of the mesh: vertices [v0, v1), faces [f0, f1), each kind in its own buffer. */
typedef struct mesh_part {
  const au_mesh_out *o;
  int v0, v1, f0, f1;
  au_textbuf v, vt, f;
} mesh_part;

/* Room for n more bytes in b (growing as au_textbuf_printf does); 0 when none can be had (b->bad). */
static int textbuf_room(au_textbuf *b, size_t n) {
  if (b->bad) return 0;
  if (b->s && b->cap - b->len > n) return 1;
  size_t cap = b->cap ? 2 * b->cap : 1 << 16;
  while (cap < b->len + n + 1) cap *= 2;
  char *q = realloc(b->s, cap);
  if (!q) {
    b->bad = 1;
    return 0;
  }
  b->s = q, b->cap = cap;
  return 1;
}

/* v in decimal at p, as printf's %d; returns the characters written (at most 11). */
static int put_int(char *p, int v) {
  char d[11];
  int n = 0, k = 0;
  unsigned u = v < 0 ? 0u - (unsigned)v : (unsigned)v;
  if (v < 0) p[k++] = '-';
  do d[n++] = (char)('0' + u % 10), u /= 10;
  while (u);
  while (n) p[k++] = d[--n];
  return k;
}

/* One face line: lead, then per corner " c[k]+add" or, with t, " c[k]+add/t[k]+add", then a newline;
 * the same bytes as the printf formats they replace ("f %d/%d ...", "3 %d %d %d"), which spent most
 * of a face's time parsing the format. */
static void face_line(au_textbuf *b, char lead, const int *c, const int *t, int add) {
  if (!textbuf_room(b, 80)) return;
  char *p = b->s + b->len, *p0 = p;
  *p++ = lead;
  for (int k = 0; k < 3; k++) {
    *p++ = ' ';
    p += put_int(p, c[k] + add);
    if (t) *p++ = '/', p += put_int(p, t[k] + add);
  }
  *p++ = '\n';
  b->len += (size_t)(p - p0);
}

static void *format_part(void *arg) {
  mesh_part *w = arg;
  const au_mesh_out *o = w->o;
  const double *P = o->P;
  const int q = o->prec;
  const char *vfmt = o->fmt == AU_FMT_OBJ ? "v %.*g %.*g %.*g\n" : "%.*g %.*g %.*g\n";
  for (int i = w->v0; i < w->v1; i++) au_textbuf_printf(&w->v, vfmt, q, P[3 * i], q, P[3 * i + 1], q, P[3 * i + 2]);
  if (o->fmt == AU_FMT_OBJ && o->uv)
    for (int i = w->v0; i < w->v1; i++) au_textbuf_printf(&w->vt, "vt %.*g %.*g\n", q, o->uv[2 * i], q, o->uv[2 * i + 1]);
  if (o->fmt == AU_FMT_OBJ && o->vt && w->v0 == 0) /* per-corner rows: all in the first part */
    for (int i = 0; i < o->nvt; i++) au_textbuf_printf(&w->vt, "vt %.*g %.*g\n", q, o->vt[2 * i], q, o->vt[2 * i + 1]);
  for (int f = w->f0; f < w->f1; f++) {
    const int *c = &o->m->F[3 * f];
    if (o->fmt != AU_FMT_OBJ) face_line(&w->f, '3', c, NULL, 0);
    else if (o->uv) face_line(&w->f, 'f', c, c, 1);
    else if (o->vt) face_line(&w->f, 'f', c, &o->Ft[3 * f], 1);
    else face_line(&w->f, 'f', c, NULL, 1);
  }
  return NULL;
}

/* From this many vertices the lines are formatted in two halves on the two cores: printf's conversion
 * of doubles at 17 digits is most of a write (docs/flow.md). */
#define AU_WRITE_SPLIT_MIN 20000

static int emit_mesh(FILE *fp, const void *ctx) {
  const au_mesh_out *o = ctx;
  const au_mesh *m = o->m;
  int bad = 0;
  errno = 0;
  if (o->fmt == AU_FMT_OFF) bad |= fprintf(fp, "OFF\n%d %d 0\n", m->nv, m->nf) < 0;
  if (o->fmt == AU_FMT_PLY)
    bad |= fprintf(fp,
                   "ply\nformat ascii 1.0\ncomment written by authalic\nelement vertex %d\nproperty double x\n"
                   "property double y\nproperty double z\nelement face %d\nproperty list uchar int vertex_indices\n"
                   "end_header\n",
                   m->nv, m->nf) < 0;
  if (o->fmt == AU_FMT_OBJ) bad |= fputs("# written by authalic\n", fp) < 0;
  mesh_part w[2];
  memset(w, 0, sizeof w);
  w[0].o = w[1].o = o;
  const int split = m->nv >= AU_WRITE_SPLIT_MIN;
  w[0].v1 = w[1].v0 = split ? m->nv / 2 : m->nv, w[1].v1 = m->nv;
  w[0].f1 = w[1].f0 = split ? m->nf / 2 : m->nf, w[1].f1 = m->nf;
  if (split) au__run_pair(format_part, &w[0], &w[1]);
  else format_part(&w[0]);
  if (w[0].v.bad || w[0].vt.bad || w[0].f.bad || w[1].v.bad || w[1].vt.bad || w[1].f.bad) {
    if (!errno) errno = ENOMEM;
    bad = 1;
  }
  au_textbuf *order[6] = {&w[0].v, &w[1].v, &w[0].vt, &w[1].vt, &w[0].f, &w[1].f};
  for (int k = 0; k < 6 && !bad; k++)
    if (order[k]->len) bad |= fwrite(order[k]->s, 1, order[k]->len, fp) != order[k]->len;
  for (int k = 0; k < 6; k++) au_textbuf_free(order[k]);
  return bad;
}

au_io_write_opts au_io_write_opts_default(void) {
  au_io_write_opts o;
  o.uv = NULL;
  o.precision = 17;
  o.nvt = 0, o.vt = NULL, o.Ft = NULL;
  o.format = AU_IO_FORMAT_AUTO;
  o.meta = NULL;
  o.geometric_type = NULL;
  return o;
}

int au_io_can_write(const char *path) {
  if (!path) return 0;
  au_fmt f = fmt_of(path);
  return f == AU_FMT_OBJ || f == AU_FMT_OFF || f == AU_FMT_PLY || f == AU_IO_FORMAT_GIFTI;
}

au_status au_io_write(const char *path, const au_mesh *m, const double *P, const au_io_write_opts *opts, au_msg *msg) {
  if (msg) msg->text[0] = '\0';
  if (!path || !m || !P || m->nv < 0 || m->nf < 0 || (m->nf > 0 && !m->F))
    return au_msg_set(msg, AU_E_ARG, "au_io_write: path, mesh and positions must be given");
  au_io_write_opts def = au_io_write_opts_default();
  if (!opts) opts = &def;
  if (opts->precision < 1 || opts->precision > 17)
    return au_msg_set(msg, AU_E_ARG, "au_io_write: precision %d is outside 1..17", opts->precision);
  for (int j = 0; j < 3 * m->nf; j++)
    if (m->F[j] < 0 || m->F[j] >= m->nv)
      return au_msg_set(msg, AU_E_ARG, "au_io_write: face %d has index %d, outside 0..%d", j / 3, m->F[j], m->nv - 1);
  if (opts->vt && (opts->uv || !opts->Ft || opts->nvt <= 0))
    return au_msg_set(msg, AU_E_ARG, "au_io_write: per-corner vt needs Ft and nvt > 0, and excludes uv");
  for (int j = 0; opts->vt && j < 3 * m->nf; j++)
    if (opts->Ft[j] < 0 || opts->Ft[j] >= opts->nvt)
      return au_msg_set(msg, AU_E_ARG, "au_io_write: face %d has vt index %d, outside 0..%d", j / 3, opts->Ft[j], opts->nvt - 1);
  au_fmt fmt = opts->format != AU_IO_FORMAT_AUTO ? opts->format : fmt_of(path);
  if (fmt == AU_IO_FORMAT_FREESURFER) return au_io__fs_write_surface(path, m, P, opts->meta, msg);
  if (fmt == AU_IO_FORMAT_GIFTI) return au_io__gii_write_surface(path, m, P, opts, msg);
  if (fmt != AU_FMT_OBJ && fmt != AU_FMT_OFF && fmt != AU_FMT_PLY)
    return au_msg_set(msg, AU_E_FORMAT, "%s: cannot write this extension (expected .obj, .off, .ply, .gii or .gii.gz, "
                      "or a format given)", path);
  au_mesh_out o = {fmt, m, P, opts->uv, opts->precision, opts->nvt, opts->vt, opts->Ft};
  return au_io__write_atomic(path, emit_mesh, &o, msg);
}

typedef struct au_text_out {
  const char *buf;
  size_t len;
} au_text_out;

static int emit_text(FILE *fp, const void *ctx) {
  const au_text_out *o = ctx;
  errno = 0;
  return o->len > 0 && fwrite(o->buf, 1, o->len, fp) != o->len;
}

au_status au_io_write_text(const char *path, const char *buf, size_t len, au_msg *msg) {
  if (msg) msg->text[0] = '\0';
  if (!path || (!buf && len > 0)) return au_msg_set(msg, AU_E_ARG, "au_io_write_text: path and buf must be given");
  au_text_out o = {buf, len};
  return au_io__write_atomic(path, emit_text, &o, msg);
}

/* ---------- per-vertex values ---------- */

/* Text values: numbers separated by blanks, commas or line ends; a line starting with '#' is a
 * comment. Counted all through, so that a wrong count is reported as the whole file's. */
static au_status read_text_scalars(const char *path, const char *buf, size_t len, int n, double **out, int *count,
                                   au_msg *msg) {
  size_t cap = n > 0 ? (size_t)n : 1024, cnt = 0;
  double *v = malloc(cap * sizeof *v);
  if (!v) return au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
  au_status st = AU_OK;
  const char *p = buf, *end = buf + len;
  for (int line = 1; p < end && st == AU_OK; line++) {
    const char *e = memchr(p, '\n', (size_t)(end - p)), *q = p;
    if (!e) e = end;
    while (q < e && (*q == ' ' || *q == '\t' || *q == '\r')) q++;
    for (; q < e && *q != '#' && st == AU_OK;) {
      while (q < e && (*q == ' ' || *q == '\t' || *q == '\r' || *q == ',')) q++;
      if (q == e) break;
      const char *t = q;
      while (t < e && *t != ' ' && *t != '\t' && *t != '\r' && *t != ',') t++;
      double x;
      if (!tok_double(q, t, &x)) {
        st = au_msg_set(msg, AU_E_FORMAT, "%s: line %d: '%.*s' is not a number", path, line, (int)(t - q > 20 ? 20 : t - q), q);
      } else if (!isfinite(x)) {
        st = au_msg_set(msg, AU_E_FORMAT, "%s: line %d: value %zu is not finite", path, line, cnt + 1);
      } else if (cnt == cap && n <= 0 && cap >= (size_t)INT_MAX / 2) {
        st = au_msg_set(msg, AU_E_FORMAT, "%s: too many values", path);
      } else {
        if (cnt == cap && n <= 0) {
          double *g = realloc(v, 2 * cap * sizeof *v);
          if (!g) st = au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
          else v = g, cap *= 2;
        }
        if (cnt < cap) v[cnt] = x;
        cnt++;
      }
      q = t;
    }
    p = e < end ? e + 1 : end;
  }
  if (st == AU_OK && n > 0 && cnt != (size_t)n)
    st = au_msg_set(msg, AU_E_FORMAT, "%s: %zu values for %d vertices (one value a vertex expected)", path, cnt, n);
  if (st == AU_OK && cnt == 0) st = au_msg_set(msg, AU_E_FORMAT, "%s: no values", path);
  if (st != AU_OK) {
    free(v);
    return st;
  }
  *out = v;
  if (count) *count = (int)cnt;
  return AU_OK;
}

au_status au_io_read_scalars(const char *path, int n, double **out, int *count, au_msg *msg) {
  if (msg) msg->text[0] = '\0';
  if (out) *out = NULL;
  if (!path || !out || n < 0) return au_msg_set(msg, AU_E_ARG, "au_io_read_scalars: bad arguments");
  char *buf;
  size_t len;
  au_status st = au_io__slurp(path, &buf, &len, msg);
  if (st != AU_OK) return st;
  const unsigned char *u = (const unsigned char *)buf;
  unsigned magic;
  au_fmt fmt = fmt_of_content(path, buf, len, &magic);
  if (fmt == AU_IO_FORMAT_FREESURFER && magic == 0xFFFFFFu)
    st = au_io__fs_read_curv(path, u, len, n, out, count, msg);
  else if (fmt == AU_IO_FORMAT_FREESURFER)
    st = au_msg_set(msg, AU_E_FORMAT, "%s: a FreeSurfer surface, not per-vertex values (a curv file)", path);
  else if (fmt == AU_IO_FORMAT_GIFTI)
    st = au_io__gii_read_scalars(path, u, len, n, out, count, msg);
  else if (memchr(buf, '\0', len))
    st = au_msg_set(msg, AU_E_FORMAT, "%s: binary data, but not a FreeSurfer curv or GIfTI file", path);
  else
    st = read_text_scalars(path, buf, len, n, out, count, msg);
  free(buf);
  return st;
}

au_status au_io_write_scalars(const char *path, int n, const double *values, int nfaces, const au_io_meta *meta,
                              au_msg *msg) {
  if (msg) msg->text[0] = '\0';
  if (!path || n <= 0 || !values) return au_msg_set(msg, AU_E_ARG, "au_io_write_scalars: bad arguments");
  if (au_io__gii_name(path)) return au_io__gii_write_scalars(path, n, values, meta, msg);
  return au_io__fs_write_curv(path, n, values, nfaces, msg);
}
