/* au_sphere_map.c - the sphere pipeline: conformal start, balancing, tangent-plane Lie advection with
 * reprojection onto the unit sphere (Zou et al. 2011, sec. 4.5.2, eq. 21-22). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "au_dec.h"
#include "au_metrics.h"
#include "au_sphere.h"

/* The staged retry (au_sphere_opts.staged_retry) runs where at least this share of the surface has
 * vertex cells under 1/e of their share: squeezed protrusions (tpose) rather than the chord floor,
 * which a staged flow does not lower (limbs8: vertex error 0.164 -> 0.193 in 6 stages). */
#define AU_STAGED_SQUEEZED 0.01
/* Each stage asks the flow for the targets current area x (target / current)^AU_STAGED_PART, per face:
 * tpose from its flow's map (vertex error 7.86) ends 0.54 with 0.6, 0.89 with 0.5 in 10 stages, and
 * stalls at 4.7 with 0.3 (docs/sphere.md). */
#define AU_STAGED_PART 0.6
/* The stages end once two in a row lower the map's vertex error (map_vertex_error) by less than this
 * fraction. */
#define AU_STAGED_GAIN 0.05

/* The weight of the global polish's angle term in the sphere map. Areas alone halve cow's and
 * cheburashka's errors but raise their mean conformal distortion (lambda 1.68 -> 1.80, 1.22 -> 1.35);
 * with 1e-3 both errors fall nearly as far (cow 0.0261 / 0.0078 -> 0.0143 / 0.0024) with lambda at or
 * under the flow's (1.66, 1.22); 1e-2 keeps cow at 0.0253 / 0.0046 (docs/sphere.md).
 * --refine-mesh polishes on areas alone: it is asked for the area bounds. */
#define AU_GPOLISH_ANGLE 1e-3

/* The sphere map's global polish stops once 20 steps have gained less than 1% of the vertex error and of
 * the per-face error (au_gpolish_opts.min_gain): screwdriver's polish ran its 200 steps, the last 77 for
 * per-face 0.0223 -> 0.0219 and vertex 0.0040 -> 0.0039. A user asks for per-face 0.03 and vertex 0.01
 * and the tolerance; 1% of a figure already within them is not worth 20 factorizations of the polish's
 * two-ring system. --refine-mesh's polish keeps its own rules. */
#define AU_GPOLISH_MIN_GAIN 0.01

/* The sphere map's global polish puts its log barrier on every face within twice its share of its least
 * triple product (au_gpolish_opts.barrier 1, not au_sphere_gpolish_settings' 0.15), at weight 0.1 (not
 * 0.05). Why: with the barrier only near the floor, the Gauss-Newton step did not see the faces it would
 * take past the floor (screwdriver's first step: 27 such faces, 25 of them outside the barrier's reach, 23
 * already below the floor in the linearized model), so each step was halved 4-9 times. Seen by the model,
 * they cost fewer steps: penguin_hr's polish 177 -> 82 steps (per-face 0.0113 -> 0.0077), screwdriver's
 * 124 -> 95, hammer's 200 -> 90 (screwdriver's steps are still halved 4-6 times in 79 of its 95). At
 * weight 0.3 cow's polish stalled after 34 steps with per-face 0.0233
 * (0.0162): the barrier's own part of the cost hid its progress from the stall rule
 * (docs/sphere-polish-speed.md). --refine-mesh's polish keeps au_sphere_gpolish_settings'. */
#define AU_GPOLISH_BARRIER 1.0
#define AU_GPOLISH_BARRIER_WEIGHT 0.1
/* At the tolerance the sphere map's polish goes on while its per-face error is above 0.009 (under a third
 * of the 0.03 a user asks for) and has fallen by 5% over the last 5 steps: with the barrier above,
 * spot_lowres reached the tolerance at per-face 0.0105 (0.0095 before) after 7 steps; with 0.01 it
 * stopped at 0.00999, with 0.009 at 0.0097. With no such floor, hand_closed, at the tolerance after one
 * step with 0.0087, went on for 23 (0.0054, CPU 3.3 -> 5.0 s). */
