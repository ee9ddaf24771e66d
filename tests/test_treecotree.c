/* test_treecotree.c - the tree-cotree decomposition (common/au_treecotree.h): on closed meshes of genus 0, 1, 2
 * and 3 and open ones with 1 to 3 boundary loops, the trees span and have no cycle, the generators number
 * 2 genus (+ loops - 1), every dual loop is a closed simple chain of faces across face-tree edges and its own
 * generator, the loops are independent in homology (cutting the surface along all of them leaves every piece
 * touching a root of the vertex tree) and dual to the primal loops; bad arguments are refused. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "au_mesh.h"
#include "au_test.h"
#include "au_treecotree.h"
#include "authalic.h"

/* The torus of revolution R = 3, r = 1 on an nu x nt grid, each quad split along a diagonal. */
static au_mesh *grid_torus(int nu, int nt) {
  au_mesh *m = NULL;
  if (au_mesh_alloc(nu * nt, 2 * nu * nt, &m) != AU_OK) return NULL;
  for (int i = 0; i < nu; i++)
    for (int j = 0; j < nt; j++) {
      double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nt, *p = m->X + 3 * (i * nt + j);
      p[0] = (3 + cos(v)) * cos(u), p[1] = (3 + cos(v)) * sin(u), p[2] = sin(v);
      int a = i * nt + j, b = ((i + 1) % nu) * nt + j, c = ((i + 1) % nu) * nt + (j + 1) % nt, d = i * nt + (j + 1) % nt;
      int *f = m->F + 6 * (i * nt + j);
      f[0] = a, f[1] = b, f[2] = c, f[3] = a, f[4] = c, f[5] = d;
    }
  return m;
}

/* The square [0, n]^2 of n x n quads split along a diagonal, without the quads of the given holes (each
 * hole [x0, x1) x [y0, y1) in quads, apart from each other and from the rim). A hole of 2 x 2 quads or more
 * leaves its inner grid vertices unreferenced. */
static au_mesh *grid_disk(int n, int nholes, const int (*hole)[4]) {
  au_mesh *m = NULL;
  if (au_mesh_alloc((n + 1) * (n + 1), 2 * n * n, &m) != AU_OK) return NULL;
  for (int i = 0; i <= n; i++)
    for (int j = 0; j <= n; j++) {
      double *p = m->X + 3 * (i * (n + 1) + j);
      p[0] = i, p[1] = j, p[2] = 0.1 * sin(i + 2.0 * j);
    }
  int nf = 0;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      int out = 0;
      for (int h = 0; h < nholes; h++) out |= i >= hole[h][0] && i < hole[h][1] && j >= hole[h][2] && j < hole[h][3];
      if (out) continue;
      int a = i * (n + 1) + j, b = (i + 1) * (n + 1) + j, c = b + 1, d = a + 1;
      int *f = m->F + 3 * nf;
      f[0] = a, f[1] = b, f[2] = c, f[3] = a, f[4] = c, f[5] = d;
      nf += 2;
    }
  m->nf = nf;
  return m;
}

/* Union-find root with path halving. */
static int uf_find(int *p, int x) {
  while (p[x] != x) p[x] = p[p[x]], x = p[x];
  return x;
}

/* The other face of interior edge e than f, -1 if f is not on e. */
static int other_face(const au_topo *t, int e, int f) {
  if (t->EF[2 * e] == f) return t->EF[2 * e + 1];
  return t->EF[2 * e + 1] == f ? t->EF[2 * e] : -1;
}

/* Every property of the decomposition of m, which must have want generators; each is checked from the mesh
 * itself, not from how the decomposition was made. */
