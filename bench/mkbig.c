/* mkbig.c - generator of large closed genus-0 meshes for the scaling benchmark (bench/scale.sh).
 *
 * usage: au_mkbig FACES OUT.obj [--smooth]
 *
 * The mesh is a geodesic icosphere of frequency n (each icosahedron face cut into n*n triangles,
 * 20*n^2 faces and 10*n^2+2 vertices; n is the smallest frequency reaching FACES) whose vertices
 * are pushed along their radius by a star-shaped height field: a few long Gaussian protrusions of
 * different sizes plus low-frequency bumps. A radial graph over the sphere cannot self-intersect,
 * so the result is always a closed, consistently oriented, genus-0 surface, while the protrusions
 * give the flow real area distortion to remove (their tips are small on the conformal sphere).
 * With --smooth the height field is left out (a plain icosphere). Needs only libm. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The icosahedron: 12 vertices, 20 faces counter-clockwise seen from outside. */
static const double ico_v[12][3] = {{-1, 1.618033988749895, 0}, {1, 1.618033988749895, 0}, {-1, -1.618033988749895, 0},
                                    {1, -1.618033988749895, 0}, {0, -1, 1.618033988749895}, {0, 1, 1.618033988749895},
                                    {0, -1, -1.618033988749895}, {0, 1, -1.618033988749895}, {1.618033988749895, 0, -1},
                                    {1.618033988749895, 0, 1},  {-1.618033988749895, 0, -1}, {-1.618033988749895, 0, 1}};
static const int ico_f[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};

/* The 30 edges of the icosahedron as (lo, hi) vertex pairs, found from the faces. */
static int edges[30][2], nedges;

static int edge_id(int a, int b) {
  int lo = a < b ? a : b, hi = a < b ? b : a;
  for (int e = 0; e < nedges; e++)
    if (edges[e][0] == lo && edges[e][1] == hi) return e;
  edges[nedges][0] = lo, edges[nedges][1] = hi;
  return nedges++;
}

/* Global index of the point t steps (0..n) along the edge from vertex a to vertex b. */
static int edge_point(int a, int b, int t, int n) {
  if (t == 0) return a;
  if (t == n) return b;
  int e = edge_id(a, b);
  int s = a < b ? t : n - t; /* steps from the lower-numbered end */
  return 12 + e * (n - 1) + (s - 1);
}

/* Radius of the surface in unit direction u: 1 plus protrusions and bumps. */
static double height(const double *u) {
  /* direction, angular width (radians), height */
  static const double bump[][5] = {
      {0.0, 0.0, 1.0, 0.25, 1.6},    {0.0, 0.0, -1.0, 0.35, 0.9},  {1.0, 0.0, 0.0, 0.18, 1.2},
      {-0.6, 0.8, 0.0, 0.30, 0.7},   {0.3, -0.7, 0.65, 0.12, 0.9}, {-0.5, -0.5, -0.7, 0.22, 0.5},
      {0.7, 0.7, -0.14, 0.40, 0.35},
  };
  double r = 1.0;
  for (size_t k = 0; k < sizeof bump / sizeof bump[0]; k++) {
    const double *b = bump[k];
    double nb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double c = (u[0] * b[0] + u[1] * b[1] + u[2] * b[2]) / nb;
    double ang = acos(c > 1 ? 1 : c < -1 ? -1 : c);
    r += b[4] * exp(-(ang * ang) / (2 * b[3] * b[3]));
  }
  r += 0.06 * sin(5 * u[0]) * sin(4 * u[1] + 1) * sin(3 * u[2] + 2);
  return r;
}

