/* au_report.c - the JSON report of a run (tool, input, timings, metrics, convergence), built with cJSON. */
#include "au_report.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "au_io.h"

/* A number, or null when it is not finite: JSON has no NaN or infinity. cJSON's own printer may
 * drop the last bit (it accepts 15 digits within an epsilon), so the shortest of 15..17 digits that
 * reads back exactly is written as raw text: a reader gets the very double that was computed. */
static cJSON *num(double v) {
  if (!isfinite(v)) return cJSON_CreateNull();
  char buf[40];
  for (int digits = 15; digits <= 17; digits++) {
    snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (strtod(buf, NULL) == v) break;
  }
  for (char *c = buf; *c; c++)
    if (*c == ',') *c = '.'; /* a locale's decimal comma is not JSON */
  return cJSON_CreateRaw(buf);
}

/* A string, or null for a missing one. */
static cJSON *str(const char *s) { return s ? cJSON_CreateString(s) : cJSON_CreateNull(); }

/* Attach item to obj under key (or append it when key is NULL). Returns 0 on any failure, the
 * item's own creation included, and then frees the item, so callers can chain `ok &= put(...)`. */
static int put(cJSON *obj, const char *key, cJSON *item) {
  if (obj && item && (key ? cJSON_AddItemToObject(obj, key, item) : cJSON_AddItemToArray(obj, item))) return 1;
  cJSON_Delete(item);
  return 0;
}

/* An array of n numbers (NULL values: an empty array). */
static cJSON *num_array(const double *v, int n) {
  cJSON *a = cJSON_CreateArray();
  int ok = a != NULL;
  for (int i = 0; ok && v && i < n; i++) ok &= put(a, NULL, num(v[i]));
  if (!ok) cJSON_Delete(a);
  return ok ? a : NULL;
}

typedef struct metric_key {
  const char *key; /* param-eval's name */
  size_t off;      /* offset of the double in au_metrics */
} metric_key;

#define AU_MK(key, field) {key, offsetof(au_metrics, field)}
static const metric_key metric_keys[] = {
    AU_MK("upsilon_mean_abs", upsilon_mean_abs), AU_MK("upsilon_std", upsilon_std),
    AU_MK("upsilon_max_abs", upsilon_max_abs), AU_MK("upsilon_p95_abs", upsilon_p95_abs),
    AU_MK("upsilon_p99_abs", upsilon_p99_abs), AU_MK("upsilon_wmean_abs", upsilon_wmean_abs),
    AU_MK("lambda_mean", lambda_mean), AU_MK("lambda_std", lambda_std), AU_MK("lambda_max", lambda_max),
    AU_MK("lambda_p95", lambda_p95), AU_MK("logr_mean_abs", logr_mean_abs), AU_MK("r_std", r_std),
    AU_MK("r_mean_abs_dev", r_mean_abs_dev), AU_MK("r_cv", r_cv), AU_MK("authalic_energy", authalic_energy),
    AU_MK("vertex_logr_mean_abs", vertex_logr_mean_abs), AU_MK("vertex_logr_max_abs", vertex_logr_max_abs),
    AU_MK("surface_area", surface_area), AU_MK("domain_area_sum", domain_area),
    AU_MK("angle_diff_mean_deg", angle_diff_mean_deg),
};
/* Keys that only mean something on the sphere; left out of planar reports. */
static const metric_key sphere_keys[] = {
    AU_MK("sph_r_mean_abs_dev", sph_r_mean_abs_dev), AU_MK("sph_r_cv", sph_r_cv),
    AU_MK("sph_vertex_logr_mean_abs", sph_vertex_logr_mean_abs),
    AU_MK("sphere_radius_max_dev", sphere_radius_max_dev), AU_MK("chord_floor_excess", chord_floor_excess),
};
#undef AU_MK

static int put_keys(cJSON *o, const au_metrics *m, const metric_key *k, size_t n) {
  int ok = 1;
  for (size_t i = 0; ok && i < n; i++) ok &= put(o, k[i].key, num(*(const double *)((const char *)m + k[i].off)));
  return ok;
}

/* The metrics object under param-eval's key names (its `excluded_faces` and `domain_area_sum` for
 * the struct's excluded and domain_area), so the two reports can be compared key by key. */
