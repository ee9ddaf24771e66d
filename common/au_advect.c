/* au_advect.c - the Lie-advection loop (Zou, Hu, Gu & Hua 2011, sec. 4.2-4.4, eq. 19-20) with local
 * step control.
 *
 * Each step asks every vertex cell for a share of its remaining area excess, solves the Poisson
 * problem C g = -dA on the current domain mesh (C: cotan stiffness, one vertex pinned, so the flux of
 * grad g out of cell i is dA_i), moves the vertices along the angle-weighted vertex gradient and puts
 * them back on the domain. Two departures from the paper keep the flow fold-free on hard meshes:
 *  - the per-step target is geometric, a cell's area ratio moves by the factor rho^(1/(K-k)), so a
 *    cell squeezed by e^8 is never asked to grow 60x in one step (the linear eq. 19 is);
 *  - the step is limited locally: a vertex moves at most max_move times the smallest inradius of its
 *    triangles. With max_move < 1/2 no triangle can invert in the plane (each edge vector changes by
 *    less than twice that, which cannot overturn the triangle); the rest of the excess is taken by
 *    later steps. A final orientation check backtracks any vertex whose triangle still flipped
 *    (possible only through the curvature of the sphere's retraction). */
#define _POSIX_C_SOURCE 200809L

#include "au_advect.h"

#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "au_advect_internal.h"
#include "au_dec.h"
#include "au_par.h"
#include "au_solver.h"

/* Smallest orientation (twice the signed area, or the triple product on the unit sphere) a triangle
 * may be moved down to: far above the ~1e-16 rounding of the determinant of unit vectors. */
#define AU_ORIENT_MARGIN 1e-13

/* The part of its orientation a triangle with a sliding boundary corner must keep along the corner's
 * real (retracted) path at the step control's fraction (see step_control). */
#define AU_BOUNDARY_KEEP 0.02

/* The least-shear step weighs a face by its target area, but by at most this many times its current
 * area (a face squeezed by e^-20 would otherwise make the system singular in double precision). Not
 * much less either: the energy is an integral, so a face weighed by its own tiny area is free to be
 * sheared, and the step control then holds its whole neighbourhood back. Measured on cow (legs
 * squeezed to areas of 1e-22): with 100 the flow crawled (step fraction 0.2-0.4) and left 15 faces
 * too small for a sign; with 1e6 it takes full steps and ends fold-free. */
#define AU_WEIGHT_CAP 1e6

/* The shape restoring (au_advect_opts.restore) acts in full while the vertex error is above this and
 * fades in proportion below it: at full strength to the end it kept the areas from converging
 * (bunny: 53 steps instead of 23, vertex 0.0054 instead of 0.0014); faded, 25 steps and 0.00064. */
#define AU_RESTORE_FADE 0.1

/* The chord polish, vertex cells above the tolerance: it ends when four steps gained less than this
 * fraction of both the vertex and the per-face error (see the stall test in advect_core). */
#define AU_POLISH_GAIN 0.05

/* Kinetic-energy weight of the least-shear step: only fixes the rigid rotations, which change neither
 * areas nor angles. */
#define AU_ROTATION_EPS 1e-6

/* The stiffest shear weight an undone step is retried with. */
#define AU_SHEAR_MAX 1e4

au_advect_opts au_advect_opts_default(void) {
  au_advect_opts o;
  memset(&o, 0, sizeof o);
  o.max_steps = 60;
  o.schedule_steps = 4;
  o.tol = 2e-3;
  o.max_move = 0.3;
  o.newton_below = 0.7;
  o.max_log_step = 1.2;
  o.face_steps = 30;
  o.face_tol = 1e-3;
  o.face_damping = 0.1;
  o.method = AU_ADVECT_LEAST_SHEAR;
  o.shear = 1;
  o.shear_tail = 0.01;
  o.sphere_areas = 1;
  o.face_gain = 0.1;
  o.restore = 0.1;
  o.lantern = 0;
  o.angle_steps = 0;
  o.angle_faces = 300;
  o.angle_cells = 1e6;
  o.angle_trust = 1;
  o.angle_switch = 0.01;
  o.polish_gap = 0.1;
  o.resolved_jump = 0.1;
  o.resolved_decay = 0.25;
  o.resolved_shear = 0.1;
  o.resolved_log_step = 2;
  return o;
}

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Orientation of face f at positions P: spherical domains use the triple product, planar ones the
 * z component of the cross product. Positive means correctly oriented. */
static double face_orient(const double *P, const int *F, int f, int spherical) {
  const double *a = P + 3 * F[3 * f], *b = P + 3 * F[3 * f + 1], *c = P + 3 * F[3 * f + 2];
  if (spherical) return au_dec_sphere_orient(a, b, c);
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Number of faces with orientation <= 0. */
static int count_folds(const double *P, const int *F, int nf, int spherical) {
  int n = 0;
  for (int f = 0; f < nf; f++) n += face_orient(P, F, f, spherical) <= 0;
  return n;
}

/* Mean |ln(target/current)| over referenced vertices. */
static double vertex_error(int nv, const unsigned char *used, const double *T, const double *A) {
  double s = 0;
  int n = 0;
  for (int i = 0; i < nv; i++) {
    if (!used[i]) continue;
    s += fabs(log(T[i] / A[i]));
    n++;
  }
  return n ? s / n : 0;
}

/* Smallest t in (0, 1] at which the triangle (a, b, c) moved by t*(da, db, dc) keeps only `keep` of its
 * orientation, 1 if it never gets there. The orientation is the triangle's area projected onto the
 * domain's normal (planar: z; sphere: the direction of the centroid), not onto its own plane: a thin
 * triangle along a great circle has a sizeable chord area but almost no spherical orientation, and a
 * small sideways move turns it over (measured on cheburashka). */
static double face_safe_t(const double *a, const double *b, const double *c, const double *da, const double *db,
                          const double *dc, double keep, int spherical) {
  double e1[3], e2[3], d1[3], d2[3], n[3];
  for (int d = 0; d < 3; d++) e1[d] = b[d] - a[d], e2[d] = c[d] - a[d], d1[d] = db[d] - da[d], d2[d] = dc[d] - da[d];
  if (spherical) {
    for (int d = 0; d < 3; d++) n[d] = a[d] + b[d] + c[d];
  } else {
    n[0] = 0, n[1] = 0, n[2] = 1;
  }
  double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(nn > 0)) return 0;
  for (int d = 0; d < 3; d++) n[d] /= nn;
#define AU_TRI(u, v) (n[0] * ((u)[1] * (v)[2] - (u)[2] * (v)[1]) + n[1] * ((u)[2] * (v)[0] - (u)[0] * (v)[2]) + n[2] * ((u)[0] * (v)[1] - (u)[1] * (v)[0]))
  /* Twice the projected area along the way: c0 + c1 t + c2 t^2. */
  double c0 = AU_TRI(e1, e2), c1 = AU_TRI(e1, d2) + AU_TRI(d1, e2), c2 = AU_TRI(d1, d2);
#undef AU_TRI
  if (!(c0 > 0)) return 0;
  double q0 = c0 * (1 - keep); /* solve c2 t^2 + c1 t + q0 = 0 for the first t > 0 */
  double tmin = 1;
  if (fabs(c2) < 1e-300) {
    if (c1 < 0) tmin = -q0 / c1;
  } else {
    double disc = c1 * c1 - 4 * c2 * q0;
    if (disc >= 0) {
      double sq = sqrt(disc), r1 = (-c1 - sq) / (2 * c2), r2 = (-c1 + sq) / (2 * c2);
      if (r1 > 0 && r1 < tmin) tmin = r1;
      if (r2 > 0 && r2 < tmin) tmin = r2;
    }
  }
  return tmin < 1 ? tmin : 1;
}

