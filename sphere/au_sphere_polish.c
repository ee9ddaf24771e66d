/* au_sphere_polish.c - the vertex polish: a sphere map's chord triangles (or, for a map of spherical
 * areas only, its spherical ones) brought nearer their shares one vertex at a time (nonlinear
 * Gauss-Seidel), after the flow.
 *
 * Why: the flow moves the whole map along one velocity field, the gradient of a potential. Where long,
 * thin chord triangles sit on their floor (a leg's or a finger's base, docs/sphere.md) the field
 * that would shrink them also stretches their neighbours, and its steps shrink to nothing. A single
 * vertex has no such tie: moved alone in its tangent plane it can slide along a long edge towards one
 * end, which lowers that edge's chord floor, while every triangle around it stays the right way up.
 * A map of spherical areas only (au_polish_opts.spherical) has no chord floor, but the same slides
 * clear local errors the flow leaves (limbs8: spherical vertex error 0.0066 -> 0.0036). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_dec.h"
#include "au_sphere.h"

/* A star's arrays are fixed: a vertex with more faces is not polished (a closed star of n faces touches
 * n + 1 cells). The other two are explained where they are used, in star_eval and the sweep loop. */
enum { POLISH_MAX_DEGREE = 64 };
#define POLISH_SPHERE_MIN 0.1 /* a face's triple product stays above this fraction of its share */
#define POLISH_STALL 0.002    /* the sweeps stop when one lowers the vertex error by less than this */

static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross(const double *a, const double *b, double *r) {
  r[0] = a[1] * b[2] - a[2] * b[1];
  r[1] = a[2] * b[0] - a[0] * b[2];
  r[2] = a[0] * b[1] - a[1] * b[0];
}

/* Chord area of the triangle (p, b, c) and its gradient with respect to p: half of (b - c) x n. */
static double chord_area_grad(const double *p, const double *b, const double *c, double *g) {
  double u[3] = {b[0] - p[0], b[1] - p[1], b[2] - p[2]}, v[3] = {c[0] - p[0], c[1] - p[1], c[2] - p[2]}, n[3];
  cross(u, v, n);
  double len = sqrt(dot(n, n));
  if (g) {
    double d[3] = {b[0] - c[0], b[1] - c[1], b[2] - c[2]};
    if (len > 0) {
      double nh[3] = {n[0] / len, n[1] / len, n[2] / len};
      cross(d, nh, g);
      g[0] *= 0.5, g[1] *= 0.5, g[2] *= 0.5;
    } else {
      g[0] = g[1] = g[2] = 0;
    }
  }
  return 0.5 * len;
}

/* The polish's view of one vertex v: its faces, each as (v, b, c) counter-clockwise, and the vertex
 * cells those faces touch (v's own and its neighbours'). */
typedef struct star {
  int nf, nc;
  int face[POLISH_MAX_DEGREE], b[POLISH_MAX_DEGREE], c[POLISH_MAX_DEGREE];
  int cellv[POLISH_MAX_DEGREE + 1];             /* vertex of each local cell; cellv[0] = v */
  int fcell[POLISH_MAX_DEGREE][3];              /* local cells of (v, b, c) */
  double area0[POLISH_MAX_DEGREE];              /* areas before the move (the polish's measure) */
  double orient0[POLISH_MAX_DEGREE];            /* spherical orientations (triple products) before it */
} star;

static int local_cell(star *s, int u) {
  for (int k = 0; k < s->nc; k++)
    if (s->cellv[k] == u) return k;
  s->cellv[s->nc] = u;
  return s->nc++;
}

typedef struct polish_ctx {
  const int *F;
  double *P;
  const double *T;  /* face targets (areas in the polish's measure: chord or spherical) */
  const double *Tc; /* cell targets */
  double *C;        /* current face areas, in that measure */
  double *cell;     /* current cells: a third of the areas of the faces around */
  double cw;        /* weight of a cell's residual */
  int spherical;    /* the spherical triangles' areas instead of the chord ones' */
} polish_ctx;

