/* au_disk_map.c - the planar domains' boundary constraints (paper 4.5.1: tangential velocity, radial
 * projection back onto the circle; square sides: velocity along the side, corners fixed) and the
 * disk, annulus and square pipelines on the shared Lie-advection loop. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "au_disk_internal.h"

au_status au_disk_bc_alloc(int nv, au_disk_bc **out) {
  if (!out || nv <= 0) return AU_E_ARG;
  *out = NULL;
  au_disk_bc *bc = calloc(1, sizeof *bc);
  if (!bc) return AU_E_NOMEM;
  bc->nv = nv;
  bc->kind = calloc((size_t)nv, 1);
  bc->value = calloc((size_t)nv, sizeof(double));
  bc->lo = 0, bc->hi = 1;
  if (!bc->kind || !bc->value) {
    au_disk_bc_free(&bc);
    return AU_E_NOMEM;
  }
  *out = bc;
  return AU_OK;
}

void au_disk_bc_free(au_disk_bc **bc) {
  if (!bc || !*bc) return;
  free((*bc)->kind);
  free((*bc)->value);
  free(*bc);
  *bc = NULL;
}

static void bc_constrain(void *ctx, int i, const double *p, double *d) {
  const au_disk_bc *bc = ctx;
  d[2] = 0;
  switch (bc->kind[i]) {
    case AU_BC_CIRCLE: {
      double r2 = p[0] * p[0] + p[1] * p[1];
      if (r2 > 0) {
        double s = (d[0] * p[0] + d[1] * p[1]) / r2;
        d[0] -= s * p[0], d[1] -= s * p[1];
      }
      break;
    }
    case AU_BC_XSIDE: d[0] = 0; break;
    case AU_BC_YSIDE: d[1] = 0; break;
    case AU_BC_FIXED: d[0] = d[1] = 0; break;
    default: break;
  }
}

static double clamp(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }

static void bc_retract(void *ctx, int i, double *p) {
  const au_disk_bc *bc = ctx;
  p[2] = 0;
  switch (bc->kind[i]) {
    case AU_BC_CIRCLE: {
      double r = hypot(p[0], p[1]);
      if (r > 0) {
        double s = bc->value[i] / r;
        p[0] *= s, p[1] *= s;
      }
      break;
    }
    case AU_BC_XSIDE: p[0] = bc->value[i], p[1] = clamp(p[1], bc->lo, bc->hi); break;
    case AU_BC_YSIDE: p[1] = bc->value[i], p[0] = clamp(p[0], bc->lo, bc->hi); break;
    default: break;
  }
}

au_advect_domain au_disk_bc_domain(const au_disk_bc *bc) {
  au_advect_domain d = {bc_constrain, bc_retract, 0, (void *)bc, 0, NULL, NULL};
  /* Vertices sliding on circles about the origin (disk, annulus): the flow moves along arcs, bent fully
   * from the smallest circle outward (au_advect_domain.arc_radius), so that the thin triangles at a
   * short boundary turn with their sliding corner. A fixed boundary does not slide and keeps straight
   * moves, which suit it better (docs/flow.md). */
  for (int i = 0; i < bc->nv; i++)
    if (bc->kind[i] == AU_BC_CIRCLE && (d.arc_radius == 0 || bc->value[i] < d.arc_radius)) d.arc_radius = bc->value[i];
  return d;
}

