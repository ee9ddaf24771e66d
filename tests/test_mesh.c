/* test_mesh.c - tests of the mesh arrays, topology and validation on meshes built in code. */
#include "au_mesh.h"
#include "au_test.h"

#include <stdlib.h>
#include <string.h>

/* C11 does not define M_PI. */
#define PI 3.14159265358979323846

/* ---------- mesh builders ---------- */

static au_mesh *mk(int nv, const double *X, int nf, const int *F) {
  au_mesh *m = NULL;
  if (au_mesh_alloc(nv, nf, &m) != AU_OK) return NULL;
  if (X) memcpy(m->X, X, (size_t)3 * nv * sizeof *X);
  if (F) memcpy(m->F, F, (size_t)3 * nf * sizeof *F);
  return m;
}

/* Orient every face of a convex mesh around the origin so its normal points outward. */
static void orient_outward(au_mesh *m) {
  for (int f = 0; f < m->nf; f++) {
    int *c = m->F + 3 * f;
    const double *p = m->X + 3 * c[0], *q = m->X + 3 * c[1], *r = m->X + 3 * c[2];
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    double d = n[0] * (p[0] + q[0] + r[0]) + n[1] * (p[1] + q[1] + r[1]) + n[2] * (p[2] + q[2] + r[2]);
    if (d < 0) {
      int t = c[1];
      c[1] = c[2];
      c[2] = t;
    }
  }
}

/* Faces of a convex polyhedron whose faces are the triples of vertices at mutual distance len. */
static au_mesh *equilateral_hull(int nv, const double *X, int nf, double len) {
  au_mesh *m = mk(nv, X, nf, NULL);
  if (!m) return NULL;
  int n = 0;
  for (int i = 0; i < nv; i++)
    for (int j = i + 1; j < nv; j++)
      for (int k = j + 1; k < nv; k++) {
        int c[3] = {i, j, k}, ok = 1;
        for (int s = 0; s < 3; s++) {
          const double *p = X + 3 * c[s], *q = X + 3 * c[(s + 1) % 3];
          double d = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
          if (fabs(d - len) > 1e-9) ok = 0;
        }
        if (ok && n < nf) memcpy(m->F + 3 * n, c, sizeof c);
        if (ok) n++;
      }
  if (n != nf) {
    au_mesh_free(&m);
    return NULL;
  }
  orient_outward(m);
  return m;
}

static au_mesh *tetra(void) {
  const double X[] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
  return equilateral_hull(4, X, 4, sqrt(8.0));
}

