/* au_io_gifti.c - GIfTI surfaces and per-vertex values through Debian's GIfTI library (giftiio).
 *
 * GIfTI (gifti.projects.nitrc.org, format 1.0) is XML: DataArrays with an intent (POINTSET for
 * vertex positions, TRIANGLE for faces, SHAPE and others for per-vertex values), a data type, an
 * index order, and data as ASCII, base64 or base64 of zlib data; metadata as name/value pairs on the
 * file and on each array; coordinate systems on the pointset.
 *
 * giftiio reads and writes by file name only and does not undo a whole-file gzip (.gii.gz, as
 * nilearn ships fsaverage), so the bytes (inflated with zlib when they start with the gzip magic)
 * go to an unlinked temporary file that giftiio opens as /proc/self/fd/N; the writer works the same
 * way backwards, and our own atomic writer puts the bytes (deflated for .gii.gz) in place.
 *
 * giftiio keeps global state (its verbosity, its XML parser's buffers) and prints its complaints on
 * stderr instead of returning them (a corrupted base64 array is reported there and then returned as
 * if read). So every use of it holds one mutex, and stderr is redirected to a temporary file while
 * giftiio runs: anything it printed while reading makes the file bad, and its first line is the
 * message (except complaints that do not concern us: see benign). Lengths announced by a file are
 * checked (a metadata-only pass first) before giftiio allocates them, ASCII arrays are counted with
 * expat (giftiio does not notice a short one), and arrays stored in external files are not read. */
#define _POSIX_C_SOURCE 200809L

#include "au_io_internal.h"

#include <expat.h>
#include <gifti_io.h>

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>
#include <zlib.h>

static pthread_mutex_t gii_lock = PTHREAD_MUTEX_INITIALIZER;

int au_io__gii_name(const char *path) {
  size_t n = path ? strlen(path) : 0;
  return (n > 4 && !strcasecmp(path + n - 4, ".gii")) || (n > 7 && !strcasecmp(path + n - 7, ".gii.gz"));
}

static int gz_name(const char *path) {
  size_t n = strlen(path);
  return n > 3 && !strcasecmp(path + n - 3, ".gz");
}

/* ---------- gzip ---------- */

/* At most this many bytes of XML per byte of a gzip file (deflate's best ratio is about 1032:1). */
#define GII_INFLATE_RATIO 1100

/* Inflate a gzip file into *out (malloc'ed, *outlen bytes plus a NUL). */
static au_status inflate_gz(const char *path, const unsigned char *buf, size_t len, unsigned char **out, size_t *outlen,
                            au_msg *msg) {
  size_t limit = len > (size_t)INT_MAX / GII_INFLATE_RATIO ? (size_t)INT_MAX : len * GII_INFLATE_RATIO + 65536;
  size_t cap = len * 4 + 65536, n = 0;
  unsigned char *o = malloc(cap + 1);
  z_stream z;
  memset(&z, 0, sizeof z);
  if (!o || inflateInit2(&z, 15 + 16) != Z_OK) {
    free(o);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
  }
  z.next_in = (unsigned char *)buf, z.avail_in = (uInt)(len > UINT_MAX ? UINT_MAX : len);
  int zs = Z_OK;
  while (zs == Z_OK) {
    if (n == cap) {
      unsigned char *g = cap < limit ? realloc(o, 2 * cap + 1) : NULL;
      if (!g) break;
      o = g, cap *= 2;
    }
    z.next_out = o + n, z.avail_out = (uInt)(cap - n > UINT_MAX ? UINT_MAX : cap - n);
    zs = inflate(&z, Z_NO_FLUSH);
    n = (size_t)(z.next_out - o);
  }
  size_t used = (size_t)(z.next_in - buf);
  inflateEnd(&z);
  au_status st = AU_OK;
  if (zs == Z_OK) st = au_msg_set(msg, AU_E_FORMAT, "%s: gzip data inflates to more than %zu bytes", path, limit);
  else if (zs == Z_BUF_ERROR) st = au_msg_set(msg, AU_E_FORMAT, "%s: the gzip data ends early (truncated?)", path);
  else if (zs != Z_STREAM_END) st = au_msg_set(msg, AU_E_FORMAT, "%s: corrupt gzip data (%s)", path, z.msg ? z.msg : "zlib error");
  else if (used != len) st = au_msg_set(msg, AU_E_FORMAT, "%s: %zu bytes after the gzip data", path, len - used);
  if (st != AU_OK) {
    free(o);
    return st;
  }
  o[n] = '\0';
  *out = o, *outlen = n;
  return AU_OK;
}