/* The area of (p, b, c) in the polish's measure, and its gradient with respect to p if g is not NULL. */
static double face_area_grad(const polish_ctx *x, const double *p, const double *b, const double *c, double *g) {
  if (!x->spherical) return chord_area_grad(p, b, c, g);
  double gall[9], a = au_dec_sphere_area(p, b, c, g ? gall : NULL);
  if (g) memcpy(g, gall, 3 * sizeof(double));
  return a;
}

/* Residuals of the star with v at p: the faces' C/T - 1, then the cells' cw log(cell/Tc); with J
 * (2 columns, tangent basis e1, e2) if J is not NULL. Returns the squared norm, or INFINITY if a face
 * turns over or collapses. */
static double star_eval(const polish_ctx *x, const star *s, const double *p, const double *e1, const double *e2,
                        double *res, double *J, double *Cnew) {
  double cl[POLISH_MAX_DEGREE + 1], dcl[POLISH_MAX_DEGREE + 1][2];
  for (int k = 0; k < s->nc; k++) cl[k] = x->cell[s->cellv[k]], dcl[k][0] = dcl[k][1] = 0;
  double E = 0;
  for (int i = 0; i < s->nf; i++) {
    const double *b = x->P + 3 * s->b[i], *c = x->P + 3 * s->c[i];
    const double T = x->T[s->face[i]], orient = au_dec_sphere_orient(p, b, c);
    /* A corner may not come onto the great circle of the opposite edge: a chord triangle can keep its
     * share there while its spherical triangle, which textures and sampling use, vanishes (three
     * corners on one great circle: no splitting of it comes out the right way round in a texture
     * chart). So the triple product (about twice a small spherical triangle's area) stays above
     * POLISH_SPHERE_MIN of the share, or, where the flow left it below, does not fall. With 0.02 the
     * cea textures of spiky_ico's and armadillo's polished maps kept slivers turned over near the
     * poles; with 0.1 none do, and cow's vertex error is 0.0079 instead of 0.0077. */
    if (!(orient > 0) || !(orient >= POLISH_SPHERE_MIN * T || orient >= s->orient0[i])) return INFINITY;
    double g[3], a = face_area_grad(x, p, b, c, J ? g : NULL);
    if (!(a > 1e-9 * T)) return INFINITY;
    Cnew[i] = a;
    res[i] = a / T - 1;
    E += res[i] * res[i];
    double d1 = J ? dot(g, e1) : 0, d2 = J ? dot(g, e2) : 0;
    if (J) J[2 * i] = d1 / T, J[2 * i + 1] = d2 / T;
    for (int k = 0; k < 3; k++) {
      int lc = s->fcell[i][k];
      cl[lc] += (a - s->area0[i]) / 3;
      dcl[lc][0] += d1 / 3, dcl[lc][1] += d2 / 3;
    }
  }
  for (int k = 0; k < s->nc; k++) {
    if (!(cl[k] > 0)) return INFINITY;
    double *r = res + s->nf + k;
    *r = x->cw * log(cl[k] / x->Tc[s->cellv[k]]);
    E += *r * *r;
    if (J) J[2 * (s->nf + k)] = x->cw * dcl[k][0] / cl[k], J[2 * (s->nf + k) + 1] = x->cw * dcl[k][1] / cl[k];
  }
  return E;
}

/* One Gauss-Newton step of vertex v, halved until the star's residual falls with every face the right
 * way up. Returns the fall (0: not moved). */
