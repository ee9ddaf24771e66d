/* test_neuro.c - neuroimaging formats (issue 19): FreeSurfer surfaces and curv files, GIfTI through
 * giftiio, metadata carried from input to output, per-vertex values, and the per-vertex areal
 * distortion. Files written by other programs (nibabel, Workbench) are checked in tests/cli/neuro.sh. */
#define _POSIX_C_SOURCE 200809L

#include "au_io.h"
#include "au_mesh.h"
#include "au_metrics.h"
#include "au_test.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char g_dir[1200];

static int make_dir(const char *case_name) {
  char base[1024];
  snprintf(base, sizeof base, "%s/neuro_tmp", AU_BINARY_DIR);
  mkdir(base, 0777);
  snprintf(g_dir, sizeof g_dir, "%s/%s", base, case_name);
  mkdir(g_dir, 0777);
  struct stat st;
  return stat(g_dir, &st) == 0 && S_ISDIR(st.st_mode);
}

static const char *tp(const char *name) {
  static char buf[4][1400];
  static int k;
  k = (k + 1) % 4;
  snprintf(buf[k], sizeof buf[k], "%s/%s", g_dir, name);
  return buf[k];
}

static int put(const char *path, const void *data, size_t len) {
  FILE *fp = fopen(path, "wb");
  if (!fp) return -1;
  size_t n = fwrite(data, 1, len, fp);
  return fclose(fp) == 0 && n == len ? 0 : -1;
}

/* The whole file into a malloc'ed buffer; NULL if it cannot be read. */
static unsigned char *slurp(const char *path, size_t *len) {
  FILE *fp = fopen(path, "rb");
  if (!fp) return NULL;
  fseek(fp, 0, SEEK_END);
  long n = ftell(fp);
  rewind(fp);
  unsigned char *b = malloc((size_t)n + 1);
  if (b && fread(b, 1, (size_t)n, fp) != (size_t)n) free(b), b = NULL;
  if (b) b[n] = 0; /* so that a text file can be searched with strstr */
  fclose(fp);
  *len = (size_t)n;
  return b;
}

static void be32(unsigned char *p, uint32_t u) {
  p[0] = (unsigned char)(u >> 24), p[1] = (unsigned char)(u >> 16), p[2] = (unsigned char)(u >> 8), p[3] = (unsigned char)u;
}

static void be_float(unsigned char *p, float f) {
  uint32_t u;
  memcpy(&u, &f, 4);
  be32(p, u);
}