static au_mesh *octahedron(void) {
  const double X[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  return equilateral_hull(6, X, 8, sqrt(2.0));
}

static au_mesh *icosahedron(void) {
  const double g = (1 + sqrt(5.0)) / 2;
  double X[36];
  int n = 0;
  for (int a = 0; a < 3; a++)
    for (int s = -1; s <= 1; s += 2)
      for (int t = -1; t <= 1; t += 2) {
        X[3 * n + a] = 0;
        X[3 * n + (a + 1) % 3] = s;
        X[3 * n + (a + 2) % 3] = t * g;
        n++;
      }
  return equilateral_hull(12, X, 20, 2.0);
}

static au_mesh *cube(void) {
  double X[24];
  for (int i = 0; i < 8; i++)
    for (int a = 0; a < 3; a++) X[3 * i + a] = (i >> a & 1) ? 1 : -1;
  au_mesh *m = mk(8, X, 12, NULL);
  if (!m) return NULL;
  int n = 0;
  for (int a = 0; a < 3; a++)
    for (int s = 0; s < 2; s++) {
      int b = (a + 1) % 3, c = (a + 2) % 3, q[4];
      const int gray[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      for (int i = 0; i < 4; i++) q[i] = s << a | gray[i][0] << b | gray[i][1] << c;
      int t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
      memcpy(m->F + 3 * n, t, sizeof t);
      n += 2;
    }
  orient_outward(m);
  return m;
}

/* One 1-to-4 subdivision with the new vertices projected to the unit sphere. */
static au_mesh *subdivide(au_mesh *m) {
  au_topo *t = NULL;
  au_mesh *r = NULL;
  if (au_mesh_topology(m, &t, NULL) != AU_OK) goto done;
  if (au_mesh_alloc(m->nv + t->ne, 4 * m->nf, &r) != AU_OK) goto done;
  for (int v = 0; v < m->nv; v++) {
    const double *p = m->X + 3 * v;
    double l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int a = 0; a < 3; a++) r->X[3 * v + a] = p[a] / l;
  }
  for (int e = 0; e < t->ne; e++) {
    const double *p = m->X + 3 * t->E[2 * e], *q = m->X + 3 * t->E[2 * e + 1];
    double c[3] = {p[0] + q[0], p[1] + q[1], p[2] + q[2]};
    double l = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (int a = 0; a < 3; a++) r->X[3 * (m->nv + e) + a] = c[a] / l;
  }
  for (int f = 0; f < m->nf; f++) {
    int a = m->F[3 * f], b = m->F[3 * f + 1], c = m->F[3 * f + 2];
    int ma = m->nv + t->FE[3 * f], mb = m->nv + t->FE[3 * f + 1], mc = m->nv + t->FE[3 * f + 2];
    int q[12] = {a, mc, mb, mc, b, ma, mb, ma, c, ma, mb, mc};
    memcpy(r->F + 12 * f, q, sizeof q);
  }
done:
  au_topo_free(&t);
  au_mesh_free(&m);
  return r;
}

enum { FLAT, ANNULUS, TORUS };

/* An nu x nv grid of quads split in two; ANNULUS wraps u, TORUS wraps u and v. */
static au_mesh *grid(int kind, int nu, int nv) {
  int pu = kind != FLAT, pv = kind == TORUS;
  int NU = pu ? nu : nu + 1, NV = pv ? nv : nv + 1;
  au_mesh *m = mk(NU * NV, NULL, 2 * nu * nv, NULL);
  if (!m) return NULL;
  for (int j = 0; j < NV; j++)
    for (int i = 0; i < NU; i++) {
      double *p = m->X + 3 * (i + NU * j), u = 2 * PI * i / nu, v = 2 * PI * j / nv, r = 1.0 + (double)j / nv;
      if (kind == FLAT) p[0] = (double)i / nu, p[1] = (double)j / nv, p[2] = 0;
      if (kind == ANNULUS) p[0] = r * cos(u), p[1] = r * sin(u), p[2] = 0;
      if (kind == TORUS) p[0] = (2 + cos(v)) * cos(u), p[1] = (2 + cos(v)) * sin(u), p[2] = sin(v);
    }
  int n = 0;
  for (int j = 0; j < nv; j++)
    for (int i = 0; i < nu; i++) {
      int a = i % NU + NU * (j % NV), b = (i + 1) % NU + NU * (j % NV);
      int c = (i + 1) % NU + NU * ((j + 1) % NV), d = i % NU + NU * ((j + 1) % NV);
      int q[6] = {a, b, c, a, c, d};
      memcpy(m->F + 6 * n++, q, sizeof q);
    }
  return m;
}

/* A fan disk: center 0 and k rim vertices, counter-clockwise seen from +z. */
static au_mesh *fan(int k) {
  au_mesh *m = mk(k + 1, NULL, k, NULL);
  if (!m) return NULL;
  for (int i = 0; i < k; i++) {
    m->X[3 * (i + 1)] = cos(2 * PI * i / k);
    m->X[3 * (i + 1) + 1] = sin(2 * PI * i / k);
    int q[3] = {0, 1 + i, 1 + (i + 1) % k};
    memcpy(m->F + 3 * i, q, sizeof q);
  }
  return m;
}

/* A latitude-longitude sphere: two poles, nlat-1 rings of nlon vertices; 2*nlon*(nlat-1) faces. */
static au_mesh *uv_sphere(int nlat, int nlon) {
  int nv = 2 + (nlat - 1) * nlon;
  au_mesh *m = mk(nv, NULL, 2 * nlon * (nlat - 1), NULL);
  if (!m) return NULL;
  m->X[2] = 1;
  m->X[3 * (nv - 1) + 2] = -1;
  for (int j = 1; j < nlat; j++)
    for (int i = 0; i < nlon; i++) {
      double th = PI * j / nlat, ph = 2 * PI * i / nlon;
      double *p = m->X + 3 * (1 + (j - 1) * nlon + i);
      p[0] = sin(th) * cos(ph), p[1] = sin(th) * sin(ph), p[2] = cos(th);
    }
  int n = 0;
#define RING(j, i) (1 + ((j) - 1) * nlon + ((i) % nlon))
  for (int i = 0; i < nlon; i++) {
    int q[3] = {0, RING(1, i), RING(1, i + 1)};
    memcpy(m->F + 3 * n++, q, sizeof q);
  }
  for (int j = 1; j < nlat - 1; j++)
    for (int i = 0; i < nlon; i++) {
      int q[6] = {RING(j, i), RING(j + 1, i), RING(j + 1, i + 1), RING(j, i), RING(j + 1, i + 1), RING(j, i + 1)};
      memcpy(m->F + 3 * n, q, sizeof q);
      n += 2;
    }
  for (int i = 0; i < nlon; i++) {
    int q[3] = {nv - 1, RING(nlat - 1, i + 1), RING(nlat - 1, i)};
    memcpy(m->F + 3 * n++, q, sizeof q);
  }
#undef RING
  orient_outward(m);
  return m;
}

/* Two meshes side by side as one mesh (b's vertices shifted by dx and renumbered after a's). */
static au_mesh *join(au_mesh *a, au_mesh *b, double dx) {
  au_mesh *m = mk(a->nv + b->nv, NULL, a->nf + b->nf, NULL);
  if (m) {
    memcpy(m->X, a->X, (size_t)3 * a->nv * sizeof *m->X);
    for (int i = 0; i < 3 * b->nv; i++) m->X[3 * a->nv + i] = b->X[i] + (i % 3 == 0 ? dx : 0);
    memcpy(m->F, a->F, (size_t)3 * a->nf * sizeof *m->F);
    for (int i = 0; i < 3 * b->nf; i++) m->F[3 * a->nf + i] = b->F[i] + a->nv;
  }
  au_mesh_free(&a);
  au_mesh_free(&b);
  return m;
}

/* ---------- invariant checks ---------- */

/* E sorted and distinct, EF/EC/FE consistent, boundary flags match the one-face edges. */
static int check_incidence(const au_mesh *m, const au_topo *t) {
  AU_CHECK_INT(t->nv, ==, m->nv);
  AU_CHECK_INT(t->nf, ==, m->nf);
  for (int e = 0; e < t->ne; e++) {
    AU_CHECK_INT(t->E[2 * e], <, t->E[2 * e + 1]);
    if (e > 0)
      AU_CHECK((long long)t->E[2 * e - 2] * m->nv + t->E[2 * e - 1] < (long long)t->E[2 * e] * m->nv + t->E[2 * e + 1]);
    AU_CHECK(t->EF[2 * e] >= 0);
    for (int s = 0; s < 2; s++) {
      int f = t->EF[2 * e + s], k = t->EC[2 * e + s];
      if (f < 0) {
        AU_CHECK_INT(k, ==, -1);
        continue;
      }
      AU_CHECK(k >= 0 && k < 3);
      AU_CHECK_INT(t->FE[3 * f + k], ==, e);
    }
    if (t->EF[2 * e + 1] < 0) AU_CHECK(t->vb[t->E[2 * e]] && t->vb[t->E[2 * e + 1]]);
  }
  for (int f = 0; f < m->nf; f++)
    for (int k = 0; k < 3; k++) {
      int e = t->FE[3 * f + k];
      AU_CHECK(e >= 0 && e < t->ne);
      AU_CHECK((t->EF[2 * e] == f && t->EC[2 * e] == k) || (t->EF[2 * e + 1] == f && t->EC[2 * e + 1] == k));
      int a = m->F[3 * f + (k + 1) % 3], b = m->F[3 * f + (k + 2) % 3];
      AU_CHECK_INT(t->E[2 * e], ==, a < b ? a : b);
      AU_CHECK_INT(t->E[2 * e + 1], ==, a < b ? b : a);
    }
  int nused = 0;
  for (int v = 0; v < m->nv; v++) nused += t->vused[v];
  AU_CHECK_INT(t->nunreferenced, ==, m->nv - nused);
  AU_CHECK_INT(t->euler, ==, nused - t->ne + m->nf);
  AU_CHECK_INT(2 * t->genus, ==, 2 * t->ncomponents - t->euler - t->nloops);
  return 0;
}

/* 1 if some face runs a -> b. */
static int has_halfedge(const au_mesh *m, int a, int b) {
  for (int f = 0; f < m->nf; f++)
    for (int k = 0; k < 3; k++)
      if (m->F[3 * f + k] == a && m->F[3 * f + (k + 1) % 3] == b) return 1;
  return 0;
}

/* Every loop step a -> b is a boundary half-edge in the faces' direction (and never b -> a);
 * every boundary vertex sits in exactly one loop, once. */
static int check_loops(const au_mesh *m, const au_topo *t) {
  int *seen = calloc((size_t)m->nv, sizeof *seen), nbe = 0, nvb = 0;
  AU_CHECK(seen);
  AU_CHECK_INT(t->loop_start[0], ==, 0);
  for (int l = 0; l < t->nloops; l++) {
    int s = t->loop_start[l], n = t->loop_start[l + 1] - s;
    AU_CHECK(n >= 3);
    for (int i = 0; i < n; i++) {
      int a = t->loop_vert[s + i], b = t->loop_vert[s + (i + 1) % n];
      AU_CHECK(has_halfedge(m, a, b));
      AU_CHECK(!has_halfedge(m, b, a));
      AU_CHECK(t->vb[a]);
      AU_CHECK_INT(seen[a]++, ==, 0);
    }
  }
  for (int e = 0; e < t->ne; e++) nbe += t->EF[2 * e + 1] < 0;
  for (int v = 0; v < m->nv; v++) nvb += t->vb[v];
  AU_CHECK_INT(t->loop_start[t->nloops], ==, nbe);
  AU_CHECK_INT(nvb, ==, nbe);
  free(seen);
  return 0;
}

/* Topology of m with every invariant checked; NULL (after printing) if anything fails. */
static au_topo *topo_checked(const au_mesh *m) {
  au_topo *t = NULL;
  au_msg msg;
  au_status s = au_mesh_topology(m, &t, &msg);
  if (s != AU_OK) {
    fprintf(stderr, "topology: %s (%s)\n", au_status_name(s), msg.text);
    return NULL;
  }
  if (check_incidence(m, t) || check_loops(m, t)) au_topo_free(&t);
  return t;
}

#define CHECK_MSG(msg, word)                                                                   \
  do {                                                                                         \
    if (!strstr((msg).text, (word))) {                                                         \
      fprintf(stderr, "%s:%d: message \"%s\" lacks \"%s\"\n", __FILE__, __LINE__, (msg).text, (word)); \
      return 1;                                                                                \
    }                                                                                          \
  } while (0)

/* Counts of a closed or bounded mesh, checked in one call. */
static int check_counts(au_mesh *m, int ne, int euler, int genus, int nloops, int ncomp) {
  AU_CHECK(m);
  au_topo *t = topo_checked(m);
  AU_CHECK(t);
  AU_CHECK_INT(t->ne, ==, ne);
  AU_CHECK_INT(t->euler, ==, euler);
  AU_CHECK_INT(t->genus, ==, genus);
  AU_CHECK_INT(t->nloops, ==, nloops);
  AU_CHECK_INT(t->ncomponents, ==, ncomp);
  AU_CHECK_INT(t->nunreferenced, ==, 0);
  au_topo_free(&t);
  AU_CHECK(t == NULL);
  au_mesh_free(&m);
  return 0;
}

/* Validate m against expect and check the status and one key word of the message. */
static int check_validate(au_mesh *m, au_mesh_expect x, au_status want, const char *w1, const char *w2) {
  AU_CHECK(m);
  au_msg msg;
  au_topo *t = (au_topo *)&msg; /* any non-NULL value: validate must overwrite it */
  AU_CHECK_STATUS(au_mesh_validate(m, &x, &t, &msg), want, &msg);
  if (want < 0) AU_CHECK(t == NULL);
  if (want >= 0) AU_CHECK(t != NULL);
  if (w1) CHECK_MSG(msg, w1);
  if (w2) CHECK_MSG(msg, w2);
  AU_CHECK(strchr(msg.text, '\n') == NULL);
  if (want == AU_OK) AU_CHECK_INT(msg.text[0], ==, 0);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}

static au_mesh_expect expect(int loops, int genus, const char *cmd) {
  au_mesh_expect x = au_mesh_expect_default();
  x.loops = loops;
  x.genus = genus;
  x.command = cmd;
  return x;
}

/* ---------- cases: arrays ---------- */

static int alloc_free(void) {
  au_mesh *m = NULL;
  AU_CHECK_STATUS(au_mesh_alloc(-1, 2, &m), AU_E_ARG, (au_msg *)NULL);
  AU_CHECK(m == NULL);
  AU_CHECK_STATUS(au_mesh_alloc(2, -1, &m), AU_E_ARG, (au_msg *)NULL);
  AU_CHECK_STATUS(au_mesh_alloc(2, 1, NULL), AU_E_ARG, (au_msg *)NULL);
  AU_CHECK_STATUS(au_mesh_alloc(5, 7, &m), AU_OK, (au_msg *)NULL);
  AU_CHECK_INT(m->nv, ==, 5);
  AU_CHECK_INT(m->nf, ==, 7);
  for (int i = 0; i < 15; i++) AU_CHECK_DBL(m->X[i], ==, 0);
  for (int i = 0; i < 21; i++) AU_CHECK_INT(m->F[i], ==, 0);
  au_mesh_free(&m);
  AU_CHECK(m == NULL);
  au_mesh_free(&m);
  au_mesh_free(NULL);
  au_topo_free(NULL);
  AU_CHECK_STATUS(au_mesh_alloc(0, 0, &m), AU_OK, (au_msg *)NULL);
  au_mesh_free(&m);
  return 0;
}

static int copy_deep(void) {
  au_mesh *a = octahedron(), *b = NULL;
  AU_CHECK(a);
  AU_CHECK_STATUS(au_mesh_copy(a, &b), AU_OK, (au_msg *)NULL);
  AU_CHECK(b->X != a->X && b->F != a->F);
  AU_CHECK_INT(b->nv, ==, 6);
  AU_CHECK_INT(b->nf, ==, 8);
  AU_CHECK(memcmp(a->X, b->X, 18 * sizeof(double)) == 0);
  AU_CHECK(memcmp(a->F, b->F, 24 * sizeof(int)) == 0);
  int f0 = a->F[0];
  b->X[0] = 42;
  b->F[0] = f0 + 1;
  AU_CHECK_DBL(a->X[0], ==, 1);
  AU_CHECK_INT(a->F[0], ==, f0);
  au_mesh_free(&b);
  AU_CHECK_STATUS(au_mesh_copy(NULL, &b), AU_E_ARG, (au_msg *)NULL);
  AU_CHECK(b == NULL);
  AU_CHECK_STATUS(au_mesh_copy(a, NULL), AU_E_ARG, (au_msg *)NULL);
  au_mesh_free(&a);
  return 0;
}

static int expect_default(void) {
  au_mesh_expect x = au_mesh_expect_default();
  AU_CHECK_INT(x.loops, ==, 0);
  AU_CHECK_INT(x.genus, ==, 0);
  AU_CHECK(x.command == NULL);
  return 0;
}

/* ---------- cases: topology ---------- */

static int topo_tetra(void) {
  au_mesh *m = tetra();
  AU_CHECK(m);
  au_topo *t = topo_checked(m);
  AU_CHECK(t);
  AU_CHECK_INT(t->ne, ==, 6);
  AU_CHECK_INT(t->euler, ==, 2);
  AU_CHECK_INT(t->genus, ==, 0);
  AU_CHECK_INT(t->nloops, ==, 0);
  AU_CHECK_INT(t->ncomponents, ==, 1);
  /* In a tetrahedron every pair of vertices is an edge, listed in lexicographic order. */
  const int E[12] = {0, 1, 0, 2, 0, 3, 1, 2, 1, 3, 2, 3};
  for (int i = 0; i < 12; i++) AU_CHECK_INT(t->E[i], ==, E[i]);
  for (int e = 0; e < 6; e++) AU_CHECK(t->EF[2 * e + 1] >= 0 && t->EF[2 * e] != t->EF[2 * e + 1]);
  for (int v = 0; v < 4; v++) AU_CHECK(!t->vb[v] && t->vused[v]);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}

static int topo_octahedron(void) { return check_counts(octahedron(), 12, 2, 0, 0, 1); }
static int topo_cube_counts(void) { return check_counts(cube(), 18, 2, 0, 0, 1); }
static int topo_icosphere(void) {
  /* Two subdivisions of the icosahedron: V 162, E 480, F 320. */
  au_mesh *m = subdivide(subdivide(icosahedron()));
  AU_CHECK(m && m->nv == 162 && m->nf == 320);
  return check_counts(m, 480, 2, 0, 0, 1);
}
static int topo_disk_grid(void) { return check_counts(grid(FLAT, 5, 4), 5 * 5 + 6 * 4 + 5 * 4, 1, 0, 1, 1); }
static int topo_disk_fan(void) { return check_counts(fan(9), 18, 1, 0, 1, 1); }
static int topo_annulus(void) { return check_counts(grid(ANNULUS, 12, 3), 12 * 4 + 12 * 3 + 12 * 3, 0, 0, 2, 1); }
static int topo_torus(void) { return check_counts(grid(TORUS, 8, 5), 3 * 40, 0, 1, 0, 1); }
static int topo_two_tetra(void) { return check_counts(join(tetra(), tetra(), 5), 12, 4, 0, 0, 2); }
static int topo_two_disks(void) { return check_counts(join(fan(5), grid(FLAT, 2, 2), 3), 10 + 16, 2, 0, 2, 2); }

static int loops_disk_order(void) {
  /* The grid's faces are counter-clockwise seen from +z, so its boundary runs counter-clockwise:
   * from vertex 0 (the corner at the origin) along the x axis first. */
  int nu = 6, nv = 4;
  au_mesh *m = grid(FLAT, nu, nv);
  AU_CHECK(m);
  au_topo *t = topo_checked(m);
  AU_CHECK(t);
  AU_CHECK_INT(t->nloops, ==, 1);
  AU_CHECK_INT(t->loop_start[1], ==, 2 * (nu + nv));
  AU_CHECK_INT(t->loop_vert[0], ==, 0);
  AU_CHECK_INT(t->loop_vert[1], ==, 1);
  AU_CHECK_INT(t->loop_vert[nu], ==, nu);
  AU_CHECK_INT(t->loop_vert[nu + 1], ==, nu + (nu + 1));
  double area = 0;
  for (int i = 0; i < t->loop_start[1]; i++) {
    const double *p = m->X + 3 * t->loop_vert[i], *q = m->X + 3 * t->loop_vert[(i + 1) % t->loop_start[1]];
    area += 0.5 * (p[0] * q[1] - q[0] * p[1]);
  }
  AU_CHECK_NEAR(area, 1.0, 1e-12);
  /* Interior vertices are not on the boundary. */
  AU_CHECK(!t->vb[1 + (nu + 1)]);
  AU_CHECK_NEAR(t->loop_len[0], 4.0, 1e-12);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}

static int loops_annulus_len(void) {
  /* Two circles of radius 1 and 2 sampled by n chords each. */
  int n = 16;
  au_mesh *m = grid(ANNULUS, n, 2);
  AU_CHECK(m);
  au_topo *t = topo_checked(m);
  AU_CHECK(t);
  AU_CHECK_INT(t->nloops, ==, 2);
  double chord = 2 * sin(PI / n);
  for (int l = 0; l < 2; l++) {
    AU_CHECK_INT(t->loop_start[l + 1] - t->loop_start[l], ==, n);
    int r = t->loop_vert[t->loop_start[l]] / n == 0 ? 1 : 2;
    AU_CHECK_NEAR(t->loop_len[l], r * n * chord, 1e-12);
  }
  /* Without positions the lengths are absent but the loops are the same. */
  double *X = m->X;
  m->X = NULL;
  au_topo *t2 = NULL;
  AU_CHECK_STATUS(au_mesh_topology(m, &t2, NULL), AU_OK, (au_msg *)NULL);
  m->X = X;
  AU_CHECK(t2->loop_len == NULL);
  AU_CHECK_INT(t2->nloops, ==, 2);
  AU_CHECK(memcmp(t2->loop_vert, t->loop_vert, 2 * n * sizeof(int)) == 0);
  au_topo_free(&t2);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}

static int topo_unreferenced(void) {
  /* A tetrahedron whose vertices are 0, 1, 3, 4 of six: 2 and 5 are unused. */
  au_mesh *a = tetra();
  AU_CHECK(a);
  const int map[4] = {0, 1, 3, 4};
  au_mesh *m = mk(6, NULL, 4, NULL);
  AU_CHECK(m);
  for (int v = 0; v < 4; v++) memcpy(m->X + 3 * map[v], a->X + 3 * v, 3 * sizeof(double));
  for (int i = 0; i < 12; i++) m->F[i] = map[a->F[i]];
  au_mesh_free(&a);
  au_topo *t = topo_checked(m);
  AU_CHECK(t);
  AU_CHECK_INT(t->nunreferenced, ==, 2);
  AU_CHECK(!t->vused[2] && !t->vused[5] && t->vused[3]);
  AU_CHECK_INT(t->euler, ==, 2);
  AU_CHECK_INT(t->genus, ==, 0);
  AU_CHECK_INT(t->ncomponents, ==, 1);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}

static int topo_nonmanifold_edge(void) {
  /* Three triangles hinged on edge (3, 7). */
  const int F[] = {3, 7, 1, 7, 3, 2, 3, 7, 5};
  au_mesh *m = mk(8, NULL, 3, F);
  AU_CHECK(m);
  au_topo *t = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_mesh_topology(m, &t, &msg), AU_E_NONMANIFOLD_EDGE, &msg);
  AU_CHECK(t == NULL);
  CHECK_MSG(msg, "(3, 7)");
  CHECK_MSG(msg, "3 faces");
  au_mesh_free(&m);
  return 0;
}