/* ---------- running giftiio ---------- */

/* An unlinked temporary file and the name giftiio can open it by. */
typedef struct gii_tmp {
  FILE *fp;
  char name[64];
} gii_tmp;

static int tmp_open(gii_tmp *t) {
  t->fp = tmpfile();
  if (!t->fp) return -1;
  snprintf(t->name, sizeof t->name, "/proc/self/fd/%d", fileno(t->fp));
  if (access(t->name, R_OK) != 0) snprintf(t->name, sizeof t->name, "/dev/fd/%d", fileno(t->fp));
  return 0;
}

/* Redirect stderr into a temporary file (giftiio's complaints); restore it with capture_end. */
typedef struct gii_capture {
  FILE *fp;
  int saved;
} gii_capture;

static int capture_begin(gii_capture *c) {
  fflush(stderr);
  c->fp = tmpfile();
  c->saved = c->fp ? dup(STDERR_FILENO) : -1;
  if (c->saved < 0 || dup2(fileno(c->fp), STDERR_FILENO) < 0) {
    if (c->saved >= 0) close(c->saved);
    if (c->fp) fclose(c->fp);
    return -1;
  }
  return 0;
}

/* Complaints of giftiio's validation about files that are fine for us: nibabel gives every array,
 * the triangles too, a coordinate system, which giftiio says only a pointset should have. */
static int benign(const char *s) { return strstr(s, "has coordsys with intent") != NULL; }

/* Restore stderr; line gets the first non-empty line giftiio printed ("" if none), without its "** ". */
static void capture_end(gii_capture *c, char *line, size_t len) {
  fflush(stderr);
  dup2(c->saved, STDERR_FILENO);
  close(c->saved);
  line[0] = '\0';
  rewind(c->fp);
  char buf[512];
  while (!line[0] && fgets(buf, sizeof buf, c->fp)) {
    char *s = buf;
    while (*s == '*' || *s == ' ' || *s == '-' || *s == '+') s++;
    s[strcspn(s, "\r\n")] = '\0';
    if (*s && !benign(s)) snprintf(line, len, "%.200s", s);
  }
  fclose(c->fp);
}

/* The most bytes a file of len bytes can honestly hold as data (base64 of deflated data at best). */
static long long data_bound(size_t len) { return (long long)len * GII_INFLATE_RATIO + 65536; }

/* Check what the arrays of a metadata-only read announce before giftiio allocates it: no external
 * data files, no more values than a file of len bytes can hold. *ascii: 1 if an array is ASCII. */
static au_status check_arrays(const char *path, const gifti_image *g, size_t len, int *ascii, au_msg *msg) {
  long long total = 0;
  *ascii = 0;
  for (int i = 0; i < g->numDA; i++) {
    const giiDataArray *d = g->darray[i];
    if (d->encoding == GIFTI_ENCODING_EXTBIN || (d->ext_fname && d->ext_fname[0]))
      return au_msg_set(msg, AU_E_FORMAT, "%s: GIfTI array %d keeps its data in an external file, which is not read",
                        path, i);
    if (d->nvals < 0 || d->nbyper <= 0 || d->nvals > data_bound(len) / d->nbyper ||
        (total += d->nvals * d->nbyper) > data_bound(len))
      return au_msg_set(msg, AU_E_FORMAT, "%s: GIfTI array %d announces %lld values, more than a %zu-byte file holds",
                        path, i, d->nvals, len);
    *ascii |= d->encoding == GIFTI_ENCODING_ASCII;
  }
  return AU_OK;
}

/* Before giftiio sees a document, expat (the XML library giftiio itself uses) checks it: giftiio
 * crashes on some documents that are not well-formed (an end tag that does not match its start
 * tag) or where GIfTI's elements sit under the wrong parent, so those are refused here, each element
 * checked against the parent the GIfTI DTD gives it. The same pass counts the numbers in each
 * DataArray's <Data>: giftiio reads ASCII data without checking that it holds as many numbers as the
 * dimensions say, and leaves the rest of its buffer as it was. */
#define XML_MAX_DEPTH 16
#define XML_MAX_DA 4096

typedef struct xml_scan {
  long long bound;                  /* the most values the document can hold (data_bound) */
  size_t len;                       /* the document's size in bytes */
  const char *stack[XML_MAX_DEPTH]; /* the open elements' names (static strings), or "" for others */
  int depth, bad, da, in_data, in_tok;
  char what[160];                   /* what is wrong, when bad */
  long long n[XML_MAX_DA];          /* n [0..da-1]: numbers in array k's data */
} xml_scan;