/* An octahedron with float-exact coordinates (radius 2). */
static const double OCT_X[18] = {2, 0, 0, -2, 0, 0, 0, 2, 0, 0, -2, 0, 0, 0, 2, 0, 0, -2};
static const int OCT_F[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
static const char FOOTER[] = "\x00\x00\x00\x02\x00\x00\x00\x00\x00\x00\x00\x14valid = 1  # volume info valid\n"
                             "filename = T1.mgz\nvolume = 256 256 256\nvoxelsize = 1 1 1\nxras = -1 0 0\n"
                             "yras = 0 0 -1\nzras = 0 1 0\ncras = 5.5 18 0\n";

/* A FreeSurfer surface of the octahedron as FreeSurfer writes it, with the footer above; *len bytes.
 * lie_nv: the vertex count the header announces (6 for the truth). */
static unsigned char *fs_octahedron(size_t *len, int lie_nv) {
  const char *stamp = "created by tester on Tue Dec  1 00:00:00 2026\n\n";
  size_t hs = 3 + strlen(stamp), n = hs + 8 + 72 + 96 + sizeof FOOTER - 1;
  unsigned char *b = malloc(n), *p = b;
  p[0] = p[1] = 0xff, p[2] = 0xfe, p += 3;
  memcpy(p, stamp, strlen(stamp)), p += strlen(stamp);
  be32(p, (uint32_t)lie_nv), be32(p + 4, 8), p += 8;
  for (int i = 0; i < 18; i++, p += 4) be_float(p, (float)OCT_X[i]);
  for (int i = 0; i < 24; i++, p += 4) be32(p, (uint32_t)OCT_F[i]);
  memcpy(p, FOOTER, sizeof FOOTER - 1);
  *len = n;
  return b;
}

static au_mesh *octahedron(void) {
  au_mesh *m = NULL;
  if (au_mesh_alloc(6, 8, &m) != AU_OK) return NULL;
  memcpy(m->X, OCT_X, sizeof OCT_X);
  memcpy(m->F, OCT_F, sizeof OCT_F);
  return m;
}

/* ---------- FreeSurfer ---------- */

/* Found by its magic number under a FreeSurfer name; vertices, faces, the created-by line kept. */
static int t_fs_read(void) {
  AU_CHECK(make_dir("fs_read"));
  size_t n;
  unsigned char *b = fs_octahedron(&n, 6);
  AU_CHECK(put(tp("lh.white"), b, n) == 0);
  free(b);
  au_mesh *m = NULL;
  au_io_meta *meta = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_io_read_meta(tp("lh.white"), &m, &meta, &msg), AU_OK, &msg);
  AU_CHECK_INT(m->nv, ==, 6);
  AU_CHECK_INT(m->nf, ==, 8);
  for (int i = 0; i < 18; i++) AU_CHECK_DBL(m->X[i], ==, OCT_X[i]);
  AU_CHECK(memcmp(m->F, OCT_F, sizeof OCT_F) == 0);
  AU_CHECK_INT(au_io_meta_format(meta), ==, AU_IO_FORMAT_FREESURFER);
  AU_CHECK(strcmp(au_io_meta_get(meta, "created_by"), "created by tester on Tue Dec  1 00:00:00 2026") == 0);
  au_topo *t = NULL;
  AU_CHECK_STATUS(au_mesh_validate(m, NULL, &t, &msg), AU_OK, &msg);
  au_topo_free(&t);
  au_mesh_free(&m);
  au_io_meta_free(&meta);
  AU_CHECK(meta == NULL);
  return 0;
}

/* FreeSurfer -> ours -> FreeSurfer: everything after the created-by line is the same bytes (the
 * positions are float32 both ways, the faces and the footer untouched). */
static int t_fs_roundtrip(void) {
  AU_CHECK(make_dir("fs_roundtrip"));
  size_t n, n2;
  unsigned char *b = fs_octahedron(&n, 6);
  AU_CHECK(put(tp("rh.white"), b, n) == 0);
  au_mesh *m = NULL;
  au_io_meta *meta = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_io_read_meta(tp("rh.white"), &m, &meta, &msg), AU_OK, &msg);
  au_io_write_opts o = au_io_write_opts_default();
  o.format = AU_IO_FORMAT_FREESURFER, o.meta = meta;
  AU_CHECK_STATUS(au_io_write(tp("rh.copy"), m, m->X, &o, &msg), AU_OK, &msg);
  unsigned char *c = slurp(tp("rh.copy"), &n2);
  AU_CHECK(c != NULL);
  const char *stamp = "created by authalic ";
  AU_CHECK(memcmp(c, "\xff\xff\xfe", 3) == 0 && memcmp(c + 3, stamp, strlen(stamp)) == 0);
  unsigned char *e1 = memchr(b + 3, '\n', n - 3), *e2 = memchr(c + 3, '\n', n2 - 3);
  AU_CHECK(e2 && e2[1] == '\n');
  AU_CHECK_INT(n - (size_t)(e1 - b), ==, n2 - (size_t)(e2 - c));
  AU_CHECK(memcmp(e1, e2, n - (size_t)(e1 - b)) == 0);
  /* Without the input's metadata there is no footer; with GIfTI output none either. */
  AU_CHECK_STATUS(au_io_write(tp("rh.bare"), m, m->X, &(au_io_write_opts){.precision = 17,
                  .format = AU_IO_FORMAT_FREESURFER}, &msg), AU_OK, &msg);
  free(c);
  c = slurp(tp("rh.bare"), &n2);
  e2 = memchr(c + 3, '\n', n2 - 3);
  AU_CHECK_INT(n2, ==, (size_t)(e2 - c) + 2 + 8 + 72 + 96);
  free(b), free(c);
  au_mesh_free(&m);
  au_io_meta_free(&meta);
  return 0;
}

