/* au_atlas_api.c - the public entry of the atlas (include/authalic.h, au_atlas): check the mesh, place
 * the cones, solve the metric, cut, lay out and pack (atlas/au_atlas.h), and the JSON report. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "au_atlas.h"
#include "au_mesh.h"

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

au_atlas_options au_atlas_options_default(void) {
  au_atlas_options o;
  memset(&o, 0, sizeof o);
  o.max_cones = au_atlas_opts_default().max_cones;
  o.raster = 1024;
  o.max_steps = au_atlas_flow_opts_default().max_steps;
  return o;
}

void au_atlas_result_free(au_atlas_result **r) {
  if (!r || !*r) return;
  au_atlas_result *p = *r;
  free(p->F), free(p->vt), free(p->Ft), free(p->cone_v), free(p->cone_angle), free(p->seam_rot);
  free(p);
  *r = NULL;
}

static void warn(au_atlas_result *r, const char *text) {
  if (r->nwarnings < 4) snprintf(r->warnings[r->nwarnings++], sizeof r->warnings[0], "%s", text);
}

au_status au_atlas(const double *V, int nv, const int *F, int nf, const au_atlas_options *opts, au_atlas_result **out,
                   au_msg *msg) {
  if (msg) msg->text[0] = '\0';
  if (!out) return au_msg_set(msg, AU_E_ARG, "au_atlas: out is NULL");
  *out = NULL;
  if (nv < 0 || nf < 0 || (nv > 0 && !V) || (nf > 0 && !F)) return au_msg_set(msg, AU_E_ARG, "au_atlas: bad mesh arrays");
  au_atlas_options o = opts ? *opts : au_atlas_options_default();
  if (o.max_cones < 1 || o.max_cones > 1000) return au_msg_set(msg, AU_E_ARG, "max_cones %d: expected 1..1000", o.max_cones);
  if (o.raster < 64 || o.raster > 16384) return au_msg_set(msg, AU_E_ARG, "raster %d: expected 64..16384", o.raster);
  if (o.max_steps < 1 || o.max_steps > 10000) return au_msg_set(msg, AU_E_ARG, "max_steps %d: expected 1..10000", o.max_steps);
  if (o.ncones < 0 || (o.ncones > 0 && (!o.cone_v || !o.cone_angle)))
    return au_msg_set(msg, AU_E_ARG, "cones: %d given without their arrays", o.ncones);
  au_atlas_result *r = calloc(1, sizeof *r);
  au_mesh *m = NULL;
  au_topo *t = NULL;
  double *u = NULL, *elen = NULL, *elen0 = NULL, *angle0 = NULL;
  int *v0 = NULL;
  au_atlas_cones c;
  au_atlas_layout L;
  memset(&c, 0, sizeof c);
  memset(&L, 0, sizeof L);
  au_status st = r ? au_mesh_alloc(nv, nf, &m) : AU_E_NOMEM;
  if (st != AU_OK) {
    free(r);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory");
  }
  memcpy(m->X, V, 3 * (size_t)nv * sizeof *V);
  memcpy(m->F, F, 3 * (size_t)nf * sizeof *F);
  double t0 = now_s();
  au_msg om = {{0}};
  au_status so = au_mesh_orient(m, NULL, &om);
  au_mesh_expect ex = au_mesh_expect_default();
  ex.loops = -1, ex.genus = -1, ex.command = "atlas";
  au_status check = au_mesh_validate(m, &ex, &t, msg);
  r->t_check = now_s() - t0;
  if (check == AU_E_ORIENTATION && so < 0) {
    if (msg) *msg = om;
    check = so;
  }
  if (check < 0) {
    st = check;
    goto fail;
  }
  if (so > 0) warn(r, om.text);
  if (check > 0) warn(r, msg ? msg->text : au_status_str(check));
  r->nv = nv, r->nf = nf, r->genus = t->genus, r->nloops = t->nloops;

  au_atlas_opts ao = au_atlas_opts_default();
  ao.max_cones = o.max_cones, ao.quarter = o.quarter != 0;
  t0 = now_s();
  if (o.ncones > 0) {
    c.n = o.ncones;
    c.v = malloc((size_t)o.ncones * sizeof *c.v), c.angle = malloc((size_t)o.ncones * sizeof *c.angle);
    if (!c.v || !c.angle) {
      st = au_msg_set(msg, AU_E_NOMEM, "out of memory");
      goto fail;
    }
    memcpy(c.v, o.cone_v, (size_t)o.ncones * sizeof *c.v);
    memcpy(c.angle, o.cone_angle, (size_t)o.ncones * sizeof *c.angle);
  } else if ((st = au_atlas_place_cones(m, t, &ao, &c, msg)) != AU_OK) {
    goto fail;
  }
  r->t_cones = now_s() - t0;
  t0 = now_s();
  au_atlas_cetm_info info;
  if (!(u = malloc((size_t)(nv > 0 ? nv : 1) * sizeof *u))) {
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory");
    goto fail;
  }
  au_status sm = au_atlas_cetm(m, t, &c, &ao, u, &info, msg);
  if (sm < 0) {
    st = sm;
    goto fail;
  }
  if (sm > 0) warn(r, msg->text);
  r->newton_steps = info.steps, r->metric_err = info.err;
  /* The first metric's outcome: restored where a re-solved metric (new cones) is dropped for it. */
  const au_status sm0 = sm;
  const double err0 = info.err;
  /* Given cones of quarter angles keep the common frame too, so their seams turn by quarter turns. */
  int quarter = ao.quarter;
  if (o.ncones > 0) {
    quarter = 1;
    for (int i = 0; i < c.n; i++) {
      double q = c.angle[i] / (3.14159265358979323846 / 2);
      quarter &= fabs(q - round(q)) <= 1e-9;
    }
  }
  if (!(elen = malloc((size_t)(t->ne > 0 ? t->ne : 1) * sizeof *elen))) {
    st = au_msg_set(msg, AU_E_NOMEM, "out of memory");
    goto fail;
  }
  au_atlas_edge_lengths(m, t, u, elen);
  if (quarter) {
    angle0 = malloc((size_t)(c.n > 0 ? c.n : 1) * sizeof *angle0);
    elen0 = malloc((size_t)(t->ne > 0 ? t->ne : 1) * sizeof *elen0);
    v0 = malloc((size_t)(c.n > 0 ? c.n : 1) * sizeof *v0);
    if (!angle0 || !elen0 || !v0) {
      st = au_msg_set(msg, AU_E_NOMEM, "out of memory");
      goto fail;
    }
    memcpy(angle0, c.angle, (size_t)c.n * sizeof *angle0);
    memcpy(v0, c.v, (size_t)c.n * sizeof *v0);
    memcpy(elen0, elen, (size_t)t->ne * sizeof *elen0);
  }
  /* With quarter cones the seams around the cones turn by quarter turns; those across the handles and between
   * boundary loops turn by the metric's holonomy, made a multiple of pi/2 here (the lengths stop being
   * conformal). Where that fails the conformal metric is kept, with a warning. */
  if (quarter) {
    /* Where the loops' holonomy is too far from multiples of pi/2 for the lengths to reach them (a triangle
     * would degenerate), automatic cones are turned by quarter turns and moved by an edge where that brings the
     * holonomies nearer (au_atlas_holonomy_balance: predicted linearly, so up to four rounds, each with the
     * metric solved again), and the fix is tried again: first with quarter turns in every round, then, from the
     * cones as they were, with moves alone in the first (the finer change, which some surfaces need). */
    au_atlas_holonomy_info hi;
    au_msg hm = {{0}};
    au_status sh = au_atlas_holonomy_fix(m, t, &c, elen, &hi, &hm);
    const double dev0 = hi.hol_dev;
    for (int plan = 0; plan < 2 && sh == AU_W_NOT_CONVERGED && o.ncones == 0; plan++) {
      int turned = 0;
      au_status sr = AU_OK;
      au_msg rm = {{0}};
      for (int round = 0; round < 4 && sh == AU_W_NOT_CONVERGED; round++) {
        int changed = 0;
        if ((st = au_atlas_holonomy_balance(m, t, &c, elen, plan == 0 || round > 0, &changed, msg)) != AU_OK) goto fail;
        if (!changed) break;
        turned += changed;
        if ((sr = au_atlas_cetm(m, t, &c, &ao, u, &info, &rm)) < 0) {
          if (msg) *msg = rm;
          st = sr;
          goto fail;
        }
        r->newton_steps += info.steps, r->metric_err = info.err;
        au_atlas_edge_lengths(m, t, u, elen);
        sh = au_atlas_holonomy_fix(m, t, &c, elen, &hi, &hm);
      }
      if (sh == AU_OK) {
        r->holonomy_cones = turned;
        if (turned > 0) {
          sm = sr;
          if (sr > 0) warn(r, rm.text);
        }
      } else if (turned > 0) {
        /* Not fixed even so: the cones and the metric as they were. */
        memcpy(c.angle, angle0, (size_t)c.n * sizeof *angle0);
        memcpy(c.v, v0, (size_t)c.n * sizeof *v0);
        memcpy(elen, elen0, (size_t)t->ne * sizeof *elen);
        r->metric_err = err0;
      }
    }
    hi.hol_dev = dev0;
    if (sh == AU_E_NOMEM) {
      st = au_msg_set(msg, sh, "%s", hm.text);
      goto fail;
    }
    if (sh != AU_OK) warn(r, hm.text);
    r->holonomy_loops = hi.loops, r->holonomy_fixed = hi.fixed, r->holonomy_dev = hi.hol_dev;
    r->holonomy_len_change = hi.max_change;
  }
  r->t_metric = now_s() - t0;
  t0 = now_s();
  /* The conformal atlas is packed by the charts' shapes only when it is the output: the flow's is packed
   * again after the flow (the flow does not depend on where the charts lie). A metric whose holonomy was fixed
   * whose atlas does not come out equal area and overlap-free is dropped for the conformal one, with a warning. */
  au_atlas_flow_info fi;
  memset(&fi, 0, sizeof fi);
  for (int attempt = 0;; attempt++) {
    if ((st = au_atlas_layout_make(m, t, &c, elen, 2.0 / o.raster, quarter, o.conformal_only != 0, &L, msg)) != AU_OK)
      goto fail;
    r->t_layout = now_s() - t0;
    if (!o.conformal_only) {
      t0 = now_s();
      au_atlas_flow_opts fo = au_atlas_flow_opts_default();
      fo.max_steps = o.max_steps;
      if ((st = au_atlas_flow(m, t, &c, &L, &fo, &fi, msg)) != AU_OK) goto fail;
      if ((st = au_atlas_separate(m, t, &L, quarter, 2.0 / o.raster, NULL, msg)) != AU_OK) goto fail;
      if ((st = au_atlas_measure(m, t, &c, &L, msg)) != AU_OK) goto fail;
      r->flow_steps = fi.steps, r->face_err_start = fi.err0, r->face_err = fi.err;
      r->equal_area = fi.err <= 0.02;
      r->t_flow = now_s() - t0;
    } else {
      r->face_err_start = r->face_err = au_atlas_face_error(m, &L);
    }
    r->overlap_texels = au_atlas_overlap_texels(nf, L.vt, L.Ft, o.raster, NULL);
    if (r->overlap_texels < 0) {
      st = au_msg_set(msg, AU_E_NOMEM, "out of memory");
      goto fail;
    }
    int bad = L.folds > 0 || r->overlap_texels > 0 || (!o.conformal_only && !r->equal_area);
    if (!bad || attempt > 0 || r->holonomy_fixed == 0) break;
    char w[200];
    snprintf(w, sizeof w, "holonomy: the atlas of the fixed metric (%d cone turns and moves) is not %s; the conformal metric "
             "is kept, seams across the %d loops are not quarter turns", r->holonomy_cones,
             r->overlap_texels > 0 || L.folds > 0 ? "overlap-free" : "equal area", r->holonomy_loops);
    warn(r, w);
    memcpy(c.angle, angle0, (size_t)c.n * sizeof *angle0);
    memcpy(c.v, v0, (size_t)c.n * sizeof *v0);
    memcpy(elen, elen0, (size_t)t->ne * sizeof *elen);
    r->holonomy_fixed = 0, r->holonomy_cones = 0, r->holonomy_len_change = 0;
    sm = sm0, r->metric_err = err0;
    au_atlas_layout_free(&L);
    t0 = now_s();
  }
  if (!o.conformal_only && !r->equal_area) {
    char w[160];
    snprintf(w, sizeof w, "the equal-area flow stopped at a per-face mean |r - 1| of %.3g after %d steps (from %.3g)",
             fi.err, fi.steps, fi.err0);
    warn(r, w);
  }
  if (L.folds > 0 || r->overlap_texels > 0) {
    st = au_msg_set(msg, AU_E_FOLD, "the atlas has %d folded faces and %ld texels covered twice", L.folds,
                    r->overlap_texels);
    goto fail;
  }
  r->F = m->F, m->F = NULL;
  r->nvt = L.nvt, r->vt = L.vt, r->Ft = L.Ft, L.vt = NULL, L.Ft = NULL;
  r->ncones = c.n, r->cone_v = c.v, r->cone_angle = c.angle, c.v = NULL, c.angle = NULL;
  r->ncharts = L.ncharts, r->nseams = L.nseams, r->ncut = L.ncut, r->seam_rot = L.seam_rot, L.seam_rot = NULL;
  r->seam_rot_dev = L.seam_rot_dev, r->seam_len_dev = L.seam_len_dev, r->coverage = L.coverage, r->folds = L.folds;
  st = sm > 0 ? sm : check > 0 ? check : so > 0 ? so : AU_OK;
  r->status = st;
  *out = r;
  r = NULL;