static int topo_bowtie(void) {
  /* Two fans of 3 faces touching at vertex 4: the faces of 4 form 2 fans, both open. */
  const int F[] = {4, 0, 1, 4, 1, 2, 4, 2, 3, 4, 5, 6, 4, 6, 7, 4, 7, 8};
  au_mesh *m = mk(9, NULL, 6, F);
  AU_CHECK(m);
  au_topo *t = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_mesh_topology(m, &t, &msg), AU_E_NONMANIFOLD_VERTEX, &msg);
  AU_CHECK(t == NULL);
  CHECK_MSG(msg, "vertex 4 ");
  CHECK_MSG(msg, "2 separate fans");
  au_mesh_free(&m);
  return 0;
}

static int topo_pinched_spheres(void) {
  /* Two octahedra sharing one vertex: around it the faces form two closed fans, and the edges are
   * all manifold, so only the fan count can tell. The shared vertex is number 7. */
  au_mesh *m = join(octahedron(), octahedron(), 2);
  AU_CHECK(m);
  /* Vertex 0 of the first octahedron is (1,0,0); vertex 1 of the second is (-1+2,0,0) = the same point. */
  for (int i = 0; i < 3 * m->nf; i++)
    if (m->F[i] == 0) m->F[i] = 7;
  AU_CHECK_NEAR(m->X[3 * 7], 1.0, 0);
  au_topo *t = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_mesh_topology(m, &t, &msg), AU_E_NONMANIFOLD_VERTEX, &msg);
  CHECK_MSG(msg, "vertex 7 ");
  CHECK_MSG(msg, "2 separate fans");
  au_mesh_free(&m);
  return 0;
}

