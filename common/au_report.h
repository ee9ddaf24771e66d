/* au_report.h - the machine-readable JSON report of a run (cJSON behind this header). */
#ifndef AU_REPORT_H
#define AU_REPORT_H

#include "au_metrics.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One named stage time ("read", "validate", "init", "flow", "metrics", "write"). */
typedef struct au_report_stage {
  const char *name;
  double seconds;
} au_report_stage;

/* What a run reports. All pointers are borrowed for the duration of au_report_write. */
typedef struct au_report_info {
  const char *tool_version;   /* e.g. "0.1.0" */
  const char *command;        /* "sphere", "disk", ... */
  const char *input, *output; /* paths as given */
  int nv, nf;
  int steps;                  /* advection steps taken */
  long factorizations;        /* sparse numeric factorizations of the whole map (0: not reported) */
  int converged;              /* 1 if the tolerance was met */
  const au_metrics *init;     /* metrics of the initial (conformal) map; may be NULL */
  const au_metrics *final;    /* metrics of the result; required */
  const au_report_stage *stages; int nstages;
  const double *step_err;     /* per-step vertex mean |log ratio| [0..steps]; may be NULL */
  const double *step_frac;    /* per-step fraction of the step taken [0..steps-1]; may be NULL */
  const char **warnings; int nwarnings;
  const double *step_face_err; /* per-step per-face mean |r - 1| [0..steps]; may be NULL */
  int polish_from;             /* > 0: the step from which step_err/step_face_err measure chord
                                  triangles (spherical ones before it); written as
                                  convergence.polish_from. 0: one measure throughout */
  int undone;                  /* steps solved and undone (not in steps); written as convergence.undone */
  int has_schedule;            /* 1: write convergence.start_jump and convergence.resolved below */
  double start_jump;           /* the start's mean jump of log r across interior edges (au_advect_report) */
  int resolved;                /* the flow ran its resolved schedule */
  int retry;                   /* sphere's lantern retry (au_sphere_report.retry): 0 none (nothing written);
                                  1 ran, discarded; 2 ran, kept; 3 due, skipped (its flow would repeat the
                                  first). Written as convergence.lantern_retry */
  double retry_err[2];         /* the vertex errors of the first map and of the retry's */
  int twist;                   /* sphere's twisted retry (au_sphere_report.twist): 0 none (nothing written);
                                  1 ran, discarded; 2 ran, kept; 3 the start (the conformal one folded).
                                  Written as convergence.twisted_start */
  int twist_faces;             /* the faces the twisted start sheared */
  double twist_err;            /* the twisted retry's vertex error */
  int polish;                  /* sphere's vertex polish (au_sphere_report.polish): 0 none (nothing written),
                                  1 discarded, 2 kept. Written as convergence.vertex_polish */
  int polish_sweeps;           /* its sweeps */
  const double *polish_err;    /* [4]: vertex error before, after; per-face error before, after */
  int global_polish;           /* the refined map's global polish (au_sphere_report.global_polish): 0 none
                                  (nothing written), 1 discarded, 2 kept. Written as convergence.global_polish */
  int global_polish_steps;     /* its steps */
  const double *global_polish_err; /* [4]: as polish_err */
  double global_polish_robust;  /* its loss's d, 0 for squares. Written as convergence.global_polish.robust */
  int staged;                  /* sphere's staged retry (au_sphere_report.staged): 0 none (nothing written),
                                  1 discarded, 2 kept. Written as convergence.staged_retry */
  int staged_stages;           /* its stages */
  const double *staged_err;    /* [2]: vertex error before it and of its map */
  int angle_from;              /* > 0: the step at which the angle steps began (au_advect_report);
                                  written as convergence.angle_from */
  const double (*lattice)[2];  /* torus: the lattice's basis (rows a1, a2), written as "lattice": [[a1x, a1y],
                                  [a2x, a2y]]; NULL: none */
  const double (*conformal_lattice)[2]; /* torus: the conformal modulus's lattice, "conformal_lattice"; NULL: none */
  const char *start;           /* how the start was made ("cotan", "meanvalue"), written as "start"; NULL: none */
  int ncircles;                /* circles: the boundary loops' circles, written as "circles": [{"vertex": v,
                                  "center": [x, y], "radius": r, "outer": bool}, ...]; 0: none */
  const double *circles;       /* [3 ncircles]: cx, cy, r */
  const int *circle_vertex;    /* [ncircles]: a vertex on each loop */
  int circle_outer;            /* the index of the outer circle */
} au_report_info;

/* Render the report as a JSON string. On success *json is malloc'ed; the caller frees it.
 * Keys of the metrics use param-eval's names (upsilon_mean_abs, r_mean_abs_dev, r_cv, folds, ...).
 * Returns AU_OK, AU_E_ARG, AU_E_NOMEM. */
au_status au_report_json(const au_report_info *info, char **json, au_msg *msg);

/* Render and write the report atomically to path. Returns AU_OK, AU_E_ARG, AU_E_NOMEM, AU_E_IO. */
au_status au_report_write(const char *path, const au_report_info *info, au_msg *msg);

#ifdef __cplusplus
}
#endif
#endif