au_disk_opts au_disk_opts_default(void) {
  au_disk_opts o;
  memset(&o, 0, sizeof o);
  o.flow = au_advect_opts_default();
  /* The measurements behind these planar defaults are in docs/flow.md. */
  /* Planar maps stop earlier than the loop's own defaults: the planar maps reach these bounds in a
   * fraction of the budget, and every map then ends below per-face 0.01 anyway. */
  o.flow.tol = 3e-3;
  o.flow.face_tol = 1e-2;
  /* The angle steps (--angles) come after the flow here, not at a vertex error of 0.01 as on the
   * sphere: handed over early, the planar maps ended with worse angles and worse faces. */
  o.flow.angle_switch = 0;
  /* In the plane a vertex may move up to 0.45 of its triangles' inradius per step (the loop's bound is
   * 1/2): fewer steps for the same quality. The sphere keeps 0.3, where the retraction's curvature
   * needs the margin. */
  o.flow.max_move = 0.45;
  /* The shear weight's floor: the flow's default 0.01 held the planar maps' last steps back (per-face
   * error creeping down by 1-2% a step once the vertex cells met the tolerance); 0.003 takes a third
   * fewer steps for a lower per-face error and angles within a degree. On the sphere the same floor
   * costs the protrusion meshes their quality, so it stays there. */
  o.flow.shear_tail = 0.003;
  /* On the resolved schedule the planar flow starts at the ordinary shear weight: the sphere's 0.1 took
   * more steps on the planar meshes. */
  o.flow.resolved_shear = o.flow.shear;
  o.boundary = AU_DISK_SLIDE;
  o.inner_radius = 0;
  o.outer_loop = -1;
  for (int q = 0; q < 4; q++) o.corners[q] = -1;
  return o;
}

/* Run the flow from the initial map in P with constraints bc; fills rep's flow part. */
static au_status run_flow(const au_mesh *m, au_advect_plan *plan, const au_disk_opts *o, const au_disk_bc *bc, double *P,
                          double *P0, au_disk_report *rep, au_msg *msg) {
  if (P0) memcpy(P0, P, sizeof(double) * 3 * (size_t)m->nv);
  au_advect_domain dom = au_disk_bc_domain(bc);
  double t0 = au__disk_now();
  au_status st = au_advect_run_plan(plan, &dom, &o->flow, P, &rep->flow, msg);
  rep->t_flow = au__disk_now() - t0;
  return st;
}

/* Common start of the three pipelines. */
#define AU_DISK_BEGIN(name, loops)                                                                  \
  if (!m || !t || !P || t->nv != m->nv || t->nloops != (loops))                                     \
    return au_msg_set(msg, AU_E_ARG, name ": bad arguments");                                       \
  au_disk_opts o = opts ? *opts : au_disk_opts_default();                                           \
  au_disk_report local;                                                                             \
  if (!rep) rep = &local;                                                                           \
  memset(rep, 0, sizeof *rep);                                                                      \
  au_disk_bc *bc = NULL;                                                                            \
  if (au_disk_bc_alloc(m->nv, &bc) != AU_OK) return au_msg_set(msg, AU_E_NOMEM, name ": out of memory"); \
  double t0 = au__disk_now();                                                                       \
  /* The flow's analysis needs only the mesh: it runs in a second thread beside the initial map. */  \
  au_advect_plan *plan = NULL;                                                                      \
  au_status st0 = au_advect_plan_start(m, t, &o.flow, &plan, msg);                                  \
  if (st0 != AU_OK) {                                                                               \
    au_disk_bc_free(&bc);                                                                           \
    return st0;                                                                                     \
  }

au_status au_disk_map(const au_mesh *m, const au_topo *t, const au_disk_opts *opts, double *P, double *P0,
                      au_disk_report *rep, au_msg *msg) {
  AU_DISK_BEGIN("disk", 1)
  au_status st = au_disk_init(m, t, P, &rep->init, msg);
  rep->t_init = au__disk_now() - t0;
  if (st == AU_OK) {
    for (int k = t->loop_start[0]; k < t->loop_start[1]; k++) {
      int v = t->loop_vert[k];
      bc->kind[v] = o.boundary == AU_DISK_FIXED ? AU_BC_FIXED : AU_BC_CIRCLE, bc->value[v] = 1;
    }
    /* A rotation of the disk changes no area and no angle: with the whole boundary sliding it is an
     * exact null mode of the flow's step system, held only by the loop's small kinetic term. Holding
     * one boundary vertex removes it and costs nothing, the map being defined up to rotation. */
    bc->kind[t->loop_vert[t->loop_start[0]]] = AU_BC_FIXED;
    st = run_flow(m, plan, &o, bc, P, P0, rep, msg);
  }
  au_advect_plan_free(&plan);
  au_disk_bc_free(&bc);
  return st;
}