/* Heap of vertices keyed by s (smallest first) for the envelope propagation. */
static void heap_up(int *heap, int *pos, const double *s, int k) {
  while (k > 0) {
    int p = (k - 1) / 2;
    if (s[heap[p]] <= s[heap[k]]) break;
    int tmp = heap[p];
    heap[p] = heap[k], heap[k] = tmp;
    pos[heap[p]] = p, pos[heap[k]] = k;
    k = p;
  }
}
static void heap_down(int *heap, int *pos, const double *s, int n, int k) {
  for (;;) {
    int l = 2 * k + 1, r = l + 1, m = k;
    if (l < n && s[heap[l]] < s[heap[m]]) m = l;
    if (r < n && s[heap[r]] < s[heap[m]]) m = r;
    if (m == k) break;
    int tmp = heap[m];
    heap[m] = heap[k], heap[k] = tmp;
    pos[heap[m]] = m, pos[heap[k]] = k;
    k = m;
  }
}

/* Vertex-to-edge adjacency in compressed rows: the edges of vertex i are adj_e[adj_start[i]..adj_start[i+1]-1]. */
typedef struct adjacency {
  int *start; /* [0..nv] */
  int *e;     /* [0..2*ne-1] */
} adjacency;

static int adjacency_build(const au_topo *t, adjacency *a) {
  a->start = calloc((size_t)t->nv + 1, sizeof(int));
  a->e = malloc(sizeof(int) * 2 * (size_t)(t->ne > 0 ? t->ne : 1));
  if (!a->start || !a->e) return 0;
  for (int e = 0; e < t->ne; e++) a->start[t->E[2 * e] + 1]++, a->start[t->E[2 * e + 1] + 1]++;
  for (int i = 0; i < t->nv; i++) a->start[i + 1] += a->start[i];
  int *fill = malloc(sizeof(int) * (size_t)(t->nv > 0 ? t->nv : 1));
  if (!fill) return 0;
  memcpy(fill, a->start, sizeof(int) * (size_t)t->nv);
  for (int e = 0; e < t->ne; e++) a->e[fill[t->E[2 * e]]++] = e, a->e[fill[t->E[2 * e + 1]]++] = e;
  free(fill);
  return 1;
}

static void adjacency_free(adjacency *a) {
  free(a->start);
  free(a->e);
  a->start = a->e = NULL;
}

/* Per-vertex step fractions s [0..nv-1] in (0, 1] for the displacement D.
 * 1. Each face allows the fraction at which it would keep only a quarter of its area; a vertex takes
 *    the smallest fraction of its faces. That alone is not safe: where neighbours take different
 *    fractions of a large common translation, the difference itself deforms the triangles.
 * 2. So s is made Lipschitz along edges: s_i <= s_j + c * r_ij / max(|D_i|, |D_j|), with r_ij the
 *    smaller inradius of the edge's triangles, which bounds the extra relative motion by c inradii.
 *    This is a shortest-path envelope, computed with Dijkstra's algorithm from every vertex at once.
 *    Only vertices below 1 can lower a neighbour (the bound only adds), so the heap starts with them
 *    and takes in a vertex when it is lowered: the work follows the restricted vertices, not the mesh
 *    (brain_disk: the envelope was 17% of the run when every vertex went through the heap).
 * inr [0..nf-1] holds the faces' inradii; heap and pos are scratch of nv ints, dn of nv doubles. */
static void envelope(const au_topo *t, const adjacency *adj, int nv, const double *inr, const double *D, double c,
                     double *s, int *heap, int *pos, double *dn) {
  enum { OUT = -2, DONE = -1 }; /* pos[i]: heap slot, or not (yet) in the heap, or settled */
  int n = 0;
  for (int i = 0; i < nv; i++) {
    dn[i] = sqrt(D[3 * i] * D[3 * i] + D[3 * i + 1] * D[3 * i + 1] + D[3 * i + 2] * D[3 * i + 2]);
    if (s[i] < 1) heap[n] = i, pos[i] = n++;
    else pos[i] = OUT;
  }
  for (int k = n / 2 - 1; k >= 0; k--) heap_down(heap, pos, s, n, k);
  while (n > 0) {
    int i = heap[0];
    heap[0] = heap[--n];
    pos[heap[0]] = 0;
    pos[i] = DONE;
    heap_down(heap, pos, s, n, 0);
    double di = dn[i];
    for (int a = adj->start[i]; a < adj->start[i + 1]; a++) {
      int e = adj->e[a], j = t->E[2 * e] == i ? t->E[2 * e + 1] : t->E[2 * e];
      if (pos[j] == DONE) continue;
      double dj = dn[j];
      double r = INFINITY;
      for (int k = 0; k < 2; k++)
        if (t->EF[2 * e + k] >= 0 && inr[t->EF[2 * e + k]] < r) r = inr[t->EF[2 * e + k]];
      double dm = di > dj ? di : dj;
      if (!(dm > 0)) continue;
      double cand = s[i] + c * r / dm;
      if (cand < s[j]) {
        s[j] = cand;
        if (pos[j] == OUT) heap[n] = j, pos[j] = n++;
        heap_up(heap, pos, s, pos[j]);
      }
    }
  }
}

/* The position of a vertex at q moved by t d. Straight, except on planar domains with an arc radius
 * (au_advect_domain.arc_radius): there the move follows the arc about the origin that d starts on
 * (radial part along the ray, tangential part as a turn), bent by the fraction min(1, r / arc_radius).
 * A boundary vertex sliding by s along a circle ends about s^2/2 inside its straight path, which the
 * retraction onto the circle makes up; a straight interior move beside it does not, so a boundary
 * triangle of height h turned over once the boundary slid by sqrt(2h). An equal-area map of a surface
 * with a short boundary needs such triangles: brain_disk's 113 boundary edges are 0.056 long on the
 * circle and their triangles' areas make them 0.001 high (aspect 30-50), and the step control held the
 * whole mesh back for them (brain_disk 16 steps, sophie 35; with arcs 9 and 6). At the disk's centre
 * the bend goes to zero: full arcs there (a turn by s/r) took demosthenes 20 -> 60 steps. */
static void move_vertex(const au_advect_domain *dom, const double *q, const double *d, double t, double *out) {
  out[0] = q[0] + t * d[0], out[1] = q[1] + t * d[1], out[2] = q[2] + t * d[2];
  if (dom->spherical || !(dom->arc_radius > 0)) return;
  double r0 = hypot(q[0], q[1]);
  if (!(r0 > 0)) return;
  double w = r0 < dom->arc_radius ? r0 / dom->arc_radius : 1;
  double ux = q[0] / r0, uy = q[1] / r0;
  double r = r0 + t * (d[0] * ux + d[1] * uy), turn = t * (d[1] * ux - d[0] * uy) / r0;
  double c = cos(turn), sn = sin(turn);
  out[0] += w * (r * (ux * c - uy * sn) - out[0]);
  out[1] += w * (r * (uy * c + ux * sn) - out[1]);
}