/* The parent each GIfTI element must have ("" for the root). */
static const char *const gii_parent[][2] = {
    {"GIFTI", ""},           {"MetaData", "GIFTI"},      {"MetaData", "DataArray"}, {"MD", "MetaData"},
    {"Name", "MD"},          {"Value", "MD"},            {"LabelTable", "GIFTI"},   {"Label", "LabelTable"},
    {"DataArray", "GIFTI"},  {"Data", "DataArray"},      {"CoordinateSystemTransformMatrix", "DataArray"},
    {"DataSpace", "CoordinateSystemTransformMatrix"},   {"TransformedSpace", "CoordinateSystemTransformMatrix"},
    {"MatrixData", "CoordinateSystemTransformMatrix"}};

/* A DataArray's attributes, checked before giftiio reads them: giftiio allocates an array whose data
 * is in an external file even when asked for the metadata only, so a file that names one, or
 * announces more values than it can hold, is refused here. Returns 0, or -1 with c->what set. */
static int check_da_attrs(xml_scan *c, const XML_Char **attr) {
  double nvals = 1;
  for (int k = 0; attr[k] && attr[k + 1]; k += 2) {
    const char *a = attr[k], *v = attr[k + 1];
    if ((!strcmp(a, "ExternalFileName") && v[0]) || (!strcmp(a, "Encoding") && !strcmp(v, "ExternalFileBinary"))) {
      snprintf(c->what, sizeof c->what, "array %d keeps its data in an external file, which is not read", c->da);
      return -1;
    }
    if (!strncmp(a, "Dim", 3) && a[3] >= '0' && a[3] <= '5' && !a[4]) {
      double d = strtod(v, NULL);
      if (d > 0) nvals *= d;
    }
  }
  if (nvals > (double)c->bound) {
    snprintf(c->what, sizeof c->what, "array %d announces %.0f values, more than a %zu-byte file holds", c->da, nvals,
             c->len);
    return -1;
  }
  return 0;
}

static void XMLCALL on_start(void *u, const XML_Char *name, const XML_Char **attr) {
  xml_scan *c = u;
  const char *parent = c->depth ? c->stack[c->depth - 1] : "", *known = NULL;
  int placed = 0;
  for (size_t k = 0; k < sizeof gii_parent / sizeof gii_parent[0]; k++)
    if (!strcmp(name, gii_parent[k][0])) known = gii_parent[k][0], placed |= !strcmp(parent, gii_parent[k][1]);
  if (!c->bad && (!known || !placed || c->depth == XML_MAX_DEPTH || (!strcmp(name, "DataArray") && c->da == XML_MAX_DA)))
    c->bad = 1, snprintf(c->what, sizeof c->what, "element <%.40s> %s <%.40s>", name,
                         known ? "is not allowed under" : "is not GIfTI's, under", *parent ? parent : "(the root)");
  if (!c->bad && !strcmp(name, "DataArray") && check_da_attrs(c, attr) != 0) c->bad = 1;
  if (c->bad) return;
  c->stack[c->depth++] = known;
  if (!strcmp(name, "DataArray")) c->n[c->da++] = 0;
  else if (!strcmp(name, "Data")) c->in_data = 1, c->in_tok = 0;
}

static void XMLCALL on_end(void *u, const XML_Char *name) {
  xml_scan *c = u;
  if (c->bad) return;
  c->depth--;
  if (!strcmp(name, "Data")) c->in_data = 0;
}

static void XMLCALL on_text(void *u, const XML_Char *s, int len) {
  xml_scan *c = u;
  if (c->bad || !c->in_data) return;
  for (int i = 0; i < len; i++) {
    int space = s[i] == ' ' || s[i] == '\t' || s[i] == '\n' || s[i] == '\r';
    if (!space && !c->in_tok) c->n[c->da - 1]++;
    c->in_tok = !space;
  }
}