au_status au_annulus_map(const au_mesh *m, const au_topo *t, const au_disk_opts *opts, double *P, double *P0,
                         au_disk_report *rep, au_msg *msg) {
  AU_DISK_BEGIN("annulus", 2)
  int outer = o.outer_loop;
  if (outer < 0) outer = t->loop_len && t->loop_len[1] > t->loop_len[0] ? 1 : 0;
  au_status st = AU_OK;
  if (outer > 1 || !(o.inner_radius >= 0 && o.inner_radius < 1))
    st = au_msg_set(msg, AU_E_ARG, "annulus: outer loop %d or inner radius %g out of range", outer, o.inner_radius);
  rep->outer_loop = outer;
  if (st == AU_OK)
    st = au_annulus_init(m, t, outer, o.inner_radius, P, &rep->inner_radius, &rep->modulus_radius, &rep->init, msg);
  rep->t_init = au__disk_now() - t0;
  if (st == AU_OK) {
    for (int l = 0; l < 2; l++)
      for (int k = t->loop_start[l]; k < t->loop_start[l + 1]; k++) {
        int v = t->loop_vert[k];
        bc->kind[v] = o.boundary == AU_DISK_FIXED ? AU_BC_FIXED : AU_BC_CIRCLE;
        bc->value[v] = l == outer ? 1 : rep->inner_radius;
      }
    /* The rigid rotation, as for the disk: one vertex of the outer loop holds still. */
    bc->kind[t->loop_vert[t->loop_start[outer]]] = AU_BC_FIXED;
    st = run_flow(m, plan, &o, bc, P, P0, rep, msg);
  }
  au_advect_plan_free(&plan);
  au_disk_bc_free(&bc);
  return st;
}

au_status au_square_map(const au_mesh *m, const au_topo *t, const au_disk_opts *opts, double *P, double *P0,
                        au_disk_report *rep, au_msg *msg) {
  AU_DISK_BEGIN("square", 1)
  /* The square keeps the flow's ordinary schedule. On the resolved one (au_advect_opts.resolved_jump)
   * the fixed sides came out ahead of the sliding ones where both flows stop, at the tolerance
   * (param-eval per-face mean |r-1|, sliding / fixed: face 0.0092 / 0.0090, mountain 0.0052 / 0.0039;
   * ordinary schedule 0.0091 / 0.0098 and 0.0048 / 0.0056). */
  o.flow.resolved_jump = 0;
  au_status st = AU_OK;
  int c[4];
  memcpy(c, o.corners, sizeof c);
  if (c[0] < 0) st = au_square_corners(m, t, c, msg);
  else st = au_square_order_corners(t, c, msg);
  memcpy(rep->corners, c, sizeof c);
  if (st == AU_OK) st = au_square_init(m, t, c, P, &rep->init, msg);
  rep->t_init = au__disk_now() - t0;
  if (st == AU_OK) {
    int n = t->loop_start[1] - t->loop_start[0], side = -1;
    const int *L = t->loop_vert + t->loop_start[0];
    int k0 = 0;
    while (L[k0] != c[0]) k0++;
    /* Walk the loop from corner 0: each corner starts the next side. */
    for (int j = 0; j < n; j++) {
      int v = L[(k0 + j) % n];
      if (side < 3 && v == c[side + 1]) {
        side++;
        bc->kind[v] = AU_BC_FIXED;
        continue;
      }
      if (o.boundary == AU_DISK_FIXED) {
        bc->kind[v] = AU_BC_FIXED;
      } else if (side == 0 || side == 2) {
        bc->kind[v] = AU_BC_YSIDE, bc->value[v] = side == 0 ? 0 : 1;
      } else {
        bc->kind[v] = AU_BC_XSIDE, bc->value[v] = side == 1 ? 1 : 0;
      }
    }
    st = run_flow(m, plan, &o, bc, P, P0, rep, msg);
  }
  au_advect_plan_free(&plan);
  au_disk_bc_free(&bc);
  return st;
}