static cJSON *metrics_json(const au_metrics *m) {
  cJSON *o = cJSON_CreateObject();
  int sphere = m->domain == AU_DOMAIN_SPHERE;
  int ok = put(o, "domain", str(sphere ? "sphere" : "plane"));
  ok = ok && put_keys(o, m, metric_keys, sizeof metric_keys / sizeof *metric_keys);
  ok = ok && (!sphere || put_keys(o, m, sphere_keys, sizeof sphere_keys / sizeof *sphere_keys));
  ok = ok && put(o, "folds", cJSON_CreateNumber(m->folds));
  ok = ok && put(o, "excluded_faces", cJSON_CreateNumber(m->excluded));
  ok = ok && (!sphere || put(o, "chord_floor_faces", cJSON_CreateNumber(m->chord_floor_faces)));
  if (!ok) cJSON_Delete(o);
  return ok ? o : NULL;
}

/* A polish's object under conv: whether it was kept (how 2), how many sweeps or steps it ran, and the
 * vertex and per-face errors before and after (e[0..3]). */
static int put_polish(cJSON *conv, const char *name, int how, const char *count_name, int count, const double *e) {
  cJSON *p = cJSON_CreateObject();
  return put(conv, name, p) && put(p, "kept", cJSON_CreateBool(how == 2)) && put(p, count_name, num(count)) &&
         put(p, "vertex_err_before", num(e[0])) && put(p, "vertex_err_after", num(e[1])) &&
         put(p, "face_err_before", num(e[2])) && put(p, "face_err_after", num(e[3]));
}

