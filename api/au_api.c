/* au_api.c - the small parts of the public API (include/authalic.h): version, memory, mesh files,
 * target names and the mesh check, the options' defaults and presets. The map itself is au_map.c. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "au_api_internal.h"
#include "au_disk.h"
#include "au_io.h"
#include "au_sphere.h"

#ifndef AU_VERSION
#define AU_VERSION "unknown"
#endif

const char *au_version(void) { return AU_VERSION; }

void au_free(void *p) { free(p); }

size_t au_struct_size(const char *name) {
  static const struct {
    const char *name;
    size_t size;
  } sizes[] = {{"au_options", sizeof(au_options)},         {"au_expert", sizeof(au_expert)},
               {"au_result", sizeof(au_result)},           {"au_metrics", sizeof(au_metrics)},
               {"au_convergence", sizeof(au_convergence)}, {"au_mesh", sizeof(au_mesh)},
               {"au_msg", sizeof(au_msg)},                 {"au_write_opts", sizeof(au_write_opts)},
               {"au_report_extra", sizeof(au_report_extra)}, {"au_tex_layout", sizeof(au_tex_layout)},
               {"au_tex_mesh", sizeof(au_tex_mesh)},       {"au_view_input", sizeof(au_view_input)},
               {"au_atlas_options", sizeof(au_atlas_options)}, {"au_atlas_result", sizeof(au_atlas_result)}};
  for (size_t k = 0; name && k < sizeof sizes / sizeof sizes[0]; k++)
    if (strcmp(name, sizes[k].name) == 0) return sizes[k].size;
  return 0;
}

au_status au_mesh_read(const char *path, au_mesh **out, au_msg *msg) { return au_io_read(path, out, msg); }

au_write_opts au_write_opts_default(void) {
  au_io_write_opts d = au_io_write_opts_default();
  au_write_opts o;
  memset(&o, 0, sizeof o);
  o.uv = d.uv, o.precision = d.precision;
  o.nvt = d.nvt, o.vt = d.vt, o.Ft = d.Ft;
  return o;
}

au_status au_mesh_write(const char *path, int nv, const double *V, int nf, const int *F, const au_write_opts *opts,
                        au_msg *msg) {
  if (!path || nv <= 0 || nf <= 0 || !V || !F) return au_msg_set(msg, AU_E_ARG, "au_mesh_write: bad arguments");
  /* The writer takes positions and faces through a mesh; it reads them only. */
  au_mesh m = {nv, nf, (double *)V, (int *)F};
  au_io_write_opts w = au_io_write_opts_default();
  if (opts) {
    w.uv = opts->uv, w.precision = opts->precision, w.nvt = opts->nvt, w.vt = opts->vt, w.Ft = opts->Ft;
    w.format = opts->format, w.meta = opts->meta, w.geometric_type = opts->geometric_type;
  }
  if (!opts || opts->radius == 0 || opts->radius == 1) return au_io_write(path, &m, V, &w, msg);
  if (!(opts->radius > 0) || opts->radius > 1e30) return au_msg_set(msg, AU_E_ARG, "au_mesh_write: radius %g", opts->radius);
  double *S = malloc(3 * (size_t)nv * sizeof *S);
  if (!S) return au_msg_set(msg, AU_E_NOMEM, "out of memory writing '%s'", path);
  for (size_t i = 0; i < 3 * (size_t)nv; i++) S[i] = opts->radius * V[i];
  au_status st = au_io_write(path, &m, S, &w, msg);
  free(S);
  return st;
}

au_status au_write_text(const char *path, const char *text, size_t len, au_msg *msg) {
  return au_io_write_text(path, text, len, msg);
}

int au_mesh_can_write(const char *path) { return path ? au_io_can_write(path) : 0; }

static const char *const target_names[] = {"sphere", "disk", "annulus", "square", "torus", "circles"};

const char *au_target_name(au_target t) {
  return (int)t >= 0 && (int)t < (int)(sizeof target_names / sizeof target_names[0]) ? target_names[t] : NULL;
}

au_mesh_expect au__target_expect(au_target t) {
  au_mesh_expect ex = au_mesh_expect_default();
  ex.loops = t == AU_TARGET_SPHERE || t == AU_TARGET_TORUS ? 0 : t == AU_TARGET_ANNULUS ? 2 : t == AU_TARGET_CIRCLES ? -1 : 1;
  ex.genus = t == AU_TARGET_TORUS ? 1 : 0;
  ex.command = au_target_name(t);
  return ex;
}

au_status au_mesh_check(const double *V, int nv, const int *F, int nf, au_target t, au_msg *msg) {
  if (!au_target_name(t)) return au_msg_set(msg, AU_E_ARG, "unknown target %d", (int)t);
  if (nv < 0 || nf < 0 || (nv > 0 && !V) || (nf > 0 && !F)) return au_msg_set(msg, AU_E_ARG, "bad mesh arrays");
  /* au_map re-orients its copy of the faces; the check does the same on a copy of its own, so that it
   * says what the map would do (a warning) rather than refuse. */
  int *Fo = malloc((size_t)(nf > 0 ? nf : 1) * 3 * sizeof *Fo);
  if (!Fo) return au_msg_set(msg, AU_E_NOMEM, "out of memory checking the mesh");
  if (nf > 0) memcpy(Fo, F, (size_t)nf * 3 * sizeof *Fo);
  au_mesh m = {nv, nf, (double *)V, Fo};
  au_msg om = {{0}};
  au_status so = au_mesh_orient(&m, NULL, &om);
  au_mesh_expect ex = au__target_expect(t);
  au_status s = au_mesh_validate(&m, &ex, NULL, msg);
  free(Fo);
  /* Validation names the problems in its own order; the faces still disagree only where the walk found
   * the surface non-orientable, which the walk names. */
  if (s < 0 && (s != AU_E_ORIENTATION || so >= 0)) return s;
  if (so < 0) {
    if (msg) *msg = om;
    return so;
  }
  if (so > 0) {
    if (s > 0 && msg) {
      char rest[sizeof msg->text];
      snprintf(rest, sizeof rest, "%s", msg->text);
      au_msg_set(msg, so, "%s; %s", om.text, rest);
    } else if (msg) {
      *msg = om;
    }
    return so;
  }
  return s;
}