/* Truncated and lying files: AU_E_FORMAT (or AU_E_INDEX) with a message naming the problem. */
static int t_fs_bad(void) {
  AU_CHECK(make_dir("fs_bad"));
  size_t n;
  unsigned char *b = fs_octahedron(&n, 6);
  au_mesh *m = NULL;
  au_msg msg;
  AU_CHECK(put(tp("trunc.white"), b, 100) == 0);
  AU_CHECK_STATUS(au_io_read(tp("trunc.white"), &m, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "truncated") && m == NULL);
  AU_CHECK(put(tp("short.white"), b, 20) == 0);
  AU_CHECK_STATUS(au_io_read(tp("short.white"), &m, &msg), AU_E_FORMAT, &msg);
  free(b);
  b = fs_octahedron(&n, 600);
  AU_CHECK(put(tp("lying.white"), b, n) == 0);
  AU_CHECK_STATUS(au_io_read(tp("lying.white"), &m, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "600 vertices"));
  free(b);
  b = fs_octahedron(&n, 5); /* the faces then name vertex 5, which is not there */
  AU_CHECK(put(tp("index.white"), b, n) == 0);
  AU_CHECK_STATUS(au_io_read(tp("index.white"), &m, &msg), AU_E_INDEX, &msg);
  b[2] = 0xff; /* a curv or quad magic */
  AU_CHECK(put(tp("quad.white"), b, n) == 0);
  AU_CHECK_STATUS(au_io_read(tp("quad.white"), &m, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "not a triangle surface"));
  free(b);
  AU_CHECK(m == NULL);
  return 0;
}