static int topo_flipped_face(void) {
  /* Reverse the tetrahedron's face on vertices {1, 2, 3}: all its edges now disagree with the
   * neighbours, and the first in edge order is (1, 2). */
  au_mesh *m = tetra();
  AU_CHECK(m);
  int f = 0;
  while (m->F[3 * f] == 0 || m->F[3 * f + 1] == 0 || m->F[3 * f + 2] == 0) f++;
  int tmp = m->F[3 * f + 1];
  m->F[3 * f + 1] = m->F[3 * f + 2];
  m->F[3 * f + 2] = tmp;
  au_topo *t = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_mesh_topology(m, &t, &msg), AU_E_ORIENTATION, &msg);
  AU_CHECK(t == NULL);
  CHECK_MSG(msg, "orientation");
  CHECK_MSG(msg, "(1, 2)");
  au_mesh_free(&m);
  return 0;
}

static int topo_args(void) {
  au_topo *t = NULL;
  au_msg msg;
  au_mesh *m = tetra();
  AU_CHECK(m);
  AU_CHECK_STATUS(au_mesh_topology(NULL, &t, &msg), AU_E_ARG, &msg);
  AU_CHECK_STATUS(au_mesh_topology(m, NULL, &msg), AU_E_ARG, &msg);
  m->F[5] = 4;
  AU_CHECK_STATUS(au_mesh_topology(m, &t, &msg), AU_E_ARG, &msg);
  AU_CHECK(t == NULL);
  m->F[5] = m->F[4];
  AU_CHECK_STATUS(au_mesh_topology(m, &t, &msg), AU_E_ARG, &msg);
  au_mesh_free(&m);
  /* An empty mesh has an empty topology. */
  AU_CHECK_STATUS(au_mesh_alloc(0, 0, &m), AU_OK, &msg);
  AU_CHECK_STATUS(au_mesh_topology(m, &t, &msg), AU_OK, &msg);
  AU_CHECK_INT(t->ne, ==, 0);
  AU_CHECK_INT(t->nloops, ==, 0);
  AU_CHECK_INT(t->ncomponents, ==, 0);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}

