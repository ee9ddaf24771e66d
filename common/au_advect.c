/* au_advect.c - the Lie-advection loop (Zou, Hu, Gu & Hua 2011, sec. 4.2-4.4, eq. 19-20) with local
 * step control, run as a machine of phases (see "the flow as a phase machine" below).
 *
 * Each step asks every face (least-shear method, au_lm.c) or vertex cell (the paper's Poisson method:
 * C g = -dA on the current domain mesh, C the cotan stiffness with one vertex pinned, so the flux of
 * grad g out of cell i is dA_i) for a share of its remaining area excess, solves for a displacement,
 * moves the vertices and puts them back on the domain. Two departures from the paper keep the flow
 * fold-free on hard meshes:
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
 * real (retracted) path at the step control's fraction (see step_control): as little as keeps its sign
 * safe, since the backtracking after the move catches the rest and more holds the boundary back. */
#define AU_BOUNDARY_KEEP 0.02

/* The least-shear step weighs a face by its target area, but by at most this many times its current
 * area (a face squeezed by e^-20 would otherwise make the system singular in double precision). Not
 * much less either: the energy is an integral, so a face weighed by its own tiny area is free to be
 * sheared, and the step control then holds its whole neighbourhood back (docs/flow.md). */
#define AU_WEIGHT_CAP 1e6

/* The shape restoring (au_advect_opts.restore) acts in full while the vertex error is above this and
 * fades in proportion below it: at full strength to the end it keeps the areas from converging. */
#define AU_RESTORE_FADE 0.1

/* The chord polish, vertex cells above the tolerance: it ends when four steps gained less than this
 * fraction of both the vertex and the per-face error (least_shear_stalled). Lower, a polish that
 * gains almost nothing runs on to the step budget. */
#define AU_POLISH_GAIN 0.05

/* With au_advect_opts.polish_steps set, the chord polish ends after those steps while its vertex error
 * is above AU_POLISH_CUT_ABOVE x tol and below AU_POLISH_CUT_BELOW: after its first
 * steps the chord polish gains 1-3% a factorization where the vertex polish after it gains 3x in a few
 * sweeps (docs/chord-polish.md). Closer to tol it goes on, and may reach it (spot: 0.0026 after two
 * steps, 0.0019 after eleven, with no polish after). Further off, the map is still far from its areas
 * and the "polish" is the flow's main work: limbs4 with a density of 0.05 on half its faces runs it at
 * vertex errors of 2.3 and more, and cut there it kept triangles too small to tell from folds. */
#define AU_POLISH_CUT_ABOVE 1.5
#define AU_POLISH_CUT_BELOW 0.1

/* Kinetic-energy weight of the least-shear step: only fixes the rigid rotations, which change neither
 * areas nor angles. */
#define AU_ROTATION_EPS 1e-6

/* The stiffest shear weight an undone step is retried with: stiffer, the step barely moves and the
 * system's last pivots lose their sign in double precision. */
#define AU_SHEAR_MAX 1e4

/* A relative slack for "no worse": an error that equals the last one up to rounding counts as equal. */
#define AU_SAME_REL 1e-9

/* An undone least-shear step is retried with the shear weight this many times stiffer. */
#define AU_SHEAR_UNDO_FACTOR 4

/* An accepted least-shear step halves the shear weight (Levenberg-Marquardt style), down to its floor. */
#define AU_SHEAR_DECAY 0.5

/* A least-shear system that rounding made indefinite is retried this many times stiffer, up to
 * AU_SHEAR_SPD_MAX: the shear term is definite but for the rotations, so enough of it restores
 * definiteness, and beyond that weight the step would barely move anything. */
#define AU_SHEAR_SPD_FACTOR 16
#define AU_SHEAR_SPD_MAX 1e6

/* The stall test compares each error with its value this many steps back: single steps are noisy
 * (an accepted step may gain nothing while the shear weight drops). */
#define AU_STALL_WINDOW 4

/* Stalled: neither error fell below this fraction of its value AU_STALL_WINDOW steps back (a 2% gain). */
#define AU_STALL_KEEP 0.98

/* In the polish with the vertex cells within tol, a single step must gain this share of face_gain:
 * the polish converges geometrically, so one step tells. */
#define AU_POLISH_STEP_SHARE 0.25

/* The spherical part may use this share of the budget (2/3): the rest is left for the chord polish. */
#define AU_SPHERICAL_BUDGET_NUM 2
#define AU_SPHERICAL_BUDGET_DEN 3

/* The angle steps take over (angle_switch) once the per-face error is also within this many times the
 * switch: earlier, the faces' areas were left further off at the end. */
#define AU_ANGLE_SWITCH_FACES 2

/* The lantern's raised shape restoring acts only once the vertex error is below this: before that the
 * whole map is still far from its areas and the long edges are not yet the obstacle. */
#define AU_LANTERN_BELOW 1

/* Below this |c2| the orientation along a move is taken as linear in t (the quadratic formula would
 * divide by it); any real triangle's c2 is far above it. */
#define AU_QUADRATIC_TINY 1e-300

/* The step control lets a triangle shrink to this fraction of its orientation in one step, no further:
 * a quarter leaves room for the envelope's differences between neighbours and for the curvature of the
 * sphere's retraction, and still lets a triangle shrink by a large factor per step. */
#define AU_FACE_KEEP 0.25

/* How often the step control halves a boundary triangle's fraction on its corners' real paths
 * (2^-12 of the step): past that the backtracking after the move takes over. */
#define AU_BOUNDARY_HALVINGS 12

/* Backtracking rounds in which a flipped triangle's corners halve their fractions; after that they
 * stay where they were (a triangle whose corners all stay cannot flip), so the loop ends. */
#define AU_BACKTRACK_HALVINGS 30

/* A triangle already below AU_ORIENT_MARGIN may shrink by at most this factor per step. */
#define AU_ORIENT_SHRINK 0.5

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
  /* bunny 9 steps and 10 factorizations instead of 10 and 11; maxplanck, ferret_brain_sim, lion_statue, brain
   * one step fewer, armadillo 9 fewer (41 -> 32); within 5% of their per-face and vertex errors but brain's vertex (0.0011 ->
   * 0.0015) and penguin_hr (docs/flow-tail.md). */
  o.sphere_resolved_schedule_steps = 3;
  o.sphere_resolved_log_step = 2.5;
  o.sphere_resolved_shear_tail = 0.007;
  /* Restoring aims each face back at the surface's shape by a fixed fraction of the linear motion, which
   * on a start whose triangles are already sheared asks for moves of several triangle sizes: the step
   * control cut bunny's first step from the coarse-to-fine start to 1.4%, and every other restoring step
   * was undone (docs/coarse-to-fine-flow.md). */
  o.restore_gate = 1;
  return o;
}

void au_advect_plain_schedule(au_advect_opts *o) {
  o->sphere_resolved_schedule_steps = o->schedule_steps;
  o->sphere_resolved_log_step = o->resolved_log_step;
  o->sphere_resolved_shear_tail = o->shear_tail;
}

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Orientation of face f at positions P: spherical domains use the triple product, planar ones the
 * z component of the cross product. Positive means correctly oriented. */
