/* texture_split_diag.c - where a texture's per-face area error comes from (issue 18): the texture
 * of a sphere map is made (au_tex_coords_opts), and its per-face error |vt share / surface share - 1|
 * is split into the map's own spherical error (spherical triangle share / surface share) and the
 * projection's (straight vt area / spherical area), per texture face and per input face (its pieces
 * summed), with a histogram of the projection's error and the worst faces.
 *
 *   au_texture_split_diag MESH MAP cea|laea|oct AREA_TOL [MAX_ROUNDS] [--worst N]
 *
 * AREA_TOL as `authalic texture --area-tol` (0 off, < 0 auto). Prints text on stdout; exit 0, or 2 on
 * bad usage or input. Measurements with it: docs/textures.md. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "authalic.h"

static double sph_area(const double *a, const double *b, const double *c) {
  double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  double det = a[0] * n[0] + a[1] * n[1] + a[2] * n[2];
  double den = 1 + (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) + (b[0] * c[0] + b[1] * c[1] + b[2] * c[2]) +
               (c[0] * a[0] + c[1] * a[1] + c[2] * a[2]);
  return fabs(2 * atan2(det, den));
}

static double flat_area(const double *a, const double *b, const double *c) {
  double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

int main(int argc, char **argv) {
  if (argc < 5) {
    fprintf(stderr, "usage: au_texture_split_diag MESH MAP cea|laea|oct AREA_TOL [MAX_ROUNDS] [--worst N]\n");
    return 2;
  }
  int worst = 0, rounds = -1;
  for (int i = 5; i < argc; i++) {
    if (strcmp(argv[i], "--worst") == 0 && i + 1 < argc) worst = atoi(argv[++i]);
    else rounds = atoi(argv[i]);
  }
  au_msg msg = {{0}};
  au_mesh *m = NULL, *mp = NULL;
  if (au_mesh_read(argv[1], &m, &msg) != AU_OK || au_mesh_read(argv[2], &mp, &msg) != AU_OK || mp->nv != m->nv) {
    fprintf(stderr, "au_texture_split_diag: %s\n", msg.text[0] ? msg.text : "MAP does not match MESH");
    return 2;
  }
  for (int i = 0; i < mp->nv; i++) {
    double *p = mp->X + 3 * i, r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int d = 0; d < 3; d++) p[d] /= r;
  }
  au_tex_opts o = au_tex_opts_default();
  o.proj = strcmp(argv[3], "laea") == 0 ? AU_TEX_LAEA : strcmp(argv[3], "oct") == 0 ? AU_TEX_OCT : AU_TEX_CEA;
  o.area_tol = atof(argv[4]);
  if (rounds >= 0) o.max_rounds = rounds;
  au_tex_mesh *t = NULL;
  if (au_tex_coords_opts(m, mp->X, &o, &t, &msg) != AU_OK) {
    fprintf(stderr, "au_texture_split_diag: %s\n", msg.text);
    return 2;
  }
  const int nf = t->nf, nf0 = m->nf;
  double *As = malloc(sizeof(double) * nf), *Ap = malloc(sizeof(double) * nf), *At = malloc(sizeof(double) * nf);
  double *ps = calloc(nf0, sizeof(double)), *pp = calloc(nf0, sizeof(double)), *pt = calloc(nf0, sizeof(double));
  if (!As || !Ap || !At || !ps || !pp || !pt) return 1;
  double SS = 0, SP = 0, ST = 0;
  for (int f = 0; f < nf; f++) {
    const int *c = t->F + 3 * f, *ct = t->Ft + 3 * f;
    As[f] = flat_area(t->X + 3 * c[0], t->X + 3 * c[1], t->X + 3 * c[2]);
    Ap[f] = sph_area(t->P + 3 * c[0], t->P + 3 * c[1], t->P + 3 * c[2]);
    const double *a = t->vt + 2 * ct[0], *b = t->vt + 2 * ct[1], *d = t->vt + 2 * ct[2];
    At[f] = 0.5 * fabs((b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]));
    SS += As[f], SP += Ap[f], ST += At[f];
    int s = t->src_face[f];
    ps[s] += As[f], pp[s] += Ap[f], pt[s] += At[f];
  }
  /* Per texture face: the texture's error, the map's spherical one, the projection's; the histogram
   * of the projection's, and the share of its sum held by slivers (spherical area under half the
   * chord triangle's: caps whose apex lies near their long edge). */
  static const double edges[] = {0.003, 0.01, 0.03, 0.1, 0.3, INFINITY};
  double etex = 0, esph = 0, eproj = 0, bin_sum[6] = {0}, sliver_sum = 0;
  int bin_n[6] = {0}, sliver_n = 0;
  for (int f = 0; f < nf; f++) {
    double e = fabs((At[f] / ST) / (Ap[f] / SP) - 1);
    etex += fabs((At[f] / ST) / (As[f] / SS) - 1), esph += fabs((Ap[f] / SP) / (As[f] / SS) - 1), eproj += e;
    int k = 0;
    while (e >= edges[k]) k++;
    bin_sum[k] += e, bin_n[k]++;
    const int *c = t->F + 3 * f;
    if (Ap[f] < 0.5 * flat_area(t->P + 3 * c[0], t->P + 3 * c[1], t->P + 3 * c[2])) sliver_sum += e, sliver_n++;
  }
  double ptex = 0, psph = 0;
  for (int s = 0; s < nf0; s++) ptex += fabs((pt[s] / ST) / (ps[s] / SS) - 1), psph += fabs((pp[s] / SP) / (ps[s] / SS) - 1);
  printf("%s %s area_tol %g: faces %d -> %d\n", argv[1], argv[3], t->area_tol, nf0, nf);
  printf("per texture face: texture %.4f = map (spherical) %.4f with projection (straight / spherical) %.4f\n",
         etex / nf, esph / nf, eproj / nf);
  printf("per input face (pieces summed): texture %.4f, map (spherical) %.4f\n", ptex / nf0, psph / nf0);
  printf("projection error: ");
  for (int k = 0; k < 6; k++)
    printf("%s%g: %d faces %.1f%%", k ? ", < " : "< ", edges[k], bin_n[k], eproj > 0 ? 100 * bin_sum[k] / eproj : 0.0);
  printf("; slivers %d faces %.1f%%\n", sliver_n, eproj > 0 ? 100 * sliver_sum / eproj : 0.0);
  for (int shown = 0, f = 0; f < nf && shown < worst; f++) {
    double e = (At[f] / ST) / (Ap[f] / SP) - 1;
    if (fabs(e) < 0.2) continue;
    const int *c = t->F + 3 * f;
    double l[3];
    for (int q = 0; q < 3; q++) {
      const double *a = t->P + 3 * c[q], *b = t->P + 3 * c[(q + 1) % 3];
      l[q] = sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
    }
    printf("face %d (input %d): projection %+.3f, spherical %.3g, chord %.3g, chord edges %.4f %.4f %.4f\n", f,
           t->src_face[f], e, Ap[f], flat_area(t->P + 3 * c[0], t->P + 3 * c[1], t->P + 3 * c[2]), l[0], l[1], l[2]);
    shown++;
  }
  au_tex_mesh_free(&t);
  au_mesh_free(&m), au_mesh_free(&mp);
  free(As), free(Ap), free(At), free(ps), free(pp), free(pt);
  return 0;
}