static int topo_scale_200k(void) {
  /* 400 x 251 latitude-longitude sphere: 200000 faces, 100002 vertices, 300000 edges. */
  au_mesh *m = uv_sphere(251, 400);
  AU_CHECK(m);
  AU_CHECK_INT(m->nf, ==, 200000);
  au_topo *t = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_mesh_validate(m, NULL, &t, &msg), AU_OK, &msg);
  AU_CHECK_INT(t->ne, ==, 300000);
  AU_CHECK_INT(t->euler, ==, 2);
  AU_CHECK_INT(t->genus, ==, 0);
  AU_CHECK_INT(t->ncomponents, ==, 1);
  for (int f = 0; f < m->nf; f++)
    for (int k = 0; k < 3; k++) {
      int e = t->FE[3 * f + k];
      AU_CHECK((t->EF[2 * e] == f && t->EC[2 * e] == k) || (t->EF[2 * e + 1] == f && t->EC[2 * e + 1] == k));
    }
  au_topo_free(&t);
  /* Cutting one cap face open gives a disk whose single loop has 3 vertices. */
  m->nf--;
  AU_CHECK_STATUS(au_mesh_topology(m, &t, &msg), AU_OK, &msg);
  AU_CHECK_INT(t->nloops, ==, 1);
  AU_CHECK_INT(t->loop_start[1], ==, 3);
  AU_CHECK_INT(t->euler, ==, 1);
  au_topo_free(&t);
  au_mesh_free(&m);
  return 0;
}

/* ---------- cases: validation ---------- */

static int validate_ok_sphere(void) {
  return check_validate(subdivide(icosahedron()), expect(0, 0, "sphere"), AU_OK, NULL, NULL);
}
static int validate_ok_disk(void) { return check_validate(grid(FLAT, 4, 4), expect(1, 0, "disk"), AU_OK, NULL, NULL); }
static int validate_ok_annulus(void) { return check_validate(grid(ANNULUS, 8, 2), expect(2, 0, NULL), AU_OK, NULL, NULL); }
static int validate_ok_torus(void) { return check_validate(grid(TORUS, 8, 6), expect(0, 1, NULL), AU_OK, NULL, NULL); }
static int validate_any(void) {
  /* A torus with a hole passes when nothing is required. */
  au_mesh *m = grid(TORUS, 8, 6);
  AU_CHECK(m);
  m->nf--;
  return check_validate(m, expect(-1, -1, NULL), AU_OK, NULL, NULL);
}

static int validate_empty(void) {
  au_mesh *m = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_mesh_validate(NULL, NULL, NULL, &msg), AU_E_ARG, &msg);
  AU_CHECK_STATUS(au_mesh_alloc(0, 0, &m), AU_OK, &msg);
  AU_CHECK(check_validate(m, au_mesh_expect_default(), AU_E_EMPTY, "empty", NULL) == 0);
  AU_CHECK_STATUS(au_mesh_alloc(4, 0, &m), AU_OK, &msg);
  return check_validate(m, au_mesh_expect_default(), AU_E_EMPTY, "empty", "0 faces");
}

static int validate_nonfinite(void) {
  au_mesh *m = octahedron();
  AU_CHECK(m);
  m->X[3 * 5 + 1] = NAN;
  AU_CHECK(check_validate(m, au_mesh_expect_default(), AU_E_NONFINITE, "vertex 5 ", "non-finite") == 0);
  m = octahedron();
  AU_CHECK(m);
  m->X[3 * 2 + 2] = -INFINITY;
  return check_validate(m, au_mesh_expect_default(), AU_E_NONFINITE, "vertex 2 ", NULL);
}

static int validate_index(void) {
  au_mesh *m = grid(FLAT, 4, 4); /* 25 vertices, 32 faces */
  AU_CHECK(m);
  m->F[3 * 9 + 1] = 120;
  m->F[3 * 12] = 30; /* a later face is also bad: the first one is named */
  AU_CHECK(check_validate(m, au_mesh_expect_default(), AU_E_INDEX, "face 9 ", "vertex 120 but the mesh has 25 vertices") == 0);
  m = grid(FLAT, 4, 4);
  AU_CHECK(m);
  m->F[3 * 2 + 2] = -1;
  return check_validate(m, au_mesh_expect_default(), AU_E_INDEX, "face 2 ", "vertex -1 ");
}

static int validate_repeat(void) {
  au_mesh *m = octahedron();
  AU_CHECK(m);
  m->F[3 * 3 + 2] = m->F[3 * 3 + 1];
  char want[32];
  snprintf(want, sizeof want, "repeats vertex %d", m->F[3 * 3 + 1]);
  AU_CHECK(check_validate(m, au_mesh_expect_default(), AU_E_FACE, "face 3 ", want) == 0);
  m = octahedron();
  AU_CHECK(m);
  m->F[3 * 6 + 2] = m->F[3 * 6];
  snprintf(want, sizeof want, "repeats vertex %d", m->F[3 * 6]);
  return check_validate(m, au_mesh_expect_default(), AU_E_FACE, "face 6 ", want);
}

