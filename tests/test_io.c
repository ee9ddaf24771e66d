/* test_io.c - mesh file reading and writing: exact round trips, kept order, exact statuses, atomic writes. */
#define _POSIX_C_SOURCE 200809L

#include "au_io.h"
#include "au_test.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

/* Each case works in its own folder under the build tree, so cases may run in parallel. */
static char g_dir[1200];

static int make_dir(const char *case_name) {
  char base[1024];
  snprintf(base, sizeof base, "%s/io_tmp", AU_BINARY_DIR);
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
  if (!fp) return 0;
  size_t n = fwrite(data, 1, len, fp);
  return fclose(fp) == 0 && n == len;
}

static int puts_file(const char *path, const char *text) { return put(path, text, strlen(text)); }

/* The whole file as a NUL-terminated string (caller frees), or NULL. */
static char *slurp(const char *path) {
  FILE *fp = fopen(path, "rb");
  if (!fp) return NULL;
  char *buf = calloc(1, 1 << 20);
  size_t n = buf ? fread(buf, 1, (1 << 20) - 1, fp) : 0;
  (void)n;
  fclose(fp);
  return buf;
}

/* Files in g_dir whose name starts with prefix. */
static int count_files(const char *prefix) {
  DIR *d = opendir(g_dir);
  if (!d) return -1;
  int n = 0;
  struct dirent *e;
  while ((e = readdir(d)))
    if (!strncmp(e->d_name, prefix, strlen(prefix))) n++;
  closedir(d);
  return n;
}

static int same_bits(const double *a, const double *b, int n) { return memcmp(a, b, sizeof(double) * (size_t)n) == 0; }

/* A small mesh whose coordinates are hard to print exactly, with an unreferenced vertex (4) and faces
 * whose corners are not in increasing order. */
static au_mesh *awkward_mesh(void) {
  au_mesh *m = NULL;
  if (au_mesh_alloc(6, 4, &m) != AU_OK) return NULL;
  const double X[18] = {0.1, 1.0 / 3.0, -2.0 / 7.0, 1e-300, 4.9406564584124654e-324, 1.7976931348623157e308,
                        3.141592653589793, -0.0, 123456789.123456789, 2.2250738585072014e-308, 0.30000000000000004, -1e-17,
                        42, 43, 44, -5.5, 6.25, 0.7};
  const int F[12] = {5, 1, 0, 3, 2, 5, 0, 2, 3, 1, 5, 3};
  memcpy(m->X, X, sizeof X);
  memcpy(m->F, F, sizeof F);
  return m;
}