static void step_control(const au_topo *t, const adjacency *adj, const int *F, int nf, int nv, const double *P,
                         const double *inr, const double *D, double c, const au_advect_domain *dom, double *s,
                         int *heap, int *pos, double *dn) {
  const int spherical = dom->spherical;
  for (int i = 0; i < nv; i++) s[i] = 1;
  for (int f = 0; f < nf; f++) {
    const int *v = F + 3 * f;
    double tf = face_safe_t(P + 3 * v[0], P + 3 * v[1], P + 3 * v[2], D + 3 * v[0], D + 3 * v[1], D + 3 * v[2], 0.25, spherical);
    if (!spherical) {
      /* The fraction above is exact for straight moves; a boundary vertex slides along its curve
       * (retract), off the straight line, and turned the thin triangles at the boundary over after
       * the step (brain_disk: every triangle the backtracking in advect_core had to mend had a
       * boundary corner, 3.5 rounds a step). So the fraction is checked on the corners' real paths
       * (move_vertex, then retract) and halved until the triangle keeps AU_BOUNDARY_KEEP of its
       * orientation. Asking for more than the backtracking does holds the boundary back (a fifth:
       * brain_disk 19 -> 23 steps; a fiftieth: 18 steps, init + flow 5.7-6.3 -> 4.9-5.3 s). Interior
       * triangles away from the boundary pass (the final orientation check covers them). */
      const double *a = P + 3 * v[0], *b = P + 3 * v[1], *cc = P + 3 * v[2];
      double o0 = (b[0] - a[0]) * (cc[1] - a[1]) - (b[1] - a[1]) * (cc[0] - a[0]);
      for (int h = 0; h < 12 && o0 > 0; h++) {
        double q[3][3];
        for (int k = 0; k < 3; k++) {
          move_vertex(dom, P + 3 * v[k], D + 3 * v[k], tf, q[k]);
          dom->retract(dom->ctx, v[k], q[k]);
        }
        double o = (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]);
        if (o >= AU_BOUNDARY_KEEP * o0) break;
        tf *= 0.5;
      }
    }
    for (int k = 0; k < 3; k++)
      if (tf < s[v[k]]) s[v[k]] = tf;
  }
  envelope(t, adj, nv, inr, D, c, s, heap, pos, dn);
}

/* The errors of the chord triangles of P against the targets As * fw (scaled to P's total chord area;
 * SM: the targets' total, AM: the vertex targets): *ferr the per-face mean |r - 1|, *verr the vertex
 * cells' mean |log ratio|. af [0..nf-1], AO [0..nv-1]: scratch. */
static void chord_errors(int nv, int nf, const int *F, const unsigned char *used, const double *P, const double *As,
                         const double *fw, const double *AM, double SM, double *af, double *AO, double *ferr, double *verr) {
  au_dec_face_areas(nf, F, P, af);
  au_dec_vertex_areas(nv, nf, F, P, af, AO);
  double SC = 0, e = 0, v = 0;
  int n = 0;
  for (int f = 0; f < nf; f++) SC += af[f];
  for (int f = 0; f < nf; f++) e += fabs(af[f] / (As[f] * fw[f] * SC / SM) - 1);
  for (int i = 0; i < nv; i++)
    if (used[i]) v += fabs(log(AM[i] * SC / SM / AO[i])), n++;
  *ferr = e / nf, *verr = n ? v / n : 0;
}

/* The flow itself, on arguments and options au_advect_run has checked. */
/* The flow hands over to the angle steps at step k (au_advect_opts.angle_steps): from here the map is
 * measured in the chord triangles' terms. Returns how many there may be (the report's arrays bound them). */
static int begin_angles(const au_advect_opts *o, int k, int *ang_phase, int *sph_phase, au_advect_report *rep) {
  *ang_phase = 1, *sph_phase = 0;
  rep->angle_from = k;
  return o->angle_steps < AU_ADVECT_MAX_STEPS - 1 - k ? o->angle_steps : AU_ADVECT_MAX_STEPS - 1 - k;
}