/* Scan the document xml[0..len) into *c (see xml_scan). */
static au_status xml_check(const char *path, const char *xml, size_t len, xml_scan *c, au_msg *msg) {
  memset(c, 0, sizeof *c);
  c->bound = data_bound(len), c->len = len;
  XML_Parser p = XML_ParserCreate(NULL);
  if (!p) return au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
  XML_SetUserData(p, c);
  XML_SetElementHandler(p, on_start, on_end);
  XML_SetCharacterDataHandler(p, on_text);
  au_status st = AU_OK;
  if (len > INT_MAX || XML_Parse(p, xml, (int)len, 1) != XML_STATUS_OK)
    st = au_msg_set(msg, AU_E_FORMAT, "%s: not well-formed XML (line %lu: %s)", path,
                    (unsigned long)XML_GetCurrentLineNumber(p), XML_ErrorString(XML_GetErrorCode(p)));
  else if (c->bad)
    st = au_msg_set(msg, AU_E_FORMAT, "%s: %s%s", path, c->what[0] == 'e' ? "not a GIfTI document: " : "GIfTI ",
                    c->what);
  XML_ParserFree(p);
  return st;
}

/* Every ASCII array of g holds exactly as many numbers as it announces. */
static au_status check_ascii(const char *path, const gifti_image *g, const xml_scan *c, au_msg *msg) {
  for (int i = 0; i < g->numDA; i++)
    if (g->darray[i]->encoding == GIFTI_ENCODING_ASCII && (i >= c->da || c->n[i] != g->darray[i]->nvals))
      return au_msg_set(msg, AU_E_FORMAT, "%s: GIfTI array %d holds %lld numbers but its dimensions announce %lld",
                        path, i, i < c->da ? c->n[i] : 0, g->darray[i]->nvals);
  return AU_OK;
}

/* giftiio's reading of the XML document xml[0..len), which it opens as name: a metadata-only pass
 * checks what the arrays announce, then the real read. Called with gii_lock held. */
static au_status gii_parse(const char *path, const char *name, const char *xml, size_t len, gifti_image **out,
                           au_msg *msg) {
  char said[256];
  gii_capture cap;
  xml_scan *scan = malloc(sizeof *scan);
  if (!scan) return au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
  au_status st = xml_check(path, xml, len, scan, msg);
  if (st != AU_OK) {
    free(scan);
    return st;
  }
  if (capture_begin(&cap) != 0) {
    free(scan);
    return au_msg_set(msg, AU_E_IO, "%s: cannot redirect giftiio's messages", path);
  }
  gifti_image *g = gifti_read_image(name, 0);
  capture_end(&cap, said, sizeof said);
  if (!g || said[0]) {
    gifti_free_image(g);
    free(scan);
    return au_msg_set(msg, AU_E_FORMAT, "%s: not a GIfTI file giftiio can read%s%s", path, said[0] ? ": " : "", said);
  }
  int ascii = 0;
  st = check_arrays(path, g, len, &ascii, msg);
  if (st == AU_OK && ascii) st = check_ascii(path, g, scan, msg);
  gifti_free_image(g);
  free(scan);
  if (st != AU_OK) return st;
  if (capture_begin(&cap) != 0) return au_msg_set(msg, AU_E_IO, "%s: cannot redirect giftiio's messages", path);
  g = gifti_read_image(name, 1);
  capture_end(&cap, said, sizeof said);
  if (!g || said[0] || !gifti_image_has_data(g)) {
    gifti_free_image(g);
    return au_msg_set(msg, AU_E_FORMAT, "%s: GIfTI data cannot be read%s%s", path, said[0] ? ": " : "", said);
  }
  *out = g;
  return AU_OK;
}

/* Read a GIfTI file's bytes (gzip or XML) into a gifti_image (free with gifti_free_image). */
static au_status gii_load(const char *path, const unsigned char *buf, size_t len, gifti_image **out, au_msg *msg) {
  unsigned char *xml = NULL;
  size_t n = len;
  *out = NULL;
  if (len >= 2 && buf[0] == 0x1f && buf[1] == 0x8b) {
    au_status st = inflate_gz(path, buf, len, &xml, &n, msg);
    if (st != AU_OK) return st;
    buf = xml;
  }
  gii_tmp t;
  au_status st = AU_OK;
  if (tmp_open(&t) != 0) st = au_msg_set(msg, AU_E_IO, "%s: cannot create a temporary file: %s", path, strerror(errno));
  else if (fwrite(buf, 1, n, t.fp) != n || fflush(t.fp) != 0)
    st = au_msg_set(msg, AU_E_IO, "%s: cannot write a temporary file: %s", path, strerror(errno));
  if (st == AU_OK) {
    pthread_mutex_lock(&gii_lock);
    st = gii_parse(path, t.name, (const char *)buf, n, out, msg);
    pthread_mutex_unlock(&gii_lock);
  }
  if (t.fp) fclose(t.fp);
  free(xml);
  return st;
}