#define AU_GPOLISH_FACE_WINDOW 5
#define AU_GPOLISH_FACE_GAIN 0.05
#define AU_GPOLISH_FACE_TARGET 0.009
/* The sphere map's global polish takes the area residuals through the pseudo-Huber loss with d 0.03
 * (au_gpolish_opts.robust) where the chord floor's excess of the map before it (chord_floor_excess) is at
 * most 0.01 of the area: there the faces held on their floor are a few outliers whose squares steered
 * every Gauss-Newton step into the triple-product floors; under the loss they weigh as their |log r| does
 * in the figures a user reads. cow 0.0158 / 0.0027 in 131 steps -> 0.0146 / 0.0020 in 44, screwdriver
 * 0.0227 / 0.0044 in 95 -> 0.0185 / 0.0019 in 59, penguin_hr 113 -> 66 steps. Where the floor is the bulk
 * of the error (the generated limbs, excess 0.019-0.12 against the shared meshes' 0.0001-0.0022) the loss
 * flattens the very residuals the polish must lower (tpose 0.22 -> 0.39, hammer 0.048 -> 0.062): squares
 * there (docs/sphere-polish-speed.md). */
#define AU_GPOLISH_ROBUST 0.03
#define AU_GPOLISH_ROBUST_BELOW 0.01

/* Where the vertex polish follows the flow, the flow's chord polish takes at most this many steps while
 * its vertex error is between 1.5 tol and 0.1 (au_advect_opts.polish_steps): the polishes after it do
 * the rest for fewer factorizations. hand_closed 109 -> 67 factorizations, cheburashka 122 -> 94,
 * airplane 147 -> 114, armadillo 41 -> 28; 1 step cost screwdriver and armadillo more, 3 gained less
 * (docs/chord-polish.md). */
#define AU_SPHERE_POLISH_STEPS 2

au_sphere_opts au_sphere_opts_default(void) {
  au_sphere_opts o;
  memset(&o, 0, sizeof o);
  o.flow = au_advect_opts_default();
  o.balance = 1;
  o.lantern_retry = 2;
  o.retry_above = 2;
  o.twist_retry = 0.02;
  o.vertex_polish = 200;
  o.polish_cells = 1;
  o.global_polish = 200;
  o.staged_retry = 8;
  o.start = AU_SPHERE_START_CONFORMAL;
  o.ml = au_sphere_ml_opts_default();
  return o;
}

/* Keep the tangent component of each displacement (eq. 22). */
static void sphere_constrain(void *ctx, int i, const double *p, double *d) {
  (void)ctx, (void)i;
  double s = d[0] * p[0] + d[1] * p[1] + d[2] * p[2];
  d[0] -= s * p[0], d[1] -= s * p[1], d[2] -= s * p[2];
}

/* Pull every point back onto the unit sphere. */
static void sphere_retract(void *ctx, int i, double *p) {
  (void)ctx, (void)i;
  double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  if (r > 0) p[0] /= r, p[1] /= r, p[2] /= r;
}

au_advect_domain au_sphere_domain(void) {
  au_advect_domain d = {sphere_constrain, sphere_retract, 1, NULL, 0, NULL, NULL};
  return d;
}

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The flow's target density of face f: its own, the mean of its corners', or 1 for equal area. */
static double density_of(const au_mesh *m, const au_advect_opts *fo, int f) {
  const int *c = m->F + 3 * f;
  return fo->face_weight ? fo->face_weight[f]
         : fo->weight    ? (fo->weight[c[0]] + fo->weight[c[1]] + fo->weight[c[2]]) / 3.0
                         : 1.0;
}

/* The face areas of the map P in the measure it is made for: its chord triangles (au_metrics and
 * param-eval measure those), or for a map of spherical areas only (sphere_areas 2, the texture
 * command's: a texture's straight triangles tend to the spherical ones) its spherical triangles. */
static void map_face_areas(int nf, const int *F, const au_advect_opts *fo, const double *P, double *area) {
  if (fo->sphere_areas == 2) au_dec_sphere_face_areas(nf, F, P, area);
  else au_dec_face_areas(nf, F, P, area);
}

/* The vertex mean |log ratio| of the map's triangles (map_face_areas), with the flow's targets: a third
 * of each face's surface area times its density. The retries compare maps by it. */