fail:
  au_atlas_result_free(&r);
  au_atlas_layout_free(&L);
  au_atlas_cones_clear(&c);
  free(u), free(elen), free(elen0), free(angle0), free(v0);
  au_topo_free(&t);
  au_mesh_free(&m);
  return st;
}

/* A growing string. */
typedef struct sbuf {
  char *s;
  size_t n, cap;
  int bad;
} sbuf;
static void sb(sbuf *b, const char *fmt, ...) {
  if (b->bad) return;
  for (;;) {
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(b->s ? b->s + b->n : NULL, b->s ? b->cap - b->n : 0, fmt, ap);
    va_end(ap);
    if (k < 0) {
      b->bad = 1;
      return;
    }
    if (b->s && b->n + (size_t)k < b->cap) {
      b->n += (size_t)k;
      return;
    }
    size_t cap = (b->cap ? 2 * b->cap : 4096) + (size_t)k;
    char *p = realloc(b->s, cap);
    if (!p) {
      b->bad = 1;
      return;
    }
    b->s = p, b->cap = cap;
  }
}
/* A JSON string of text (quotes and backslashes escaped, control characters dropped). */
static void sb_str(sbuf *b, const char *text) {
  sb(b, "\"");
  for (const char *p = text; *p; p++) {
    if (*p == '"' || *p == '\\') sb(b, "\\%c", *p);
    else if ((unsigned char)*p >= 0x20) sb(b, "%c", *p);
  }
  sb(b, "\"");
}