/* ---------- arrays ---------- */

/* Element k (in storage order) of an array's data, as a double; NAN for a type not handled. */
static double da_value(const giiDataArray *d, long long k) {
  switch (d->datatype) {
    case NIFTI_TYPE_FLOAT32: return ((const float *)d->data)[k];
    case NIFTI_TYPE_FLOAT64: return ((const double *)d->data)[k];
    case NIFTI_TYPE_INT32: return ((const int32_t *)d->data)[k];
    case NIFTI_TYPE_UINT32: return ((const uint32_t *)d->data)[k];
    case NIFTI_TYPE_INT16: return ((const int16_t *)d->data)[k];
    case NIFTI_TYPE_UINT16: return ((const uint16_t *)d->data)[k];
    case NIFTI_TYPE_INT8: return ((const int8_t *)d->data)[k];
    case NIFTI_TYPE_UINT8: return ((const uint8_t *)d->data)[k];
    case NIFTI_TYPE_INT64: return (double)((const int64_t *)d->data)[k];
    case NIFTI_TYPE_UINT64: return (double)((const uint64_t *)d->data)[k];
    default: return NAN;
  }
}

/* 1 if da_value reads this data type. */
static int type_read(int datatype) {
  switch (datatype) {
    case NIFTI_TYPE_FLOAT32: case NIFTI_TYPE_FLOAT64: case NIFTI_TYPE_INT32: case NIFTI_TYPE_UINT32:
    case NIFTI_TYPE_INT16: case NIFTI_TYPE_UINT16: case NIFTI_TYPE_INT8: case NIFTI_TYPE_UINT8:
    case NIFTI_TYPE_INT64: case NIFTI_TYPE_UINT64: return 1;
    default: return 0;
  }
}

/* Check that d is a rows x 3 array (or, cols == 1, a vector of rows values) with data of a type
 * da_value reads; *rows gets the row count. */
static au_status da_shape(const char *path, const giiDataArray *d, const char *what, int cols, long long *rows,
                          au_msg *msg) {
  int nd = d->num_dim;
  long long r = nd >= 1 ? d->dims[0] : 0, c = nd >= 2 ? d->dims[1] : 1;
  int ok = nd >= 1 && nd <= 2 && r > 0 && c == cols && r * c == d->nvals && r <= INT_MAX / 3 && d->data;
  if (!ok && cols == 1 && nd == 2 && d->dims[0] == 1 && d->dims[1] > 0 && d->data) /* a 1 x n row */
    r = d->dims[1], ok = r == d->nvals && r <= INT_MAX / 3;
  if (!ok)
    return au_msg_set(msg, AU_E_FORMAT, "%s: the %s array has %d dimension%s (%d x %d), not n x %d", path, what, nd,
                      nd == 1 ? "" : "s", nd >= 1 ? d->dims[0] : 0, nd >= 2 ? d->dims[1] : 1, cols);
  int nbyper = 0, swap = 0;
  if (!type_read(d->datatype) || gifti_datatype_sizes(d->datatype, &nbyper, &swap) != 0 || nbyper != d->nbyper)
    return au_msg_set(msg, AU_E_FORMAT, "%s: the %s array has data type %s, which is not read", path, what,
                      gifti_datatype2str(d->datatype));
  *rows = r;
  return AU_OK;
}

/* Element (r, c) of a rows x cols array in its index order. */
static double da_at(const giiDataArray *d, long long rows, int cols, long long r, int c) {
  return da_value(d, d->ind_ord == GIFTI_IND_ORD_COL_MAJOR ? c * rows + r : r * cols + c);
}

/* The one array of the given intent; NULL with a message when there is none or more than one. */
static giiDataArray *find_one(const char *path, gifti_image *g, int intent, const char *what, au_msg *msg) {
  giiDataArray *found = NULL;
  int n = 0;
  for (int i = 0; i < g->numDA; i++)
    if (g->darray[i] && g->darray[i]->intent == intent) n++, found = found ? found : g->darray[i];
  if (n == 1) return found;
  au_msg_set(msg, AU_E_FORMAT, "%s: %d %s arrays; a GIfTI surface has one%s", path, n, what,
             n == 0 && intent == NIFTI_INTENT_POINTSET ? " (values such as .shape.gii belong to --density or --attr)" : "");
  return NULL;
}

/* Drop the arrays' data, keeping the metadata for an output. */
static void drop_data(gifti_image *g) {
  for (int i = 0; i < g->numDA; i++) {
    free(g->darray[i]->data);
    g->darray[i]->data = NULL;
  }
}