static au_status advect_core(const au_mesh *m, const au_topo *t, const au_advect_domain *dom, const au_advect_opts *opts,
                             au_lm **lmp, double *P, au_advect_report *rep, au_msg *msg) {
  const au_advect_opts o = *opts;
  memset(rep, 0, sizeof *rep);

  const int nv = m->nv, nf = m->nf, *F = m->F;
  const int sph = dom->spherical;
  au_status st = AU_OK;
  au_solver *solver = NULL;
  au_gn *gn = NULL, *gnf = NULL;
  au_ang *ang = NULL; /* the angle step (o.angle_steps), made when first needed */
  au_lm *lm = *lmp; /* the plan's: analyzed once, perhaps while the start was being computed */
  const int ls = o.method == AU_ADVECT_LEAST_SHEAR;
  double *AM = malloc(sizeof(double) * nv), *AO = malloc(sizeof(double) * nv), *b = malloc(sizeof(double) * nv);
  double *g = malloc(sizeof(double) * nv), *lim = malloc(sizeof(double) * nv), *af = malloc(sizeof(double) * nf);
  double *dn = malloc(sizeof(double) * nv); /* the step control's |D_i| */
  double *Gf = malloc(sizeof(double) * 3 * nf), *D = malloc(sizeof(double) * 3 * nv);
  double *Pold = malloc(sizeof(double) * 3 * nv), *w = malloc(sizeof(double) * (t->ne > 0 ? t->ne : 1));
  unsigned char *fixed = calloc((size_t)nv, 1), *bad = calloc((size_t)nv, 1);
  int *heap = malloc(sizeof(int) * nv), *hpos = malloc(sizeof(int) * nv);
  double *inr = malloc(sizeof(double) * nf), *As = malloc(sizeof(double) * nf), *fw = malloc(sizeof(double) * nf);
  double *dA_f = malloc(sizeof(double) * nf), *orient_old = malloc(sizeof(double) * nf);
  adjacency adj = {NULL, NULL};
  if (!AM || !AO || !b || !g || !dn || !lim || !af || !Gf || !D || !Pold || !w || !fixed || !bad || !heap || !hpos || !inr || !As || !fw || !dA_f || !orient_old ||
      !adjacency_build(t, &adj)) {
    st = au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
    goto done;
  }

  /* Target areas: the surface's triangle areas times the density (per face: the face's own, or the
   * mean of its corners'). */
  au_dec_face_areas(nf, F, m->X, As);
  for (int f = 0; f < nf; f++)
    fw[f] = o.face_weight ? o.face_weight[f]
            : o.weight    ? (o.weight[F[3 * f]] + o.weight[F[3 * f + 1]] + o.weight[F[3 * f + 2]]) / 3.0
                          : 1.0;
  /* A vertex cell's target is a third of each of its faces' targets, with a per-vertex density too:
   * the flow drives the faces, and vertex targets of their own (area times the vertex's density)
   * disagree with the faces' where the density jumps, which left the vertex error at 0.057 on a sphere
   * with density 4 on one half. */
  memset(AM, 0, sizeof(double) * nv);
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) AM[F[3 * f + k]] += As[f] * fw[f] / 3.0;
  double SM = 0;
  for (int i = 0; i < nv; i++) SM += AM[i];
  if (!(SM > 0)) {
    st = au_msg_set(msg, AU_E_ARG, "advect: the surface has no area");
    goto done;
  }

  int folds = count_folds(P, F, nf, sph);
  if (folds) {
    st = au_msg_set(msg, AU_E_FOLD, "advect: the initial map has %d folded triangles", folds);
    goto done;
  }

  /* The Poisson problem is a pure Neumann problem (closed sphere, or a boundary that only slides):
   * pin the first referenced vertex; unreferenced vertices have empty rows and are fixed too. */
  int pinned = -1;
  for (int i = 0; i < nv; i++) {
    if (!t->vused[i]) fixed[i] = 1;
    else if (pinned < 0) pinned = i, fixed[i] = 1;
  }
  double t0;

  int k, face_phase = 0, face_steps = 0;
  /* sph_phase: the spherical-area part of the flow (o.sphere_areas); phase_start: the first step of
   * the current part, so that the stall test compares like with like. */
  int sph_phase = sph && ls && o.sphere_areas, phase_start = 0;
  double alpha = o.shear; /* the least-shear step's current shear weight */
  double prev_err = INFINITY, prev_ferr = INFINITY, prev_flog = INFINITY;
  int retry = 0;                 /* this step retries an undone one */
  int measured_jump = 0;         /* the start's resolution has been measured (rep->start_jump) */
  int exhausted = 0;             /* no stiffer step is worth a try: this part of the flow ends */
  int ang_phase = 0, ang_left = 0; /* the angle steps (o.angle_steps, begin_angles), and how many remain */
  double ang_prev = INFINITY;      /* the vertex error before the last angle step */
  au_dec_face_areas(nf, F, m->X, As);
  for (k = 0;; k++) {
    /* On the sphere the domain's areas are the spherical triangles' (see au_lm.c): they vanish where
     * the corners come onto one great circle, and they sum to 4 pi. */
    if (sph_phase) au_dec_sphere_face_areas(nf, F, P, af);
    else au_dec_face_areas(nf, F, P, af);
    au_dec_vertex_areas(nv, nf, F, P, af, AO);
    double SO = 0;
    for (int f = 0; f < nf; f++) SO += af[f];
    double scale = SO / SM;
    /* b temporarily holds the target areas of this domain's total. */
    for (int i = 0; i < nv; i++) b[i] = AM[i] * scale;
    double err = vertex_error(nv, t->vused, b, AO);
    /* Per face: the mean |r - 1| (reported) and, for the least-shear step's control, the mean |log r|. */
    double ferr = 0, flog = 0;
    for (int f = 0; f < nf; f++) {
      double r = af[f] / (As[f] * fw[f] * scale);
      ferr += fabs(r - 1);
      if (ls) flog += fabs(log(r));
    }
    ferr /= nf, flog /= nf;
    if (!measured_jump) {
      /* The start's resolution, measured once: the mean jump of log r between the two faces of each
       * interior edge. Where it is small the wanted correction is smooth at the mesh's scale, and the
       * flow can drop the shear weight faster and let faces grow more per step (au_advect_opts). */
      double sj = 0;
      int nj = 0;
      for (int e = 0; e < t->ne; e++) {
        int f0 = t->EF[2 * e], f1 = t->EF[2 * e + 1];
        if (f0 < 0 || f1 < 0) continue;
        double r0 = af[f0] / (As[f0] * fw[f0]), r1 = af[f1] / (As[f1] * fw[f1]);
        if (r0 > 0 && r1 > 0) sj += fabs(log(r0 / r1)), nj++;
      }
      rep->start_jump = nj ? sj / nj : 0;
      /* Equal-area maps only: with a prescribed density bunny undid 14 steps and missed the tolerance
       * (weight 4 on one half), or undid 5 and took longer (a smooth weight from 1 to 4). */
      rep->resolved = ls && nj > 0 && !o.weight && !o.face_weight && rep->start_jump <= o.resolved_jump;
      if (rep->resolved) alpha = o.resolved_shear;
      measured_jump = 1;
    }
    rep->err[k] = err;
    rep->face_err[k] = ferr;
    if (!(err == err) || !(ferr == ferr)) {
      st = au_msg_set(msg, AU_E_NUMERIC, "advect: area error is not a number at step %d", k);
      goto done;
    }
    if (o.progress) o.progress(o.user, k, o.max_steps, ls ? ferr : err);
    if (o.cancel && __atomic_load_n(o.cancel, __ATOMIC_ACQUIRE)) {
      st = au_msg_set(msg, AU_E_CANCELLED, "advect: cancelled at step %d", k);
      goto done;
    }
    if (ang_phase) {
      /* An angle step that took the vertex cells above both the tolerance and where they were is undone,
       * and the phase ends there. */
      if (err > o.tol && err > ang_prev * (1 + 1e-9)) {
        memcpy(P, Pold, sizeof(double) * 3 * nv);
        rep->undone++;
        ang_left = 0, ang_prev = INFINITY;
        k -= 2;
        continue;
      }
      if (ang_left-- <= 0) break;
      ang_prev = err;
    } else if (ls && o.angle_steps > 0 && o.angle_switch > 0 && err <= o.angle_switch && ferr <= 2 * o.angle_switch &&
               k + 1 < AU_ADVECT_MAX_STEPS) {
      /* The flow hands over to the angle steps (o.angle_switch), once its faces are within twice that
       * too (spot: at step 7 the faces were at 0.027 and ended at 0.018; at step 9, 0.017): measured
       * again in the chord triangles' terms, the step number staying. */
      ang_left = begin_angles(&o, k, &ang_phase, &sph_phase, rep);
      k--;
      continue;
    } else if (ls) {
      /* Levenberg-Marquardt control of the shear weight: a step that made the per-face error worse is
       * undone and retried stiffer; an accepted one lets the next be bolder, down to shear_tail. The
       * error is the mean |log r| over the faces, the quantity the steps' targets are set in: the mean
       * |r - 1| barely sees a squeezed face grow (r from 1e-6 to 1e-5) and punishes an overgrown one
       * without bound, so it undid good steps (bunny: 9 of the first 12 with max_log_step 2). */
      if (k > 0 && !(flog <= prev_flog * (1 + 1e-9))) {
        /* The undone step leaves no trace: the loop goes back to the step it was taken from, which
         * is measured again (the same map) and solved again, stiffer. Counted, each cost two steps of
         * the budget, and the stall test read their copies of the last errors as no progress. Past
         * AU_SHEAR_MAX, or with the budget spent (max_steps solves, undone ones included), no stiffer
         * step is worth a try: this part of the flow ends at the last accepted map (hand_closed:
         * retried without end, the weight reached 1e6 and the last pivots went non-positive). */
        memcpy(P, Pold, sizeof(double) * 3 * nv);
        retry = 1;
        rep->undone++;
        if (alpha * 4 <= AU_SHEAR_MAX && k + rep->undone <= o.max_steps) alpha *= 4;
        else exhausted = 1;
        k -= 2;
        continue;
      }
      /* The resolved schedule drops the weight faster, until a step has been undone. Its floor is
       * shear_tail, or face_shear_tail (if set) once the vertex cells meet tol. */
      const double least = o.face_shear_tail > 0 && err <= o.tol ? o.face_shear_tail : o.shear_tail;
      if (k > 0) alpha = fmax((rep->resolved && !rep->undone ? o.resolved_decay : 0.5) * alpha, least);
      prev_flog = flog;
      /* Stalled: neither error gained 2% in the last four steps, or, once the vertex cells meet the
       * tolerance, face_gain (the refinement must be worth its steps). In the chord polish with the
       * vertex cells still above the tolerance, AU_POLISH_GAIN: with 2% armadillo crept on to the step
       * budget, 11 polish steps for vertex 0.00367 -> 0.00344, per-face 0.0111 -> 0.0109, about 2 s;
       * with 5% it takes 45 steps instead of 49, vertex 0.00350 (spot_lowres, whose polish still gains
       * 8% in four steps, is unchanged). */
      const int polish = !sph_phase && phase_start > 0;
      double keep = err <= o.tol ? 1 - o.face_gain : polish ? 1 - AU_POLISH_GAIN : 0.98;
      int stalled = exhausted || (k >= o.schedule_steps + 4 && k >= phase_start + 4 && ferr > keep * rep->face_err[k - 4] &&
                                  err > keep * rep->err[k - 4]);
      exhausted = 0;
      /* In the polish, with the vertex cells within the tolerance, one step tells: a quarter of the gain.
       * (Two steps for half the gain cost lion_statue a 12th step for per-face 0.00801 -> 0.00796.) */
      if (polish && err <= o.tol && k >= phase_start + 1 && ferr > (1 - 0.25 * o.face_gain) * rep->face_err[k - 1])
        stalled = 1;
      /* The spherical part ends when its vertex cells meet the tolerance (the chord polish refines the
       * faces from there), when it stalls, or when it has used two thirds of the steps. */
      int sph_done = sph_phase && ((k > 0 && k + rep->undone >= (o.max_steps * 2) / 3) || (k >= o.schedule_steps && err <= o.tol));
      /* Done: the vertex cells within tol and the faces within face_tol (not the larger of the two: with
       * the planar tol of 3e-3, --refine-faces stopped at per-face 0.0030 on every disk and annulus
       * mesh instead of going on to its 1e-3: amoeba_annulus r_cv 0.0042 -> 0.0014). */
      if ((err <= o.tol && ferr <= o.face_tol) || stalled || sph_done) {
        /* The chord triangles' areas (the ones a reader of the output sees) need a polish only where
         * they differ from the spherical ones: on long, thin triangles, or if their vertex cells miss the
         * tolerance. Elsewhere it costs steps for nothing (lion_statue: 6 steps, per-face 0.00455 ->
         * 0.00445). */
        double cferr = 0, cerr = 0;
        if (sph_phase) chord_errors(nv, nf, F, t->vused, P, As, fw, AM, SM, af, AO, &cferr, &cerr);
        if (sph_phase && (cerr > o.tol || cferr > (1 + o.polish_gap) * ferr)) {
          /* Polish the chord triangles' areas from here: measure this map again in their terms (the
           * step number stays), with the stiff start of the shear weight. */
          sph_phase = 0;
          phase_start = k;
          rep->polish_from = k;
          prev_err = prev_ferr = prev_flog = INFINITY;
          alpha = o.shear;
          k--;
          continue;
        }
        if (o.angle_steps > 0 && !ang_phase && k + 1 < AU_ADVECT_MAX_STEPS) {
          /* The angle steps, measured in the chord triangles' terms from here (the map is measured again;
           * the step number stays). */
          ang_left = begin_angles(&o, k, &ang_phase, &sph_phase, rep);
          k--;
          continue;
        }
        rep->converged = err <= o.tol;
        break;
      }
    } else if (face_phase) {
      /* Refine while the per-face error falls; a step that made it worse is undone. */
      if (ferr >= prev_ferr) {
        memcpy(P, Pold, sizeof(double) * 3 * nv);
        rep->err[k] = err = prev_err;
        rep->face_err[k] = ferr = prev_ferr;
        rep->converged = err <= o.tol;
        break;
      }
      if (ferr <= o.face_tol || face_steps >= o.face_steps) {
        rep->converged = err <= o.tol;
        break;
      }
    } else if (err <= o.tol) {
      rep->converged = 1;
      /* The vertex cells are equal: go on with the triangles themselves. */
      if (o.face_steps > 0 && ferr > o.face_tol) face_phase = 1;
      else break;
    }
    prev_err = err, prev_ferr = ferr;
    if (!ang_phase && k + rep->undone >= o.max_steps) { /* the budget counts undone solves too */
      if (!(ls && o.angle_steps > 0 && k + 1 < AU_ADVECT_MAX_STEPS)) break;
      /* The angle steps come on top of the flow's budget (measured in the chord triangles' terms). */
      ang_left = begin_angles(&o, k, &ang_phase, &sph_phase, rep);
      k--;
      continue;
    }

    t0 = now_s();
    if (ang_phase) {
      if (!ang) {
        st = au__ang_create(m, &ang, msg);
        if (st != AU_OK) goto done;
      }
      /* Targets in this map's units: b holds the cells', Gf gets the faces'. */
      for (int f = 0; f < nf; f++) Gf[f] = As[f] * fw[f] * scale;
      st = au__ang_step(ang, dom, P, Gf, b, o.angle_faces, o.angle_cells, o.angle_trust, D, msg);
    } else if (ls) {
      /* Per-face targets on the geometric schedule, each ratio moving at most e^max_log_step (on the
       * resolved schedule e^resolved_log_step). */
      double s = k < o.schedule_steps ? 1.0 / (double)(o.schedule_steps - k) : 1.0, sum_new = 0;
      const double cap = rep->resolved ? o.resolved_log_step : o.max_log_step;
      for (int f = 0; f < nf; f++) {
        double lr = s * log(As[f] * fw[f] * scale / af[f]);
        if (lr > cap) lr = cap;
        if (lr < -cap) lr = -cap;
        dA_f[f] = af[f] * exp(lr);
        sum_new += dA_f[f];
      }
      double renorm = SO / sum_new;
      /* dA_f is the wanted change of the area; the step is linear in the motion, and a triangle scaled
       * by s has area s^2: asked to grow by rho, a linear step that predicts rho overshoots to about
       * ((1 + rho) / 2)^2 (e^1.2 = 3.3 becomes 4.7). So growth is asked as the similarity that gives it,
       * 2 (sqrt(rho) - 1); shrinking is left as it is (the sqrt would ask for more, towards collapse),
       * and the changes are recentred to sum to zero, as a tangent motion's do. */
      double tot = 0;
      for (int f = 0; f < nf; f++) {
        double rho = dA_f[f] * renorm / af[f];
        dA_f[f] = af[f] * (rho > 1 ? 2 * (sqrt(rho) - 1) : rho - 1);
        tot += dA_f[f];
      }
      for (int f = 0; f < nf; f++) dA_f[f] -= af[f] * (tot / SO);
      if (!lm) {
        st = au__lm_create(m, t, lmp, msg);
        if (st != AU_OK) goto done;
        lm = *lmp;
      }
      /* Face weights: the target areas (the faces' shares of the surface), at most AU_WEIGHT_CAP times
       * the current area so that the system stays well conditioned. */
      for (int f = 0; f < nf; f++) Gf[f] = fmin(As[f] * fw[f] * scale, AU_WEIGHT_CAP * af[f]);
      /* Shape restoring, faded out as the vertex cells approach their areas (it would hold them off). */
      /* Not in a retry: the restoring target grows with the shear weight, so a step undone for making the
       * areas worse would be retried ever more purely as shape restoring, and undone again (measured:
       * dumbbell stuck at 0.21 for 35 steps). */
      double restore = sph_phase && !retry ? o.restore * fmin(1, err / AU_RESTORE_FADE) : 0;
      retry = 0;
      const double lantern = restore > 0 && err < 1 ? o.lantern : 0;
      st = au__lm_step(lm, dom, P, dA_f, Gf, alpha, AU_ROTATION_EPS, sph_phase, restore, lantern, D, msg);
      if (st == AU_E_NOT_SPD) {
        /* Rounding made the system indefinite: retry stiffer (the shear term is definite but for the
         * rotations), or, as stiff as it gets, end this part of the flow here. Nothing has moved: the
         * next round sees the same map. */
        rep->frac[k] = 0;
        if (alpha < 1e6) alpha *= 16;
        else exhausted = 1, k--;
        memcpy(Pold, P, sizeof(double) * 3 * nv);
        msg ? (void)(msg->text[0] = '\0') : (void)0;
        st = AU_OK;
        continue;
      }
    } else if (face_phase) {
      /* Per-face refinement: damped Gauss-Newton on the triangle areas. */
      if (!gnf) {
        st = au__gn_create(m, t, 1, &gnf, msg);
        if (st != AU_OK) goto done;
      }
      for (int f = 0; f < nf; f++) dA_f[f] = As[f] * fw[f] * scale - af[f];
      for (int i = 0; i < nv; i++) g[i] = AO[i] > 0 ? 1.0 / AO[i] : 0;
      st = au__gn_step(gnf, dom, P, g, dA_f, o.face_damping, D, msg);
      face_steps++;
      rep->face_steps = face_steps;
    } else {
      /* Geometric schedule: the area ratio of each cell moves by rho^s; renormalize so the wanted
       * changes sum to zero (the Poisson problem is then consistent). */
      double s = k < o.schedule_steps ? 1.0 / (double)(o.schedule_steps - k) : 1.0;
      double sum_new = 0;
      for (int i = 0; i < nv; i++) {
        if (!t->vused[i]) {
          b[i] = 0;
          continue;
        }
        /* The ratio moves by rho^s, but never by more than a factor e^max_log_step in one step. */
        double lr = s * log(b[i] / AO[i]);
        if (lr > o.max_log_step) lr = o.max_log_step;
        if (lr < -o.max_log_step) lr = -o.max_log_step;
        b[i] = AO[i] * exp(lr);
        sum_new += b[i];
      }
      double renorm = SO / sum_new;
      for (int i = 0; i < nv; i++) b[i] = t->vused[i] ? (b[i] * renorm - AO[i]) : 0; /* b = dA */
      if (err < o.newton_below) {
        /* Polish: the exact Gauss-Newton step (au_gn.c), weights 1/(domain vertex area). */
        if (!gn) {
          st = au__gn_create(m, t, 0, &gn, msg);
          if (st != AU_OK) goto done;
        }
        for (int i = 0; i < nv; i++) g[i] = AO[i] > 0 ? 1.0 / AO[i] : 0;
        st = au__gn_step(gn, dom, P, g, b, 0, D, msg);
      } else {
        /* The paper's step: C g = -dA, move along the angle-weighted vertex gradient. */
        for (int i = 0; i < nv; i++) b[i] = -b[i];
        au_dec_cotan(t, F, P, w);
        if (!solver) st = au_solver_create(nv, t->ne, t->E, fixed, AU_ORDER_FILL, &solver, msg); /* analyzed once */
        if (st == AU_OK) st = au_solver_factor(solver, w, NULL, msg);
        if (st == AU_OK) {
          memset(g, 0, sizeof(double) * nv);
          st = au_solver_solve(solver, 1, b, g, msg);
        }
        if (st == AU_OK) {
          au_dec_face_grad(nf, F, P, g, Gf);
          st = au_dec_vertex_grad(nv, nf, F, P, Gf, D);
        }
        if (st == AU_OK)
          for (int i = 0; i < nv; i++) dom->constrain(dom->ctx, i, P + 3 * i, D + 3 * i);
      }
    }
    rep->t_solve += now_s() - t0;
    if (st != AU_OK) goto done;

    /* Local step control (see the banner): per-face safe fractions, then a Lipschitz envelope. */
    for (int f = 0; f < nf; f++) {
      const int *c = F + 3 * f;
      double per = 0;
      for (int e = 0; e < 3; e++) {
        const double *p = P + 3 * c[e], *q = P + 3 * c[(e + 1) % 3];
        per += sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
      }
      inr[f] = per > 0 ? 2.0 * af[f] / per : 0;
    }
    step_control(t, &adj, F, nf, nv, P, inr, D, o.max_move, dom, lim, heap, hpos, dn);
    double frac_sum = 0;
    int nused = 0;
    for (int i = 0; i < nv; i++) {
      if (!t->vused[i]) {
        lim[i] = 0;
        continue;
      }
      frac_sum += lim[i];
      nused++;
    }
    rep->frac[k] = nused ? frac_sum / nused : 0;
    memcpy(Pold, P, sizeof(double) * 3 * nv);
    for (int f = 0; f < nf; f++) orient_old[f] = face_orient(P, F, f, sph);
    for (int tries = 0;; tries++) {
      /* A vertex that does not move keeps its exact position: retracting it again could nudge a
       * nearly flat triangle across zero. */
      for (int i = 0; i < nv; i++) {
        double *p = P + 3 * i, *q = Pold + 3 * i, *d = D + 3 * i;
        if (lim[i] == 0) {
          p[0] = q[0], p[1] = q[1], p[2] = q[2];
          continue;
        }
        move_vertex(dom, q, d, lim[i], p);
        dom->retract(dom->ctx, i, p);
      }
      int nbad = 0;
      memset(bad, 0, (size_t)nv);
      for (int f = 0; f < nf; f++) {
        /* Orientation with a margin: a triangle must stay above AU_ORIENT_MARGIN, so that its sign
         * survives a re-normalization of the output by a reader (param-eval normalizes again) and the
         * rounding of other formulas for the same sign. One already below it (the tiny triangles of a
         * squeezed start) may shrink by at most half per step: comparing it with its old value
         * exactly would only compare rounding noise. */
        double o_new = face_orient(P, F, f, sph);
        if (o_new > AU_ORIENT_MARGIN || (o_new > 0 && o_new >= 0.5 * orient_old[f])) continue;
        nbad++;
        for (int e = 0; e < 3; e++) bad[F[3 * f + e]] = 1;
      }
      if (!nbad) break;
      /* Backtrack locally and smoothly: halve the fraction of the vertices of flipped triangles and
       * restore the Lipschitz envelope, so that the neighbours slow down with them (halving alone
       * would shear the triangles around them). After enough halvings they stay where they were;
       * a triangle whose corners all stay is unchanged, so every further round freezes at least one
       * more vertex and the loop ends. */
      for (int i = 0; i < nv; i++)
        if (bad[i]) lim[i] = tries < 30 ? 0.5 * lim[i] : 0;
      envelope(t, &adj, nv, inr, D, o.max_move, lim, heap, hpos, dn);
    }
  }
  rep->steps = k;
  /* Converged means the vertex error met the tolerance, however the loop ended (the step budget can
   * run out while the per-face refinement is still going). */
  rep->converged = rep->err[k] <= o.tol;
  if (!rep->converged) st = AU_W_NOT_CONVERGED;
  if (st == AU_W_NOT_CONVERGED)
    au_msg_set(msg, st, "area error %.3g after %d steps (tolerance %.3g)", rep->err[k], k, o.tol);