static double face_orient(const double *P, const int *F, const double *shift, int f, int spherical) {
  double qa[3], qb[3], qc[3];
  const double *a = au__corner(P, F, shift, f, 0, qa), *b = au__corner(P, F, shift, f, 1, qb), *c = au__corner(P, F, shift, f, 2, qc);
  if (spherical) return au_dec_sphere_orient(a, b, c);
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* The faces' areas at P, of the shifted corners where the domain has shifts (au_advect_domain.shift):
 * each face's corners are gathered and measured by the same formula. */
static void face_areas(int nf, const int *F, const double *P, const double *shift, double *af) {
  if (!shift) {
    au_dec_face_areas(nf, F, P, af);
    return;
  }
  static const int tri[3] = {0, 1, 2};
  for (int f = 0; f < nf; f++) {
    double q[9];
    for (int k = 0; k < 3; k++) au__corner(P, F, shift, f, k, q + 3 * k);
    au_dec_face_areas(1, tri, q, af + f);
  }
}

/* Number of faces with orientation <= 0. */
static int count_folds(const double *P, const int *F, const double *shift, int nf, int spherical) {
  int n = 0;
  for (int f = 0; f < nf; f++) n += face_orient(P, F, shift, f, spherical) <= 0;
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
 * small sideways move turns it over. */
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
  if (fabs(c2) < AU_QUADRATIC_TINY) {
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
 *    and takes in a vertex when it is lowered: the work follows the restricted vertices, not the mesh.
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
 * with a short boundary needs such triangles (aspect 30-50), and the step control held the whole mesh
 * back for them. At the disk's centre the bend goes to zero: full arcs there (a turn by s/r) cost many
 * steps, since a small move near the centre turns by a large angle (docs/flow.md). */
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
  const double *shift = dom->shift;
  for (int i = 0; i < nv; i++) s[i] = 1;
  for (int f = 0; f < nf; f++) {
    const int *v = F + 3 * f;
    double qa[3], qb[3], qc[3];
    const double *a = au__corner(P, F, shift, f, 0, qa), *b = au__corner(P, F, shift, f, 1, qb),
                 *cc = au__corner(P, F, shift, f, 2, qc);
    double tf = face_safe_t(a, b, cc, D + 3 * v[0], D + 3 * v[1], D + 3 * v[2], AU_FACE_KEEP, spherical);
    if (!spherical) {
      /* The fraction above is exact for straight moves; a boundary vertex slides along its curve
       * (retract), off the straight line, and turned the thin triangles at the boundary over after
       * the step (they were the ones the backtracking in take_step had to mend, several rounds a
       * step). So the fraction is checked on the corners' real paths (move_vertex, then retract) and
       * halved until the triangle keeps AU_BOUNDARY_KEEP of its orientation. Asking for more than
       * the backtracking does holds the boundary back. Interior triangles away from the boundary pass
       * (the final orientation check covers them). */
      double o0 = (b[0] - a[0]) * (cc[1] - a[1]) - (b[1] - a[1]) * (cc[0] - a[0]);
      for (int h = 0; h < AU_BOUNDARY_HALVINGS && o0 > 0; h++) {
        double q[3][3];
        for (int k = 0; k < 3; k++) {
          move_vertex(dom, P + 3 * v[k], D + 3 * v[k], tf, q[k]);
          dom->retract(dom->ctx, v[k], q[k]);
          /* The corner's own translation (a flat torus's faces across the seams). */
          for (int d = 0; shift && d < 3; d++) q[k][d] += shift[9 * (size_t)f + 3 * k + d];
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
  au_dec_face_areas(nf, F, P, af); /* the sphere's polish only: no shifts */
  au_dec_vertex_areas(nv, nf, F, P, af, AO);
  double SC = 0, e = 0, v = 0;
  int n = 0;
  for (int f = 0; f < nf; f++) SC += af[f];
  for (int f = 0; f < nf; f++) e += fabs(af[f] / (As[f] * fw[f] * SC / SM) - 1);
  for (int i = 0; i < nv; i++)
    if (used[i]) v += fabs(log(AM[i] * SC / SM / AO[i])), n++;
  *ferr = e / nf, *verr = n ? v / n : 0;
}

/* ---------------------------------------------------------------- the flow as a phase machine
 *
 * The flow is a sequence of phases. Each round of the loop measures the current map (in the terms of
 * the current phase), asks the phase whether to step, and if so solves for a displacement and moves
 * the vertices under the step control. A phase's decision is one of four verdicts: take a step; stop;
 * measure this map again at the same step number (the phase has changed, and with it the terms the map
 * is measured in); or redo the previous step (the last step made the map worse: it is undone, and the
 * map before it is measured again at its own step number, so an undone step leaves no trace in the
 * report but its count in au_advect_report.undone).
 *
 * The phases, with the rules by which the flow enters and leaves each, are the table flow_phases below.
 * Every phase but the angle steps also ends when the budget (max_steps solves, undone ones included)
 * is spent: to the angle steps if there are any, else the end (check_budget). */

/* The phases; flow_phases gives each one's entry and exit rules. */
typedef enum flow_phase { FLOW_CELLS, FLOW_FACES, FLOW_SPHERICAL, FLOW_CHORD, FLOW_POLISH, FLOW_ANGLES } flow_phase;

/* What a phase decides after measuring the map. */
typedef enum flow_verdict {
  FLOW_STEP,      /* solve and move, then the next step number */
  FLOW_STOP,      /* the flow ends at this step number */
  FLOW_REMEASURE, /* the phase changed (or its part ended): measure this map again, same step number */
  FLOW_REDO       /* the last step was undone: measure the map before it again, at its step number */
} flow_verdict;

/* What a phase's solve produced. */
typedef enum flow_solved {
  SOLVED_MOVE,     /* D holds a displacement: move along it under the step control */
  SOLVED_NEXT,     /* nothing moved; the next step number measures the same map (a stiffer retry) */
  SOLVED_REMEASURE /* nothing moved; this part of the flow is exhausted: measure again, same step */
} flow_solved;

/* Everything the flow carries from step to step. Arrays: nv- or nf-sized scratch unless noted. */
typedef struct flow_state {
  const au_mesh *m;
  const au_topo *t;
  const au_advect_domain *dom;
  const au_advect_opts *o;
  au_advect_report *rep;
  au_msg *msg;
  int nv, nf;
  const int *F;
  int sph; /* spherical domain */
  int ls;  /* least-shear method */
  /* targets, fixed for the run */
  double *As;  /* [nf] the surface's triangle areas */
  double *fw;  /* [nf] the faces' densities */
  double *AM;  /* [nv] the vertex cells' targets: a third of each face's As * fw */
  double SM;   /* sum of AM */
  /* the current map's measure (measure_map) */
  double *af;  /* [nf] the domain's face areas (spherical in the spherical phase, else chord) */
  double *AO;  /* [nv] the domain's vertex cells */
  double *b;   /* [nv] the cells' targets in the domain's total, then the Poisson step's right side */
  double SO, scale; /* the domain's total area, and SO / SM */
  double err, ferr, flog; /* vertex mean |ln ratio|, per-face mean |r - 1| and mean |ln r| */
  /* the step */
  double *D;    /* [3nv] displacement */
  double *Pold; /* [3nv] the map before the last step (what an undo goes back to) */
  double *P;    /* [3nv] the map, in/out */
  double *g, *Gf, *dA_f, *w; /* solve scratch: [nv], [3nf], [nf], [ne] */
  double *lim, *dn, *inr, *orient_old; /* step control: fractions [nv], |D_i| [nv], inradii [nf], [nf] */
  unsigned char *fixed, *bad;          /* [nv] the Poisson solve's pinned vertices; flipped corners */
  int *heap, *hpos;                    /* [nv] the envelope's heap */
  adjacency adj;
  /* solvers, made when first needed (lm: the plan's) */
  au_solver *solver;
  au_gn *gn, *gnf;
  au_ang *ang;
  au_lm **lmp;
  /* the machine */
  flow_phase phase;
  int k;            /* step number */
  int phase_start;  /* the first step of the current least-shear part (stall tests compare like with like) */
  double alpha;     /* the least-shear step's shear weight */
  double prev_err, prev_ferr, prev_flog; /* the last measure that led to a step */
  int retry;        /* the next least-shear solve retries an undone step */
  int restored;     /* the last least-shear solve had shape restoring */
  int restore_off;  /* shape restoring is off for the rest of this run (see solve_least_shear) */
  int near_start;   /* the start is near equal area and already sheared (see start_shear) */
  int measured_jump;/* rep->start_jump has been measured */
  int exhausted;    /* no stiffer step is worth a try: this part of the flow ends */
  int ang_left;     /* angle steps that remain */
  double ang_prev;  /* the vertex error before the last angle step */
  int face_steps;   /* per-face refinement steps taken (Poisson method) */
} flow_state;

/* What the rest of a flow reads at the start of a round, besides what measure_map recomputes from P:
 * the machine's fields of flow_state, the report so far and the map. (Not the map before the last step:
 * the recorded round went on to its solve, so it undid nothing, and the resumed round decides the same.) */
struct au_advect_fork {
  int ready;          /* recorded at the round where a lantern would first act; no more recording */
  const au_mesh *m;   /* the mesh the recording flow ran on (the plan's, reordered or not) */
  int nv;
  double *P;
  au_advect_report rep;
  flow_phase phase;
  int k, phase_start, retry, restored, restore_off, near_start, measured_jump, exhausted, ang_left, face_steps;
  double alpha, prev_err, prev_ferr, prev_flog, ang_prev;
};

static void flow_state_free(flow_state *s) {
  au_solver_free(&s->solver);
  au__gn_free(&s->gn);
  au__gn_free(&s->gnf);
  au__ang_free(&s->ang);
  free(s->AM), free(s->AO), free(s->b), free(s->g), free(s->dn), free(s->lim), free(s->af), free(s->Gf), free(s->D);
  free(s->Pold), free(s->w), free(s->fixed), free(s->bad), free(s->heap), free(s->hpos), free(s->inr), free(s->As);
  free(s->fw), free(s->dA_f), free(s->orient_old);
  adjacency_free(&s->adj);
}

/* The scratch arrays; 0 when out of memory (what was allocated is freed by flow_state_free). */
static int flow_state_alloc(flow_state *s) {
  const size_t nv = (size_t)s->nv, nf = (size_t)s->nf, ne = (size_t)(s->t->ne > 0 ? s->t->ne : 1);
  s->AM = malloc(sizeof(double) * nv), s->AO = malloc(sizeof(double) * nv), s->b = malloc(sizeof(double) * nv);
  s->g = malloc(sizeof(double) * nv), s->lim = malloc(sizeof(double) * nv), s->af = malloc(sizeof(double) * nf);
  s->dn = malloc(sizeof(double) * nv);
  s->Gf = malloc(sizeof(double) * 3 * nf), s->D = malloc(sizeof(double) * 3 * nv);
  s->Pold = malloc(sizeof(double) * 3 * nv), s->w = malloc(sizeof(double) * ne);
  s->fixed = calloc(nv, 1), s->bad = calloc(nv, 1);
  s->heap = malloc(sizeof(int) * nv), s->hpos = malloc(sizeof(int) * nv);
  s->inr = malloc(sizeof(double) * nf), s->As = malloc(sizeof(double) * nf), s->fw = malloc(sizeof(double) * nf);
  s->dA_f = malloc(sizeof(double) * nf), s->orient_old = malloc(sizeof(double) * nf);
  return s->AM && s->AO && s->b && s->g && s->dn && s->lim && s->af && s->Gf && s->D && s->Pold && s->w && s->fixed &&
         s->bad && s->heap && s->hpos && s->inr && s->As && s->fw && s->dA_f && s->orient_old &&
         adjacency_build(s->t, &s->adj);
}

/* The targets: the surface's triangle areas times the density (per face: the face's own, or the mean of
 * its corners'), and the vertex cells' targets. Returns AU_OK or AU_E_ARG (no area). */
static au_status flow_targets(flow_state *s) {
  const au_advect_opts *o = s->o;
  const int nv = s->nv, nf = s->nf, *F = s->F;
  double *As = s->As, *fw = s->fw, *AM = s->AM;
  au_dec_face_areas(nf, F, s->m->X, As);
  for (int f = 0; f < nf; f++)
    fw[f] = o->face_weight ? o->face_weight[f]
            : o->weight    ? (o->weight[F[3 * f]] + o->weight[F[3 * f + 1]] + o->weight[F[3 * f + 2]]) / 3.0
                           : 1.0;
  /* A vertex cell's target is a third of each of its faces' targets, with a per-vertex density too:
   * the flow drives the faces, and vertex targets of their own (area times the vertex's density)
   * disagree with the faces' where the density jumps, which left the vertex error far off on a sphere
   * with density 4 on one half. */
  memset(AM, 0, sizeof(double) * nv);
  for (int f = 0; f < nf; f++)
    for (int k = 0; k < 3; k++) AM[F[3 * f + k]] += As[f] * fw[f] / 3.0;
  double SM = 0;
  for (int i = 0; i < nv; i++) SM += AM[i];
  s->SM = SM;
  if (!(SM > 0)) return au_msg_set(s->msg, AU_E_ARG, "advect: the surface has no area");
  return AU_OK;
}

/* The start's shear: the mean over faces of ln(sigma1 / sigma2), the singular values of the linear map
 * from the surface triangle to the domain's chord triangle (param-eval's Lambda). */
static double start_shear(const flow_state *s) {
  const double *X = s->m->X, *P = s->P;
  double sum = 0;
  int n = 0;
  for (int f = 0; f < s->nf; f++) {
    const int *v = s->F + 3 * f;
    double fr[2][2][2]; /* [surface, domain][edge][x, y] in each triangle's own frame */
    int ok = 1;
    for (int q = 0; q < 2 && ok; q++) {
      double buf[3][3];
      const double *c[3];
      for (int k = 0; k < 3; k++) c[k] = q == 0 ? X + 3 * v[k] : au__corner(P, s->F, s->dom->shift, f, k, buf[k]);
      double e1[3] = {c[1][0] - c[0][0], c[1][1] - c[0][1], c[1][2] - c[0][2]};
      double e2[3] = {c[2][0] - c[0][0], c[2][1] - c[0][1], c[2][2] - c[0][2]};
      double l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
      double x2 = l1 > 0 ? (e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]) / l1 : 0;
      double cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      double y2 = l1 > 0 ? sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]) / l1 : 0;
      if (!(l1 > 0) || !(y2 > 0)) ok = 0;
      fr[q][0][0] = l1, fr[q][0][1] = 0, fr[q][1][0] = x2, fr[q][1][1] = y2;
    }
    if (!ok) continue;
    /* J = Dm Sm^-1 with Sm = [s1 s2] (columns the surface's edges), Dm likewise. */
    double s11 = fr[0][0][0], s12 = fr[0][1][0], s22 = fr[0][1][1];
    double d11 = fr[1][0][0], d12 = fr[1][1][0], d22 = fr[1][1][1];
    double J11 = d11 / s11, J12 = (d12 - J11 * s12) / s22, J21 = 0, J22 = d22 / s22;
    double cf = hypot(J11 + J22, J21 - J12), an = hypot(J11 - J22, J12 + J21);
    if (!(cf > an)) continue;
    sum += log((cf + an) / (cf - an)), n++;
  }
  return n ? sum / n : 0;
}

/* The start's resolution, measured once: the mean jump of log r between the two faces of each interior
 * edge. Where it is small the wanted correction is smooth at the mesh's scale, and the flow can drop
 * the shear weight faster and let faces grow more per step (au_advect_opts.resolved_jump). */
static void measure_start_jump(flow_state *s) {
  const au_topo *t = s->t;
  const au_advect_opts *o = s->o;
  const double *af = s->af, *As = s->As, *fw = s->fw;
  double sj = 0;
  int nj = 0;
  for (int e = 0; e < t->ne; e++) {
    int f0 = t->EF[2 * e], f1 = t->EF[2 * e + 1];
    if (f0 < 0 || f1 < 0) continue;
    double r0 = af[f0] / (As[f0] * fw[f0]), r1 = af[f1] / (As[f1] * fw[f1]);
    if (r0 > 0 && r1 > 0) sj += fabs(log(r0 / r1)), nj++;
  }
  s->rep->start_jump = nj ? sj / nj : 0;
  /* A start already near equal area whose triangles are already sheared away from the surface's (the
   * coarse-to-fine start: mean Lambda 0.35-1.2 at vertex error 0.1-0.7, where a conformal start has
   * Lambda 0.03-0.55 at 0.6-10) gets no shape restoring, and its chord polish keeps the spherical part's
   * shear weight (docs/coarse-to-fine-flow.md). */
  s->rep->start_shear = start_shear(s);
  if (s->ls && o->restore_gate > 0 && s->rep->start_shear > o->restore_gate * s->err) s->restore_off = 1, s->near_start = 1;
  /* Equal-area maps only: with a prescribed density the resolved schedule undid many steps and
   * missed the tolerance (docs/flow.md). */
  s->rep->resolved = s->ls && nj > 0 && !o->weight && !o->face_weight && s->rep->start_jump <= o->resolved_jump;
  if (s->rep->resolved) s->alpha = o->resolved_shear;
  s->measured_jump = 1;
}

/* Measure the map at step k in the current phase's terms, record the errors, report progress and
 * honour a cancellation. Returns AU_OK, AU_E_NUMERIC or AU_E_CANCELLED. */
static au_status measure_map(flow_state *s) {
  const int nv = s->nv, nf = s->nf, *F = s->F, k = s->k;
  const au_advect_opts *o = s->o;
  double *af = s->af, *AO = s->AO, *b = s->b, *P = s->P;
  /* On the sphere the domain's areas are the spherical triangles' (see au_lm.c): they vanish where the
   * corners come onto one great circle, and they sum to 4 pi. */
  if (s->phase == FLOW_SPHERICAL) au_dec_sphere_face_areas(nf, F, P, af);
  else face_areas(nf, F, P, s->dom->shift, af);
  au_dec_vertex_areas(nv, nf, F, P, af, AO);
  double SO = 0;
  for (int f = 0; f < nf; f++) SO += af[f];
  double scale = SO / s->SM;
  /* b holds the target areas of this domain's total. */
  for (int i = 0; i < nv; i++) b[i] = s->AM[i] * scale;
  double err = vertex_error(nv, s->t->vused, b, AO);
  /* Per face: the mean |r - 1| (reported) and, for the least-shear step's control, the mean |log r|. */
  double ferr = 0, flog = 0;
  for (int f = 0; f < nf; f++) {
    double r = af[f] / (s->As[f] * s->fw[f] * scale);
    ferr += fabs(r - 1);
    if (s->ls) flog += fabs(log(r));
  }
  ferr /= nf, flog /= nf;
  s->SO = SO, s->scale = scale, s->err = err, s->ferr = ferr, s->flog = flog;
  if (!s->measured_jump) measure_start_jump(s);
  s->rep->err[k] = err;
  s->rep->face_err[k] = ferr;
  if (!(err == err) || !(ferr == ferr))
    return au_msg_set(s->msg, AU_E_NUMERIC, "advect: area error is not a number at step %d", k);
  if (o->progress) o->progress(o->user, k, o->max_steps, s->ls ? ferr : err);
  if (o->cancel && __atomic_load_n(o->cancel, __ATOMIC_ACQUIRE))
    return au_msg_set(s->msg, AU_E_CANCELLED, "advect: cancelled at step %d", k);
  return AU_OK;
}

/* Go back to the map before the last step. */
static void undo_step(flow_state *s) {
  memcpy(s->P, s->Pold, sizeof(double) * 3 * s->nv);
  s->rep->undone++;
}

/* Enter the angle steps at step k: from here the map is measured in the chord triangles' terms, the
 * step number staying. Their number is bounded by the report's arrays. */
static flow_verdict begin_angles(flow_state *s) {
  const int room = AU_ADVECT_MAX_STEPS - 1 - s->k;
  s->phase = FLOW_ANGLES;
  s->rep->angle_from = s->k;
  s->ang_left = s->o->angle_steps < room ? s->o->angle_steps : room;
  return FLOW_REMEASURE;
}

/* Whether the angle steps may still begin: there are some, and the report has room for a step. */
static int angles_possible(const flow_state *s) { return s->o->angle_steps > 0 && s->k + 1 < AU_ADVECT_MAX_STEPS; }

/* ---- decisions: one per phase (the phase table below) ---- */

/* Poisson method, vertex cells: once they meet tol, go on with the triangles themselves. */
static flow_verdict decide_cells(flow_state *s) {
  if (s->err > s->o->tol) return FLOW_STEP;
  s->rep->converged = 1;
  if (s->o->face_steps > 0 && s->ferr > s->o->face_tol) {
    s->phase = FLOW_FACES; /* this very round takes the first refinement step */
    return FLOW_STEP;
  }
  return FLOW_STOP;
}

/* Poisson method, per-face refinement: refine while the per-face error falls; a step that made it worse
 * is undone and the flow ends at the map before it. */
static flow_verdict decide_faces(flow_state *s) {
  au_advect_report *rep = s->rep;
  if (s->ferr >= s->prev_ferr) {
    memcpy(s->P, s->Pold, sizeof(double) * 3 * s->nv);
    rep->err[s->k] = s->err = s->prev_err;
    rep->face_err[s->k] = s->ferr = s->prev_ferr;
    rep->converged = s->err <= s->o->tol;
    return FLOW_STOP;
  }
  if (s->ferr <= s->o->face_tol || s->face_steps >= s->o->face_steps) {
    rep->converged = s->err <= s->o->tol;
    return FLOW_STOP;
  }
  return FLOW_STEP;
}

/* Least shear: Levenberg-Marquardt control of the shear weight. A step that made the per-face mean
 * |log r| worse is undone and redone stiffer (the mean |r - 1| barely sees a squeezed face grow and
 * punishes an overgrown one without bound, so it undid good steps). Past AU_SHEAR_MAX, or with the
 * budget spent, no stiffer step is worth a try: this part of the flow ends at the last accepted map.
 * Returns 1 if the step was undone. */
static int least_shear_undo(flow_state *s) {
  if (!(s->k > 0 && !(s->flog <= s->prev_flog * (1 + AU_SAME_REL)))) return 0;
  undo_step(s);
  s->retry = 1;
  if (s->alpha * AU_SHEAR_UNDO_FACTOR <= AU_SHEAR_MAX && s->k + s->rep->undone <= s->o->max_steps)
    s->alpha *= AU_SHEAR_UNDO_FACTOR;
  else s->exhausted = 1;
  return 1;
}

/* Least shear: whether this part of the flow has stalled (and the exhausted flag is consumed). Neither
 * error gained 2% in AU_STALL_WINDOW steps, or, once the vertex cells meet tol, face_gain (the
 * refinement must be worth its steps); in the chord polish with the vertex cells above tol,
 * AU_POLISH_GAIN, or after polish_steps steps while they miss tol by a margin (AU_POLISH_CUT_*); in the polish
 * with them within tol, one step must gain a share of face_gain. */
static int least_shear_stalled(flow_state *s) {
  const au_advect_opts *o = s->o;
  const au_advect_report *rep = s->rep;
  const int k = s->k, polish = s->phase == FLOW_POLISH;
  const double err = s->err, ferr = s->ferr;
  double keep = err <= o->tol ? 1 - o->face_gain : polish ? 1 - AU_POLISH_GAIN : AU_STALL_KEEP;
  int stalled = s->exhausted || (k >= o->schedule_steps + AU_STALL_WINDOW && k >= s->phase_start + AU_STALL_WINDOW &&
                                 ferr > keep * rep->face_err[k - AU_STALL_WINDOW] && err > keep * rep->err[k - AU_STALL_WINDOW]);
  s->exhausted = 0;
  if (polish && o->polish_steps > 0 && k - s->phase_start >= o->polish_steps && err > AU_POLISH_CUT_ABOVE * o->tol &&
      err < AU_POLISH_CUT_BELOW)
    stalled = 1;
  if (polish && err <= o->tol && k >= s->phase_start + 1 && ferr > (1 - AU_POLISH_STEP_SHARE * o->face_gain) * rep->face_err[k - 1])
    stalled = 1;
  return stalled;
}

/* Least shear: this part of the flow is done. From the spherical part, polish the chord triangles' areas
 * (the ones a reader of the output sees) where they differ from the spherical ones: on long, thin
 * triangles, or if their vertex cells miss tol (elsewhere it costs steps for nothing). Then the angle
 * steps, if any; else the end. */
static flow_verdict least_shear_done(flow_state *s) {
  const au_advect_opts *o = s->o;
  /* sphere_areas 2 keeps the spherical map: a texture's straight triangles tend to the spherical
   * ones, so the polish's gain in chord terms is a loss there. */
  if (s->phase == FLOW_SPHERICAL && o->sphere_areas != 2) {
    double cferr = 0, cerr = 0;
    chord_errors(s->nv, s->nf, s->F, s->t->vused, s->P, s->As, s->fw, s->AM, s->SM, s->af, s->AO, &cferr, &cerr);
    if (cerr > o->tol || cferr > (1 + o->polish_gap) * s->ferr) {
      /* The polish measures this map again in the chord triangles' terms, with the stiff start of the
       * shear weight. One that begins at step 0 is the chord flow itself. */
      s->phase = s->k > 0 ? FLOW_POLISH : FLOW_CHORD;
      s->phase_start = s->k;
      s->rep->polish_from = s->k;
      s->prev_err = s->prev_ferr = s->prev_flog = INFINITY;
      if (!s->near_start) s->alpha = o->shear;
      return FLOW_REMEASURE;
    }
  }
  if (angles_possible(s)) return begin_angles(s);
  s->rep->converged = s->err <= o->tol;
  return FLOW_STOP;
}

/* Least shear (spherical, chord, polish). */
static flow_verdict decide_least_shear(flow_state *s) {
  const au_advect_opts *o = s->o;
  const int k = s->k;
  const double err = s->err, ferr = s->ferr;
  /* The flow hands over to the angle steps early (angle_switch), once its faces are close too. */
  if (angles_possible(s) && o->angle_switch > 0 && err <= o->angle_switch && ferr <= AU_ANGLE_SWITCH_FACES * o->angle_switch)
    return begin_angles(s);
  if (least_shear_undo(s)) return FLOW_REDO;
  /* An accepted step lets the next be bolder. The resolved schedule drops the weight faster, until a
   * step has been undone. Its floor is shear_tail (on the sphere's resolved schedule, until then,
   * sphere_resolved_shear_tail), or face_shear_tail (if set) once the vertex cells meet tol. */
  const double tail = s->rep->resolved && s->sph && !s->rep->undone ? o->sphere_resolved_shear_tail : o->shear_tail;
  const double least = o->face_shear_tail > 0 && err <= o->tol ? o->face_shear_tail : tail;
  if (k > 0) s->alpha = fmax((s->rep->resolved && !s->rep->undone ? o->resolved_decay : AU_SHEAR_DECAY) * s->alpha, least);
  s->prev_flog = s->flog;
  const int stalled = least_shear_stalled(s);
  /* The spherical part ends when its vertex cells meet tol (the chord polish refines the faces from
   * there), when it stalls, or when it has used its share of the budget. */
  const int sph_done = s->phase == FLOW_SPHERICAL &&
                       ((k > 0 && k + s->rep->undone >= (o->max_steps * AU_SPHERICAL_BUDGET_NUM) / AU_SPHERICAL_BUDGET_DEN) ||
                        (k >= o->schedule_steps && err <= o->tol));
  /* Done: the vertex cells within tol and the faces within face_tol (each its own bound). */
  if ((err <= o->tol && ferr <= o->face_tol) || stalled || sph_done) return least_shear_done(s);
  return FLOW_STEP;
}

/* The angle steps: one that took the vertex cells above both tol and where they were is undone, and the
 * phase ends there. */
static flow_verdict decide_angles(flow_state *s) {
  if (s->err > s->o->tol && s->err > s->ang_prev * (1 + AU_SAME_REL)) {
    undo_step(s);
    s->ang_left = 0, s->ang_prev = INFINITY;
    return FLOW_REDO;
  }
  if (s->ang_left-- <= 0) return FLOW_STOP;
  s->ang_prev = s->err;
  return FLOW_STEP;
}

/* Every phase but the angle steps: the budget counts undone solves too. Once it is spent the angle
 * steps (if any) come on top of it. */
static flow_verdict check_budget(flow_state *s) {
  if (s->phase == FLOW_ANGLES || s->k + s->rep->undone < s->o->max_steps) return FLOW_STEP;
  if (!(s->ls && angles_possible(s))) return FLOW_STOP;
  return begin_angles(s);
}

/* ---- solves: one per phase, each filling D ---- */

/* The angle step: targets in this map's units (b holds the cells', Gf gets the faces'). */
static au_status solve_angles(flow_state *s, flow_solved *out) {
  const au_advect_opts *o = s->o;
  au_status st = AU_OK;
  *out = SOLVED_MOVE;
  if (!s->ang && (st = au__ang_create(s->m, &s->ang, s->msg)) != AU_OK) return st;
  for (int f = 0; f < s->nf; f++) s->Gf[f] = s->As[f] * s->fw[f] * s->scale;
  return au__ang_step(s->ang, s->dom, s->P, s->Gf, s->b, o->angle_faces, o->angle_cells, o->angle_trust, s->D, s->msg);
}

/* The least-shear step's wanted per-face area changes dA_f: targets on the geometric schedule, each
 * ratio moving at most e^max_log_step (on the resolved schedule e^resolved_log_step; on the sphere's,
 * until a step is undone, sphere_resolved_schedule_steps and e^sphere_resolved_log_step). */
static void least_shear_targets(flow_state *s) {
  const au_advect_opts *o = s->o;
  const int nf = s->nf, k = s->k;
  const double *af = s->af, *As = s->As, *fw = s->fw, scale = s->scale, SO = s->SO;
  double *dA_f = s->dA_f;
  const int sph_resolved = s->rep->resolved && s->sph && !s->rep->undone;
  const int K = sph_resolved ? o->sphere_resolved_schedule_steps : o->schedule_steps;
  double sch = k < K ? 1.0 / (double)(K - k) : 1.0, sum_new = 0;
  const double cap = sph_resolved ? o->sphere_resolved_log_step : s->rep->resolved ? o->resolved_log_step : o->max_log_step;
  for (int f = 0; f < nf; f++) {
    double lr = sch * log(As[f] * fw[f] * scale / af[f]);
    if (lr > cap) lr = cap;
    if (lr < -cap) lr = -cap;
    dA_f[f] = af[f] * exp(lr);
    sum_new += dA_f[f];
  }
  double renorm = SO / sum_new;
  /* The step is linear in the motion, and a triangle scaled by s has area s^2: asked to grow by rho, a
   * linear step that predicts rho overshoots to about ((1 + rho) / 2)^2. So growth is asked as the
   * similarity that gives it, 2 (sqrt(rho) - 1); shrinking is left as it is (the sqrt would ask for
   * more, towards collapse), and the changes are recentred to sum to zero, as a tangent motion's do. */
  double tot = 0;
  for (int f = 0; f < nf; f++) {
    double rho = dA_f[f] * renorm / af[f];
    dA_f[f] = af[f] * (rho > 1 ? 2 * (sqrt(rho) - 1) : rho - 1);
    tot += dA_f[f];
  }
  for (int f = 0; f < nf; f++) dA_f[f] -= af[f] * (tot / SO);
}

/* The least-shear step (spherical, chord, polish). */
static au_status solve_least_shear(flow_state *s, flow_solved *out) {
  const au_advect_opts *o = s->o;
  const int nf = s->nf, sph_areas = s->phase == FLOW_SPHERICAL;
  au_status st = AU_OK;
  *out = SOLVED_MOVE;
  least_shear_targets(s);
  if (!*s->lmp && (st = au__lm_create(s->m, s->t, s->lmp, s->msg)) != AU_OK) return st;
  /* Face weights: the target areas (the faces' shares of the surface), at most AU_WEIGHT_CAP times the
   * current area so that the system stays well conditioned. */
  for (int f = 0; f < nf; f++) s->Gf[f] = fmin(s->As[f] * s->fw[f] * s->scale, AU_WEIGHT_CAP * s->af[f]);
  /* Shape restoring, faded out as the vertex cells approach their areas (it would hold them off), and
   * not in a retry: the restoring target grows with the shear weight, so a step undone for making the
   * areas worse would be retried ever more purely as shape restoring, and undone again. */
  /* In a map of spherical areas only (sphere_areas 2) the spherical part is the whole flow, and once a
   * restoring step has been undone for making the areas worse, every later one is too: restoring and
   * a retry without it alternate, half the solves are wasted and each kept step gains about 1%
   * (data/tpose.obj: 20 of 40 solves undone, spherical vertex error 0.029 at the end). So it stays
   * off for the rest of the run, and the lantern, which raises restoring, with it. Switching it off
   * only once restoring fades (error below AU_RESTORE_FADE) was less robust: tpose with restore 0.08
   * stayed squeezed (0.57 per face against 0.0155), 40 steps 0.0160 against 0.0121. In the chord maps
   * the spherical part hands over to the chord polish, and the same rule there moved the maps both
   * ways (docs/sphere.md). */
  if (s->retry && s->restored && o->sphere_areas == 2) s->restore_off = 1;
  double restore = sph_areas && !s->retry && !s->restore_off ? o->restore * fmin(1, s->err / AU_RESTORE_FADE) : 0;
  s->restored = restore > 0;
  s->retry = 0;
  const int lantern_on = restore > 0 && s->err < AU_LANTERN_BELOW;
  if (lantern_on) s->rep->lantern_steps++;
  /* The state recorded at this round's start is where a flow with the lantern parts from this one. */
  if (lantern_on && o->fork_record && o->fork_record->P) o->fork_record->ready = 1;
  const double lantern = lantern_on ? o->lantern : 0;
  st = au__lm_step(*s->lmp, s->dom, s->P, s->dA_f, s->Gf, s->alpha, AU_ROTATION_EPS, sph_areas, restore, lantern, s->D, s->msg);
  if (st != AU_E_NOT_SPD) return st;
  /* Rounding made the system indefinite: retry stiffer at the next step number, or, as stiff as it
   * gets, end this part of the flow here. Nothing has moved: the next round sees the same map. */
  s->rep->frac[s->k] = 0;
  if (s->alpha < AU_SHEAR_SPD_MAX) s->alpha *= AU_SHEAR_SPD_FACTOR, *out = SOLVED_NEXT;
  else s->exhausted = 1, *out = SOLVED_REMEASURE;
  memcpy(s->Pold, s->P, sizeof(double) * 3 * s->nv);
  if (s->msg) s->msg->text[0] = '\0';
  return AU_OK;
}

/* Poisson method, per-face refinement: damped Gauss-Newton on the triangle areas. */
static au_status solve_faces(flow_state *s, flow_solved *out) {
  au_status st = AU_OK;
  *out = SOLVED_MOVE;
  if (!s->gnf && (st = au__gn_create(s->m, s->t, 1, &s->gnf, s->msg)) != AU_OK) return st;
  for (int f = 0; f < s->nf; f++) s->dA_f[f] = s->As[f] * s->fw[f] * s->scale - s->af[f];
  for (int i = 0; i < s->nv; i++) s->g[i] = s->AO[i] > 0 ? 1.0 / s->AO[i] : 0;
  st = au__gn_step(s->gnf, s->dom, s->P, s->g, s->dA_f, s->o->face_damping, s->D, s->msg);
  s->face_steps++;
  s->rep->face_steps = s->face_steps;
  return st;
}

/* The paper's step: C g = -dA on the current domain mesh (analyzed once), then the displacement along
 * the angle-weighted vertex gradient, constrained to the domain. b holds dA. */
static au_status poisson_step(flow_state *s) {
  const int nv = s->nv, nf = s->nf, *F = s->F;
  double *b = s->b, *g = s->g, *P = s->P;
  au_status st = AU_OK;
  for (int i = 0; i < nv; i++) b[i] = -b[i];
  au_dec_cotan(s->t, F, P, s->w);
  if (!s->solver) st = au_solver_create(nv, s->t->ne, s->t->E, s->fixed, AU_ORDER_FILL, &s->solver, s->msg);
  if (st == AU_OK) st = au_solver_factor(s->solver, s->w, NULL, s->msg);
  if (st == AU_OK) {
    memset(g, 0, sizeof(double) * nv);
    st = au_solver_solve(s->solver, 1, b, g, s->msg);
  }
  if (st == AU_OK) {
    au_dec_face_grad(nf, F, P, g, s->Gf);
    st = au_dec_vertex_grad(nv, nf, F, P, s->Gf, s->D);
  }
  if (st == AU_OK)
    for (int i = 0; i < nv; i++) s->dom->constrain(s->dom->ctx, i, P + 3 * i, s->D + 3 * i);
  return st;
}

/* Poisson method, vertex cells: the geometric schedule (each cell's ratio moves by rho^s, never by more
 * than e^max_log_step), renormalized so the wanted changes sum to zero (the Poisson problem is then
 * consistent); the exact Gauss-Newton step (au_gn.c) below newton_below, the paper's step above. */
static au_status solve_cells(flow_state *s, flow_solved *out) {
  const au_advect_opts *o = s->o;
  const int nv = s->nv, k = s->k;
  const unsigned char *used = s->t->vused;
  double *b = s->b, *AO = s->AO, *g = s->g;
  au_status st = AU_OK;
  *out = SOLVED_MOVE;
  double sch = k < o->schedule_steps ? 1.0 / (double)(o->schedule_steps - k) : 1.0;
  double sum_new = 0;
  for (int i = 0; i < nv; i++) {
    if (!used[i]) {
      b[i] = 0;
      continue;
    }
    double lr = sch * log(b[i] / AO[i]);
    if (lr > o->max_log_step) lr = o->max_log_step;
    if (lr < -o->max_log_step) lr = -o->max_log_step;
    b[i] = AO[i] * exp(lr);
    sum_new += b[i];
  }
  double renorm = s->SO / sum_new;
  for (int i = 0; i < nv; i++) b[i] = used[i] ? (b[i] * renorm - AO[i]) : 0; /* b = dA */
  if (!(s->err < o->newton_below)) return poisson_step(s);
  /* Weights 1/(domain vertex area). */
  if (!s->gn && (st = au__gn_create(s->m, s->t, 0, &s->gn, s->msg)) != AU_OK) return st;
  for (int i = 0; i < nv; i++) g[i] = AO[i] > 0 ? 1.0 / AO[i] : 0;
  return au__gn_step(s->gn, s->dom, s->P, g, b, 0, s->D, s->msg);
}

/* ---- the phase table ---- */

typedef struct flow_phase_rule {
  const char *name;
  const char *entry; /* when the flow enters the phase */
  const char *exit;  /* when it leaves, and for where (decide) */
  flow_verdict (*decide)(flow_state *s);               /* the exit rules, applied after measuring */
  au_status (*solve)(flow_state *s, flow_solved *out); /* the phase's step */
} flow_phase_rule;

/* Indexed by flow_phase. The least-shear phases measure the map in the spherical triangles' terms
 * (spherical) or in the chord triangles' (the others); the Poisson ones in the chord triangles'. */
static const flow_phase_rule flow_phases[] = {
    [FLOW_CELLS] = {"cells", "Poisson method: at the start",
                    "vertex error <= tol: to faces if face_steps > 0 and the faces miss face_tol, else the end",
                    decide_cells, solve_cells},
    [FLOW_FACES] = {"faces", "Poisson method: from cells",
                    "the per-face error rose (that step undone), met face_tol, or face_steps were taken: the end",
                    decide_faces, solve_faces},
    [FLOW_SPHERICAL] = {"spherical", "least shear on the sphere with sphere_areas: at the start",
                        "vertex error <= tol, stalled, or 2/3 of the budget used: to polish where the chord "
                        "triangles lag, else to angles (angle_steps) or the end; the angle switch: to angles",
                        decide_least_shear, solve_least_shear},
    [FLOW_CHORD] = {"chord", "least shear otherwise (planar domains, sphere_areas 0): at the start",
                    "both errors within tol and face_tol, or stalled: to angles (angle_steps) or the end; "
                    "the angle switch: to angles",
                    decide_least_shear, solve_least_shear},
    [FLOW_POLISH] = {"polish", "from spherical, at a step > 0 (at step 0 the polish is the chord phase)",
                     "as chord, with the polish's own stall tests", decide_least_shear, solve_least_shear},
    [FLOW_ANGLES] = {"angles", "angle_steps > 0: from a least-shear phase at the angle switch, at its end, "
                     "or when the budget is spent",
                     "angle_steps taken, or a step raised the vertex error above tol and above where it was "
                     "(that step undone): the end",
                     decide_angles, solve_angles},
};

/* ---- the move ---- */

/* The step control's fractions lim for D (see the banner): per-face safe fractions, then a Lipschitz
 * envelope; the report gets their mean. */
static void step_fractions(flow_state *s) {
  const int nv = s->nv, nf = s->nf, *F = s->F;
  const double *P = s->P, *af = s->af;
  double *inr = s->inr, *lim = s->lim;
  for (int f = 0; f < nf; f++) {
    double per = 0, buf[3][3];
    const double *cp[3];
    for (int e = 0; e < 3; e++) cp[e] = au__corner(P, F, s->dom->shift, f, e, buf[e]);
    for (int e = 0; e < 3; e++) {
      const double *p = cp[e], *q = cp[(e + 1) % 3];
      per += sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
    }
    inr[f] = per > 0 ? 2.0 * af[f] / per : 0;
  }
  step_control(s->t, &s->adj, F, nf, nv, P, inr, s->D, s->o->max_move, s->dom, lim, s->heap, s->hpos, s->dn);
  double frac_sum = 0;
  int nused = 0;
  for (int i = 0; i < nv; i++) {
    if (!s->t->vused[i]) {
      lim[i] = 0;
      continue;
    }
    frac_sum += lim[i];
    nused++;
  }
  s->rep->frac[s->k] = nused ? frac_sum / nused : 0;
}

/* Move every vertex by its fraction of D and mark the corners of triangles that turned (or fell below
 * the margin); returns how many triangles did. A vertex that does not move keeps its exact position:
 * retracting it again could nudge a nearly flat triangle across zero. */
static int move_and_check(flow_state *s) {
  const int nv = s->nv, nf = s->nf, *F = s->F;
  double *P = s->P;
  if (s->dom->begin_move) s->dom->begin_move(s->dom->ctx, NULL, s->Pold, s->D, s->lim);
  for (int i = 0; i < nv; i++) {
    double *p = P + 3 * i, *q = s->Pold + 3 * i, *d = s->D + 3 * i;
    if (s->lim[i] == 0) {
      p[0] = q[0], p[1] = q[1], p[2] = q[2];
      continue;
    }
    move_vertex(s->dom, q, d, s->lim[i], p);
    s->dom->retract(s->dom->ctx, i, p);
  }
  int nbad = 0;
  memset(s->bad, 0, (size_t)nv);
  for (int f = 0; f < nf; f++) {
    /* Orientation with a margin: a triangle must stay above AU_ORIENT_MARGIN, so that its sign survives
     * a re-normalization of the output by a reader and the rounding of other formulas for the same
     * sign. One already below it (the tiny triangles of a squeezed start) may shrink by at most
     * AU_ORIENT_SHRINK per step: comparing it with its old value exactly would only compare rounding. */
    double o_new = face_orient(P, F, s->dom->shift, f, s->sph);
    if (o_new > AU_ORIENT_MARGIN || (o_new > 0 && o_new >= AU_ORIENT_SHRINK * s->orient_old[f])) continue;
    nbad++;
    for (int e = 0; e < 3; e++) s->bad[F[3 * f + e]] = 1;
  }
  return nbad;
}

/* Take the step D under the step control, backtracking locally and smoothly where a triangle still
 * turned: the fractions of its corners are halved and the Lipschitz envelope restored, so that the
 * neighbours slow down with them (halving alone would shear the triangles around them). */
static void take_step(flow_state *s) {
  const int nv = s->nv;
  step_fractions(s);
  memcpy(s->Pold, s->P, sizeof(double) * 3 * nv);
  for (int f = 0; f < s->nf; f++) s->orient_old[f] = face_orient(s->P, s->F, s->dom->shift, f, s->sph);
  for (int tries = 0; move_and_check(s); tries++) {
    for (int i = 0; i < nv; i++)
      if (s->bad[i]) s->lim[i] = tries < AU_BACKTRACK_HALVINGS ? 0.5 * s->lim[i] : 0;
    envelope(s->t, &s->adj, nv, s->inr, s->D, s->o->max_move, s->lim, s->heap, s->hpos, s->dn);
  }
}

/* ---- a flow's recorded state (au_advect_fork) ---- */

au_advect_fork *au_advect_fork_new(void) { return calloc(1, sizeof(au_advect_fork)); }

void au_advect_fork_free(au_advect_fork **fp) {
  if (!fp || !*fp) return;
  free((*fp)->P);
  free(*fp);
  *fp = NULL;
}

int au_advect_fork_ready(const au_advect_fork *f) { return f && f->ready; }

/* Record s at the start of a round (until the fork is ready). Out of memory the fork stays unready, and
 * a flow that would resume from it runs from its start. */
static void fork_save(au_advect_fork *f, const flow_state *s) {
  const size_t bytes = sizeof(double) * 3 * (size_t)s->nv;
  if (!f->P || f->m != s->m) {
    free(f->P);
    f->m = s->m, f->nv = s->nv;
    if (!(f->P = malloc(bytes))) {
      f->m = NULL, f->nv = 0;
      return;
    }
  }
  memcpy(f->P, s->P, bytes);
  f->rep = *s->rep;
  f->phase = s->phase, f->k = s->k, f->phase_start = s->phase_start, f->retry = s->retry, f->restored = s->restored;
  f->restore_off = s->restore_off, f->near_start = s->near_start, f->measured_jump = s->measured_jump;
  f->exhausted = s->exhausted, f->ang_left = s->ang_left, f->face_steps = s->face_steps;
  f->alpha = s->alpha, f->prev_err = s->prev_err, f->prev_ferr = s->prev_ferr, f->prev_flog = s->prev_flog;
  f->ang_prev = s->ang_prev;
}

/* Start s from the recorded state f (ready, of a flow on the same mesh). */
static void fork_load(const au_advect_fork *f, flow_state *s) {
  memcpy(s->P, f->P, sizeof(double) * 3 * (size_t)s->nv);
  *s->rep = f->rep;
  s->phase = f->phase, s->k = f->k, s->phase_start = f->phase_start, s->retry = f->retry, s->restored = f->restored;
  s->restore_off = f->restore_off, s->near_start = f->near_start, s->measured_jump = f->measured_jump;
  s->exhausted = f->exhausted, s->ang_left = f->ang_left, s->face_steps = f->face_steps;
  s->alpha = f->alpha, s->prev_err = f->prev_err, s->prev_ferr = f->prev_ferr, s->prev_flog = f->prev_flog;
  s->ang_prev = f->ang_prev;
}

/* ---- the run ---- */

/* Set the run up: scratch, targets, the fold check of the entry map, the pinned vertex, the first phase. */
static au_status flow_begin(flow_state *s) {
  if (!flow_state_alloc(s)) return au_msg_set(s->msg, AU_E_NOMEM, "advect: out of memory");
  au_status st = flow_targets(s);
  if (st != AU_OK) return st;
  int folds = count_folds(s->P, s->F, s->dom->shift, s->nf, s->sph);
  if (folds) return au_msg_set(s->msg, AU_E_FOLD, "advect: the initial map has %d folded triangles", folds);
  /* The Poisson problem is a pure Neumann problem (closed sphere, or a boundary that only slides): pin
   * the first referenced vertex; unreferenced vertices have empty rows and are fixed too. */
  int pinned = -1;
  for (int i = 0; i < s->nv; i++) {
    if (!s->t->vused[i]) s->fixed[i] = 1;
    else if (pinned < 0) pinned = i, s->fixed[i] = 1;
  }
  s->phase = !s->ls ? FLOW_CELLS : s->sph && s->o->sphere_areas ? FLOW_SPHERICAL : FLOW_CHORD;
  s->alpha = s->o->shear;
  s->prev_err = s->prev_ferr = s->prev_flog = INFINITY;
  s->ang_prev = INFINITY;
  return AU_OK;
}

/* One round at step k: measure, decide, solve, move. Sets *verdict to what the loop does next. */
static au_status flow_round(flow_state *s, flow_verdict *verdict) {
  au_status st = measure_map(s);
  if (st != AU_OK) return st;
  *verdict = flow_phases[s->phase].decide(s);
  if (*verdict != FLOW_STEP) return AU_OK;
  s->prev_err = s->err, s->prev_ferr = s->ferr;
  *verdict = check_budget(s);
  if (*verdict != FLOW_STEP) return AU_OK;
  double t0 = now_s();
  flow_solved solved = SOLVED_MOVE;
  st = flow_phases[s->phase].solve(s, &solved);
  /* A system that came out indefinite moved nothing: a stiffer retry at the next step number, or, as
   * stiff as it gets, this part of the flow measured again at this one (solve_least_shear). */
  if (solved == SOLVED_NEXT) return AU_OK;
  if (solved == SOLVED_REMEASURE) {
    *verdict = FLOW_REMEASURE;
    return AU_OK;
  }
  s->rep->t_solve += now_s() - t0;
  if (st != AU_OK) return st;
  take_step(s);
  return AU_OK;
}

/* The flow itself, on arguments and options au_advect_run has checked. */
static au_status advect_core(const au_mesh *m, const au_topo *t, const au_advect_domain *dom, const au_advect_opts *opts,
                             au_lm **lmp, double *P, au_advect_report *rep, au_msg *msg) {
  memset(rep, 0, sizeof *rep);
  flow_state s;
  memset(&s, 0, sizeof s);
  s.m = m, s.t = t, s.dom = dom, s.o = opts, s.rep = rep, s.msg = msg, s.P = P, s.lmp = lmp;
  s.nv = m->nv, s.nf = m->nf, s.F = m->F, s.sph = dom->spherical, s.ls = opts->method == AU_ADVECT_LEAST_SHEAR;
  au_status st = flow_begin(&s);
  s.k = 0;
  /* A flow resumed from another's recorded state starts at that state's round (au_advect_fork). */
  const au_advect_fork *from = opts->fork_resume;
  if (st == AU_OK && from && from->ready && from->m == m && from->nv == s.nv) fork_load(from, &s);
  while (st == AU_OK) {
    if (opts->fork_record && !opts->fork_record->ready) fork_save(opts->fork_record, &s);
    flow_verdict v = FLOW_STEP;
    st = flow_round(&s, &v);
    if (st != AU_OK || v == FLOW_STOP) break;
    if (v == FLOW_REDO) s.k--;
    else if (v == FLOW_STEP) s.k++;
  }
  if (st == AU_OK) {
    const int k = s.k;
    rep->steps = k;
    /* Converged means the vertex error met the tolerance, however the loop ended (the step budget can
     * run out while the per-face refinement is still going). */
    rep->converged = rep->err[k] <= opts->tol;
    if (!rep->converged) {
      st = AU_W_NOT_CONVERGED;
      au_msg_set(msg, st, "area error %.3g after %d steps (tolerance %.3g)", rep->err[k], k, opts->tol);
    }
  }
  flow_state_free(&s);
  return st;
}

/* Below this many vertices the mesh is worked on in its own order. */
#define AU_REORDER_MIN 4096

/* The domain's callbacks, called with the caller's vertex numbers. */
typedef struct reordered_domain {
  const au_advect_domain *dom;
  const int *orig; /* orig[i]: the caller's number of vertex i of the reordered mesh */
  const int *inv;  /* inv[v]: the reordered number of the caller's vertex v */
} reordered_domain;

static void reordered_constrain(void *ctx, int i, const double *p, double *d) {
  const reordered_domain *r = ctx;
  r->dom->constrain(r->dom->ctx, r->orig[i], p, d);
}

static void reordered_retract(void *ctx, int i, double *p) {
  const reordered_domain *r = ctx;
  r->dom->retract(r->dom->ctx, r->orig[i], p);
}

static void reordered_begin_move(void *ctx, const int *row, const double *P, const double *D, const double *lim) {
  const reordered_domain *r = ctx;
  (void)row;
  r->dom->begin_move(r->dom->ctx, r->inv, P, D, lim);
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
     * cache (a quarter of the flow's time on lion_statue, docs/flow.md). */
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
  if (o.max_steps < 0 || o.max_steps > AU_ADVECT_MAX_STEPS || o.schedule_steps < 1 || o.polish_steps < 0 || !(o.max_move > 0 && o.max_move < 0.5) ||
      !(o.tol >= 0) || !(o.face_gain >= 0 && o.face_gain < 1) || !(o.restore >= 0 && o.restore <= 1) || !(o.restore_gate >= 0) || !(o.lantern >= 0) ||
      o.angle_steps < 0 || !(o.angle_faces >= 0) || !(o.angle_cells >= 0) || !(o.angle_trust > 0) || !(o.angle_switch >= 0) ||
      !(o.polish_gap >= 0) || !(o.resolved_jump >= 0) || !(o.resolved_decay > 0 && o.resolved_decay <= 1) || !(o.resolved_shear >= 0) || !(o.face_shear_tail >= 0) ||
      !(o.resolved_log_step > 0) || o.sphere_resolved_schedule_steps < 1 || !(o.sphere_resolved_log_step > 0) ||
      !(o.sphere_resolved_shear_tail >= 0))
    return au_msg_set(msg, AU_E_ARG, "advect: options out of range");
  if (o.weight && o.face_weight) return au_msg_set(msg, AU_E_ARG, "advect: give a per-vertex or a per-face density, not both");
  /* The Poisson method's systems (au_gn.c, the cotan stiffness) read the corners unshifted. */
  if (dom->shift && o.method != AU_ADVECT_LEAST_SHEAR)
    return au_msg_set(msg, AU_E_ARG, "advect: the Poisson method does not support per-corner shifts (the flat torus)");
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
  double *sh2 = dom->shift ? malloc(sizeof(double) * 9 * (size_t)nf) : NULL;
  st = AU_OK;
  if (!P2 || (o.weight && !w2) || (o.face_weight && !fw2) || (dom->shift && !sh2)) {
    st = au_msg_set(msg, AU_E_NOMEM, "advect: out of memory");
    goto done;
  }
  for (int k = 0; k < nv; k++) {
    memcpy(P2 + 3 * k, P + 3 * orig[k], 3 * sizeof(double));
    if (w2) w2[k] = o.weight[orig[k]];
  }
  for (int f = 0; f < nf && fw2; f++) fw2[f] = o.face_weight[forig[f]];
  /* The shifts go with their faces (the copy keeps each face's corner order). */
  for (int f = 0; f < nf && sh2; f++) memcpy(sh2 + 9 * (size_t)f, dom->shift + 9 * (size_t)forig[f], 9 * sizeof(double));
  reordered_domain rd = {dom, orig, plan->inv};
  au_advect_domain dom2 = {reordered_constrain, reordered_retract, dom->spherical, &rd, dom->arc_radius, sh2,
                           dom->begin_move ? reordered_begin_move : NULL};
  o.weight = w2, o.face_weight = fw2;
  st = advect_core(plan->m2, plan->t2, &dom2, &o, &plan->lm, P2, rep, msg);
  for (int k = 0; k < nv; k++) memcpy(P + 3 * orig[k], P2 + 3 * k, 3 * sizeof(double));
done:
  free(P2), free(w2), free(fw2), free(sh2);
  return st;
}