static double map_vertex_error(const au_mesh *m, const au_topo *t, const au_advect_opts *fo, const double *P) {
  const int nv = m->nv, nf = m->nf, *F = m->F;
  double *as = malloc(sizeof(double) * (size_t)nf), *ad = malloc(sizeof(double) * (size_t)nf);
  double *vs = calloc((size_t)nv, sizeof(double)), *vd = calloc((size_t)nv, sizeof(double));
  double err = INFINITY;
  if (as && ad && vs && vd) {
    au_dec_face_areas(nf, F, m->X, as);
    map_face_areas(nf, F, fo, P, ad);
    double ss = 0, sd = 0;
    for (int f = 0; f < nf; f++) {
      const int *c = F + 3 * f;
      const double w = density_of(m, fo, f);
      for (int k = 0; k < 3; k++) vs[c[k]] += as[f] * w / 3, vd[c[k]] += ad[f] / 3;
      ss += as[f] * w, sd += ad[f];
    }
    double sum = 0;
    int n = 0;
    for (int i = 0; i < nv; i++) {
      if (!t->vused[i]) continue;
      sum += vd[i] > 0 && vs[i] > 0 ? fabs(log((vd[i] / sd) / (vs[i] / ss))) : INFINITY;
      n++;
    }
    err = n ? sum / n : 0;
  }
  free(as), free(ad), free(vs), free(vd);
  return err;
}

/* The flow's per-face target densities (NULL for equal area; else caller frees *w). */
static int face_density(const au_mesh *m, const au_advect_opts *fo, double **w) {
  *w = NULL;
  if (!fo->face_weight && !fo->weight) return 0;
  if (!(*w = malloc(sizeof(double) * (size_t)m->nf))) return -1;
  for (int f = 0; f < m->nf; f++) (*w)[f] = density_of(m, fo, f);
  return 0;
}

/* The per-face mean |r - 1| of the map's triangles (map_face_areas) against the flow's targets
 * (au_metrics' r_mean_abs_dev, without its exclusion of degenerate faces). */
static double map_face_error(const au_mesh *m, const au_advect_opts *fo, const double *w, const double *P) {
  const int nf = m->nf, *F = m->F;
  double *as = malloc(sizeof(double) * (size_t)nf), *ad = malloc(sizeof(double) * (size_t)nf), err = INFINITY;
  if (as && ad && nf > 0) {
    au_dec_face_areas(nf, F, m->X, as);
    map_face_areas(nf, F, fo, P, ad);
    double ss = 0, sd = 0, sum = 0;
    for (int f = 0; f < nf; f++) as[f] *= w ? w[f] : 1.0, ss += as[f], sd += ad[f];
    for (int f = 0; f < nf; f++) sum += as[f] > 0 ? fabs((ad[f] / sd) / (as[f] / ss) - 1) : 0;
    err = sum / nf;
  }
  free(as), free(ad);
  return err;
}

/* The chord floor's excess (au_metrics.chord_floor_excess): the area by which faces' least chord areas
 * (au_dec_sphere_chord_floor) exceed their shares, as a fraction of the chord triangles' total; the
 * shares weighted by w (per face, NULL: equal area). NAN out of memory: both gates that read it (the
 * twisted retry's and the global polish's loss) then keep their default way. */
static double chord_floor_excess(const au_mesh *m, const double *w, const double *P) {
  const int nf = m->nf, *F = m->F;
  double *as = malloc(sizeof(double) * (size_t)nf), *ad = malloc(sizeof(double) * (size_t)nf), excess = NAN;
  if (as && ad) {
    au_dec_face_areas(nf, F, m->X, as);
    au_dec_face_areas(nf, F, P, ad);
    double ss = 0, sd = 0;
    for (int f = 0; f < nf; f++) as[f] *= w ? w[f] : 1.0, ss += as[f], sd += ad[f];
    excess = au_dec_sphere_floor_excess((size_t)nf, F, P, as, ss, sd, NULL);
  }
  free(as), free(ad);
  return excess;
}

