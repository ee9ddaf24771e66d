/* au_texture_internal.h - what the texture files share among themselves (au_texture.c: layouts and
 * coordinates; au_texsplit.c: the adaptive splitting and the choice of axis; au_octahedral.c: the
 * equal-area octahedral map). Not installed. */
#ifndef AU_TEXTURE_INTERNAL_H
#define AU_TEXTURE_INTERNAL_H

#include "au_texture.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The equal-area octahedral map (au_octahedral.c). forward: a nonzero p -> uv in [-1, 1]^2;
 * inverse: uv anywhere within one square's width of [-1, 1]^2 (the continuation past the edges is
 * wrapped back first) -> a unit vector p; wrap: uv of the continuation -> the same point's uv in
 * the square; copy k (0..8): the k-th continuation copy of uv (0: uv itself). */
void au__oct_forward(const double p[3], double uv[2]);
void au__oct_inverse(const double uv[2], double p[3]);
void au__oct_wrap(double uv[2]);
void au__oct_copy(const double uv[2], int k, double out[2]);

/* The texture mesh while it is built, in the texture's frame (the map's frame turned by the
 * layout's rotation R). t->X, t->F, t->src_face, t->nv, t->nf grow with the splits; t->P is filled
 * at the end. */
typedef struct au__tex_work {
  au_tex_mesh *t;
  double *C;              /* C [0..3nv-1]: each vertex's point on the map's flat (chordal) triangle, so
                             that a vertex at surface point x has C = the piecewise linear map of x */
  double *Q;              /* Q [0..3nv-1]: the unit vector of C: the vertex on the sphere */
  unsigned char *is_pole; /* is_pole [0..nv-1]: cea only: 1 on a pole (its u is the face's choice) */
  double *raw;            /* raw [0..4nv-1]: the vertex in its charts, in area-preserving units
                             (steradians): cea (lon, z); laea (north x, y, south x, y); oct
                             sqrt(pi) (u, v) */
  int nraw;               /* vertices whose raw coordinates are current */
  int nvcap, nfcap;       /* room in X, C, Q, is_pole, raw / F, src_face */
} au__tex_work;

/* Room for nv vertices and nf faces. Returns 0 when out of memory. */
int au__tex_reserve(au__tex_work *w, int nv, int nf);

/* The raw chart coordinates of the vertices nraw..nv-1 (then nraw = nv). */
au_status au__tex_raw_update(au__tex_work *w, au_tex_proj proj, au_msg *msg);

/* The corners of face f in its chart, raw units, as straight-edged triangle xy [0..5]; which: out,
 * the chart (cea: the shift of each corner in turns, packed; laea: 0 north, 1 south; oct: the copy
 * index of each corner, packed base 9). Returns 1 if a corner is a pole (cea), else 0. */
int au__tex_face_raw(const au__tex_work *w, au_tex_proj proj, int f, double xy[6], int *which);

/* The area splitting of one try: tol, the tolerance on |straight / spherical area - 1| (0: none);
 * target, the per-face texture error at which it stops (0: none); growth, the faces' growth at which
 * it stops; worst_first: the worst faces first, by longest-edge propagation (else every face above
 * tol each round). */
typedef struct au__tex_area {
  double tol, target;
  int growth, worst_first;
  int stop_nf;    /* > 0: no area splits once the faces are this many (a replay up to best_nf) */
  double best_e;  /* out, with a target: the lowest per-face texture error of a fold-free round */
  int best_nf;    /* out: the faces then */
} au__tex_area;

/* Split faces until none is turned over in its chart and (while rounds, the growth budget and the
 * target last) every face's straight texture area is within plan->tol of its spherical area
 * (au_texsplit.c, rule there). Returns AU_OK, AU_E_NOMEM, AU_E_NUMERIC (folds left after the
 * rounds). */
au_status au__tex_refine(au__tex_work *w, const au_tex_opts *opts, au__tex_area *plan, au_msg *msg);

/* The rotation R (row-major 3x3, texture point = R p) asked for by opts for the map P (nv x 3,
 * unit) with faces F (nf x 3). Returns AU_OK, AU_E_ARG, AU_E_NOMEM. */
au_status au__tex_axis(const au_tex_opts *opts, int nv, const double *P, int nf, const int *F, double R[9],
                       au_msg *msg);

/* Signed area of the spherical triangle (a, b, c), unit vectors (Oosterom & Strackee 1983). */
double au__sph_tri_area(const double *a, const double *b, const double *c);

#ifdef __cplusplus
}
#endif
#endif