au_status au_io__gii_read_surface(const char *path, const unsigned char *buf, size_t len, au_mesh **out,
                                  au_io_meta *meta, au_msg *msg) {
  gifti_image *g;
  au_status st = gii_load(path, buf, len, &g, msg);
  if (st != AU_OK) return st;
  giiDataArray *P = find_one(path, g, NIFTI_INTENT_POINTSET, "POINTSET", msg), *T = NULL;
  if (P) T = find_one(path, g, NIFTI_INTENT_TRIANGLE, "TRIANGLE", msg);
  long long nv = 0, nf = 0;
  st = !P || !T ? AU_E_FORMAT : da_shape(path, P, "POINTSET", 3, &nv, msg);
  if (st == AU_OK) st = da_shape(path, T, "TRIANGLE", 3, &nf, msg);
  if (st == AU_OK) st = au_io__mesh_new(path, nv, nf, out, msg);
  for (long long i = 0; st == AU_OK && i < nv; i++)
    for (int c = 0; c < 3; c++) (*out)->X[3 * i + c] = da_at(P, nv, 3, i, c);
  for (long long f = 0; st == AU_OK && f < nf; f++)
    for (int c = 0; c < 3 && st == AU_OK; c++) {
      double v = da_at(T, nf, 3, f, c);
      if (!(v >= 0 && v < (double)nv && v == floor(v)))
        st = au_msg_set(msg, AU_E_INDEX, "%s: face %lld: index %g is out of range (%lld vertices, counted from 0)",
                        path, f, v, nv);
      else (*out)->F[3 * f + c] = (int)v;
    }
  if (st != AU_OK) {
    au_mesh_free(out);
    gifti_free_image(g);
    return st;
  }
  drop_data(g);
  meta->gii = g;
  return AU_OK;
}

au_status au_io__gii_read_scalars(const char *path, const unsigned char *buf, size_t len, int n, double **out,
                                  int *count, au_msg *msg) {
  gifti_image *g;
  au_status st = gii_load(path, buf, len, &g, msg);
  if (st != AU_OK) return st;
  giiDataArray *d = NULL;
  int nd = 0;
  for (int i = 0; i < g->numDA; i++)
    if (g->darray[i]->intent != NIFTI_INTENT_POINTSET && g->darray[i]->intent != NIFTI_INTENT_TRIANGLE)
      nd++, d = d ? d : g->darray[i];
  long long rows = 0;
  if (nd != 1)
    st = au_msg_set(msg, AU_E_FORMAT, "%s: %d arrays of per-vertex values; one expected%s", path, nd,
                    nd == 0 ? " (a surface file?)" : "");
  else st = da_shape(path, d, "values", 1, &rows, msg);
  if (st == AU_OK && n > 0 && rows != n)
    st = au_msg_set(msg, AU_E_FORMAT, "%s: %lld values for %d vertices (one value a vertex expected)", path, rows, n);
  double *v = st == AU_OK ? malloc((size_t)rows * sizeof *v) : NULL;
  if (st == AU_OK && !v) st = au_msg_set(msg, AU_E_NOMEM, "out of memory reading '%s'", path);
  for (long long i = 0; st == AU_OK && i < rows; i++)
    if (!isfinite(v[i] = da_value(d, i))) st = au_msg_set(msg, AU_E_FORMAT, "%s: value %lld is not finite", path, i + 1);
  gifti_free_image(g);
  if (st != AU_OK) {
    free(v);
    return st;
  }
  *out = v;
  if (count) *count = (int)rows;
  return AU_OK;
}

const char *au_io__gii_meta_get(const void *gii, const char *name) {
  const gifti_image *g = gii;
  const char *v = gifti_get_meta_value(&g->meta, name);
  for (int i = 0; !v && i < g->numDA; i++)
    if (g->darray[i]->intent == NIFTI_INTENT_POINTSET) v = gifti_get_meta_value(&g->darray[i]->meta, name);
  return v;
}

void au_io__gii_free(void *gii) {
  if (gii) gifti_free_image(gii);
}

/* ---------- writing ---------- */

typedef struct gii_bytes {
  const unsigned char *b;
  size_t n;
  int gz;
} gii_bytes;