au_status au_sphere_polish_map(const au_mesh *m, const au_topo *t, const au_sphere_opts *o, double *P,
                               au_sphere_report *rep, au_msg *msg) {
  double *w = NULL, *P2 = malloc(sizeof(double) * 3 * (size_t)m->nv);
  if (!P2 || face_density(m, &o->flow, &w) < 0) {
    free(P2);
    return au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
  }
  memcpy(P2, P, sizeof(double) * 3 * (size_t)m->nv);
  au_polish_opts po = {o->vertex_polish, o->polish_cells, o->flow.tol, o->flow.cancel, o->flow.sphere_areas == 2};
  au_status st = au_sphere_vertex_polish(m, t, w, P2, &po, &rep->polish_sweeps, msg);
  if (st == AU_OK) {
    rep->polish_err[0] = map_vertex_error(m, t, &o->flow, P);
    rep->polish_err[1] = map_vertex_error(m, t, &o->flow, P2);
    rep->polish_err[2] = map_face_error(m, &o->flow, w, P);
    rep->polish_err[3] = map_face_error(m, &o->flow, w, P2);
    rep->polish = 1;
    if (rep->polish_err[1] < rep->polish_err[0] && rep->polish_err[3] <= rep->polish_err[2]) {
      memcpy(P, P2, sizeof(double) * 3 * (size_t)m->nv);
      rep->polish = 2;
    }
  }
  /* The global polish, where the vertex polish left a chord map short of its tolerance: one vertex at a
   * time cannot widen or narrow a band as a whole (sphere/au_sphere_gpolish.c). */
  const double e = rep->polish == 2 ? rep->polish_err[1] : rep->polish_err[0];
  if (st == AU_OK && o->global_polish > 0 && o->flow.sphere_areas != 2 && e > o->flow.tol &&
      m->nv <= AU_GPOLISH_MAX_VERTICES) {
    memcpy(P2, P, sizeof(double) * 3 * (size_t)m->nv);
    au_gpolish_opts go = au_sphere_gpolish_settings(o->global_polish, AU_GPOLISH_ANGLE, o->flow.tol, o->flow.cancel);
    go.min_gain = AU_GPOLISH_MIN_GAIN;
    go.barrier = AU_GPOLISH_BARRIER, go.barrier_weight = AU_GPOLISH_BARRIER_WEIGHT;
    if (chord_floor_excess(m, w, P) <= AU_GPOLISH_ROBUST_BELOW) go.robust = AU_GPOLISH_ROBUST;
    go.face_window = AU_GPOLISH_FACE_WINDOW, go.face_gain = AU_GPOLISH_FACE_GAIN, go.face_target = AU_GPOLISH_FACE_TARGET;
    st = au_sphere_global_polish(m, t, w, P2, &go, &rep->global_polish_steps, msg);
    if (st == AU_OK) {
      double *g = rep->global_polish_err;
      g[0] = e, g[1] = map_vertex_error(m, t, &o->flow, P2);
      g[2] = rep->polish == 2 ? rep->polish_err[3] : rep->polish_err[2], g[3] = map_face_error(m, &o->flow, w, P2);
      rep->global_polish = 1, rep->global_polish_robust = go.robust;
      if (g[1] < g[0] && g[3] <= g[2]) {
        memcpy(P, P2, sizeof(double) * 3 * (size_t)m->nv);
        rep->global_polish = 2;
      }
    }
  }
  free(P2), free(w);
  return st;
}

/* 1 if a flow with the lantern (au_advect_opts.lantern > 0) from the same start could differ from the flow
 * that made report r, 0 if it would repeat it step for step. The lantern raises a face's shape restoring
 * only at the steps solved with restoring on and the vertex error low enough (r->lantern_steps counts
 * them): tpose's strong twisted start stays above that for its 24 spherical steps, and its lantern retry
 * ran the same 28 steps again to the same map (test_sphere.lantern_skipped checks the equality). */
static int lantern_would_act(const au_advect_report *r) { return r->lantern_steps > 0; }

/* A retry's outcome against the map kept so far (P, its vertex error e by map_vertex_error, *st): a
 * cancelled retry ends the map with its status; one whose map P2 has the lower error e2 replaces P, the
 * report's flow (r2) and the status. Returns 1 if it replaced. */
static int keep_better(int nv, au_status st2, double e2, const double *P2, const au_advect_report *r2, const au_msg *msg2,
                       double e, double *P, au_sphere_report *rep, au_status *st, au_msg *msg) {
  if (st2 == AU_E_CANCELLED) {
    *st = st2;
    if (msg) *msg = *msg2;
    return 0;
  }
  if (!(e2 < e)) return 0;
  memcpy(P, P2, sizeof(double) * 3 * (size_t)nv);
  rep->flow = *r2;
  *st = st2;
  if (msg) *msg = *msg2;
  return 1;
}