static int check_mesh(const au_mesh *m, int want_genus, int want_loops, int want_gen) {
  au_topo *t = NULL;
  au_treecotree *tc = NULL;
  au_msg msg = {{0}};
  AU_CHECK(m != NULL);
  AU_CHECK_STATUS(au_mesh_topology(m, &t, &msg), AU_OK, &msg);
  AU_CHECK_INT(t->genus, ==, want_genus);
  AU_CHECK_INT(t->nloops, ==, want_loops);
  AU_CHECK_STATUS(au_treecotree_build(t, &tc, &msg), AU_OK, &msg);
  const int nv = t->nv, nf = t->nf, ne = t->ne;
  AU_CHECK_INT(tc->nv, ==, nv);
  AU_CHECK_INT(tc->nf, ==, nf);
  AU_CHECK_INT(tc->ne, ==, ne);
  AU_CHECK_INT(tc->ngen, ==, want_gen);
  AU_CHECK_INT(tc->ngen, ==, 2 * t->genus + (t->nloops > 0 ? t->nloops - 1 : 0));
  int *p = malloc((size_t)(nv > nf ? nv : nf) * sizeof *p), *cross = calloc((size_t)ne, sizeof *cross);
  int *edges = malloc((size_t)nf * sizeof *edges), *faces = malloc((size_t)nf * sizeof *faces);
  int *lstart = malloc(((size_t)tc->ngen + 1) * sizeof *lstart), *all = malloc(((size_t)tc->ngen * nf + 1) * sizeof *all);
  unsigned char *seenf = calloc((size_t)nf, 1), *par = calloc((size_t)ne, 1);
  AU_CHECK(p && cross && edges && faces && lstart && all && seenf && par);

  /* The edges' kinds: boundary exactly on one-face edges; the vertex tree a forest with one root per
   * component of the forest: the boundary vertices (or one vertex when closed) and nothing else. */
  int nused = 0, nroots = 0, ntree = 0, ncotree = 0, ngen = 0;
  for (int v = 0; v < nv; v++) nused += t->vused[v], nroots += t->vused[v] && (t->nloops > 0 ? t->vb[v] : 0);
  if (t->nloops == 0) nroots = 1;
  for (int v = 0; v < nv; v++) p[v] = v;
  for (int e = 0; e < ne; e++) {
    AU_CHECK_INT(tc->kind[e] == AU_TCT_BOUNDARY, ==, t->EF[2 * e + 1] < 0);
    if (tc->kind[e] == AU_TCT_TREE) {
      int a = uf_find(p, t->E[2 * e]), b = uf_find(p, t->E[2 * e + 1]);
      AU_CHECK(a != b); /* no cycle */
      p[a] = b, ntree++;
    }
    ncotree += tc->kind[e] == AU_TCT_COTREE, ngen += tc->kind[e] == AU_TCT_GENERATOR;
  }
  AU_CHECK_INT(ntree, ==, nused - nroots); /* spanning: a forest of nroots trees over the used vertices */
  AU_CHECK_INT(ngen, ==, tc->ngen);
  for (int v = 0; v < nv; v++) {
    int e = tc->vparent[v];
    int root = !t->vused[v] || (t->nloops > 0 ? t->vb[v] : e < 0);
    if (root) {
      AU_CHECK_INT(e, ==, -1);
      continue;
    }
    AU_CHECK(e >= 0 && e < ne);
    AU_CHECK_INT(tc->kind[e], ==, AU_TCT_TREE);
    AU_CHECK(t->E[2 * e] == v || t->E[2 * e + 1] == v);
  }
  if (t->nloops == 0) { /* one root */
    int r = 0;
    for (int v = 0; v < nv; v++) r += t->vused[v] && tc->vparent[v] < 0;
    AU_CHECK_INT(r, ==, 1);
  }
  /* The face tree: nf - 1 edges, no cycle, parents and depths consistent, forder a parents-first order. */
  AU_CHECK_INT(ncotree, ==, nf - 1);
  for (int f = 0; f < nf; f++) p[f] = f;
  for (int e = 0; e < ne; e++)
    if (tc->kind[e] == AU_TCT_COTREE) {
      int a = uf_find(p, t->EF[2 * e]), b = uf_find(p, t->EF[2 * e + 1]);
      AU_CHECK(a != b);
      p[a] = b;
    }
  AU_CHECK_INT(tc->forder[0], ==, 0);
  AU_CHECK_INT(tc->fparent[0], ==, -1);
  AU_CHECK_INT(tc->fdepth[0], ==, 0);
  for (int q = 0; q < nf; q++) {
    int f = tc->forder[q];
    AU_CHECK(f >= 0 && f < nf && !seenf[f]);
    seenf[f] = 1;
    if (q == 0) continue;
    int e = tc->fparent[f], g = other_face(t, e, f);
    AU_CHECK_INT(tc->kind[e], ==, AU_TCT_COTREE);
    AU_CHECK(g >= 0 && seenf[g]);
    AU_CHECK_INT(tc->fdepth[f], ==, tc->fdepth[g] + 1);
  }
  /* The dual loops: closed, simple, across face-tree edges and their own generator. */
  int nall = 0;
  for (int k = 0; k < tc->ngen; k++) {
    AU_CHECK_INT(tc->kind[tc->gen[k]], ==, AU_TCT_GENERATOR);
    if (k > 0) AU_CHECK(tc->gen[k] > tc->gen[k - 1]);
    int n = au_treecotree_dual_loop(t, tc, k, edges, faces);
    AU_CHECK(n >= 2 && n <= nf);
    AU_CHECK_INT(edges[0], ==, tc->gen[k]);
    memset(seenf, 0, (size_t)nf);
    lstart[k] = nall;
    for (int i = 0; i < n; i++) {
      if (i > 0) AU_CHECK_INT(tc->kind[edges[i]], ==, AU_TCT_COTREE);
      AU_CHECK(!seenf[faces[i]]);
      seenf[faces[i]] = 1;
      /* faces[i] is entered across edges[i] (from faces[i - 1]) and left across edges[i + 1]. */
      AU_CHECK_INT(other_face(t, edges[i], faces[i]), ==, faces[(i + n - 1) % n]);
      AU_CHECK(other_face(t, edges[(i + 1) % n], faces[i]) >= 0);
      cross[edges[i]]++, all[nall++] = edges[i];
    }
  }
  lstart[tc->ngen] = nall;
  /* Independent in homology: a Z/2 sum of the loops that bounds would cut off vertices with no root (closed:
   * split the surface) along its edges; each loop crosses its generator alone, so no sum is empty. */
  for (int k = 0; k < tc->ngen; k++) AU_CHECK_INT(cross[tc->gen[k]], ==, 1);
  for (int v = 0; v < nv; v++) p[v] = v;
  for (int e = 0; e < ne; e++)
    if (!cross[e]) p[uf_find(p, t->E[2 * e])] = uf_find(p, t->E[2 * e + 1]);
  unsigned char *rooted = calloc((size_t)nv, 1);
  AU_CHECK(rooted != NULL);
  for (int v = 0; v < nv; v++)
    if (t->vused[v] && tc->vparent[v] < 0) rooted[uf_find(p, v)] = 1;
  for (int v = 0; v < nv; v++)
    if (t->vused[v]) AU_CHECK(rooted[uf_find(p, v)]);
  /* Dual to the primal loops: primal loop j (generator j and the vertex tree's paths from its ends to their
   * roots, summed mod 2) shares exactly delta_ij edges with dual loop i. */
  for (int j = 0; j < tc->ngen; j++) {
    memset(par, 0, (size_t)ne);
    int g = tc->gen[j];
    par[g] ^= 1;
    for (int s = 0; s < 2; s++)
      for (int v = t->E[2 * g + s], hops = 0; tc->vparent[v] >= 0; hops++) {
        AU_CHECK(hops < nv);
        int e = tc->vparent[v];
        par[e] ^= 1, v = t->E[2 * e] == v ? t->E[2 * e + 1] : t->E[2 * e];
      }
    for (int i = 0; i < tc->ngen; i++) {
      int shared = 0;
      for (int q = lstart[i]; q < lstart[i + 1]; q++) shared += par[all[q]];
      AU_CHECK_INT(shared, ==, i == j);
    }
  }
  fprintf(stderr, "V %d F %d E %d genus %d loops %d: %d generators, dual loops of %d faces in all\n", nv, nf, ne,
          t->genus, t->nloops, tc->ngen, nall);
  AU_CHECK_INT(au_treecotree_dual_loop(t, tc, tc->ngen, edges, faces), ==, -1);
  AU_CHECK_INT(au_treecotree_dual_loop(t, tc, -1, edges, faces), ==, -1);
  free(p), free(cross), free(edges), free(faces), free(lstart), free(all), free(seenf), free(par), free(rooted);
  au_treecotree_free(&tc);
  AU_CHECK(tc == NULL);
  au_treecotree_free(&tc); /* NULL-safe */
  au_treecotree_free(NULL);
  au_topo_free(&t);
  return 0;
}