au_status au_atlas_result_json(const au_atlas_result *r, double t_read, double t_write, char **json, au_msg *msg) {
  if (!r || !json) return au_msg_set(msg, AU_E_ARG, "au_atlas_result_json: bad arguments");
  *json = NULL;
  sbuf b = {0};
  sb(&b, "{\n  \"command\": \"atlas\",\n  \"version\": \"%s\",\n  \"status\": \"%s\",\n", au_version(),
     au_status_name(r->status));
  sb(&b, "  \"vertices\": %d,\n  \"faces\": %d,\n  \"genus\": %d,\n  \"boundary_loops\": %d,\n", r->nv, r->nf, r->genus,
     r->nloops);
  sb(&b, "  \"equal_area\": %s,\n", r->equal_area ? "true" : "false");
  sb(&b, "  \"cones\": [");
  for (int i = 0; i < r->ncones; i++)
    sb(&b, "%s{\"vertex\": %d, \"angle\": %.17g, \"angle_deg\": %.6f}", i ? ", " : "", r->cone_v[i], r->cone_angle[i],
       r->cone_angle[i] * 180 / 3.14159265358979323846);
  sb(&b, "],\n  \"charts\": %d,\n  \"cut_edges\": %d,\n  \"seams\": [", r->ncharts, r->ncut);
  for (int i = 0; i < r->nseams; i++)
    sb(&b, "%s{\"rotation_deg\": %.9f}", i ? ", " : "", r->seam_rot[i] * 180 / 3.14159265358979323846);
  sb(&b, "],\n  \"seam_rotation_dev_deg\": %.3g,\n  \"seam_length_dev\": %.3g,\n",
     r->seam_rot_dev * 180 / 3.14159265358979323846, r->seam_len_dev);
  sb(&b, "  \"coverage\": %.6f,\n  \"folds\": %d,\n  \"overlap_texels\": %ld,\n", r->coverage, r->folds,
     r->overlap_texels);
  sb(&b, "  \"metric\": {\"newton_steps\": %d, \"angle_error\": %.3g},\n", r->newton_steps, r->metric_err);
  sb(&b, "  \"holonomy\": {\"loops\": %d, \"cone_changes\": %d, \"fixed\": %d, \"deviation_deg\": %.6g, "
     "\"max_length_change\": %.6g},\n", r->holonomy_loops, r->holonomy_cones, r->holonomy_fixed, r->holonomy_dev * 180 / 3.14159265358979323846, r->holonomy_len_change);
  sb(&b, "  \"flow\": {\"steps\": %d, \"face_error_start\": %.6g, \"face_error\": %.6g},\n", r->flow_steps,
     r->face_err_start, r->face_err);
  sb(&b, "  \"time\": {");
  if (t_read >= 0) sb(&b, "\"read\": %.4f, ", t_read);
  sb(&b, "\"validate\": %.4f, \"cones\": %.4f, \"metric\": %.4f, \"layout\": %.4f, \"flow\": %.4f", r->t_check,
     r->t_cones, r->t_metric, r->t_layout, r->t_flow);
  if (t_write >= 0) sb(&b, ", \"write\": %.4f", t_write);
  sb(&b, "},\n  \"warnings\": [");
  for (int i = 0; i < r->nwarnings; i++) {
    if (i) sb(&b, ", ");
    sb_str(&b, r->warnings[i]);
  }
  sb(&b, "]\n}\n");
  if (b.bad) {
    free(b.s);
    return au_msg_set(msg, AU_E_NOMEM, "out of memory writing the report");
  }
  *json = b.s;
  return AU_OK;
}