/* The twisted retry (au_sphere_opts.twist_retry): the map made again from the twisted start
 * (au_sphere_twisted, balanced), kept in place of P (error e by map_vertex_error) if its vertex error is
 * lower; rep->twist, twist_faces and twist_err say what happened. */
static void twisted_retry(const au_mesh *m, const au_topo *t, au_advect_plan *plan, const au_advect_domain *dom,
                          const au_sphere_opts *o, double e, double *P, au_sphere_report *rep, au_status *st, au_msg *msg) {
  au_advect_report *r3 = malloc(sizeof *r3);
  double *P3 = malloc(sizeof(double) * 3 * (size_t)m->nv);
  au_msg msg3 = {0};
  int nsheared = 0;
  au_status st3 = r3 && P3 ? au_sphere_twisted(m, t, P3, &nsheared, &msg3) : AU_E_NOMEM;
  if (st3 == AU_OK && nsheared > 0) {
    if (o->balance) st3 = au_sphere_balance(m, t, P3, &msg3);
    if (st3 == AU_OK) st3 = au_advect_run_plan(plan, dom, &o->flow, P3, r3, &msg3);
    double e3 = st3 == AU_OK || st3 == AU_W_NOT_CONVERGED ? map_vertex_error(m, t, &o->flow, P3) : INFINITY;
    rep->twist_faces = nsheared, rep->twist_err = e3;
    rep->twist = 1 + keep_better(m->nv, st3, e3, P3, r3, &msg3, e, P, rep, st, msg);
  }
  free(r3), free(P3);
}

/* The staged retry (au_sphere_opts.staged_retry). A single flow asks every cell for its whole way at
 * once (in steps of at most e^1.2): on a map with limbs squeezed by e^-20 beside an over-grown half, the
 * wanted motion is a radian or more, of which the step control lets 1-12% through, and the flow stands
 * still (tpose; docs/sphere.md). A flow towards a part of the way, run to its end, then the next
 * from there, keeps going. Each stage's targets are the map's own face areas times (share / area)^part;
 * the last run asks for the shares themselves, from the best stage's map. Its map replaces P (with its
 * report and status) if its vertex error (map_vertex_error) is lower. */
static void staged_retry(const au_mesh *m, const au_topo *t, au_advect_plan *plan, const au_advect_domain *dom,
                         const au_sphere_opts *o, const double *Pstart, double *P, au_sphere_report *rep, au_status *st,
                         au_msg *msg) {
  const int nv = m->nv, nf = m->nf;
  double *P2 = malloc(sizeof(double) * 3 * (size_t)nv), *Pb = malloc(sizeof(double) * 3 * (size_t)nv);
  double *w = malloc(sizeof(double) * (size_t)nf), *as = malloc(sizeof(double) * (size_t)nf);
  double *ad = malloc(sizeof(double) * (size_t)nf);
  au_advect_report *r2 = malloc(sizeof *r2);
  au_msg m2 = {0};
  if (!P2 || !Pb || !w || !as || !ad || !r2) goto done; /* out of memory: the map stays as it is */
  const double e0 = map_vertex_error(m, t, &o->flow, P);
  double eb = e0;
  int stages = 0, idle = 0;
  memcpy(P2, Pstart ? Pstart : P, sizeof(double) * 3 * (size_t)nv);
  memcpy(Pb, P, sizeof(double) * 3 * (size_t)nv);
  au_dec_face_areas(nf, m->F, m->X, as);
  double ss = 0;
  for (int f = 0; f < nf; f++) ss += as[f];
  au_advect_opts fo = o->flow;
  au_status s2 = AU_OK;
  for (int k = 0; k < o->staged_retry && idle < 2; k++) {
    map_face_areas(nf, m->F, &o->flow, P2, ad);
    double sd = 0;
    for (int f = 0; f < nf; f++) sd += ad[f];
    /* (area / share)^(1 - part) as the density: the target area is area^(1 - part) share^part. A face
     * the map has made degenerate asks for its share's part from nothing: the floor keeps it positive. */
    for (int f = 0; f < nf; f++) w[f] = pow(fmax((ad[f] / sd) / (as[f] / ss), 1e-300), 1 - AU_STAGED_PART);
    fo.face_weight = w;
    s2 = au_advect_run_plan(plan, dom, &fo, P2, r2, &m2);
    if (s2 == AU_E_CANCELLED) break;
    if (s2 < 0) break; /* a numerical failure: the best stage so far stands */
    stages++;
    double e = map_vertex_error(m, t, &o->flow, P2);
    if (e < (1 - AU_STAGED_GAIN) * eb) idle = 0;
    else idle++;
    if (e < eb) eb = e, memcpy(Pb, P2, sizeof(double) * 3 * (size_t)nv);
  }
  rep->staged = 1, rep->staged_stages = stages, rep->staged_err[0] = e0, rep->staged_err[1] = e0;
  if (s2 == AU_E_CANCELLED) {
    *st = s2;
    if (msg) *msg = m2;
    goto done;
  }
  if (!(eb < e0)) goto done;
  /* The last run, towards the shares themselves. */
  memcpy(P2, Pb, sizeof(double) * 3 * (size_t)nv);
  s2 = au_advect_run_plan(plan, dom, &o->flow, P2, r2, &m2);
  double e = s2 == AU_OK || s2 == AU_W_NOT_CONVERGED ? map_vertex_error(m, t, &o->flow, P2) : INFINITY;
  rep->staged_err[1] = e;
  if (keep_better(nv, s2, e, P2, r2, &m2, e0, P, rep, st, msg)) rep->staged = 2;
done:
  free(P2), free(Pb), free(w), free(as), free(ad), free(r2);
}