static int validate_nonmanifold_edge(void) {
  /* A tetrahedron with an extra fin on edge (1, 3): that edge has 3 faces. */
  au_mesh *a = tetra();
  AU_CHECK(a);
  au_mesh *m = mk(5, NULL, 5, NULL);
  AU_CHECK(m);
  memcpy(m->X, a->X, 12 * sizeof(double));
  m->X[12] = 3;
  memcpy(m->F, a->F, 12 * sizeof(int));
  int fin[3] = {1, 3, 4};
  memcpy(m->F + 12, fin, sizeof fin);
  au_mesh_free(&a);
  return check_validate(m, au_mesh_expect_default(), AU_E_NONMANIFOLD_EDGE, "non-manifold edge (1, 3)", "shared by 3 faces");
}

static int validate_nonmanifold_vertex(void) {
  const int F[] = {4, 0, 1, 4, 1, 2, 4, 2, 3, 4, 5, 6, 4, 6, 7, 4, 7, 8};
  au_mesh *m = mk(9, NULL, 6, F);
  AU_CHECK(m);
  for (int v = 0; v < 9; v++) m->X[3 * v] = v, m->X[3 * v + 1] = v * v;
  return check_validate(m, expect(1, 0, "disk"), AU_E_NONMANIFOLD_VERTEX, "vertex 4 is non-manifold", "2 separate fans");
}

static int validate_orientation(void) {
  /* Flip one face of a grid disk; its diagonal edge (a, c) is where both faces of the quad disagree. */
  au_mesh *m = grid(FLAT, 3, 3);
  AU_CHECK(m);
  int f = 2 * 4; /* first triangle of the centre quad: (5, 6, 10) */
  AU_CHECK(m->F[3 * f] == 5 && m->F[3 * f + 1] == 6 && m->F[3 * f + 2] == 10);
  m->F[3 * f + 1] = 10;
  m->F[3 * f + 2] = 6;
  return check_validate(m, expect(1, 0, "disk"), AU_E_ORIENTATION, "orientation", "(5, 6)");
}

static int validate_components(void) {
  au_mesh *m = join(tetra(), join(tetra(), tetra(), 5), 5);
  return check_validate(m, au_mesh_expect_default(), AU_E_COMPONENTS, "3 connected components", "expected 1");
}

static int validate_disk_for_sphere(void) {
  au_mesh *m = grid(FLAT, 8, 8);
  return check_validate(m, expect(0, 0, "sphere"), AU_E_BOUNDARY, "1 boundary loop (32 vertices)", "map a disk-like mesh onto the disk");
}

static int validate_boundary_before_genus(void) {
  /* A torus with one face removed has genus 1 and a boundary: sphere must hear about the boundary. */
  au_mesh *m = grid(TORUS, 8, 6);
  AU_CHECK(m);
  m->nf--;
  return check_validate(m, expect(0, 0, "sphere"), AU_E_BOUNDARY, "1 boundary loop (3 vertices)", "the sphere map needs a closed surface");
}

static int validate_closed_for_disk(void) {
  return check_validate(octahedron(), expect(1, 0, "disk"), AU_E_BOUNDARY, "closed mesh given to the disk map", "map it onto the sphere");
}

static int validate_annulus_for_disk(void) {
  au_mesh *m = grid(ANNULUS, 10, 2);
  AU_CHECK(check_validate(m, expect(1, 0, "disk"), AU_E_BOUNDARY, "2 boundary loops (sizes 10, 10)", "needs 1") == 0);
  m = grid(ANNULUS, 10, 2);
  return check_validate(m, expect(1, 0, NULL), AU_E_BOUNDARY, "2 boundary loops", "expected 1");
}

static int validate_genus(void) {
  AU_CHECK(check_validate(grid(TORUS, 8, 6), au_mesh_expect_default(), AU_E_GENUS, "genus 1", "expected genus 0") == 0);
  return check_validate(octahedron(), expect(0, 1, NULL), AU_E_GENUS, "genus 0", "expected genus 1");
}

static int validate_degenerate(void) {
  /* Move the octahedron's top vertex to the midpoint of two equator vertices: exactly the face on
   * those three becomes a segment. */
  au_mesh *m = octahedron();
  AU_CHECK(m);
  double mid[3] = {0.5, 0.5, 0};
  memcpy(m->X + 3 * 4, mid, sizeof mid);
  int bad = -1;
  for (int f = 0; f < 8; f++) {
    int *c = m->F + 3 * f, has[6] = {0};
    for (int k = 0; k < 3; k++) has[c[k]] = 1;
    if (has[0] && has[2] && has[4]) bad = f;
  }
  AU_CHECK(bad >= 0);
  char want[32];
  snprintf(want, sizeof want, "face %d has zero area", bad);
  AU_CHECK(check_validate(m, au_mesh_expect_default(), AU_E_DEGENERATE, want, "(1 such face)") == 0);
  /* The test is relative: the same mesh a million times smaller fails the same way. */
  m = octahedron();
  AU_CHECK(m);
  memcpy(m->X + 3 * 4, mid, sizeof mid);
  for (int i = 0; i < 18; i++) m->X[i] *= 1e-6;
  AU_CHECK(check_validate(m, au_mesh_expect_default(), AU_E_DEGENERATE, want, NULL) == 0);
  /* Two faces collapse when the top vertex lands on an equator vertex. */
  m = octahedron();
  AU_CHECK(m);
  m->X[12] = 1, m->X[14] = 0;
  AU_CHECK(check_validate(m, au_mesh_expect_default(), AU_E_DEGENERATE, "zero area (2 such faces)", NULL) == 0);
  /* A thin but real face (area ratio ~2e-11) is accepted, at any scale. */
  m = octahedron();
  AU_CHECK(m);
  m->X[12] = 0.5, m->X[13] = 0.5, m->X[14] = 1e-10;
  for (int i = 0; i < 18; i++) m->X[i] *= 1e6;
  return check_validate(m, au_mesh_expect_default(), AU_OK, NULL, NULL);
}

static int validate_zero_total_area(void) {
  au_mesh *m = octahedron();
  AU_CHECK(m);
  for (int i = 0; i < 18; i++) m->X[i] = 3;
  return check_validate(m, au_mesh_expect_default(), AU_E_DEGENERATE, "total area", NULL);
}