done:
  au_solver_free(&solver);
  au__gn_free(&gn);
  free(AM), free(AO), free(b), free(g), free(dn), free(lim), free(af), free(Gf), free(D), free(Pold), free(w), free(fixed), free(bad);
  free(heap), free(hpos), free(inr), free(As), free(fw), free(dA_f), free(orient_old);
  au__gn_free(&gnf);
  au__ang_free(&ang);
  adjacency_free(&adj);
  return st;
}

/* Below this many vertices the mesh is worked on in its own order. */
#define AU_REORDER_MIN 4096

/* The domain's callbacks, called with the caller's vertex numbers. */
typedef struct reordered_domain {
  const au_advect_domain *dom;
  const int *orig; /* orig[i]: the caller's number of vertex i of the reordered mesh */
} reordered_domain;

static void reordered_constrain(void *ctx, int i, const double *p, double *d) {
  const reordered_domain *r = ctx;
  r->dom->constrain(r->dom->ctx, r->orig[i], p, d);
}

static void reordered_retract(void *ctx, int i, double *p) {
  const reordered_domain *r = ctx;
  r->dom->retract(r->dom->ctx, r->orig[i], p);
}

/* Spread the low 10 bits of x to every third bit. */
static unsigned long long spread3(unsigned long long x) {
  x &= 0x3ff;
  x = (x | (x << 16)) & 0x30000ffULL;
  x = (x | (x << 8)) & 0x300f00fULL;
  x = (x | (x << 4)) & 0x30c30c3ULL;
  x = (x | (x << 2)) & 0x9249249ULL;
  return x;
}