/* The start: coarse-to-fine where asked (one that fails leaves the conformal start to make the map: no
 * mesh is refused for its start), else the conformal start; where every conformal attempt folds, the
 * strong twisted start; a conformal start then balanced (o->balance). *ml_done: the coarse-to-fine start made it; *strong: the strong
 * twisted start did, with this many sheared faces. */
static au_status sphere_start(const au_mesh *m, const au_topo *t, const au_sphere_opts *o, double *P,
                              au_sphere_report *rep, int *ml_done, int *strong, au_msg *msg) {
  au_status st = AU_OK;
  *ml_done = 0, *strong = 0;
  if (o->start == AU_SPHERE_START_MULTILEVEL && !o->flow.face_weight) {
    au_msg msg1 = {0};
    au_status s1 = au_sphere_multilevel(m, t, o, P, &rep->ml, &msg1);
    if (s1 == AU_OK) *ml_done = 1, rep->start = AU_SPHERE_START_MULTILEVEL;
    else if (s1 == AU_E_CANCELLED || s1 == AU_E_NOMEM) {
      if (msg) *msg = msg1;
      return s1;
    } else
      rep->ml_fallback = msg1;
  }
  if (!*ml_done) st = au_sphere_conformal(m, t, P, msg);
  if (st == AU_E_FOLD && o->twist_retry > 0) {
    /* Every conformal attempt folded (nested protrusions squeezed past any coordinate): the strong
     * twisted start, if it does not fold, is the start. */
    au_msg msg1 = {0};
    int nsheared = 0;
    if (au_sphere_twisted_strong(m, t, P, &nsheared, &msg1) == AU_OK && nsheared > 0) st = AU_OK, *strong = nsheared;
  }
  if (st == AU_OK && o->balance && !*ml_done) st = au_sphere_balance(m, t, P, msg);
  return st;
}

/* The lantern retry (au_sphere_opts.lantern_retry): the flow again from the start with the lantern on,
 * resumed from the first flow's state where the lantern first acts (fork, if recorded); the better map
 * kept. *ek: the kept map's vertex error. */