au_status au_report_json(const au_report_info *info, char **json, au_msg *msg) {
  if (json) *json = NULL;
  if (!info || !json || !info->final) return au_msg_set(msg, AU_E_ARG, "report: missing info, output or final metrics");
  if (info->nstages < 0 || (info->nstages > 0 && !info->stages) || info->nwarnings < 0 ||
      (info->nwarnings > 0 && !info->warnings) || info->steps < 0)
    return au_msg_set(msg, AU_E_ARG, "report: negative count or missing stage/warning array");

  cJSON *root = cJSON_CreateObject(), *time = cJSON_CreateObject(), *conv = cJSON_CreateObject();
  cJSON *warn = cJSON_CreateArray();
  int ok = root && time && conv && warn;
  double total = 0;
  for (int i = 0; ok && i < info->nstages; i++) {
    ok &= put(time, info->stages[i].name ? info->stages[i].name : "?", num(info->stages[i].seconds));
    total += info->stages[i].seconds;
  }
  ok = ok && put(time, "total", num(total));
  ok = ok && put(conv, "err", num_array(info->step_err, info->steps + 1));
  ok = ok && put(conv, "frac", num_array(info->step_frac, info->steps));
  ok = ok && put(conv, "face_err", num_array(info->step_face_err, info->steps + 1));
  if (info->polish_from > 0) ok = ok && put(conv, "polish_from", num(info->polish_from));
  ok = ok && put(conv, "undone", num(info->undone));
  if (info->has_schedule)
    ok = ok && put(conv, "start_jump", num(info->start_jump)) && put(conv, "resolved", cJSON_CreateBool(info->resolved != 0));
  if (info->angle_from > 0) ok = ok && put(conv, "angle_from", num(info->angle_from));
  if (ok && info->retry > 0) {
    cJSON *lr = cJSON_CreateObject();
    ok = put(conv, "lantern_retry", lr) && put(lr, "kept", cJSON_CreateBool(info->retry == 2));
    if (info->retry == 3) ok = ok && put(lr, "skipped", cJSON_CreateBool(1));
    else ok = ok && put(lr, "vertex_err_first", num(info->retry_err[0])) && put(lr, "vertex_err_retry", num(info->retry_err[1]));
  }
  if (ok && info->twist > 0) {
    cJSON *tw = cJSON_CreateObject();
    ok = put(conv, "twisted_start", tw) && put(tw, "kept", cJSON_CreateBool(info->twist >= 2)) &&
         put(tw, "faces_sheared", num(info->twist_faces)) && put(tw, "vertex_err", num(info->twist_err)) &&
         put(tw, "conformal_start_folded", cJSON_CreateBool(info->twist == 3));
  }
  if (ok && info->polish > 0 && info->polish_err)
    ok = put_polish(conv, "vertex_polish", info->polish, "sweeps", info->polish_sweeps, info->polish_err);
  if (ok && info->global_polish > 0 && info->global_polish_err)
    ok = put_polish(conv, "global_polish", info->global_polish, "steps", info->global_polish_steps, info->global_polish_err) &&
         put(cJSON_GetObjectItemCaseSensitive(conv, "global_polish"), "robust", num(info->global_polish_robust));
  if (ok && info->staged > 0 && info->staged_err) {
    cJSON *sr = cJSON_CreateObject();
    ok = put(conv, "staged_retry", sr) && put(sr, "kept", cJSON_CreateBool(info->staged == 2)) &&
         put(sr, "stages", num(info->staged_stages)) && put(sr, "vertex_err_before", num(info->staged_err[0])) &&
         put(sr, "vertex_err_after", num(info->staged_err[1]));
  }
  for (int i = 0; ok && i < info->nwarnings; i++) ok &= put(warn, NULL, str(info->warnings[i]));

  ok = ok && put(root, "tool", str("authalic")) && put(root, "version", str(info->tool_version)) &&
       put(root, "command", str(info->command)) && put(root, "input", str(info->input)) &&
       put(root, "output", str(info->output)) && put(root, "V", cJSON_CreateNumber(info->nv)) &&
       put(root, "F", cJSON_CreateNumber(info->nf)) && put(root, "steps", cJSON_CreateNumber(info->steps)) &&
       put(root, "converged", cJSON_CreateBool(info->converged != 0)) &&
       put(root, "folds", cJSON_CreateNumber(info->final->folds));
  const double(*lat[2])[2] = {info->lattice, info->conformal_lattice};
  const char *lat_key[2] = {"lattice", "conformal_lattice"};
  for (int q = 0; q < 2; q++) {
    if (!ok || !lat[q]) continue;
    cJSON *a = cJSON_CreateArray();
    ok = put(root, lat_key[q], a) && put(a, NULL, num_array(lat[q][0], 2)) && put(a, NULL, num_array(lat[q][1], 2));
  }
  if (info->start) ok = ok && put(root, "start", str(info->start));
  if (info->factorizations > 0) ok = ok && put(root, "factorizations", cJSON_CreateNumber((double)info->factorizations));
  if (ok && info->ncircles > 0) {
    cJSON *a = cJSON_CreateArray();
    ok = put(root, "circles", a);
    for (int l = 0; ok && l < info->ncircles; l++) {
      cJSON *c = cJSON_CreateObject();
      ok = put(a, NULL, c) && put(c, "vertex", cJSON_CreateNumber(info->circle_vertex[l])) &&
           put(c, "center", num_array(info->circles + 3 * l, 2)) && put(c, "radius", num(info->circles[3 * l + 2])) &&
           put(c, "outer", cJSON_CreateBool(l == info->circle_outer));
    }
  }
  /* Once attached, the sub-objects belong to root; clear the pointers so the failure path below
   * frees each exactly once. */
  if (ok) ok = put(root, "time", time), time = NULL;
  ok = ok && put(root, "metrics", metrics_json(info->final));
  ok = ok && (!info->init || put(root, "initial_metrics", metrics_json(info->init)));
  if (ok) ok = put(root, "convergence", conv), conv = NULL;
  if (ok) ok = put(root, "warnings", warn), warn = NULL;
  if (ok) *json = cJSON_Print(root);
  cJSON_Delete(root), cJSON_Delete(time), cJSON_Delete(conv), cJSON_Delete(warn);
  if (!*json) return au_msg_set(msg, AU_E_NOMEM, "report: out of memory while building the JSON");
  return AU_OK;
}

au_status au_report_write(const char *path, const au_report_info *info, au_msg *msg) {
  if (!path || !*path) return au_msg_set(msg, AU_E_ARG, "report: no output path");
  char *json = NULL;
  au_status st = au_report_json(info, &json, msg);
  if (st != AU_OK) return st;
  /* A text file ends with a newline. */
  size_t len = strlen(json);
  char *buf = realloc(json, len + 2);
  if (!buf) {
    free(json);
    return au_msg_set(msg, AU_E_NOMEM, "report: out of memory");
  }
  buf[len] = '\n', buf[len + 1] = '\0';
  st = au_io_write_text(path, buf, len + 1, msg);
  free(buf);
  return st;
}