typedef struct morton_key {
  unsigned long long code;
  double x, y, z; /* ties (vertices in one cell) go by position, so the order depends on the mesh, not its numbering */
  int i;
} morton_key;

static int cmp_morton(const void *a, const void *b) {
  const morton_key *p = a, *q = b;
  if (p->code != q->code) return p->code < q->code ? -1 : 1;
  if (p->x != q->x) return p->x < q->x ? -1 : 1;
  if (p->y != q->y) return p->y < q->y ? -1 : 1;
  if (p->z != q->z) return p->z < q->z ? -1 : 1;
  return (p->i > q->i) - (p->i < q->i);
}

/* The smallest new number among face v's corners. */
static int first_corner(const int *inv, const int *v) {
  int a = inv[v[0]], b = inv[v[1]], c = inv[v[2]];
  return a < b ? (a < c ? a : c) : (b < c ? b : c);
}

/* A cache-friendly order of m: vertices along a Morton (Z-order) curve through their surface
 * positions, faces by their first vertex in that order. orig [0..nv-1]: the caller's number of each new
 * vertex, inv [0..nv-1] its inverse; forig [0..nf-1]: the caller's number of each new face.
 * Returns 0 when out of memory. */
static int locality_order(const au_mesh *m, int *orig, int *inv, int *forig) {
  const int nv = m->nv, nf = m->nf;
  morton_key *key = malloc(sizeof(morton_key) * (size_t)nv);
  int *count = calloc((size_t)nv + 1, sizeof(int));
  if (!key || !count) {
    free(key), free(count);
    return 0;
  }
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int i = 0; i < nv; i++)
    for (int d = 0; d < 3; d++) lo[d] = fmin(lo[d], m->X[3 * i + d]), hi[d] = fmax(hi[d], m->X[3 * i + d]);
  double ext = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
  double sc = ext > 0 ? 1023.0 / ext : 0;
  for (int i = 0; i < nv; i++) {
    unsigned long long c = 0;
    for (int d = 0; d < 3; d++) c |= spread3((unsigned long long)((m->X[3 * i + d] - lo[d]) * sc)) << d;
    key[i] = (morton_key){c, m->X[3 * i], m->X[3 * i + 1], m->X[3 * i + 2], i};
  }
  qsort(key, (size_t)nv, sizeof(morton_key), cmp_morton);
  for (int k = 0; k < nv; k++) orig[k] = key[k].i, inv[orig[k]] = k;
  /* Faces by their smallest new vertex number (a counting sort keeps it stable). */
  for (int f = 0; f < nf; f++) count[first_corner(inv, m->F + 3 * f) + 1]++;
  for (int k = 0; k < nv; k++) count[k + 1] += count[k];
  for (int f = 0; f < nf; f++) forig[count[first_corner(inv, m->F + 3 * f)]++] = f;
  free(key), free(count);
  return 1;
}