static int validate_unreferenced(void) {
  au_mesh *a = octahedron();
  AU_CHECK(a);
  /* Octahedron vertices at 0..2 and 5..7 of nine: 3, 4 and 8 are unreferenced. */
  const int map[6] = {0, 1, 2, 5, 6, 7};
  au_mesh *m = mk(9, NULL, 8, NULL);
  AU_CHECK(m);
  for (int v = 0; v < 6; v++) memcpy(m->X + 3 * map[v], a->X + 3 * v, 3 * sizeof(double));
  for (int i = 0; i < 24; i++) m->F[i] = map[a->F[i]];
  au_mesh_free(&a);
  au_msg msg;
  au_topo *t = NULL;
  AU_CHECK_STATUS(au_mesh_validate(m, NULL, &t, &msg), AU_W_UNREFERENCED, &msg);
  CHECK_MSG(msg, "3 vertices are referenced by no face (first: 3)");
  CHECK_MSG(msg, "keep their place");
  AU_CHECK(t);
  AU_CHECK_INT(t->nunreferenced, ==, 3);
  AU_CHECK_INT(t->euler, ==, 2);
  au_topo_free(&t);
  /* Errors win over the warning: a NaN on an unreferenced vertex is still an error (every
   * coordinate is checked), and so is a flipped face. */
  m->X[3 * 4] = NAN;
  AU_CHECK_STATUS(au_mesh_validate(m, NULL, &t, &msg), AU_E_NONFINITE, &msg);
  CHECK_MSG(msg, "vertex 4 ");
  m->X[3 * 4] = 0;
  int tmp = m->F[1];
  m->F[1] = m->F[2];
  m->F[2] = tmp;
  AU_CHECK_STATUS(au_mesh_validate(m, NULL, &t, &msg), AU_E_ORIENTATION, &msg);
  AU_CHECK(t == NULL);
  au_mesh_free(&m);
  /* One unreferenced vertex is said in the singular. */
  a = tetra();
  AU_CHECK(a);
  m = mk(5, NULL, 4, a->F);
  AU_CHECK(m);
  memcpy(m->X, a->X, 12 * sizeof(double));
  au_mesh_free(&a);
  AU_CHECK_STATUS(au_mesh_validate(m, NULL, NULL, &msg), AU_W_UNREFERENCED, &msg);
  CHECK_MSG(msg, "1 vertex is referenced by no face (4)");
  au_mesh_free(&m);
  return 0;
}

static int validate_no_topo_out(void) {
  /* Without a topology pointer validation still works and frees what it built. */
  au_msg msg;
  au_mesh *m = cube();
  AU_CHECK(m);
  AU_CHECK_STATUS(au_mesh_validate(m, NULL, NULL, &msg), AU_OK, &msg);
  AU_CHECK_STATUS(au_mesh_validate(m, NULL, NULL, NULL), AU_OK, &msg);
  au_mesh_free(&m);
  return 0;
}


/* ---------- orientation repair (au_mesh_orient) ---------- */

/* A Moebius strip of n quads (2n vertices, 2n faces): the last quad joins the top of the first
 * segment to the bottom of the last, so no orientation of the faces agrees everywhere. */
static au_mesh *moebius(int n) {
  au_mesh *m = mk(2 * n, NULL, 2 * n, NULL);
  if (!m) return NULL;
  for (int i = 0; i < n; i++)
    for (int s = 0; s < 2; s++) {
      double th = 2 * PI * i / n, w = s ? -0.3 : 0.3, r = 1 + w * cos(th / 2);
      double *p = m->X + 3 * (i + s * n);
      p[0] = r * cos(th), p[1] = r * sin(th), p[2] = w * sin(th / 2);
    }
  for (int i = 0; i < n; i++) {
    int t = i, b = n + i, tn = i + 1, bn = n + i + 1;
    if (i == n - 1) tn = n, bn = 0; /* the half twist: top meets bottom */
    int q[6] = {t, b, bn, t, bn, tn};
    memcpy(m->F + 6 * i, q, sizeof q);
  }
  return m;
}

static void flip_face(au_mesh *m, int f) {
  int tmp = m->F[3 * f + 1];
  m->F[3 * f + 1] = m->F[3 * f + 2];
  m->F[3 * f + 2] = tmp;
}

static int orient_consistent(void) {
  /* An oriented mesh is left alone, byte for byte. */
  au_mesh *m = grid(TORUS, 6, 5), *c = NULL;
  AU_CHECK(m);
  AU_CHECK_STATUS(au_mesh_copy(m, &c), AU_OK, NULL);
  au_msg msg;
  int n = -1;
  AU_CHECK_STATUS(au_mesh_orient(m, &n, &msg), AU_OK, &msg);
  AU_CHECK_INT(n, ==, 0);
  AU_CHECK_INT(msg.text[0], ==, 0);
  AU_CHECK(memcmp(m->F, c->F, 3 * (size_t)m->nf * sizeof *m->F) == 0);
  au_mesh_free(&m);
  au_mesh_free(&c);
  return 0;
}

static int orient_two_flipped(void) {
  /* Two reversed faces of a closed torus and of a disk come back as they were, with a warning that
   * names the count and the first; validation then passes. */
  for (int kind = 0; kind < 2; kind++) {
    au_mesh *m = kind ? grid(FLAT, 5, 4) : grid(TORUS, 8, 6), *c = NULL;
    AU_CHECK(m);
    AU_CHECK_STATUS(au_mesh_copy(m, &c), AU_OK, NULL);
    flip_face(m, 3);
    flip_face(m, m->nf - 2);
    au_msg msg;
    int n = 0;
    AU_CHECK_STATUS(au_mesh_orient(m, &n, &msg), AU_W_REORIENTED, &msg);
    AU_CHECK_INT(n, ==, 2);
    CHECK_MSG(msg, "re-oriented 2 of ");
    CHECK_MSG(msg, "first: face 3)");
    AU_CHECK(memcmp(m->F, c->F, 3 * (size_t)m->nf * sizeof *m->F) == 0);
    au_mesh_expect x = au_mesh_expect_default();
    x.loops = kind ? 1 : 0, x.genus = kind ? 0 : 1;
    AU_CHECK_STATUS(au_mesh_validate(m, &x, NULL, &msg), AU_OK, &msg);
    au_mesh_free(&m);
    au_mesh_free(&c);
  }
  return 0;
}

static int orient_majority(void) {
  /* All faces but one reversed: the walk starts at the kept face, and the orientation that reverses
   * fewer faces wins, so only that one face is turned. Each component is decided on its own. */
  au_mesh *a = grid(FLAT, 4, 4), *b = grid(FLAT, 3, 3);
  AU_CHECK(a && b);
  au_mesh *m = mk(a->nv + b->nv, NULL, a->nf + b->nf, NULL);
  AU_CHECK(m);
  memcpy(m->X, a->X, 3 * (size_t)a->nv * sizeof *m->X);
  memcpy(m->X + 3 * a->nv, b->X, 3 * (size_t)b->nv * sizeof *m->X);
  memcpy(m->F, a->F, 3 * (size_t)a->nf * sizeof *m->F);
  for (int i = 0; i < 3 * b->nf; i++) m->F[3 * a->nf + i] = b->F[i] + a->nv;
  for (int f = 1; f < a->nf; f++) flip_face(m, f); /* component a: all but face 0 reversed */
  flip_face(m, a->nf + 4);                          /* component b: one face reversed */
  au_msg msg;
  int n = 0;
  AU_CHECK_STATUS(au_mesh_orient(m, &n, &msg), AU_W_REORIENTED, &msg);
  AU_CHECK_INT(n, ==, 2);
  CHECK_MSG(msg, "first: face 0)");
  for (int f = 0; f < a->nf; f++) flip_face(a, f); /* every face of a reversed, face 0 now too */
  AU_CHECK(memcmp(m->F, a->F, 3 * (size_t)a->nf * sizeof *m->F) == 0);
  for (int i = 0; i < 3 * b->nf; i++) AU_CHECK_INT(m->F[3 * a->nf + i], ==, b->F[i] + a->nv);
  au_mesh_free(&a);
  au_mesh_free(&b);
  au_mesh_free(&m);
  return 0;
}