int main(int argc, char **argv) {
  if (argc < 3 || argc > 4 || (argc == 4 && strcmp(argv[3], "--smooth") != 0)) {
    fprintf(stderr, "usage: au_mkbig FACES OUT.obj [--smooth]\n"
                    "  writes a closed genus-0 mesh of at least FACES triangles (20*n^2 for the smallest such n)\n");
    return 2;
  }
  char *end;
  errno = 0;
  long want = strtol(argv[1], &end, 10);
  if (*end || errno || want < 20 || want > 50000000) {
    fprintf(stderr, "au_mkbig: FACES '%s': expected a whole number from 20 to 50000000\n", argv[1]);
    return 2;
  }
  int smooth = argc == 4;
  int n = 1;
  while (20L * n * n < want) n++;
  long nv = 10L * n * n + 2, nf = 20L * n * n;
  double *X = malloc(sizeof(double) * 3 * (size_t)nv);
  int *F = malloc(sizeof(int) * 3 * (size_t)nf);
  int *local = malloc(sizeof(int) * (size_t)(n + 1) * (size_t)(n + 2) / 2);
  if (!X || !F || !local) {
    fprintf(stderr, "au_mkbig: out of memory\n");
    return 1;
  }
  /* Global numbering: the 12 corners, then n-1 points per edge, then the points inside each face. */
  long next_inner = 12 + 30L * (n - 1), jf = 0;
  for (int f = 0; f < 20; f++) {
    int A = ico_f[f][0], B = ico_f[f][1], C = ico_f[f][2];
    /* Point (i, j), i + j <= n, is A + i/n (B - A) + j/n (C - A); local[] holds its global index. */
#define L(i, j) local[(size_t)(i) * (size_t)(2 * n + 3 - (i)) / 2 + (size_t)(j)]
    for (int i = 0; i <= n; i++) {
      for (int j = 0; i + j <= n; j++) {
        int g;
        if (j == 0) g = edge_point(A, B, i, n);
        else if (i == 0) g = edge_point(A, C, j, n);
        else if (i + j == n) g = edge_point(B, C, j, n);
        else g = (int)next_inner++;
        L(i, j) = g;
        double p[3];
        for (int k = 0; k < 3; k++)
          p[k] = ico_v[A][k] + (double)i / n * (ico_v[B][k] - ico_v[A][k]) + (double)j / n * (ico_v[C][k] - ico_v[A][k]);
        double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (int k = 0; k < 3; k++) p[k] /= r;
        double h = smooth ? 1.0 : height(p);
        for (int k = 0; k < 3; k++) X[3 * (size_t)g + k] = h * p[k];
      }
    }
    for (int i = 0; i < n; i++) {
      for (int j = 0; i + j < n; j++) {
        int *t = &F[3 * jf++];
        t[0] = L(i, j), t[1] = L(i + 1, j), t[2] = L(i, j + 1);
        if (i + j < n - 1) {
          t = &F[3 * jf++];
          t[0] = L(i + 1, j), t[1] = L(i + 1, j + 1), t[2] = L(i, j + 1);
        }
      }
    }
#undef L
  }
  if (next_inner != nv || jf != nf || nedges != 30) {
    fprintf(stderr, "au_mkbig: internal error (%ld of %ld vertices, %ld of %ld faces)\n", next_inner, nv, jf, nf);
    return 1;
  }
  FILE *fp = fopen(argv[2], "w");
  if (!fp) {
    fprintf(stderr, "au_mkbig: cannot create '%s': %s\n", argv[2], strerror(errno));
    return 1;
  }
  fprintf(fp, "# au_mkbig %s%s: geodesic icosphere, frequency %d, %ld vertices, %ld faces\n", argv[1],
          smooth ? " --smooth" : "", n, nv, nf);
  for (long i = 0; i < nv; i++) fprintf(fp, "v %.10g %.10g %.10g\n", X[3 * i], X[3 * i + 1], X[3 * i + 2]);
  for (long f = 0; f < nf; f++) fprintf(fp, "f %d %d %d\n", F[3 * f] + 1, F[3 * f + 1] + 1, F[3 * f + 2] + 1);
  int bad = ferror(fp);
  if (fclose(fp) != 0 || bad) {
    fprintf(stderr, "au_mkbig: cannot write '%s'\n", argv[2]);
    return 1;
  }
  free(X);
  free(F);
  free(local);
  return 0;
}