/* What a flow needs that depends only on the mesh's connectivity (and positions, for the order):
 * the cache-friendly copy of a large mesh and the least-shear system's analysis. */
struct au_advect_plan {
  const au_mesh *m; /* the caller's mesh and topology */
  const au_topo *t;
  /* Meshes of AU_REORDER_MIN vertices or more: the copy in locality order (else NULL). */
  au_mesh *m2;
  au_topo *t2;
  int *orig, *inv, *forig;
  au_lm *lm; /* the least-shear system of the mesh the flow runs on, or NULL until needed */
  /* au_advect_plan_start: the thread preparing the plan and what it reports. */
  pthread_t thread;
  int running;
  sigset_t caller_mask;
  au_status st;
  au_msg msg;
};

/* Wait for the plan's thread, if it runs, and give the calling thread its SIGTERM back (one that came
 * meanwhile arrives now). */
static void plan_join(au_advect_plan *p) {
  if (!p->running) return;
  pthread_join(p->thread, NULL);
  p->running = 0;
  pthread_sigmask(SIG_SETMASK, &p->caller_mask, NULL);
}

void au_advect_plan_free(au_advect_plan **pp) {
  if (!pp || !*pp) return;
  au_advect_plan *p = *pp;
  plan_join(p);
  au_topo_free(&p->t2);
  au_mesh_free(&p->m2);
  free(p->orig), free(p->inv), free(p->forig);
  au__lm_free(&p->lm);
  free(p);
  *pp = NULL;
}

/* Fill the plan: the reordered copy, then (least-shear method) the system's analysis. */
static au_status plan_fill(au_advect_plan *p, int least_shear, au_msg *msg) {
  const au_mesh *m = p->m;
  const int nv = m->nv, nf = m->nf;
  if (nv >= AU_REORDER_MIN) {
    /* Large meshes are worked on in a cache-friendly copy: the step's assembly and the area and step
     * control loops read each face's corners, and in a mesh stored in scan order those reads miss the
     * cache (measured: lion_statue's flow 5.1-5.5 s in its own order, 4.0-4.3 s along a Morton curve). */
    p->orig = malloc(sizeof(int) * (size_t)nv), p->forig = malloc(sizeof(int) * (size_t)nf);
    p->inv = malloc(sizeof(int) * (size_t)nv);
    if (!p->orig || !p->forig || !p->inv || au_mesh_alloc(nv, nf, &p->m2) != AU_OK || !locality_order(m, p->orig, p->inv, p->forig))
      return au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
    for (int k = 0; k < nv; k++) memcpy(p->m2->X + 3 * k, m->X + 3 * p->orig[k], 3 * sizeof(double));
    for (int f = 0; f < nf; f++)
      for (int c = 0; c < 3; c++) p->m2->F[3 * f + c] = p->inv[m->F[3 * p->forig[f] + c]];
    au_status st = au_mesh_topology(p->m2, &p->t2, msg);
    if (st != AU_OK) return st;
  }
  if (!least_shear) return AU_OK;
  return au__lm_create(p->m2 ? p->m2 : p->m, p->t2 ? p->t2 : p->t, &p->lm, msg);
}