static int run_data(const char *name, int genus, int loops, int ngen) {
  au_mesh *m = au_test_data_mesh(name);
  int r = check_mesh(m, genus, loops, ngen);
  au_mesh_free(&m);
  return r;
}

/* A grid torus: 2 generators. */
static int torus(void) {
  au_mesh *m = grid_torus(15, 7);
  int r = check_mesh(m, 1, 0, 2);
  au_mesh_free(&m);
  return r ? r : run_data("torus_r3", 1, 0, 2);
}

/* The double torus (4), the pretzel (6), and a sphere (0). */
static int closed_genus(void) {
  int r = run_data("genus2", 2, 0, 4);
  if (!r) r = run_data("genus3", 3, 0, 6);
  return r ? r : run_data("ellipsoid", 0, 0, 0);
}

/* A disk with two holes, one of them leaving an unreferenced vertex (2 generators); a disk (0); an annulus
 * (1); genus 2 with two boundary loops (5). */
static int open_surfaces(void) {
  const int holes[2][4] = {{3, 5, 3, 5}, {8, 9, 4, 9}};
  au_mesh *m = grid_disk(12, 2, holes);
  int r = check_mesh(m, 0, 3, 2);
  au_mesh_free(&m);
  if (!r) {
    m = grid_disk(6, 0, NULL);
    r = check_mesh(m, 0, 1, 0);
    au_mesh_free(&m);
  }
  if (!r) r = run_data("annulus_bump", 0, 2, 1);
  return r ? r : run_data("genus2_2loops", 2, 2, 5);
}