static double polish_vertex(polish_ctx *x, const int *vf_start, const int *vf, int v) {
  star s;
  s.nf = vf_start[v + 1] - vf_start[v];
  s.nc = 0;
  if (s.nf < 3 || s.nf > POLISH_MAX_DEGREE) return 0;
  local_cell(&s, v);
  for (int i = 0; i < s.nf; i++) {
    int f = vf[vf_start[v] + i];
    const int *c = x->F + 3 * f;
    int k = c[0] == v ? 0 : c[1] == v ? 1 : 2;
    s.face[i] = f, s.b[i] = c[(k + 1) % 3], s.c[i] = c[(k + 2) % 3];
    s.fcell[i][0] = 0, s.fcell[i][1] = local_cell(&s, s.b[i]), s.fcell[i][2] = local_cell(&s, s.c[i]);
    s.area0[i] = x->C[f];
    s.orient0[i] = au_dec_sphere_orient(x->P + 3 * v, x->P + 3 * s.b[i], x->P + 3 * s.c[i]);
  }
  double *p0 = x->P + 3 * v, e1[3], e2[3];
  /* A tangent basis at p0: the axis least aligned with p0, made orthogonal to it. */
  int ax = fabs(p0[0]) <= fabs(p0[1]) && fabs(p0[0]) <= fabs(p0[2]) ? 0 : fabs(p0[1]) <= fabs(p0[2]) ? 1 : 2;
  double a[3] = {0, 0, 0};
  a[ax] = 1;
  cross(p0, a, e1);
  double l1 = sqrt(dot(e1, e1));
  e1[0] /= l1, e1[1] /= l1, e1[2] /= l1;
  cross(p0, e1, e2);
  const int nr = s.nf + s.nc;
  double res[2 * POLISH_MAX_DEGREE + 1], J[2 * (2 * POLISH_MAX_DEGREE + 1)], Cn[POLISH_MAX_DEGREE];
  double E0 = star_eval(x, &s, p0, e1, e2, res, J, Cn);
  if (!isfinite(E0)) return 0;
  double h11 = 0, h12 = 0, h22 = 0, g1 = 0, g2 = 0;
  for (int i = 0; i < nr; i++) {
    h11 += J[2 * i] * J[2 * i], h12 += J[2 * i] * J[2 * i + 1], h22 += J[2 * i + 1] * J[2 * i + 1];
    g1 += J[2 * i] * res[i], g2 += J[2 * i + 1] * res[i];
  }
  const double mu = 1e-6 * (h11 + h22) + 1e-300;
  h11 += mu, h22 += mu;
  const double det = h11 * h22 - h12 * h12;
  if (!(det > 0)) return 0;
  double dx = -(h22 * g1 - h12 * g2) / det, dy = -(h11 * g2 - h12 * g1) / det;
  for (int tries = 0; tries < 20; tries++, dx *= 0.5, dy *= 0.5) {
    double p[3] = {p0[0] + dx * e1[0] + dy * e2[0], p0[1] + dx * e1[1] + dy * e2[1], p0[2] + dx * e1[2] + dy * e2[2]};
    double lp = sqrt(dot(p, p));
    p[0] /= lp, p[1] /= lp, p[2] /= lp;
    double E = star_eval(x, &s, p, e1, e2, res, NULL, Cn);
    if (!(E < E0)) continue;
    for (int i = 0; i < s.nf; i++) {
      const double d = (Cn[i] - s.area0[i]) / 3;
      x->cell[v] += d, x->cell[s.b[i]] += d, x->cell[s.c[i]] += d;
      x->C[s.face[i]] = Cn[i];
    }
    memcpy(p0, p, sizeof p);
    return E0 - E;
  }
  return 0;
}