/* An empty plan for m and t, after checking the arguments (*out is set to NULL first). */
static au_status plan_new(const au_mesh *m, const au_topo *t, au_advect_plan **out, au_advect_plan **pp, au_msg *msg) {
  if (!out) return au_msg_set(msg, AU_E_ARG, "advect: bad arguments");
  *out = NULL;
  if (!m || !t || m->nv <= 0 || m->nf <= 0 || t->nv != m->nv) return au_msg_set(msg, AU_E_ARG, "advect: bad arguments");
  au_advect_plan *p = calloc(1, sizeof *p);
  if (!p) return au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
  p->m = m, p->t = t;
  *pp = p;
  return AU_OK;
}

au_status au_advect_plan_create(const au_mesh *m, const au_topo *t, const au_advect_opts *opts, au_advect_plan **out,
                                au_msg *msg) {
  au_advect_plan *p = NULL;
  au_status st = plan_new(m, t, out, &p, msg);
  if (st != AU_OK) return st;
  au_advect_opts o = opts ? *opts : au_advect_opts_default();
  st = plan_fill(p, o.method == AU_ADVECT_LEAST_SHEAR, msg);
  if (st != AU_OK) {
    au_advect_plan_free(&p);
    return st;
  }
  *out = p;
  return AU_OK;
}

static void *plan_thread(void *arg) {
  au_advect_plan *p = arg;
  p->st = plan_fill(p, 1, &p->msg);
  return NULL;
}

au_status au_advect_plan_start(const au_mesh *m, const au_topo *t, const au_advect_opts *opts, au_advect_plan **out,
                               au_msg *msg) {
  au_advect_opts o = opts ? *opts : au_advect_opts_default();
  /* Small meshes, or another method: no thread is worth it. */
  if (!m || m->nv < AU_REORDER_MIN || o.method != AU_ADVECT_LEAST_SHEAR) return au_advect_plan_create(m, t, opts, out, msg);
  au_advect_plan *p = NULL;
  au_status st = plan_new(m, t, out, &p, msg);
  if (st != AU_OK) return st;
  /* The ordering (METIS, through GKlib) traps SIGTERM for its length and jumps back into itself from
   * the handler: delivered to this thread, that jump would cross threads. So this thread holds SIGTERM
   * back until the plan is done (au_advect_plan_wait); the new thread inherits the mask. */
  sigset_t term;
  sigemptyset(&term);
  sigaddset(&term, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &term, &p->caller_mask);
  if (pthread_create(&p->thread, NULL, plan_thread, p) != 0) {
    pthread_sigmask(SIG_SETMASK, &p->caller_mask, NULL);
    st = plan_fill(p, 1, msg); /* no thread: prepare it here */
    if (st != AU_OK) {
      au_advect_plan_free(&p);
      return st;
    }
  } else {
    p->running = 1;
  }
  *out = p;
  return AU_OK;
}

au_status au_advect_plan_wait(au_advect_plan *p, au_msg *msg) {
  if (!p) return au_msg_set(msg, AU_E_ARG, "advect: bad arguments");
  if (!p->running) return AU_OK;
  plan_join(p);
  if (p->st != AU_OK) {
    if (msg) *msg = p->msg;
    return p->st;
  }
  return AU_OK;
}

au_status au_advect_run(const au_mesh *m, const au_topo *t, const au_advect_domain *dom, const au_advect_opts *opts,
                        double *P, au_advect_report *rep, au_msg *msg) {
  au_advect_plan *plan = NULL;
  au_status st = au_advect_plan_create(m, t, opts, &plan, msg);
  if (st == AU_OK) st = au_advect_run_plan(plan, dom, opts, P, rep, msg);
  au_advect_plan_free(&plan);
  return st;
}

au_status au_advect_run_plan(au_advect_plan *plan, const au_advect_domain *dom, const au_advect_opts *opts, double *P,
                             au_advect_report *rep, au_msg *msg) {
  if (!plan) return au_msg_set(msg, AU_E_ARG, "advect: bad arguments");
  au_status st = au_advect_plan_wait(plan, msg);
  if (st != AU_OK) return st;
  const au_mesh *m = plan->m;
  const au_topo *t = plan->t;
  if (!dom || !dom->constrain || !dom->retract || !P)
    return au_msg_set(msg, AU_E_ARG, "advect: bad arguments");
  au_advect_opts o = opts ? *opts : au_advect_opts_default();
  if (o.max_steps < 0 || o.max_steps > AU_ADVECT_MAX_STEPS || o.schedule_steps < 1 || !(o.max_move > 0 && o.max_move < 0.5) ||
      !(o.tol >= 0) || !(o.face_gain >= 0 && o.face_gain < 1) || !(o.restore >= 0 && o.restore <= 1) || !(o.lantern >= 0) ||
      o.angle_steps < 0 || !(o.angle_faces >= 0) || !(o.angle_cells >= 0) || !(o.angle_trust > 0) || !(o.angle_switch >= 0) ||
      !(o.polish_gap >= 0) || !(o.resolved_jump >= 0) || !(o.resolved_decay > 0 && o.resolved_decay <= 1) || !(o.resolved_shear >= 0) || !(o.face_shear_tail >= 0) ||
      !(o.resolved_log_step > 0))
    return au_msg_set(msg, AU_E_ARG, "advect: options out of range");
  if (o.weight && o.face_weight) return au_msg_set(msg, AU_E_ARG, "advect: give a per-vertex or a per-face density, not both");
  for (int f = 0; f < m->nf && o.face_weight; f++)
    if (!(o.face_weight[f] > 0 && o.face_weight[f] < INFINITY))
      return au_msg_set(msg, AU_E_DENSITY, "density of face %d is %g; it must be positive and finite", f, o.face_weight[f]);
  for (int i = 0; i < m->nv && o.weight; i++)
    if (t->vused[i] && !(o.weight[i] > 0 && o.weight[i] < INFINITY))
      return au_msg_set(msg, AU_E_DENSITY, "density of vertex %d is %g; it must be positive and finite", i, o.weight[i]);
  au_advect_report local_rep;
  if (!rep) rep = &local_rep;
  if (!plan->m2) return advect_core(m, t, dom, &o, &plan->lm, P, rep, msg);

  /* The flow runs on the plan's reordered copy; positions and densities go over and back. */
  const int nv = m->nv, nf = m->nf;
  const int *orig = plan->orig, *forig = plan->forig;
  double *P2 = malloc(sizeof(double) * 3 * (size_t)nv);
  double *w2 = o.weight ? malloc(sizeof(double) * (size_t)nv) : NULL, *fw2 = o.face_weight ? malloc(sizeof(double) * (size_t)nf) : NULL;
  st = AU_OK;
  if (!P2 || (o.weight && !w2) || (o.face_weight && !fw2)) {
    st = au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
    goto done;
  }
  for (int k = 0; k < nv; k++) {
    memcpy(P2 + 3 * k, P + 3 * orig[k], 3 * sizeof(double));
    if (w2) w2[k] = o.weight[orig[k]];
  }
  for (int f = 0; f < nf && fw2; f++) fw2[f] = o.face_weight[forig[f]];
  reordered_domain rd = {dom, orig};
  au_advect_domain dom2 = {reordered_constrain, reordered_retract, dom->spherical, &rd, dom->arc_radius};
  o.weight = w2, o.face_weight = fw2;
  st = advect_core(plan->m2, plan->t2, &dom2, &o, &plan->lm, P2, rep, msg);
  for (int k = 0; k < nv; k++) memcpy(P + 3 * orig[k], P2 + 3 * k, 3 * sizeof(double));
done:
  free(P2), free(w2), free(fw2);
  return st;
}