static void lantern_retry(const au_mesh *m, const au_topo *t, au_advect_plan *plan, const au_advect_domain *dom,
                          const au_sphere_opts *o, const double *Pstart, const au_advect_fork *fork, double *P, double *ek,
                          au_sphere_report *rep, au_status *st, au_msg *msg) {
  au_advect_report *r2 = malloc(sizeof *r2);
  double *P2 = malloc(sizeof(double) * 3 * (size_t)m->nv);
  au_msg msg2 = {0};
  if (r2 && P2) {
    au_advect_opts o2 = o->flow;
    o2.lantern = o->lantern_retry;
    /* The steps before the lantern first acts are the first flow's: the retry starts where they end. */
    o2.fork_resume = fork;
    memcpy(P2, Pstart, sizeof(double) * 3 * (size_t)m->nv);
    au_status st2 = au_advect_run_plan(plan, dom, &o2, P2, r2, &msg2);
    double e1 = st2 == AU_OK || st2 == AU_W_NOT_CONVERGED ? map_vertex_error(m, t, &o->flow, P2) : INFINITY;
    rep->retry_err[0] = *ek, rep->retry_err[1] = e1;
    rep->retry = 1 + keep_better(m->nv, st2, e1, P2, r2, &msg2, *ek, P, rep, st, msg);
    if (rep->retry == 2) *ek = e1;
    if (rep->twist == 3) rep->twist_err = *ek;
  }
  free(r2), free(P2);
}

/* The retries, for a first flow that missed its tolerance (*st AU_W_NOT_CONVERGED, its map's vertex error
 * e0): the twisted and lantern retries only where the map before them misses the tolerance well
 * (retry_above), the staged retry where it misses it and is squeezed; each map kept only where it is
 * better (docs/sphere-stages.md, docs/sphere-retries.md). Pstart: the start (NULL: no lantern retry, and
 * the staged retry starts from P). */
static void sphere_retries(const au_mesh *m, const au_topo *t, au_advect_plan *plan, const au_advect_domain *dom,
                           const au_sphere_opts *o, const double *Pstart, const au_advect_fork *fork, int ml_done, int strong,
                           double e0, double *P, au_sphere_report *rep, au_status *st, au_msg *msg) {
  const double well = o->retry_above * o->flow.tol;
  /* The twisted retry (au_sphere_opts.twist_retry): from the twisted start, for a map that misses its
   * tolerance well with much of its chord area on the floor (the floor excess is the gate: nearly every
   * mesh has faces to shear, near the puncture if nowhere else). It comes before the lantern retry, which
   * then runs only if the twisted map was not kept: after the first flow the generated limbs' excess is
   * 0.11-0.36 and the shared meshes' at most 0.019 (screwdriver), and on every mesh past the gate the
   * lantern's map was discarded and the twisted one kept (limbs4, limbs8, coil, hammer), so the lantern's
   * flow was spent for nothing there (docs/sphere-stages.md). */
  const int twist_gate = !strong && o->twist_retry > 0 && e0 > well;
  if (twist_gate && chord_floor_excess(m, NULL, P) > o->twist_retry) twisted_retry(m, t, plan, dom, o, e0, P, rep, st, msg);
  /* The lantern retry: only for a map that misses its tolerance well, and not from the coarse-to-fine
   * start, which squeezes no protrusion for the lantern to open: from it the retry returned the same map
   * (spot, cow, screwdriver, hand_closed) or a worse one (bunny), and its one better map (penguin_hr) was
   * replaced by the twisted retry's (bench/coarse-to-fine.md). */
  double ek = rep->twist == 2 ? rep->twist_err : e0;
  int lantern_due = *st == AU_W_NOT_CONVERGED && Pstart && !ml_done && rep->twist != 2 && ek > well;
  /* ... and not where its flow would repeat the first one's (the first flow's map, not the twisted
   * retry's, which was not kept here). */
  if (lantern_due && !lantern_would_act(&rep->flow)) lantern_due = 0, rep->lantern_skipped = 1;
  /* The staged retry (below) before the lantern's where the map is squeezed enough for it: the staged
   * flows start from the start, not from the map, and where their map was kept the lantern's had been
   * made for nothing (octopus: lantern kept, then replaced by the staged map; docs/sphere-retries.md). */
  const int staged_allowed = o->staged_retry > 0 && !o->flow.weight && !o->flow.face_weight;
  int staged_done = 0, nsq = 0;
  if (lantern_due && staged_allowed && au__metrics_squeezed(m->nv, m->nf, m->X, P, m->F, &nsq) >= AU_STAGED_SQUEEZED) {
    staged_retry(m, t, plan, dom, o, Pstart, P, rep, st, msg);
    staged_done = 1;
    if (rep->staged == 2) ek = rep->staged_err[1], lantern_due = 0;
    if (*st != AU_W_NOT_CONVERGED) lantern_due = 0;
  }
  if (lantern_due) lantern_retry(m, t, plan, dom, o, Pstart, fork, P, &ek, rep, st, msg);
  /* A map the lantern did not bring within the gate may still have its floor excess past it. */
  if (twist_gate && !rep->twist && *st == AU_W_NOT_CONVERGED && ek > well && chord_floor_excess(m, NULL, P) > o->twist_retry)
    twisted_retry(m, t, plan, dom, o, ek, P, rep, st, msg);
  if (*st == AU_W_NOT_CONVERGED && staged_allowed && !staged_done &&
      au__metrics_squeezed(m->nv, m->nf, m->X, P, m->F, &nsq) >= AU_STAGED_SQUEEZED)
    staged_retry(m, t, plan, dom, o, Pstart, P, rep, st, msg);
}