static int orient_moebius(void) {
  /* A Moebius strip cannot be oriented: the walk names the edge where it met itself reversed, and
   * the faces are left as they were. The public check says the same; a strip with one face reversed
   * too is still refused. */
  au_mesh *m = moebius(8), *c = NULL;
  AU_CHECK(m);
  AU_CHECK_STATUS(au_mesh_copy(m, &c), AU_OK, NULL);
  au_topo *t = NULL;
  au_msg msg;
  AU_CHECK_STATUS(au_mesh_topology(m, &t, &msg), AU_E_ORIENTATION, &msg); /* it is a manifold */
  for (int flipped = 0; flipped < 2; flipped++) {
    if (flipped) flip_face(m, 5), flip_face(c, 5);
    int n = -1;
    AU_CHECK_STATUS(au_mesh_orient(m, &n, &msg), AU_E_ORIENTATION, &msg);
    AU_CHECK_INT(n, ==, 0);
    CHECK_MSG(msg, "non-orientable");
    CHECK_MSG(msg, "edge (");
    AU_CHECK(memcmp(m->F, c->F, 3 * (size_t)m->nf * sizeof *m->F) == 0);
    AU_CHECK_STATUS(au_mesh_check(m->X, m->nv, m->F, m->nf, AU_TARGET_DISK, &msg), AU_E_ORIENTATION, &msg);
    CHECK_MSG(msg, "non-orientable");
  }
  /* The walk from face 0 goes round both ways and meets itself reversed halfway, on the diagonal of
   * the fifth quad (faces 8 and 9): the first edge where no orientation agrees. */
  AU_CHECK_STATUS(au_mesh_orient(m, NULL, &msg), AU_E_ORIENTATION, &msg);
  CHECK_MSG(msg, "edge (4, 13) (faces 9 and 8)");
  au_mesh_free(&m);
  au_mesh_free(&c);
  return 0;
}

static int orient_errors(void) {
  /* Problems that come before orientation are named as validation names them, and leave F alone. */
  au_msg msg;
  AU_CHECK_STATUS(au_mesh_orient(NULL, NULL, &msg), AU_E_ARG, &msg);
  au_mesh *m = tetra();
  AU_CHECK(m);
  m->F[5] = 9;
  AU_CHECK_STATUS(au_mesh_orient(m, NULL, &msg), AU_E_INDEX, &msg);
  CHECK_MSG(msg, "face 1 refers to vertex 9");
  m->F[5] = m->F[4];
  AU_CHECK_STATUS(au_mesh_orient(m, NULL, &msg), AU_E_FACE, &msg);
  au_mesh_free(&m);
  /* Three faces on edge (0, 1), one of them reversed against the others. */
  static const double X[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
  static const int F[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  m = mk(5, X, 3, F);
  AU_CHECK(m);
  AU_CHECK_STATUS(au_mesh_orient(m, NULL, &msg), AU_E_NONMANIFOLD_EDGE, &msg);
  CHECK_MSG(msg, "(0, 1)");
  AU_CHECK_INT(m->F[6], ==, 0);
  au_mesh_free(&m);
  /* The public check: a flipped face is a warning now, with the unreferenced vertices after it. */
  m = tetra();
  AU_CHECK(m);
  au_mesh *u = mk(5, NULL, 4, m->F);
  AU_CHECK(u);
  memcpy(u->X, m->X, 12 * sizeof(double));
  flip_face(u, 2);
  AU_CHECK_STATUS(au_mesh_check(u->X, u->nv, u->F, u->nf, AU_TARGET_SPHERE, &msg), AU_W_REORIENTED, &msg);
  CHECK_MSG(msg, "re-oriented 1 of 4 faces");
  CHECK_MSG(msg, "referenced by no face (4)");
  AU_CHECK(u->F[7] == m->F[8] && u->F[8] == m->F[7]); /* the caller's faces are not touched */
  au_mesh_free(&u);
  au_mesh_free(&m);
  return 0;
}

int main(int argc, char **argv) {
  static const au_test_case cases[] = {
      {"alloc_free", alloc_free},
      {"copy_deep", copy_deep},
      {"expect_default", expect_default},
      {"topo_tetra", topo_tetra},
      {"topo_octahedron", topo_octahedron},
      {"topo_cube_counts", topo_cube_counts},
      {"topo_icosphere", topo_icosphere},
      {"topo_disk_grid", topo_disk_grid},
      {"topo_disk_fan", topo_disk_fan},
      {"topo_annulus", topo_annulus},
      {"topo_torus", topo_torus},
      {"topo_two_tetra", topo_two_tetra},
      {"topo_two_disks", topo_two_disks},
      {"loops_disk_order", loops_disk_order},
      {"loops_annulus_len", loops_annulus_len},
      {"topo_unreferenced", topo_unreferenced},
      {"topo_nonmanifold_edge", topo_nonmanifold_edge},
      {"topo_bowtie", topo_bowtie},
      {"topo_pinched_spheres", topo_pinched_spheres},
      {"topo_flipped_face", topo_flipped_face},
      {"topo_args", topo_args},
      {"orient_consistent", orient_consistent},
      {"orient_two_flipped", orient_two_flipped},
      {"orient_majority", orient_majority},
      {"orient_moebius", orient_moebius},
      {"orient_errors", orient_errors},
      {"topo_scale_200k", topo_scale_200k},
      {"validate_ok_sphere", validate_ok_sphere},
      {"validate_ok_disk", validate_ok_disk},
      {"validate_ok_annulus", validate_ok_annulus},
      {"validate_ok_torus", validate_ok_torus},
      {"validate_any", validate_any},
      {"validate_empty", validate_empty},
      {"validate_nonfinite", validate_nonfinite},
      {"validate_index", validate_index},
      {"validate_repeat", validate_repeat},
      {"validate_nonmanifold_edge", validate_nonmanifold_edge},
      {"validate_nonmanifold_vertex", validate_nonmanifold_vertex},
      {"validate_orientation", validate_orientation},
      {"validate_components", validate_components},
      {"validate_disk_for_sphere", validate_disk_for_sphere},
      {"validate_boundary_before_genus", validate_boundary_before_genus},
      {"validate_closed_for_disk", validate_closed_for_disk},
      {"validate_annulus_for_disk", validate_annulus_for_disk},
      {"validate_genus", validate_genus},
      {"validate_degenerate", validate_degenerate},
      {"validate_zero_total_area", validate_zero_total_area},
      {"validate_unreferenced", validate_unreferenced},
      {"validate_no_topo_out", validate_no_topo_out},
  };
  return au_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0]));
}