/* The XML as it is, or gzip-compressed (for .gii.gz). */
static int emit_bytes(FILE *fp, const void *ctx) {
  const gii_bytes *o = ctx;
  errno = 0;
  if (!o->gz) return fwrite(o->b, 1, o->n, fp) != o->n;
  z_stream z;
  memset(&z, 0, sizeof z);
  if (deflateInit2(&z, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
    errno = ENOMEM;
    return 1;
  }
  unsigned char out[65536];
  z.next_in = (unsigned char *)o->b, z.avail_in = (uInt)o->n;
  int zs = Z_OK, bad = 0;
  while (zs == Z_OK && !bad) {
    z.next_out = out, z.avail_out = sizeof out;
    zs = deflate(&z, Z_FINISH);
    size_t k = sizeof out - z.avail_out;
    bad = (zs != Z_OK && zs != Z_STREAM_END) || fwrite(out, 1, k, fp) != k;
  }
  deflateEnd(&z);
  if (bad && !errno) errno = EIO;
  return bad;
}

/* Let giftiio write g into a temporary file, then put those bytes at path atomically. */
static au_status gii_store(const char *path, gifti_image *g, au_msg *msg) {
  for (int i = 0; i < g->numDA; i++)
    g->darray[i]->encoding = GIFTI_ENCODING_B64GZ, g->darray[i]->endian = gifti_get_this_endian();
  gii_tmp t;
  if (tmp_open(&t) != 0) return au_msg_set(msg, AU_E_IO, "%s: cannot create a temporary file: %s", path, strerror(errno));
  char said[256];
  gii_capture cap;
  pthread_mutex_lock(&gii_lock);
  int rc = -1;
  said[0] = '\0';
  if (capture_begin(&cap) == 0) {
    rc = gifti_write_image(g, t.name, 1);
    capture_end(&cap, said, sizeof said);
  }
  pthread_mutex_unlock(&gii_lock);
  au_status st = AU_OK;
  long size = rc == 0 && fseek(t.fp, 0, SEEK_END) == 0 ? ftell(t.fp) : -1;
  unsigned char *b = size > 0 ? malloc((size_t)size) : NULL;
  if (rc != 0 || size <= 0)
    st = au_msg_set(msg, AU_E_IO, "%s: giftiio could not write the file%s%s", path, said[0] ? ": " : "", said);
  else if (!b) st = au_msg_set(msg, AU_E_NOMEM, "out of memory writing '%s'", path);
  else if (fseek(t.fp, 0, SEEK_SET) != 0 || fread(b, 1, (size_t)size, t.fp) != (size_t)size)
    st = au_msg_set(msg, AU_E_IO, "%s: cannot read back giftiio's output", path);
  fclose(t.fp);
  if (st == AU_OK) {
    gii_bytes o = {b, (size_t)size, gz_name(path)};
    st = au_io__write_atomic(path, emit_bytes, &o, msg);
  }
  free(b);
  return st;
}

/* A new image of arrays with the given intents, types and shapes (rows x cols[i], cols 1: a vector),
 * data allocated; NULL when out of memory. */
static gifti_image *gii_new(int nda, const int *intent, const int *type, const int *rows, const int *cols) {
  int dims[2] = {rows[0], cols[0]};
  gifti_image *g = gifti_create_image(nda, intent[0], type[0], cols[0] > 1 ? 2 : 1, dims, 1);
  for (int i = 1; g && i < nda; i++) {
    giiDataArray *d = g->darray[i];
    d->intent = intent[i], d->datatype = type[i], d->num_dim = cols[i] > 1 ? 2 : 1;
    d->dims[0] = rows[i], d->dims[1] = cols[i] > 1 ? cols[i] : 0;
    d->nvals = (long long)rows[i] * cols[i];
    free(d->data);
    d->data = NULL;
    if (gifti_update_nbyper(g) != 0 || gifti_alloc_DA_data(g, &i, 1) != 0) {
      gifti_free_image(g);
      return NULL;
    }
  }
  return g;
}

/* The input's metadata into the output: the file's name/value pairs (except those that say when,
 * by whom and with which library the input was written), and for a surface the pointset's pairs
 * and coordinate systems and the triangles' pairs. Returns 0, or -1 when out of memory. */
static int copy_meta(gifti_image *g, const gifti_image *in, int surface) {
  static const char *const skip[] = {"Date", "UserName", "gifticlib-version"};
  for (int k = 0; k < in->meta.length; k++) {
    int keep = in->meta.name[k] && in->meta.value[k];
    for (size_t s = 0; keep && s < sizeof skip / sizeof skip[0]; s++) keep = strcmp(in->meta.name[k], skip[s]) != 0;
    if (keep && gifti_add_to_meta(&g->meta, in->meta.name[k], in->meta.value[k], 1) != 0) return -1;
  }
  for (int i = 0; i < in->numDA; i++) {
    const giiDataArray *d = in->darray[i];
    giiDataArray *o = NULL;
    for (int j = 0; j < g->numDA; j++)
      if (g->darray[j]->intent == d->intent) o = g->darray[j];
    if (!surface) { /* values: where the surface lies is said in the file's metadata */
      const char *names[2] = {"AnatomicalStructurePrimary", "AnatomicalStructureSecondary"};
      for (int k = 0; k < 2; k++) {
        const char *v = d->intent == NIFTI_INTENT_POINTSET ? gifti_get_meta_value(&d->meta, names[k]) : NULL;
        if (v && !gifti_get_meta_value(&g->meta, names[k]) && gifti_add_to_meta(&g->meta, names[k], v, 1) != 0) return -1;
      }
      continue;
    }
    if (!o || (d->intent != NIFTI_INTENT_POINTSET && d->intent != NIFTI_INTENT_TRIANGLE)) continue;
    if (gifti_copy_nvpairs(&o->meta, &d->meta) != 0) return -1;
    for (int c = 0; d->intent == NIFTI_INTENT_POINTSET && c < d->numCS; c++) {
      giiCoordSystem **cs = realloc(o->coordsys, (size_t)(o->numCS + 1) * sizeof *cs);
      if (!cs) return -1;
      o->coordsys = cs;
      if (!(cs[o->numCS] = gifti_copy_CoordSystem(d->coordsys[c]))) return -1;
      o->numCS++;
    }
  }
  return 0;
}

au_status au_io__gii_write_surface(const char *path, const au_mesh *m, const double *P, const au_io_write_opts *opts,
                                   au_msg *msg) {
  au_status cst = au_io__check_float32(path, m->nv, P, "a GIfTI pointset", msg);
  if (cst != AU_OK) return cst;
  const int intent[2] = {NIFTI_INTENT_POINTSET, NIFTI_INTENT_TRIANGLE}, type[2] = {NIFTI_TYPE_FLOAT32, NIFTI_TYPE_INT32};
  const int rows[2] = {m->nv, m->nf}, cols[2] = {3, 3};
  pthread_mutex_lock(&gii_lock);
  gifti_image *g = gii_new(2, intent, type, rows, cols);
  const au_io_meta *meta = opts->meta;
  int bad = !g || (meta && meta->gii && copy_meta(g, meta->gii, 1) != 0) ||
            (opts->geometric_type && gifti_add_to_meta(&g->darray[0]->meta, "GeometricType", opts->geometric_type, 1));
  pthread_mutex_unlock(&gii_lock);
  if (bad) {
    gifti_free_image(g);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory writing '%s'", path);
  }
  float *x = g->darray[0]->data;
  int32_t *f = g->darray[1]->data;
  for (size_t i = 0; i < 3 * (size_t)m->nv; i++) x[i] = (float)P[i];
  for (size_t j = 0; j < 3 * (size_t)m->nf; j++) f[j] = m->F[j];
  au_status st = gii_store(path, g, msg);
  pthread_mutex_lock(&gii_lock);
  gifti_free_image(g);
  pthread_mutex_unlock(&gii_lock);
  return st;
}

au_status au_io__gii_write_scalars(const char *path, int n, const double *values, const au_io_meta *meta,
                                   au_msg *msg) {
  for (int i = 0; i < n; i++)
    if (!au_io__fits_float(values[i]))
      return au_msg_set(msg, AU_E_FORMAT, "%s: value %d (%g) does not fit GIfTI's float32", path, i + 1, values[i]);
  const int intent = NIFTI_INTENT_SHAPE, type = NIFTI_TYPE_FLOAT32, one = 1;
  pthread_mutex_lock(&gii_lock);
  gifti_image *g = gii_new(1, &intent, &type, &n, &one);
  int bad = !g || (meta && meta->gii && copy_meta(g, meta->gii, 0) != 0);
  pthread_mutex_unlock(&gii_lock);
  if (bad) {
    gifti_free_image(g);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory writing '%s'", path);
  }
  float *v = g->darray[0]->data;
  for (int i = 0; i < n; i++) v[i] = (float)values[i];
  au_status st = gii_store(path, g, msg);
  pthread_mutex_lock(&gii_lock);
  gifti_free_image(g);
  pthread_mutex_unlock(&gii_lock);
  return st;
}