/* NULL or faceless topology and several components: AU_E_ARG, nothing returned. */
static int bad_args(void) {
  au_msg msg = {{0}};
  au_treecotree dummy, *tc = &dummy; /* cleared on failure */
  AU_CHECK_STATUS(au_treecotree_build(NULL, &tc, &msg), AU_E_ARG, &msg);
  AU_CHECK(tc == NULL);
  /* Two disjoint grid tori, side by side. */
  au_mesh *a = grid_torus(6, 5), *m = NULL;
  AU_CHECK(a != NULL);
  AU_CHECK_STATUS(au_mesh_alloc(2 * a->nv, 2 * a->nf, &m), AU_OK, NULL);
  for (int i = 0; i < 3 * a->nv; i++) m->X[i] = a->X[i], m->X[3 * a->nv + i] = a->X[i] + (i % 3 == 0 ? 10 : 0);
  for (int i = 0; i < 3 * a->nf; i++) m->F[i] = a->F[i], m->F[3 * a->nf + i] = a->F[i] + a->nv;
  au_topo *t = NULL;
  AU_CHECK_STATUS(au_mesh_topology(m, &t, &msg), AU_OK, &msg);
  AU_CHECK_INT(t->ncomponents, ==, 2);
  tc = &dummy;
  AU_CHECK_STATUS(au_treecotree_build(t, &tc, &msg), AU_E_ARG, &msg);
  AU_CHECK(tc == NULL);
  AU_CHECK(strstr(msg.text, "2 components") != NULL);
  AU_CHECK_STATUS(au_treecotree_build(t, NULL, &msg), AU_E_ARG, &msg);
  au_topo_free(&t);
  au_mesh_free(&m);
  au_mesh_free(&a);
  return 0;
}

int main(int argc, char **argv) {
  static const au_test_case cases[] = {
      {"torus", torus},
      {"closed_genus", closed_genus},
      {"open_surfaces", open_surfaces},
      {"bad_args", bad_args},
  };
  return au_test_main(argc, argv, cases, (int)(sizeof cases / sizeof *cases));
}