au_status au_sphere_map(const au_mesh *m, const au_topo *t, const au_sphere_opts *opts, double *P, double *P0,
                        au_sphere_report *rep, au_msg *msg) {
  if (!m || !t || !P) return au_msg_set(msg, AU_E_ARG, "sphere: bad arguments");
  au_sphere_opts o = opts ? *opts : au_sphere_opts_default();
  au_sphere_report local;
  if (!rep) rep = &local;
  memset(rep, 0, sizeof *rep);
  const size_t bytes = sizeof(double) * 3 * (size_t)m->nv;
  double t0 = now_s();
  /* The flow's analysis needs only the mesh: it runs in a second thread beside the start. */
  au_advect_plan *plan = NULL;
  au_status st = au_advect_plan_start(m, t, &o.flow, &plan, msg);
  int ml_done = 0, strong = 0;
  if (st == AU_OK) st = sphere_start(m, t, &o, P, rep, &ml_done, &strong, msg);
  /* The flows from the coarse-to-fine start keep the resolved schedule they were tuned with: the
   * sphere's shorter one took cow's map from per-face 0.0140 to 0.0190 there (docs/flow-tail.md). */
  if (ml_done) au_advect_plain_schedule(&o.flow);
  /* The chord polish cut short where the vertex polish follows, unless angle steps do (they start from
   * the flow's end). */
  if (o.vertex_polish > 0 && o.flow.angle_steps == 0 && o.flow.polish_steps == 0) o.flow.polish_steps = AU_SPHERE_POLISH_STEPS;
  rep->t_init = now_s() - t0;
  if (st == AU_OK) {
    if (P0) memcpy(P0, P, bytes);
    au_advect_domain dom = au_sphere_domain();
    t0 = now_s();
    /* The lantern retry starts from the start. */
    double *Pstart = NULL;
    if (o.lantern_retry > 0 && o.flow.lantern == 0 && !(Pstart = malloc(bytes))) st = au_msg_set(msg, AU_E_NOMEM, "sphere: out of memory");
    if (Pstart) memcpy(Pstart, P, bytes);
    /* The first flow records its state where a lantern would first act, for the lantern retry to
     * resume from (without it, that retry repeats those steps from the start). */
    au_advect_fork *fork = Pstart ? au_advect_fork_new() : NULL;
    au_advect_opts first = o.flow;
    first.fork_record = fork;
    if (st == AU_OK) st = au_advect_run_plan(plan, &dom, &first, P, &rep->flow, msg);
    double e0 = st == AU_W_NOT_CONVERGED ? map_vertex_error(m, t, &o.flow, P) : 0;
    if (strong && (st == AU_OK || st == AU_W_NOT_CONVERGED)) rep->twist = 3, rep->twist_faces = strong, rep->twist_err = e0;
    if (st == AU_W_NOT_CONVERGED) sphere_retries(m, t, plan, &dom, &o, Pstart, fork, ml_done, strong, e0, P, rep, &st, msg);
    au_advect_fork_free(&fork);
    free(Pstart);
    if (st == AU_W_NOT_CONVERGED && o.vertex_polish > 0) {
      au_status sp = au_sphere_polish_map(m, t, &o, P, rep, msg);
      if (sp != AU_OK) st = sp;
      else if ((rep->polish == 2 && rep->polish_err[1] <= o.flow.tol) ||
               (rep->global_polish == 2 && rep->global_polish_err[1] <= o.flow.tol))
        st = AU_OK, rep->flow.converged = 1;
    }
    rep->t_flow = now_s() - t0;
  }
  au_advect_plan_free(&plan);
  return st;
}
