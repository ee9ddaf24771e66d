/* au_sphere_map.c - the sphere pipeline: conformal start, balancing, tangent-plane Lie advection with
 * reprojection onto the unit sphere (Zou et al. 2011, sec. 4.5.2, eq. 21-22). */
#include <math.h>
#include <string.h>
#include <time.h>

#include "au_sphere.h"

au_sphere_opts au_sphere_opts_default(void) {
  au_sphere_opts o;
  memset(&o, 0, sizeof o);
  o.flow = au_advect_opts_default();
  o.balance = 1;
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
  au_advect_domain d = {sphere_constrain, sphere_retract, 1, NULL, 0};
  return d;
}

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

au_status au_sphere_map(const au_mesh *m, const au_topo *t, const au_sphere_opts *opts, double *P, double *P0,
                        au_sphere_report *rep, au_msg *msg) {
  if (!m || !t || !P) return au_msg_set(msg, AU_E_ARG, "sphere: bad arguments");
  au_sphere_opts o = opts ? *opts : au_sphere_opts_default();
  au_sphere_report local;
  if (!rep) rep = &local;
  memset(rep, 0, sizeof *rep);
  double t0 = now_s();
  /* The flow's analysis needs only the mesh: it runs in a second thread beside the conformal start. */
  au_advect_plan *plan = NULL;
  au_status st = au_advect_plan_start(m, t, &o.flow, &plan, msg);
  if (st == AU_OK) st = au_sphere_conformal(m, t, P, msg);
  if (st == AU_OK && o.balance) st = au_sphere_balance(m, t, P, msg);
  rep->t_init = now_s() - t0;
  if (st == AU_OK) {
    if (P0) memcpy(P0, P, sizeof(double) * 3 * (size_t)m->nv);
    au_advect_domain dom = au_sphere_domain();
    t0 = now_s();
    st = au_advect_run_plan(plan, &dom, &o.flow, P, &rep->flow, msg);
    rep->t_flow = now_s() - t0;
  }
  au_advect_plan_free(&plan);
  return st;
}