au_status au_sphere_vertex_polish(const au_mesh *m, const au_topo *t, const double *face_w, double *P,
                                  const au_polish_opts *po, int *sweeps, au_msg *msg) {
  if (sweeps) *sweeps = 0;
  if (!m || !t || !P || !po || po->max_sweeps < 0 || !(po->cell_weight >= 0))
    return au_msg_set(msg, AU_E_ARG, "polish: bad arguments");
  const int max_sweeps = po->max_sweeps;
  const double cell_weight = po->cell_weight, tol = po->tol;
  const int nv = m->nv, nf = m->nf, *F = m->F;
  int *vf_start = calloc((size_t)nv + 1, sizeof(int)), *vf = malloc(sizeof(int) * 3 * (size_t)nf);
  double *As = malloc(sizeof(double) * (size_t)nf), *T = malloc(sizeof(double) * (size_t)nf);
  double *C = malloc(sizeof(double) * (size_t)nf), *Tc = calloc((size_t)nv, sizeof(double));
  double *cell = calloc((size_t)nv, sizeof(double));
  au_status st = AU_OK;
  if (!vf_start || !vf || !As || !T || !C || !Tc || !cell) {
    st = au_msg_set(msg, AU_E_NOMEM, "polish: out of memory");
    goto done;
  }
  for (int i = 0; i < 3 * nf; i++) vf_start[F[i] + 1]++;
  for (int v = 0; v < nv; v++) vf_start[v + 1] += vf_start[v];
  /* Faces by vertex: cell[] counts each vertex's faces filled so far (it is zeroed before use). */
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) {
      const int v = F[3 * f + k];
      vf[vf_start[v] + (int)cell[v]++] = f;
    }
  au_dec_face_areas(nf, F, m->X, As);
  double sA = 0;
  for (int f = 0; f < nf; f++) As[f] *= face_w ? face_w[f] : 1.0, sA += As[f];
  polish_ctx x = {F, P, T, Tc, C, cell, sqrt(cell_weight * (double)nf / (double)(nv > 0 ? nv : 1)), po->spherical};
  double verr_last = INFINITY;
  for (int sweep = 0; sweep < max_sweeps; sweep++) {
    /* The shares are of the chord triangles' total, as the metrics measure them; it moves a little
     * with every vertex, so the targets follow it once a sweep (the spherical triangles' total is 4 pi
     * throughout). */
    if (po->spherical) au_dec_sphere_face_areas(nf, F, P, C);
    else au_dec_face_areas(nf, F, P, C);
    double sC = 0;
    for (int f = 0; f < nf; f++) sC += C[f];
    memset(cell, 0, sizeof(double) * (size_t)nv);
    memset(Tc, 0, sizeof(double) * (size_t)nv);
    double verr = 0;
    for (int f = 0; f < nf; f++) {
      T[f] = As[f] / sA * sC;
      for (int k = 0; k < 3; k++) cell[F[3 * f + k]] += C[f] / 3, Tc[F[3 * f + k]] += T[f] / 3;
    }
    /* Done at the tolerance, as the flow is: the vertex cells' mean |log ratio| (the metrics' measure). */
    int nused = 0;
    for (int v = 0; v < nv; v++)
      if (t->vused[v]) verr += fabs(log(cell[v] / Tc[v])), nused++;
    verr = nused ? verr / nused : 0;
    if (verr <= tol) break;
    /* ... and when a sweep gained less than POLISH_STALL of it: the floor faces' squares dominate the
     * faces' residual, so a gain in the vertex cells is the measure of progress (cheburashka stopped
     * after 8 sweeps at vertex 0.0051 by a gain in that residual, 30 sweeps give 0.0041). */
    if (sweep > 0 && !(verr < (1 - POLISH_STALL) * verr_last)) break;
    verr_last = verr;
    if (po->cancel && __atomic_load_n(po->cancel, __ATOMIC_ACQUIRE)) {
      st = au_msg_set(msg, AU_E_CANCELLED, "polish: cancelled at sweep %d", sweep);
      break;
    }
    for (int v = 0; v < nv; v++)
      if (t->vused[v] && !t->vb[v]) polish_vertex(&x, vf_start, vf, v); /* a closed star (sphere maps have only those) */
    if (sweeps) *sweeps = sweep + 1;
  }
done:
  free(vf_start), free(vf), free(As), free(T), free(C), free(Tc), free(cell);
  return st;
}