void au_target_defaults(au_target t, int *max_steps, double *tol) {
  au_advect_opts f;
  au_sphere_opts s;
  au__flow_defaults(t, 0, &f, &s);
  if (max_steps) *max_steps = f.max_steps;
  if (tol) *tol = f.tol;
}

au_options au_options_default(void) {
  au_options o;
  memset(&o, 0, sizeof o);
  o.tol = -1;
  o.restore_shapes = -1;
  o.balance = 1;
  o.boundary = AU_BOUNDARY_SLIDE;
  o.outer_loop = AU_OUTER_LONGER;
  o.measure_start = 1;
  for (int k = 0; k < 4; k++) o.corners[k] = -1;
  return o;
}

/* The angle preset's step count: five steps took spot's mean angle error from 28.7 to 25.4 degrees
 * with the vertex cells within 1e-4; more steps gain little (docs/flow.md). */
#define AU_PRESET_ANGLE_STEPS 5

au_options au_options_preset(au_preset p) {
  au_options o = au_options_default();
  if (p == AU_PRESET_REFINE_FACES) o.refine_faces = 1;
  if (p == AU_PRESET_ANGLES) o.angle_steps = AU_PRESET_ANGLE_STEPS;
  return o;
}

/* The planar --refine-faces values: the per-face stop of the sphere (1e-3; the planar 1e-2 would end
 * the refinement), and a shear weight allowed down to 3e-4 once the vertex cells are equal. */
#define AU_PLANAR_REFINE_SHEAR_TAIL 3e-4
/* Refinement goes on while it gains 2% in four steps: as long as anything happens. */
#define AU_REFINE_FACE_GAIN 0.02

void au__flow_defaults(au_target t, int refine_faces, au_advect_opts *flow, au_sphere_opts *sphere) {
  memset(sphere, 0, sizeof *sphere);
  if (t == AU_TARGET_SPHERE) {
    *sphere = au_sphere_opts_default();
    *flow = sphere->flow;
    /* For accuracy, not speed: the ordinary schedule (on the resolved one the chord polish stalled on
     * undone steps), the polish whenever the chord error is larger and to its own end (not cut short
     * where the vertex polish follows), the angle steps after it all. */
    if (refine_faces)
      flow->face_gain = AU_REFINE_FACE_GAIN, flow->polish_gap = 0, flow->resolved_jump = 0, flow->angle_switch = 0,
      flow->polish_steps = AU_ADVECT_MAX_STEPS;
  } else {
    au_disk_opts d = au_disk_opts_default();
    *flow = d.flow;
    if (refine_faces)
      flow->face_gain = AU_REFINE_FACE_GAIN, flow->face_tol = au_advect_opts_default().face_tol, flow->resolved_jump = 0,
      flow->face_shear_tail = AU_PLANAR_REFINE_SHEAR_TAIL, flow->angle_switch = 0;
  }
}

/* The tuning fields, copied one way or the other by the same list so the two directions cannot drift. */
#define AU_EXPERT_FIELDS(X)                                                                                           \
  X(shear) X(shear_tail) X(face_shear_tail) X(schedule_steps) X(max_log_step) X(newton_below) X(face_steps)          \
  X(face_tol) X(face_damping) X(max_move) X(face_gain) X(sphere_areas) X(polish_gap) X(restore) X(lantern)           \
  X(resolved_jump) X(resolved_shear) X(resolved_decay) X(resolved_log_step) X(angle_faces) X(angle_cells)            \
  X(angle_trust) X(angle_switch)

au_expert au_expert_default(au_target t, int refine_faces) {
  au_advect_opts f;
  au_expert e;
  memset(&e, 0, sizeof e);
  au_sphere_opts s;
  au__flow_defaults(t, refine_faces, &f, &s);
  e.lantern_retry = s.lantern_retry, e.retry_above = s.retry_above, e.twist_retry = s.twist_retry;
  e.vertex_polish = s.vertex_polish, e.polish_cells = s.polish_cells, e.staged_retry = s.staged_retry;
  e.global_polish = s.global_polish;
  e.method = (int)f.method;
#define AU_FROM_FLOW(name) e.name = f.name;
  AU_EXPERT_FIELDS(AU_FROM_FLOW)
#undef AU_FROM_FLOW
  return e;
}

void au__flow_from_expert(const au_expert *e, au_advect_opts *f) {
  f->method = e->method == 1 ? AU_ADVECT_POISSON : AU_ADVECT_LEAST_SHEAR;
#define AU_TO_FLOW(name) f->name = e->name;
  AU_EXPERT_FIELDS(AU_TO_FLOW)
#undef AU_TO_FLOW
  /* The sphere's shorter resolved schedule stands in for three of these where the caller left them at
   * their defaults; one the caller set holds on that schedule too. */
  const au_advect_opts d = au_advect_opts_default();
  if (e->schedule_steps != d.schedule_steps) f->sphere_resolved_schedule_steps = e->schedule_steps;
  if (e->resolved_log_step != d.resolved_log_step) f->sphere_resolved_log_step = e->resolved_log_step;
  if (e->shear_tail != d.shear_tail) f->sphere_resolved_shear_tail = e->shear_tail;
}