/* curv: written and read back (float32 values), its header as FreeSurfer's; bad files refused. */
static int t_curv(void) {
  AU_CHECK(make_dir("curv"));
  double v[5] = {0.5, -1.25, 3, 1e-3, -7.5e4}, *r = NULL;
  au_msg msg;
  int count = 0;
  AU_CHECK_STATUS(au_io_write_scalars(tp("lh.thickness"), 5, v, 6, NULL, &msg), AU_OK, &msg);
  size_t n;
  unsigned char *b = slurp(tp("lh.thickness"), &n);
  AU_CHECK_INT(n, ==, 15 + 20);
  AU_CHECK(b[0] == 0xff && b[1] == 0xff && b[2] == 0xff && b[6] == 5 && b[10] == 6 && b[14] == 1);
  AU_CHECK_STATUS(au_io_read_scalars(tp("lh.thickness"), 0, &r, &count, &msg), AU_OK, &msg);
  AU_CHECK_INT(count, ==, 5);
  for (int i = 0; i < 5; i++) AU_CHECK_DBL(r[i], ==, (double)(float)v[i]);
  free(r);
  AU_CHECK_STATUS(au_io_read_scalars(tp("lh.thickness"), 6, &r, NULL, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(r == NULL && strstr(msg.text, "5 values for 6 vertices"));
  AU_CHECK(put(tp("cut.curv"), b, n - 3) == 0);
  AU_CHECK_STATUS(au_io_read_scalars(tp("cut.curv"), 0, &r, NULL, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "truncated"));
  be_float(b + 19, NAN);
  AU_CHECK(put(tp("nan.curv"), b, n) == 0);
  AU_CHECK_STATUS(au_io_read_scalars(tp("nan.curv"), 0, &r, NULL, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "value 2 is not finite"));
  free(b);
  double big = 1e300;
  AU_CHECK_STATUS(au_io_write_scalars(tp("big.curv"), 1, &big, 0, NULL, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(access(tp("big.curv"), F_OK) != 0);
  return 0;
}

/* The text format of per-vertex values: blanks, commas, comments. */
static int t_text_scalars(void) {
  AU_CHECK(make_dir("text_scalars"));
  const char *s = "# sulc\n1 2,3\n\n-4.5e0\n";
  AU_CHECK(put(tp("v.txt"), s, strlen(s)) == 0);
  double *r = NULL;
  int count = 0;
  au_msg msg;
  AU_CHECK_STATUS(au_io_read_scalars(tp("v.txt"), 4, &r, &count, &msg), AU_OK, &msg);
  AU_CHECK(count == 4 && r[0] == 1 && r[2] == 3 && r[3] == -4.5);
  free(r);
  const char *bad = "1 2 x\n";
  AU_CHECK(put(tp("bad.txt"), bad, strlen(bad)) == 0);
  AU_CHECK_STATUS(au_io_read_scalars(tp("bad.txt"), 0, &r, NULL, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "line 1: 'x' is not a number"));
  AU_CHECK_STATUS(au_io_read_scalars(tp("none.txt"), 0, &r, NULL, &msg), AU_E_IO, &msg);
  return 0;
}

/* ---------- GIfTI ---------- */

/* A surface written as .gii and as .gii.gz reads back with the same faces and float32 positions;
 * the GeometricType asked for is there; the .gii.gz is gzip. */
static int t_gifti_roundtrip(void) {
  AU_CHECK(make_dir("gifti_roundtrip"));
  au_mesh *m = octahedron(), *r = NULL;
  AU_CHECK(m != NULL);
  au_msg msg;
  const char *names[2] = {"oct.surf.gii", "oct.gii.gz"};
  for (int k = 0; k < 2; k++) {
    au_io_write_opts o = au_io_write_opts_default();
    o.geometric_type = "Spherical";
    double P[18];
    for (int i = 0; i < 18; i++) P[i] = m->X[i] / 3;
    AU_CHECK_STATUS(au_io_write(tp(names[k]), m, P, &o, &msg), AU_OK, &msg);
    au_io_meta *meta = NULL;
    AU_CHECK_STATUS(au_io_read_meta(tp(names[k]), &r, &meta, &msg), AU_OK, &msg);
    AU_CHECK(r->nv == 6 && r->nf == 8 && memcmp(r->F, OCT_F, sizeof OCT_F) == 0);
    for (int i = 0; i < 18; i++) AU_CHECK_DBL(r->X[i], ==, (double)(float)P[i]);
    AU_CHECK_INT(au_io_meta_format(meta), ==, AU_IO_FORMAT_GIFTI);
    AU_CHECK(au_io_meta_get(meta, "GeometricType") && !strcmp(au_io_meta_get(meta, "GeometricType"), "Spherical"));
    size_t n;
    unsigned char *b = slurp(tp(names[k]), &n);
    AU_CHECK(b && (k == 0 ? memcmp(b, "<?xml", 5) == 0 : (b[0] == 0x1f && b[1] == 0x8b)));
    free(b);
    au_mesh_free(&r);
    au_io_meta_free(&meta);
  }
  au_mesh_free(&m);
  return 0;
}

/* The input's metadata goes into the output: the structure and the coordinate system kept, the
 * GeometricType replaced, the input's Date and UserName not repeated; into a .shape.gii the structure. */
static int t_gifti_meta(void) {
  AU_CHECK(make_dir("gifti_meta"));
  const char *xml =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<GIFTI Version=\"1.0\" NumberOfDataArrays=\"2\">\n"
      "<MetaData><MD><Name>Date</Name><Value>yesterday</Value></MD><MD><Name>Subject</Name><Value>bert</Value></MD></MetaData>\n"
      "<DataArray Intent=\"NIFTI_INTENT_POINTSET\" DataType=\"NIFTI_TYPE_FLOAT32\" ArrayIndexingOrder=\"RowMajorOrder\" "
      "Dimensionality=\"2\" Dim0=\"6\" Dim1=\"3\" Encoding=\"ASCII\" Endian=\"LittleEndian\" ExternalFileName=\"\" "
      "ExternalFileOffset=\"\">\n<MetaData><MD><Name>AnatomicalStructurePrimary</Name><Value>CortexLeft</Value></MD>"
      "<MD><Name>GeometricType</Name><Value>Anatomical</Value></MD></MetaData>\n"
      "<CoordinateSystemTransformMatrix><DataSpace>NIFTI_XFORM_UNKNOWN</DataSpace><TransformedSpace>NIFTI_XFORM_TALAIRACH"
      "</TransformedSpace><MatrixData>1 0 0 10 0 1 0 20 0 0 1 30 0 0 0 1</MatrixData></CoordinateSystemTransformMatrix>\n"
      "<Data>2 0 0 -2 0 0 0 2 0 0 -2 0 0 0 2 0 0 -2</Data></DataArray>\n"
      "<DataArray Intent=\"NIFTI_INTENT_TRIANGLE\" DataType=\"NIFTI_TYPE_INT32\" ArrayIndexingOrder=\"ColumnMajorOrder\" "
      "Dimensionality=\"2\" Dim0=\"8\" Dim1=\"3\" Encoding=\"ASCII\" Endian=\"LittleEndian\" ExternalFileName=\"\" "
      "ExternalFileOffset=\"\">\n<Data>0 2 1 3 2 1 3 0  2 1 3 0 0 2 1 3  4 4 4 4 5 5 5 5</Data></DataArray>\n</GIFTI>\n";
  AU_CHECK(put(tp("lh.white.gii"), xml, strlen(xml)) == 0);
  au_mesh *m = NULL, *r = NULL;
  au_io_meta *meta = NULL, *meta2 = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_io_read_meta(tp("lh.white.gii"), &m, &meta, &msg), AU_OK, &msg);
  AU_CHECK(memcmp(m->F, OCT_F, sizeof OCT_F) == 0); /* column-major faces read right */
  for (int i = 0; i < 18; i++) AU_CHECK_DBL(m->X[i], ==, OCT_X[i]);
  au_io_write_opts o = au_io_write_opts_default();
  o.meta = meta, o.geometric_type = "Flat";
  AU_CHECK_STATUS(au_io_write(tp("out.gii"), m, m->X, &o, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_io_read_meta(tp("out.gii"), &r, &meta2, &msg), AU_OK, &msg);
  AU_CHECK(!strcmp(au_io_meta_get(meta2, "AnatomicalStructurePrimary"), "CortexLeft"));
  AU_CHECK(!strcmp(au_io_meta_get(meta2, "GeometricType"), "Flat"));
  AU_CHECK(!strcmp(au_io_meta_get(meta2, "Subject"), "bert"));
  AU_CHECK(au_io_meta_get(meta2, "Date") == NULL);
  au_mesh_free(&r);
  size_t n;
  char *b = (char *)slurp(tp("out.gii"), &n);
  AU_CHECK(b && strstr(b, "NIFTI_XFORM_TALAIRACH") && strstr(b, "10.000000"));
  free(b);
  double v[6] = {1, 2, 3, 4, 5, 6}, *rv = NULL;
  AU_CHECK_STATUS(au_io_write_scalars(tp("d.shape.gii"), 6, v, 8, meta, &msg), AU_OK, &msg);
  b = (char *)slurp(tp("d.shape.gii"), &n);
  AU_CHECK(b && strstr(b, "NIFTI_INTENT_SHAPE") && strstr(b, "CortexLeft"));
  free(b);
  AU_CHECK_STATUS(au_io_read_scalars(tp("d.shape.gii"), 6, &rv, NULL, &msg), AU_OK, &msg);
  for (int i = 0; i < 6; i++) AU_CHECK_DBL(rv[i], ==, v[i]);
  free(rv);
  /* A surface is not values, values are not a surface. */
  AU_CHECK_STATUS(au_io_read_scalars(tp("out.gii"), 0, &rv, NULL, &msg), AU_E_FORMAT, &msg);
  AU_CHECK_STATUS(au_io_read(tp("d.shape.gii"), &r, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "0 POINTSET arrays"));
  au_mesh_free(&m);
  au_io_meta_free(&meta);
  au_io_meta_free(&meta2);
  return 0;
}

/* Truncated, corrupt and lying GIfTI files are refused with one line, giftiio's complaints included. */
static int t_gifti_bad(void) {
  AU_CHECK(make_dir("gifti_bad"));
  au_mesh *m = octahedron(), *r = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_io_write(tp("ok.gii"), m, m->X, NULL, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_io_write(tp("ok.gii.gz"), m, m->X, NULL, &msg), AU_OK, &msg);
  size_t n, nz;
  char *b = (char *)slurp(tp("ok.gii"), &n);
  unsigned char *z = slurp(tp("ok.gii.gz"), &nz);
  AU_CHECK(put(tp("cut.gii"), b, n / 2) == 0);
  AU_CHECK_STATUS(au_io_read(tp("cut.gii"), &r, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "cut.gii: not well-formed XML (line ") && !strchr(msg.text, '\n'));
  AU_CHECK(put(tp("cut.gii.gz"), z, nz - 10) == 0);
  AU_CHECK_STATUS(au_io_read(tp("cut.gii.gz"), &r, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "truncated"));
  char *dim = strstr(b, "Dim0=\"6\"");
  AU_CHECK(dim != NULL);
  memcpy(dim, "Dim0=\"9\"", 8); /* more vertices than the data holds: giftiio's complaint */
  AU_CHECK(put(tp("lying.gii"), b, n) == 0);
  AU_CHECK_STATUS(au_io_read(tp("lying.gii"), &r, &msg), AU_E_FORMAT, &msg);
  const char *huge = "<?xml version=\"1.0\"?><GIFTI Version=\"1.0\" NumberOfDataArrays=\"1\"><DataArray "
                     "Intent=\"NIFTI_INTENT_POINTSET\" DataType=\"NIFTI_TYPE_FLOAT32\" ArrayIndexingOrder=\"RowMajorOrder\" "
                     "Dimensionality=\"2\" Dim0=\"2000000000\" Dim1=\"3\" Encoding=\"ASCII\" Endian=\"LittleEndian\" "
                     "ExternalFileName=\"\" ExternalFileOffset=\"\"><Data>1 2 3</Data></DataArray></GIFTI>";
  AU_CHECK(put(tp("huge.gii"), huge, strlen(huge)) == 0);
  AU_CHECK_STATUS(au_io_read(tp("huge.gii"), &r, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "more than a"));
  /* An ASCII array with fewer numbers than it announces (giftiio itself says nothing). */
  char *short_ascii = strdup(huge), *d0 = strstr(short_ascii, "Dim0=\"2000000000\"");
  AU_CHECK(d0 != NULL);
  memcpy(d0, "Dim0=\"2\"         ", 17);
  AU_CHECK(put(tp("short.gii"), short_ascii, strlen(short_ascii)) == 0);
  free(short_ascii);
  AU_CHECK_STATUS(au_io_read(tp("short.gii"), &r, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "holds 3 numbers but its dimensions announce 6"));
  AU_CHECK(r == NULL);
  free(b), free(z);
  au_mesh_free(&m);
  return 0;
}

/* The real fsaverage5 files of ../shared/neuro: 10242 vertices, 20480 faces, a closed genus-0
 * surface; CortexRight; sulc has one value per vertex, those nibabel reads. */
static int t_fsaverage5(void) {
  char w[1024], s[1024];
  snprintf(w, sizeof w, "%s/neuro/fsaverage5/white_right.gii.gz", AU_SHARED_DIR);
  snprintf(s, sizeof s, "%s/neuro/fsaverage5/sulc_right.gii.gz", AU_SHARED_DIR);
  if (access(w, R_OK) != 0 || access(s, R_OK) != 0) {
    fprintf(stderr, "SKIP: %s is absent\n", w);
    return AU_SKIP;
  }
  au_mesh *m = NULL;
  au_io_meta *meta = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_io_read_meta(w, &m, &meta, &msg), AU_OK, &msg);
  AU_CHECK(m->nv == 10242 && m->nf == 20480);
  AU_CHECK(!strcmp(au_io_meta_get(meta, "AnatomicalStructurePrimary"), "CortexRight"));
  au_mesh_expect ex = au_mesh_expect_default();
  ex.loops = 0, ex.genus = 0;
  au_topo *t = NULL;
  AU_CHECK_STATUS(au_mesh_validate(m, &ex, &t, &msg), AU_OK, &msg);
  double *v = NULL;
  AU_CHECK_STATUS(au_io_read_scalars(s, m->nv, &v, NULL, &msg), AU_OK, &msg);
  double lo = v[0], hi = v[0];
  for (int i = 0; i < m->nv; i++) lo = fmin(lo, v[i]), hi = fmax(hi, v[i]);
  /* Sulcal depth of both signs; nibabel reads -1.4924682 .. 1.8412241 and starts 0.26513985. */
  AU_CHECK_NEAR(lo, -1.4924682, 1e-6);
  AU_CHECK_NEAR(hi, 1.8412241, 1e-6);
  AU_CHECK_NEAR(v[0], 0.26513985, 1e-7);
  free(v);
  au_topo_free(&t);
  au_mesh_free(&m);
  au_io_meta_free(&meta);
  return 0;
}

/* ---------- distortion ---------- */

/* The identity map (any scale) has distortion 0; the domain's scale and the sphere's radius do not
 * matter; a face twice its share gives its corners log2 values that are checked by hand. */
static int t_distortion(void) {
  double P[18], d[6];
  int ndeg = -1;
  for (int i = 0; i < 18; i++) P[i] = OCT_X[i] * 50;
  AU_CHECK_STATUS(au_metrics_vertex_distortion(6, 8, OCT_X, P, OCT_F, AU_DOMAIN_SPHERE, d, &ndeg), AU_OK, NULL);
  for (int i = 0; i < 6; i++) AU_CHECK_NEAR(d[i], 0, 1e-14);
  AU_CHECK_INT(ndeg, ==, 0);
  /* A plane square of 2 triangles mapped to a rectangle that doubles the first triangle's area
   * only where vertex 1 moves: shares computed by hand. */
  const double X[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const int F[6] = {0, 1, 2, 0, 2, 3};
  double Q[12] = {0, 0, 9, 2, -1, 9, 1, 1, 9, 0, 1, 9}; /* z ignored on the plane */
  double dd[4];
  AU_CHECK_STATUS(au_metrics_vertex_distortion(4, 2, X, Q, F, AU_DOMAIN_PLANE, dd, NULL), AU_OK, NULL);
  double a1 = 0.5 * fabs(2.0 * 1 - (-1.0) * 1), a2 = 0.5; /* domain triangle areas: 1.5, 0.5 */
  double tot = a1 + a2, vd[4] = {(a1 + a2) / 3, a1 / 3, (a1 + a2) / 3, a2 / 3}, vs[4] = {1. / 3, 1. / 6, 1. / 3, 1. / 6};
  for (int i = 0; i < 4; i++) AU_CHECK_NEAR(dd[i], log2((vd[i] / tot) / vs[i]), 1e-14);
  AU_CHECK_STATUS(au_metrics_vertex_distortion(4, 2, X, Q, F, (au_domain)5, dd, NULL), AU_E_ARG, NULL);
  AU_CHECK_STATUS(au_metrics_vertex_distortion(4, 0, X, Q, F, AU_DOMAIN_PLANE, dd, NULL), AU_E_ARG, NULL);
  /* An unused vertex gets 0 and is counted. */
  double X5[15], Q5[15], d5[5];
  memcpy(X5, X, sizeof X), memcpy(Q5, Q, sizeof Q);
  for (int k = 12; k < 15; k++) X5[k] = Q5[k] = 7;
  AU_CHECK_STATUS(au_metrics_vertex_distortion(5, 2, X5, Q5, F, AU_DOMAIN_PLANE, d5, &ndeg), AU_OK, NULL);
  AU_CHECK(ndeg == 1 && d5[4] == 0 && d5[1] == dd[1]);
  return 0;
}

int main(int argc, char **argv) {
  static const au_test_case cases[] = {
      {"fs_read", t_fs_read},       {"fs_roundtrip", t_fs_roundtrip},       {"fs_bad", t_fs_bad},
      {"curv", t_curv},             {"text_scalars", t_text_scalars},       {"gifti_roundtrip", t_gifti_roundtrip},
      {"gifti_meta", t_gifti_meta}, {"gifti_bad", t_gifti_bad},             {"fsaverage5", t_fsaverage5},
      {"distortion", t_distortion},
  };
  return au_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0]));
}