static int roundtrip(const char *name, const au_io_write_opts *opts) {
  au_mesh *m = awkward_mesh(), *r = NULL;
  au_msg msg = {{0}};
  AU_CHECK(m != NULL);
  AU_CHECK_STATUS(au_io_write(tp(name), m, m->X, opts, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_io_read(tp(name), &r, &msg), AU_OK, &msg);
  AU_CHECK_INT(r->nv, ==, m->nv);
  AU_CHECK_INT(r->nf, ==, m->nf);
  AU_CHECK(same_bits(r->X, m->X, 3 * m->nv));
  AU_CHECK(memcmp(r->F, m->F, sizeof(int) * 3 * (size_t)m->nf) == 0);
  AU_CHECK_INT(count_files(name), ==, 1); /* no temporary file left beside it */
  au_mesh_free(&m);
  au_mesh_free(&r);
  AU_CHECK(r == NULL);
  return 0;
}

static int t_roundtrip_obj(void) {
  AU_CHECK(make_dir("roundtrip_obj"));
  return roundtrip("a.obj", NULL);
}
static int t_roundtrip_off(void) {
  AU_CHECK(make_dir("roundtrip_off"));
  return roundtrip("a.off", NULL);
}
static int t_roundtrip_ply(void) {
  AU_CHECK(make_dir("roundtrip_ply"));
  return roundtrip("a.ply", NULL);
}

/* With uv the OBJ gets one `vt` per vertex and `f a/a b/b c/c`; reading ignores the uv and keeps faces. */
static int t_obj_uv(void) {
  AU_CHECK(make_dir("obj_uv"));
  double uv[12];
  for (int i = 0; i < 12; i++) uv[i] = i / 11.0;
  au_io_write_opts o = au_io_write_opts_default();
  o.uv = uv;
  if (roundtrip("uv.obj", &o)) return 1;
  char *text = slurp(tp("uv.obj"));
  AU_CHECK(text != NULL);
  AU_CHECK(strstr(text, "\nvt 0 0.090909090909090912\n") != NULL);
  AU_CHECK(strstr(text, "\nf 6/6 2/2 1/1\n") != NULL);
  free(text);
  return 0;
}

/* Large meshes are formatted in two halves on two threads (au_io.c, AU_WRITE_SPLIT_MIN): the file is
 * the same as written in one piece. A strip of 30001 vertices (odd, so the halves differ) with awkward
 * coordinates and uv: it reads back bit for bit, the faces in order, and the line right after the
 * first half of the vertices, of the vt lines and of the faces is where it belongs. */
static int t_write_halves(void) {
  AU_CHECK(make_dir("write_halves"));
  const int nv = 30001, nf = nv - 2;
  au_mesh *m = NULL, *r = NULL;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_mesh_alloc(nv, nf, &m), AU_OK, NULL);
  double *uv = malloc(sizeof(double) * 2 * (size_t)nv);
  AU_CHECK(uv != NULL);
  for (int i = 0; i < nv; i++) {
    m->X[3 * i] = i / 7.0, m->X[3 * i + 1] = (i % 2) / 3.0 + 1e-9 * i, m->X[3 * i + 2] = -i * 0.1;
    uv[2 * i] = i / (double)nv, uv[2 * i + 1] = 1.0 / (i + 1);
  }
  for (int f = 0; f < nf; f++) {
    int *c = m->F + 3 * f;
    c[0] = f, c[1] = f % 2 ? f + 2 : f + 1, c[2] = f % 2 ? f + 1 : f + 2;
  }
  au_io_write_opts o = au_io_write_opts_default();
  o.uv = uv;
  AU_CHECK_STATUS(au_io_write(tp("strip.obj"), m, m->X, &o, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_io_read(tp("strip.obj"), &r, &msg), AU_OK, &msg);
  AU_CHECK_INT(r->nv, ==, nv);
  AU_CHECK_INT(r->nf, ==, nf);
  AU_CHECK(same_bits(r->X, m->X, 3 * nv));
  AU_CHECK(memcmp(r->F, m->F, sizeof(int) * 3 * (size_t)nf) == 0);
  FILE *fp = fopen(tp("strip.obj"), "rb");
  AU_CHECK(fp != NULL);
  fseek(fp, 0, SEEK_END);
  long size = ftell(fp);
  rewind(fp);
  char *text = calloc(1, (size_t)size + 1);
  AU_CHECK(text != NULL && fread(text, 1, (size_t)size, fp) == (size_t)size);
  fclose(fp);
  char want[128];
  snprintf(want, sizeof want, "\nvt %.17g %.17g\n", uv[2 * (nv / 2)], uv[2 * (nv / 2) + 1]);
  char *a = strstr(text, want);
  snprintf(want, sizeof want, "\nvt %.17g %.17g\n", uv[2 * (nv / 2 - 1)], uv[2 * (nv / 2 - 1) + 1]);
  char *b = strstr(text, want);
  AU_CHECK(a != NULL && b != NULL && b < a);
  free(text);
  free(uv);
  au_mesh_free(&m);
  au_mesh_free(&r);
  return 0;
}

/* precision below 17 rounds as %.*g does; outside 1..17 is an argument error. */
static int t_write_precision(void) {
  AU_CHECK(make_dir("write_precision"));
  au_mesh *m = awkward_mesh(), *r = NULL;
  au_msg msg = {{0}};
  au_io_write_opts o = au_io_write_opts_default();
  AU_CHECK_INT(o.precision, ==, 17);
  AU_CHECK(o.uv == NULL);
  o.precision = 3;
  AU_CHECK_STATUS(au_io_write(tp("p.off"), m, m->X, &o, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_io_read(tp("p.off"), &r, &msg), AU_OK, &msg);
  AU_CHECK_DBL(r->X[1], ==, 0.333);
  AU_CHECK_DBL(r->X[6], ==, 3.14);
  o.precision = 0;
  AU_CHECK_STATUS(au_io_write(tp("q.off"), m, m->X, &o, &msg), AU_E_ARG, &msg);
  o.precision = 18;
  AU_CHECK_STATUS(au_io_write(tp("q.off"), m, m->X, &o, &msg), AU_E_ARG, &msg);
  AU_CHECK_INT(count_files("q.off"), ==, 0);
  au_mesh_free(&m);
  au_mesh_free(&r);
  return 0;
}

/* A file whose faces use the vertices in scrambled order, with an unreferenced vertex (index 2):
 * every reader must keep the file's vertex order and faces exactly. */
static const double k_scr_X[15] = {0, 0, 0, 1, 0, 0, 9, 9, 9, 0, 1, 0, 0, 0, 1};
static const int k_scr_F[12] = {4, 3, 1, 0, 4, 1, 3, 4, 0, 1, 3, 0};

static int check_scrambled(const char *path) {
  au_mesh *m = NULL;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_io_read(path, &m, &msg), AU_OK, &msg);
  AU_CHECK_INT(m->nv, ==, 5);
  AU_CHECK_INT(m->nf, ==, 4);
  for (int i = 0; i < 15; i++) AU_CHECK_DBL(m->X[i], ==, k_scr_X[i]);
  for (int j = 0; j < 12; j++) AU_CHECK_INT(m->F[j], ==, k_scr_F[j]);
  au_mesh_free(&m);
  return 0;
}

static int t_order_kept(void) {
  AU_CHECK(make_dir("order_kept"));
  AU_CHECK(puts_file(tp("s.obj"), "v 0 0 0\nv 1 0 0\nv 9 9 9\nv 0 1 0\nv 0 0 1\n"
                                  "f 5 4 2\nf 1 5 2\nf 4 5 1\nf 2 4 1\n"));
  AU_CHECK(puts_file(tp("s.off"), "OFF\n5 4 0\n0 0 0\n1 0 0\n9 9 9\n0 1 0\n0 0 1\n"
                                  "3 4 3 1\n3 0 4 1\n3 3 4 0\n3 1 3 0\n"));
  AU_CHECK(puts_file(tp("s.ply"), "ply\nformat ascii 1.0\ncomment scrambled\nelement vertex 5\n"
                                  "property float x\nproperty float y\nproperty float z\nproperty uchar red\n"
                                  "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
                                  "0 0 0 1\n1 0 0 2\n9 9 9 3\n0 1 0 4\n0 0 1 5\n3 4 3 1\n3 0 4 1\n3 3 4 0\n3 1 3 0\n"));
  if (check_scrambled(tp("s.obj")) || check_scrambled(tp("s.off")) || check_scrambled(tp("s.ply"))) return 1;
  return 0;
}

/* Binary PLY in both byte orders, float and double coordinates, an extra element and a face
 * property after the list: all decoded exactly. */
static void be_put(unsigned char **p, const void *v, int n, int big) {
  for (int k = 0; k < n; k++) (*p)[k] = ((const unsigned char *)v)[big ? n - 1 - k : k];
  *p += n;
}

static int write_binary_ply(const char *path, int big, int dbl) {
  unsigned char buf[4096], *p = buf;
  const uint16_t one = 1;
  int host_big = *(const unsigned char *)&one == 0;
  int swap = big != host_big;
  p += sprintf((char *)p, "ply\nformat binary_%s_endian 1.0\nelement material 1\nproperty list uchar short ids\n"
                          "element vertex 5\nproperty %s x\nproperty %s y\nproperty %s z\n"
                          "element face 4\nproperty list uchar uint vertex_indices\nproperty ushort tag\nend_header\n",
               big ? "big" : "little", dbl ? "double" : "float", dbl ? "double" : "float", dbl ? "double" : "float");
  unsigned char c = 2;
  int16_t ids[2] = {-3, 7};
  be_put(&p, &c, 1, swap);
  be_put(&p, &ids[0], 2, swap);
  be_put(&p, &ids[1], 2, swap);
  for (int i = 0; i < 15; i++) {
    float f = (float)k_scr_X[i];
    if (dbl)
      be_put(&p, &k_scr_X[i], 8, swap);
    else
      be_put(&p, &f, 4, swap);
  }
  for (int j = 0; j < 4; j++) {
    unsigned char three = 3;
    uint16_t tag = 0xbeef;
    be_put(&p, &three, 1, swap);
    for (int k = 0; k < 3; k++) {
      uint32_t v = (uint32_t)k_scr_F[3 * j + k];
      be_put(&p, &v, 4, swap);
    }
    be_put(&p, &tag, 2, swap);
  }
  return put(path, buf, (size_t)(p - buf));
}

static int t_ply_binary(void) {
  AU_CHECK(make_dir("ply_binary"));
  for (int big = 0; big < 2; big++)
    for (int dbl = 0; dbl < 2; dbl++) {
      AU_CHECK(write_binary_ply(tp("b.ply"), big, dbl));
      if (check_scrambled(tp("b.ply"))) {
        fprintf(stderr, "binary PLY, big endian %d, double %d\n", big, dbl);
        return 1;
      }
    }
  /* Cut the last face short: truncation is a format error, not a smaller mesh. */
  AU_CHECK(write_binary_ply(tp("b.ply"), 0, 1));
  struct stat st;
  AU_CHECK(stat(tp("b.ply"), &st) == 0);
  AU_CHECK(truncate(tp("b.ply"), st.st_size - 3) == 0);
  au_mesh *m = NULL;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_io_read(tp("b.ply"), &m, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(m == NULL);
  AU_CHECK(strstr(msg.text, "face 3") != NULL);
  return 0;
}

/* OBJ forms: CRLF, comments, blank lines, `v x y z w`, vertex colours, vt/vn, `f a/b/c`,
 * `f a//c`, negative (relative) indices, groups and materials. */
static int t_obj_forms(void) {
  AU_CHECK(make_dir("obj_forms"));
  AU_CHECK(puts_file(tp("f.obj"), "# comment\r\nmtllib x.mtl\r\no thing\r\n\r\n"
                                  "v 0 0 0 1\r\nv 1 0 0 0.5 0.5 0.5\r\n  v 9 9 9\r\nvt 0 0\r\nvt 1 0\r\nvn 0 0 1\r\n"
                                  "v 0 1 0 # trailing comment\r\nv\t0\t0\t1\r\n"
                                  "g part\r\nusemtl m\r\ns off\r\n"
                                  "f -1/1/1 -2/2/1 -4/1/1\r\n"      /* 4 3 1 with negatives */
                                  "f 1//1 5//1 2//1\r\n"            /* 0 4 1 */
                                  "f 4/2 5/1 1/2\r\n"               /* 3 4 0 */
                                  "f 2/1/1 4/2/1 1/1/1"));          /* 1 3 0, no final line break */
  if (check_scrambled(tp("f.obj"))) return 1;
  /* A UTF-8 byte-order mark before the first record is not part of it. */
  AU_CHECK(puts_file(tp("bom.obj"), "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 9 9 9\nv 0 1 0\nv 0 0 1\n"
                                    "f 5 4 2\nf 1 5 2\nf 4 5 1\nf 2 4 1\n"));
  return check_scrambled(tp("bom.obj"));
}

static int t_off_forms(void) {
  AU_CHECK(make_dir("off_forms"));
  /* Counts on the header line, CRLF, comments, colours after face indices, and a COFF variant. */
  AU_CHECK(puts_file(tp("a.off"), "OFF 5 4 0\r\n# c\r\n0 0 0\r\n1 0 0\r\n9 9 9\r\n\r\n0 1 0\r\n0 0 1\r\n"
                                  "3 4 3 1 255 0 0\r\n3 0 4 1\r\n3 3 4 0 # x\r\n3 1 3 0\r\n\r\n"));
  AU_CHECK(puts_file(tp("b.off"), "COFF\n5 4 6\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n9 9 9 1 1 1 1\n0 1 0 1 1 1 1\n"
                                  "0 0 1 1 1 1 1\n3 4 3 1\n3 0 4 1\n3 3 4 0\n3 1 3 0\n"));
  if (check_scrambled(tp("a.off")) || check_scrambled(tp("b.off"))) return 1;
  return 0;
}

/* Non-finite coordinates are read (validation names the vertex); garbage tokens are not. */
static int t_nonfinite(void) {
  AU_CHECK(make_dir("nonfinite"));
  au_mesh *m = NULL;
  au_msg msg = {{0}};
  AU_CHECK(puts_file(tp("n.obj"), "v nan 0 0\nv inf -inf 1\nv 0 -nan INF\nf 1 2 3\n"));
  AU_CHECK_STATUS(au_io_read(tp("n.obj"), &m, &msg), AU_OK, &msg);
  AU_CHECK(isnan(m->X[0]));
  AU_CHECK(isinf(m->X[3]) && m->X[3] > 0);
  AU_CHECK(isinf(m->X[4]) && m->X[4] < 0);
  AU_CHECK(isnan(m->X[7]) && isinf(m->X[8]));
  /* Written non-finite values read back as the same kind of value. */
  AU_CHECK_STATUS(au_io_write(tp("n.off"), m, m->X, NULL, &msg), AU_OK, &msg);
  au_mesh *r = NULL;
  AU_CHECK_STATUS(au_io_read(tp("n.off"), &r, &msg), AU_OK, &msg);
  for (int i = 0; i < 9; i++) AU_CHECK(isnan(r->X[i]) == isnan(m->X[i]) && isinf(r->X[i]) == isinf(m->X[i]));
  au_mesh_free(&r);
  au_mesh_free(&m);
  AU_CHECK(puts_file(tp("g.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 zero\nf 1 2 3\n"));
  AU_CHECK_STATUS(au_io_read(tp("g.obj"), &m, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "g.obj:3:") != NULL);
  AU_CHECK(puts_file(tp("g.off"), "OFF\n3 1 0\n0 0 0\n1 0 0x\n0 1 0\n3 0 1 2\n"));
  AU_CHECK_STATUS(au_io_read(tp("g.off"), &m, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "g.off:4:") != NULL);
  AU_CHECK(puts_file(tp("g2.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n"));
  AU_CHECK_STATUS(au_io_read(tp("g2.obj"), &m, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(m == NULL);
  return 0;
}

/* A non-manifold edge (0,1 shared by three faces) must reach validation unrepaired. */
static int t_nonmanifold_kept(void) {
  AU_CHECK(make_dir("nonmanifold_kept"));
  const int F[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  const char *stl = "solid t\n"
                    "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
                    "facet normal 0 0 0\nouter loop\nvertex 1 0 0\nvertex 0 0 0\nvertex 0 -1 0\nendloop\nendfacet\n"
                    "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
                    "endsolid t\n";
  AU_CHECK(puts_file(tp("n.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n"));
  AU_CHECK(puts_file(tp("n.stl"), stl));
  const char *files[2] = {"n.obj", "n.stl"};
  for (int k = 0; k < 2; k++) {
    au_mesh *m = NULL;
    au_msg msg = {{0}};
    AU_CHECK_STATUS(au_io_read(tp(files[k]), &m, &msg), AU_OK, &msg);
    AU_CHECK_INT(m->nv, ==, 5);
    AU_CHECK_INT(m->nf, ==, 3);
    for (int j = 0; j < 9; j++) AU_CHECK_INT(m->F[j], ==, F[j]);
    AU_CHECK_DBL(m->X[3 * 3 + 1], ==, -1.0);
    AU_CHECK_DBL(m->X[3 * 4 + 2], ==, 1.0);
    au_mesh_free(&m);
  }
  return 0;
}

/* STL, ASCII and binary: equal positions merged in order of first appearance (an STL file has no
 * other vertex order), every facet kept with its corners in the file's order. */
static int t_stl(void) {
  AU_CHECK(make_dir("stl"));
  const float V[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.1f, 0.2f, 1.5f}};
  const int F[12] = {0, 1, 2, 0, 3, 1, 1, 3, 2, 2, 3, 0}; /* vertices first appear in order 0..3 */
  unsigned char buf[84 + 4 * 50], *p = buf + 84;
  memset(buf, 0, sizeof buf);
  memcpy(buf, "solid but binary", 16); /* binary files that start with "solid" exist; the size decides */
  buf[80] = 4;
  for (int j = 0; j < 4; j++) {
    memset(p, 0, 12);
    for (int k = 0; k < 3; k++) memcpy(p + 12 + 12 * k, V[F[3 * j + k]], 12);
    p += 50;
  }
  AU_CHECK(put(tp("b.STL"), buf, sizeof buf));
  char text[2048], *q = text;
  q += sprintf(q, "solid tet\n");
  for (int j = 0; j < 4; j++) {
    q += sprintf(q, "  facet normal 0 0 0\n    outer loop\n");
    for (int k = 0; k < 3; k++)
      q += sprintf(q, "      vertex %.9g %.9g %.9g\n", V[F[3 * j + k]][0], V[F[3 * j + k]][1], V[F[3 * j + k]][2]);
    q += sprintf(q, "    endloop\n  endfacet\n");
  }
  sprintf(q, "endsolid tet\n");
  AU_CHECK(puts_file(tp("a.stl"), text));
  const char *files[2] = {"b.STL", "a.stl"};
  for (int k = 0; k < 2; k++) {
    au_mesh *m = NULL;
    au_msg msg = {{0}};
    AU_CHECK_STATUS(au_io_read(tp(files[k]), &m, &msg), AU_OK, &msg);
    AU_CHECK_INT(m->nv, ==, 4);
    AU_CHECK_INT(m->nf, ==, 4);
    for (int i = 0; i < 12; i++) AU_CHECK_DBL(m->X[i], ==, (double)V[i / 3][i % 3]);
    for (int j = 0; j < 12; j++) AU_CHECK_INT(m->F[j], ==, F[j]);
    au_mesh_free(&m);
  }
  /* A facet whose corners coincide is dropped by OpenMesh: that is reported, not hidden. */
  AU_CHECK(puts_file(tp("d.stl"), "solid d\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                                  "endloop\nendfacet\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 0\n"
                                  "vertex 0 1 0\nendloop\nendfacet\nendsolid d\n"));
  au_mesh *m = NULL;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_io_read(tp("d.stl"), &m, &msg), AU_E_FORMAT, &msg);
  AU_CHECK(strstr(msg.text, "2 facets") != NULL);
  return 0;
}

/* ---------- exact statuses on bad input ---------- */

static int expect(const char *name, const char *content, size_t len, au_status want, const char *in_msg) {
  au_mesh *m = (au_mesh *)&m; /* must be reset to NULL on failure */
  au_msg msg = {{0}};
  if (content && !put(tp(name), content, len)) return 1;
  AU_CHECK_STATUS(au_io_read(tp(name), &m, &msg), want, &msg);
  AU_CHECK(m == NULL);
  AU_CHECK(msg.text[0] != '\0');
  if (in_msg && !strstr(msg.text, in_msg)) {
    fprintf(stderr, "%s: message '%s' lacks '%s'\n", name, msg.text, in_msg);
    return 1;
  }
  return 0;
}
static int expect_s(const char *name, const char *text, au_status want, const char *in_msg) {
  return expect(name, text, text ? strlen(text) : 0, want, in_msg);
}
#define EXPECT(name, text, want, in_msg) AU_CHECK(expect_s(name, text, want, in_msg) == 0)

static int t_err_missing(void) {
  AU_CHECK(make_dir("err_missing"));
  EXPECT("nothing_here.obj", NULL, AU_E_IO, "nothing_here.obj");
  au_msg msg = {{0}};
  au_mesh *m = NULL;
  AU_CHECK_STATUS(au_io_read(NULL, &m, &msg), AU_E_ARG, &msg);
  AU_CHECK_STATUS(au_io_read(tp("x.obj"), NULL, &msg), AU_E_ARG, &msg);
  return 0;
}

static int t_err_directory(void) {
  AU_CHECK(make_dir("err_directory"));
  mkdir(tp("dir.obj"), 0777);
  EXPECT("dir.obj", NULL, AU_E_IO, "directory");
  return 0;
}

static int t_err_extension(void) {
  AU_CHECK(make_dir("err_extension"));
  const char *tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT("tri.xyz", tri, AU_E_FORMAT, "extension");
  EXPECT("tri", tri, AU_E_FORMAT, "extension");
  EXPECT("tri.obj.bak", tri, AU_E_FORMAT, "extension");
  /* The extension is matched in any case. */
  au_mesh *m = NULL;
  au_msg msg = {{0}};
  AU_CHECK(puts_file(tp("TRI.OBJ"), tri));
  AU_CHECK_STATUS(au_io_read(tp("TRI.OBJ"), &m, &msg), AU_OK, &msg);
  AU_CHECK_INT(m->nf, ==, 1);
  au_mesh_free(&m);
  return 0;
}

static int t_err_empty(void) {
  AU_CHECK(make_dir("err_empty"));
  EXPECT("e.obj", "", AU_E_EMPTY, NULL);
  EXPECT("e.off", "", AU_E_EMPTY, NULL);
  EXPECT("e.ply", "", AU_E_EMPTY, NULL);
  EXPECT("e.stl", "", AU_E_EMPTY, NULL);
  EXPECT("c.obj", "# only a comment\n\n", AU_E_EMPTY, NULL);
  EXPECT("v.obj", "v 0 0 0\nv 1 0 0\n", AU_E_EMPTY, NULL);
  EXPECT("z.off", "OFF\n0 0 0\n", AU_E_EMPTY, NULL);
  EXPECT("s.stl", "solid x\nendsolid x\n", AU_E_EMPTY, NULL);
  EXPECT("p.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                  "end_header\n0 0 0\n", AU_E_EMPTY, NULL);
  return 0;
}

static int t_err_truncated(void) {
  AU_CHECK(make_dir("err_truncated"));
  const char *verts = "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  char buf[256];
  snprintf(buf, sizeof buf, "%s3 0 2 1\n3 0 1 3\n", verts);
  EXPECT("faces.off", buf, AU_E_FORMAT, "after 2 of 4 faces");
  EXPECT("verts.off", "OFF\n4 4 6\n0 0 0\n1 0 0\n", AU_E_FORMAT, "after 2 of 4 vertices");
  /* Header counts too small: the rest would silently be lost. */
  snprintf(buf, sizeof buf, "%s3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n", "OFF\n4 3 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
  EXPECT("extra.off", buf, AU_E_FORMAT, "extra.off:10:");
  snprintf(buf, sizeof buf, "%s3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n", "OFF\n3 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
  EXPECT("fewv.off", buf, AU_E_FORMAT, "fewv.off:6:");
  EXPECT("huge.off", "OFF\n400000000 1 0\n0 0 0\n", AU_E_FORMAT, NULL);
  EXPECT("nohdr.off", "4 4 6\n0 0 0\n", AU_E_FORMAT, "not an OFF file");
  EXPECT("t.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
                  "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n",
         AU_E_FORMAT, "face 0");
  EXPECT("h.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\n", AU_E_FORMAT, "end_header");
  return 0;
}

static int t_err_index(void) {
  AU_CHECK(make_dir("err_index"));
  const char *v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
  char buf[256];
  snprintf(buf, sizeof buf, "%sf 1 2 3\nf 1 2 5\n", v);
  EXPECT("hi.obj", buf, AU_E_INDEX, "face 1");
  snprintf(buf, sizeof buf, "%sf 1 2 3\nf 0 2 3\n", v);
  EXPECT("zero.obj", buf, AU_E_INDEX, "face 1");
  /* -5 counts back past the first vertex. */
  snprintf(buf, sizeof buf, "%sf -1 -2 -5\n", v);
  EXPECT("neg.obj", buf, AU_E_INDEX, "face 0");
  /* A negative index counts back from the vertices defined before the face, not from all. */
  EXPECT("early.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n", AU_E_INDEX, "early.obj:3:");
  EXPECT("hi.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", AU_E_INDEX, "face 0");
  EXPECT("neg.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", AU_E_INDEX, "face 0");
  EXPECT("hi.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
                   "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
                   "3 0 1 2\n3 0 1 3\n", AU_E_INDEX, "face 1");
  /* Forward references with positive indices are legal OBJ. */
  au_mesh *m = NULL;
  au_msg msg = {{0}};
  AU_CHECK(puts_file(tp("fwd.obj"), "v 0 0 0\nf 1 2 3\nv 1 0 0\nv 0 1 0\n"));
  AU_CHECK_STATUS(au_io_read(tp("fwd.obj"), &m, &msg), AU_OK, &msg);
  AU_CHECK_INT(m->F[2], ==, 2);
  au_mesh_free(&m);
  return 0;
}

static int t_err_face(void) {
  AU_CHECK(make_dir("err_face"));
  const char *v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";
  char buf[256];
  snprintf(buf, sizeof buf, "%sf 1 2 3\nf 1 2 4 3\n", v);
  EXPECT("quad.obj", buf, AU_E_FACE, "face 1 has 4 corners");
  snprintf(buf, sizeof buf, "%sf 1 2\n", v);
  EXPECT("two.obj", buf, AU_E_FACE, "face 0 has 2 corners");
  EXPECT("quad.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n4 0 1 3 2\n", AU_E_FACE, "face 0 has 4 corners");
  EXPECT("quad.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
                     "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n"
                     "4 0 1 3 2\n", AU_E_FACE, "face 0 has 4 corners");
  return 0;
}

/* Random bytes under a text extension are a format error, never a crash or a mesh. */
static int t_err_garbage(void) {
  AU_CHECK(make_dir("err_garbage"));
  const char *names[4] = {"g.obj", "g.off", "g.ply", "g.stl"};
  uint32_t s = 12345u;
  for (int trial = 0; trial < 8; trial++) {
    unsigned char buf[3000];
    for (size_t i = 0; i < sizeof buf; i++) {
      s = s * 1664525u + 1013904223u;
      buf[i] = (unsigned char)(s >> 24);
    }
    for (int k = 0; k < 4; k++) AU_CHECK(expect(names[k], (const char *)buf, sizeof buf, AU_E_FORMAT, names[k]) == 0);
  }
  /* A PNG signature under .obj: caught on the line of the first control byte. */
  EXPECT("png.obj", "\x89PNG\r\n\x1a\n\0\0\0\rIHDR", AU_E_FORMAT, "png.obj:2:");
  return 0;
}

/* ---------- writing ---------- */

static int t_write_missing_dir(void) {
  AU_CHECK(make_dir("write_missing_dir"));
  au_mesh *m = awkward_mesh();
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_io_write(tp("no_such_dir/out.obj"), m, m->X, NULL, &msg), AU_E_IO, &msg);
  AU_CHECK(strstr(msg.text, "no_such_dir/out.obj") != NULL);
  AU_CHECK_STATUS(au_io_write_text(tp("no_such_dir/r.json"), "{}", 2, &msg), AU_E_IO, &msg);
  AU_CHECK_INT(count_files("no_such_dir"), ==, 0);
  au_mesh_free(&m);
  return 0;
}

/* A write that fails half way (the file-size limit makes write() fail with EFBIG) and a rename that
 * fails (the target is a directory) both leave the old target as it was and no temporary file. */
static int t_write_atomic(void) {
  AU_CHECK(make_dir("write_atomic"));
  au_mesh *m = awkward_mesh();
  au_msg msg = {{0}};
  const char *old = "original contents\n";
  AU_CHECK(puts_file(tp("keep.off"), old));
  struct rlimit saved, small;
  AU_CHECK(getrlimit(RLIMIT_FSIZE, &saved) == 0);
  small = saved;
  small.rlim_cur = 100;
  signal(SIGXFSZ, SIG_IGN);
  AU_CHECK(setrlimit(RLIMIT_FSIZE, &small) == 0);
  au_status st = au_io_write(tp("keep.off"), m, m->X, NULL, &msg);
  AU_CHECK(setrlimit(RLIMIT_FSIZE, &saved) == 0);
  AU_CHECK_STATUS(st, AU_E_IO, &msg);
  AU_CHECK(strstr(msg.text, "keep.off") != NULL);
  char *text = slurp(tp("keep.off"));
  AU_CHECK(text && strcmp(text, old) == 0);
  free(text);
  AU_CHECK_INT(count_files("keep.off"), ==, 1);

  mkdir(tp("isdir.obj"), 0777);
  AU_CHECK_STATUS(au_io_write(tp("isdir.obj"), m, m->X, NULL, &msg), AU_E_IO, &msg);
  struct stat sb;
  AU_CHECK(stat(tp("isdir.obj"), &sb) == 0 && S_ISDIR(sb.st_mode));
  AU_CHECK_INT(count_files("isdir.obj"), ==, 1);

  /* A successful write replaces the old file whole. */
  AU_CHECK_STATUS(au_io_write(tp("keep.off"), m, m->X, NULL, &msg), AU_OK, &msg);
  text = slurp(tp("keep.off"));
  AU_CHECK(text && strncmp(text, "OFF\n6 4 0\n", 10) == 0);
  free(text);
  AU_CHECK_INT(count_files("keep.off"), ==, 1);
  au_mesh_free(&m);
  return 0;
}

/* New files get the mode fopen would give them (not mkstemp's 0600); replaced files keep theirs. */
static int t_write_mode(void) {
  AU_CHECK(make_dir("write_mode"));
  au_msg msg = {{0}};
  unlink(tp("new.json")); /* left by an earlier run */
  mode_t old = umask(022);
  AU_CHECK_STATUS(au_io_write_text(tp("new.json"), "{}\n", 3, &msg), AU_OK, &msg);
  struct stat st;
  AU_CHECK(stat(tp("new.json"), &st) == 0);
  AU_CHECK_INT(st.st_mode & 0777, ==, 0644);
  AU_CHECK(chmod(tp("new.json"), 0640) == 0);
  AU_CHECK_STATUS(au_io_write_text(tp("new.json"), "[]\n", 3, &msg), AU_OK, &msg);
  AU_CHECK(stat(tp("new.json"), &st) == 0);
  AU_CHECK_INT(st.st_mode & 0777, ==, 0640);
  umask(old);
  return 0;
}

static int t_write_text(void) {
  AU_CHECK(make_dir("write_text"));
  au_msg msg = {{0}};
  const char body[] = "{\"a\": 1,\n \"nul\": \"\0\"}";
  AU_CHECK_STATUS(au_io_write_text(tp("r.json"), body, sizeof body - 1, &msg), AU_OK, &msg);
  FILE *fp = fopen(tp("r.json"), "rb");
  AU_CHECK(fp != NULL);
  char got[64];
  size_t n = fread(got, 1, sizeof got, fp);
  fclose(fp);
  AU_CHECK_INT(n, ==, sizeof body - 1);
  AU_CHECK(memcmp(got, body, n) == 0);
  AU_CHECK_STATUS(au_io_write_text(tp("empty.txt"), NULL, 0, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_io_write_text(NULL, "x", 1, &msg), AU_E_ARG, &msg);
  AU_CHECK_STATUS(au_io_write_text(tp("x.txt"), NULL, 1, &msg), AU_E_ARG, &msg);
  return 0;
}

static int t_write_args(void) {
  AU_CHECK(make_dir("write_args"));
  au_mesh *m = awkward_mesh();
  au_msg msg = {{0}};
  AU_CHECK(au_io_can_write("a.obj") && au_io_can_write("dir.x/A.OFF") && au_io_can_write("b.Ply"));
  AU_CHECK(!au_io_can_write("a.stl") && !au_io_can_write("a.obj.tmp") && !au_io_can_write("obj") &&
           !au_io_can_write("dir.obj/x") && !au_io_can_write(NULL));
  AU_CHECK_STATUS(au_io_write(tp("a.stl"), m, m->X, NULL, &msg), AU_E_FORMAT, &msg);
  AU_CHECK_STATUS(au_io_write(tp("a.obj"), m, NULL, NULL, &msg), AU_E_ARG, &msg);
  AU_CHECK_STATUS(au_io_write(tp("a.obj"), NULL, m->X, NULL, &msg), AU_E_ARG, &msg);
  m->F[4] = 6;
  AU_CHECK_STATUS(au_io_write(tp("a.obj"), m, m->X, NULL, &msg), AU_E_ARG, &msg);
  AU_CHECK(strstr(msg.text, "face 1") != NULL);
  AU_CHECK_INT(count_files("a."), ==, 0);
  au_mesh_free(&m);
  return 0;
}

/* The shared cow (closed genus 0): the reader must keep every vertex and face. */
static int t_shared_cow(void) {
  char path[1024];
  if (!au_test_shared_mesh("cow.off", path, sizeof path)) return AU_SKIP;
  au_mesh *m = NULL;
  au_msg msg = {{0}};
  AU_CHECK_STATUS(au_io_read(path, &m, &msg), AU_OK, &msg);
  AU_CHECK_INT(m->nv, ==, 2762);
  AU_CHECK_INT(m->nf, ==, 5520);
  for (int j = 0; j < 3 * m->nf; j++) AU_CHECK(m->F[j] >= 0 && m->F[j] < m->nv);
  au_mesh_free(&m);
  return 0;
}

int main(int argc, char **argv) {
  static const au_test_case cases[] = {
      {"roundtrip_obj", t_roundtrip_obj},   {"roundtrip_off", t_roundtrip_off},
      {"roundtrip_ply", t_roundtrip_ply},   {"obj_uv", t_obj_uv},   {"write_halves", t_write_halves},
      {"write_precision", t_write_precision}, {"order_kept", t_order_kept},
      {"ply_binary", t_ply_binary},         {"obj_forms", t_obj_forms},
      {"off_forms", t_off_forms},           {"nonfinite", t_nonfinite},
      {"nonmanifold_kept", t_nonmanifold_kept}, {"stl", t_stl},
      {"err_missing", t_err_missing},       {"err_directory", t_err_directory},
      {"err_extension", t_err_extension},   {"err_empty", t_err_empty},
      {"err_truncated", t_err_truncated},   {"err_index", t_err_index},
      {"err_face", t_err_face},             {"err_garbage", t_err_garbage},
      {"write_missing_dir", t_write_missing_dir}, {"write_atomic", t_write_atomic},
      {"write_mode", t_write_mode},         {"write_text", t_write_text},
      {"write_args", t_write_args},         {"shared_cow", t_shared_cow},
  };
  return au_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0]));
}
