/* cmd_sphere.c - `authalic sphere IN OUT`: a closed genus-0 mesh onto the unit sphere. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "au_advect.h"
#include "au_sphere.h"
#include "cli.h"

#define HELP "authalic sphere --help"

/* The options of the sphere command, with the defaults read from the library. */
void cli_print_sphere_options(void) {
  au_sphere_opts d = au_sphere_opts_default();
  printf("options of sphere:\n"
         "  --report R.json  write a JSON report: metrics of the result and of the initial conformal\n"
         "                   map, per-step errors, stage times, warnings\n"
         "  --steps K        most advection steps, 1..%d (default %d)\n"
         "  --tol T          stop when the vertex mean |log area ratio| is below T, T >= 0 (default %g)\n"
         "  --density FILE   prescribed density: one positive number per vertex (or per face) of IN, in\n"
         "                   order, whitespace-separated, or a FreeSurfer curv or GIfTI .shape.gii/.func.gii\n"
         "                   file; domain area is proportional to density x surface area\n"
         "  --restore-shapes F  while the spherical areas are driven, aim each step's shear a fraction\n"
         "                   F (0..1, default %g; 0: off) back at the surface's triangle shapes: fewer long,\n"
         "                   thin triangles (hand_closed per-face 0.051 with 0, 0.018 with 0.1)\n"
         "  --refine-faces   once the vertex cells meet the tolerance, go on refining the triangles'\n"
         "                   areas as long as it helps at all (default: while it gains %g%% in 4 steps);\n"
         "                   it also keeps the flow's ordinary schedule on well-resolved meshes\n"
         "  --angles N       from a vertex error of %g on, N steps (1..%d) towards the map of least\n"
         "                   Dirichlet energy with the vertex cells held at their areas: less angle\n"
         "                   distortion, vertex cells within about 1e-4, the triangles' areas held near\n"
         "                   theirs (weight %g); each step costs several flow steps (bunny: 0.4 s).\n"
         "                   With --refine-faces they come after the refinement\n"
         "  --no-balance     skip the Moebius balancing of the conformal start\n"
         "  --init-only      stop after the conformal start (and balancing), for comparison\n"
         "  --quiet          no progress and no summary on stderr (errors and warnings remain)\n",
         AU_ADVECT_MAX_STEPS, d.flow.max_steps, d.flow.tol, d.flow.restore, 100 * d.flow.face_gain,
         d.flow.angle_switch, AU_ANGLE_STEPS_MAX, d.flow.angle_faces);
  cli_print_neuro_options(1);
  printf("  --help           this text\n");
}

static void print_sphere_help(void) {
  printf("usage: authalic sphere IN OUT [options]\n\n"
         "Maps the closed genus-0 triangle mesh IN onto the unit sphere so that every vertex cell keeps\n"
         "its share of the surface area, and writes the map to OUT (.obj .off .ply .gii .gii.gz; another\n"
         "name gets IN's format, so a FreeSurfer surface gives a FreeSurfer sphere). IN may also be a\n"
         "FreeSurfer surface (lh.white) or GIfTI (.gii, .gii.gz). Progress and a summary line go to\n"
         "stderr; OUT and the report are written only when the whole run succeeded.\n\n");
  cli_print_sphere_options();
}

/* Everything the sphere command was asked to do. */
typedef struct sphere_args {
  const char *in, *out, *report, *density;
  int steps, has_steps; /* --steps, and whether it was given */
  double tol;
  int has_tol;
  int no_balance, quiet, init_only, refine_faces;
  double restore;
  int has_restore;
  int angles; /* --angles N, 0 if not given */
  cli_neuro_args neuro; /* --format, --distortion, --radius */
} sphere_args;

/* Parse `authalic sphere ...` (argv[0] is "sphere"). Returns -1 to go on, else an exit code. */
static int parse_sphere(int argc, char **argv, sphere_args *a) {
  int npos = 0, dashdash = 0;
  for (int i = 1; i < argc; i++) {
    const char *s = argv[i];
    if (dashdash || s[0] != '-' || s[1] == '\0') {
      if (npos == 0) a->in = s;
      else if (npos == 1) a->out = s;
      else return cli_usage_error(HELP, "unexpected extra argument '%s'", s);
      npos++;
      continue;
    }
    if (strcmp(s, "--") == 0) {
      dashdash = 1;
    } else if (strcmp(s, "--help") == 0 || strcmp(s, "-h") == 0) {
      print_sphere_help();
      return EXIT_OK;
    } else if (strcmp(s, "--no-balance") == 0) {
      if (a->no_balance++) return cli_usage_error(HELP, "option '%s' given twice", s);
    } else if (strcmp(s, "--quiet") == 0) {
      if (a->quiet++) return cli_usage_error(HELP, "option '%s' given twice", s);
    } else if (strcmp(s, "--init-only") == 0) {
      if (a->init_only++) return cli_usage_error(HELP, "option '%s' given twice", s);
    } else if (strcmp(s, "--refine-faces") == 0) {
      if (a->refine_faces++) return cli_usage_error(HELP, "option '%s' given twice", s);
    } else if (strcmp(s, "--report") == 0 || strcmp(s, "--steps") == 0 || strcmp(s, "--tol") == 0 ||
               strcmp(s, "--density") == 0 || strcmp(s, "--restore-shapes") == 0 || strcmp(s, "--angles") == 0) {
      if (i + 1 >= argc) return cli_usage_error(HELP, "option '%s' needs a value", s);
      const char *v = argv[++i];
      if (strcmp(s, "--angles") == 0) {
        if (a->angles) return cli_usage_error(HELP, "option '%s' given twice", s);
        if (cli_parse_int(v, 1, AU_ANGLE_STEPS_MAX, &a->angles))
          return cli_usage_error(HELP, "--angles '%s': expected a whole number from 1 to %d", v, AU_ANGLE_STEPS_MAX);
      } else if (strcmp(s, "--restore-shapes") == 0) {
        if (a->has_restore++) return cli_usage_error(HELP, "option '%s' given twice", s);
        if (cli_parse_nonneg(v, &a->restore) || a->restore > 1)
          return cli_usage_error(HELP, "--restore-shapes '%s': expected a number from 0 to 1", v);
      } else if (strcmp(s, "--density") == 0) {
        if (a->density) return cli_usage_error(HELP, "option '%s' given twice", s);
        if (!*v) return cli_usage_error(HELP, "option '--density' needs a file name");
        a->density = v;
      } else if (strcmp(s, "--report") == 0) {
        if (a->report) return cli_usage_error(HELP, "option '%s' given twice", s);
        if (!*v) return cli_usage_error(HELP, "option '--report' needs a file name");
        a->report = v;
      } else if (strcmp(s, "--steps") == 0) {
        if (a->has_steps++) return cli_usage_error(HELP, "option '%s' given twice", s);
        if (cli_parse_int(v, 1, AU_ADVECT_MAX_STEPS, &a->steps))
          return cli_usage_error(HELP, "--steps '%s': expected a whole number from 1 to %d", v, AU_ADVECT_MAX_STEPS);
      } else {
        if (a->has_tol++) return cli_usage_error(HELP, "option '%s' given twice", s);
        if (cli_parse_nonneg(v, &a->tol)) return cli_usage_error(HELP, "--tol '%s': expected a finite number >= 0", v);
      }
    } else {
      int k = cli_parse_neuro(HELP, argc, argv, &i, 1, &a->neuro);
      if (k < 0) return EXIT_USAGE;
      if (k == 0) return cli_usage_error(HELP, "unknown option '%s'", s);
    }
  }
  if (npos < 2) return cli_usage_error(HELP, npos == 0 ? "missing input and output files" : "missing output file");
  if (!*a->in || !*a->out) return cli_usage_error(HELP, "empty file name");
  if (a->init_only && (a->has_steps || a->has_tol || a->density || a->refine_faces || a->has_restore || a->angles))
    return cli_usage_error(HELP, "--init-only runs no advection: --steps, --tol, --density, --refine-faces, "
                                 "--restore-shapes and --angles do not apply");
  int rc = cli_check_outputs(HELP, a->in, a->out, a->report);
  const char *d = a->neuro.distortion;
  if (!rc && d && (cli_same_file(d, a->in) || cli_same_file(d, a->out) || (a->report && cli_same_file(d, a->report)) ||
                   (a->density && cli_same_file(d, a->density))))
    rc = cli_usage_error(HELP, "--distortion '%s' is also another input or output file", d);
  if (!rc && d) rc = cli_check_writable_path(HELP, d, "--distortion");
  return rc ? rc : -1;
}

/* Read a density file (au_io_read_scalars: text, FreeSurfer curv or GIfTI values): nv values (per
 * vertex) or nf (per face), each positive and finite. On success *out (malloc'ed) and *count are set
 * and -1 is returned; otherwise the error is printed and the exit code returned. */
static int read_density(const char *path, int nv, int nf, double **out, int *count) {
  FILE *fp = fopen(path, "r");
  if (!fp) {
    fprintf(stderr, "authalic: error: %s: cannot open the density file: %s\n", path, strerror(errno));
    return EXIT_USAGE;
  }
  fclose(fp);
  au_msg msg = {{0}};
  double *v = NULL;
  int n = 0;
  au_status st = au_io_read_scalars(path, 0, &v, &n, &msg);
  if (st != AU_OK) return cli_fail(path, st, &msg);
  for (int i = 0; i < n; i++)
    if (!(v[i] > 0)) {
      fprintf(stderr, "authalic: error: %s: value %d ('%g') is not a positive finite number\n", path, i + 1, v[i]);
      free(v);
      return EXIT_USAGE;
    }
  if (n != nv && n != nf) {
    fprintf(stderr, "authalic: error: %s: %d values; the mesh has %d vertices and %d faces\n", path, n, nv, nf);
    free(v);
    return EXIT_USAGE;
  }
  *out = v, *count = n;
  return -1;
}

/* The sphere command after parsing. All resources are released at `done`. */
static int run_sphere(const sphere_args *a) {
  double t_start = cli_now(), t0;
  au_report_stage stages[8];
  int nst = 0, rc = EXIT_INTERNAL;
  cli_warnings warn;
  warn.n = 0;
  au_mesh *m = NULL;
  au_topo *topo = NULL;
  double *P = NULL, *Pinit = NULL, *density = NULL, *Pw = NULL;
  au_io_meta *meta = NULL;
  au_io_format ofmt = AU_IO_FORMAT_AUTO;
  au_msg msg = {{0}};
  au_status st;
  au_metrics fin, ini;
  int have_init = 0;

  cli_progress_state prog;
  cli_progress_init(&prog, a->quiet);
  au_sphere_opts opts = au_sphere_opts_default();
  if (a->has_steps) opts.flow.max_steps = a->steps;
  if (a->has_tol) opts.flow.tol = a->tol;
  /* --refine-faces is for accuracy, not speed: it runs the ordinary schedule. On the resolved one the
   * chord polish of bunny stalled on undone steps at per-face 0.0063 (12 steps), against 0.0031 in 60
   * steps on the ordinary one (lion_statue 0.0029 against 0.0031). */
  if (a->refine_faces)
    opts.flow.face_gain = 0.02, opts.flow.polish_gap = 0, opts.flow.resolved_jump = 0, opts.flow.angle_switch = 0;
  if (a->has_restore) opts.flow.restore = a->restore;
  opts.flow.angle_steps = a->angles;
  if (a->no_balance) opts.balance = 0;
  if (!a->quiet) opts.flow.progress = cli_progress, opts.flow.user = &prog;

  au_mesh_expect ex = au_mesh_expect_default();
  ex.loops = 0, ex.genus = 0, ex.command = "sphere";
  rc = cli_load_meta(a->in, &ex, &m, &topo, &meta, &warn, stages, &nst);
  if (rc >= 0) goto done;
  rc = cli_output_format(HELP, a->out, a->neuro.format, meta, &ofmt);
  if (rc) goto done;
  rc = EXIT_INTERNAL;

  if (a->density) {
    int nval = 0;
    rc = read_density(a->density, m->nv, m->nf, &density, &nval);
    if (rc >= 0) goto done;
    rc = EXIT_INTERNAL;
    if (nval == m->nv) opts.flow.weight = density;
    else opts.flow.face_weight = density;
  }

  size_t n3 = 3 * (size_t)m->nv;
  P = malloc(n3 * sizeof *P);
  if (!P) {
    rc = cli_fail(a->in, AU_E_NOMEM, NULL);
    goto done;
  }

  au_sphere_report rep;
  memset(&rep, 0, sizeof rep);
  if (a->init_only) {
    t0 = cli_now();
    st = au_sphere_conformal(m, topo, P, &msg);
    if (st == AU_OK && opts.balance) st = au_sphere_balance(m, topo, P, &msg);
    rep.t_init = cli_now() - t0;
  } else {
    /* The report also gives the starting map's metrics. */
    if (a->report && !(Pinit = malloc(n3 * sizeof *Pinit))) {
      rc = cli_fail(a->in, AU_E_NOMEM, NULL);
      goto done;
    }
    st = au_sphere_map(m, topo, &opts, P, Pinit, &rep, &msg);
    cli_progress_end(&prog);
  }
  if (st < 0) {
    rc = cli_fail(a->in, st, &msg);
    goto done;
  }
  t0 = cli_now();
  double t_init_metrics = 0;
  if (Pinit) {
    au_status mst = au_metrics_compute(m->nv, m->nf, m->X, Pinit, m->F, AU_DOMAIN_SPHERE, &ini, NULL, NULL);
    if (mst != AU_OK) {
      rc = cli_fail(a->in, mst, NULL);
      goto done;
    }
    have_init = 1;
    t_init_metrics = cli_now() - t0;
  }
  const int not_converged = st == AU_W_NOT_CONVERGED;
  if (not_converged) {
    int k = rep.flow.steps;
    cli_warn(&warn, a->in, "tolerance %g not reached in %d steps (error %.3e)", opts.flow.tol, k, rep.flow.err[k]);
  }
  stages[nst++] = (au_report_stage){"init", rep.t_init};
  stages[nst++] = (au_report_stage){"flow", rep.t_flow};

  t0 = cli_now();
  st = au_metrics_compute(m->nv, m->nf, m->X, P, m->F, AU_DOMAIN_SPHERE, &fin, NULL, NULL);
  if (st != AU_OK) {
    rc = cli_fail(a->in, st, NULL);
    goto done;
  }
  /* A folded map is never written: zero folds is the tool's promise, not a hope. */
  rc = cli_refuse_folds(a->in, &fin, not_converged);
  if (rc >= 0) goto done;
  /* Only when it matters: a single floor-bound face after a short run is no news. */
  if (not_converged && fin.chord_floor_faces > 0 && fin.chord_floor_excess >= 1e-4)
    cli_warn(&warn, a->in,
             "%d long, thin triangles of the map cannot bring their chord area down to their share without shorter "
             "long edges (a long edge's chord runs under the sphere; excess %.2g%% of the area): a finer mesh there "
             "lowers that error",
             fin.chord_floor_faces, 100 * fin.chord_floor_excess);
  stages[nst++] = (au_report_stage){"metrics", cli_now() - t0 + t_init_metrics};
  stages[nst] = (au_report_stage){"write", 0};
  au_report_info info = {AU_VERSION, "sphere", a->in, a->out, m->nv, m->nf,
                         rep.flow.steps, a->init_only ? 0 : rep.flow.converged,
                         have_init ? &ini : NULL, &fin, stages, nst + 1,
                         a->init_only ? NULL : rep.flow.err, a->init_only ? NULL : rep.flow.frac,
                         warn.list, warn.n, a->init_only ? NULL : rep.flow.face_err,
                         a->init_only ? 0 : rep.flow.polish_from, a->init_only ? 0 : rep.flow.undone,
                         !a->init_only, rep.flow.start_jump, rep.flow.resolved,
                         rep.retry, {rep.retry_err[0], rep.retry_err[1]}, a->init_only ? 0 : rep.flow.angle_from};
  /* The distortion file first (its own atomic write), removed again if OUT cannot be published. */
  if (a->neuro.distortion) {
    rc = cli_write_distortion(a->neuro.distortion, m, P, AU_DOMAIN_SPHERE, meta);
    if (rc >= 0) goto done;
  }
  au_io_write_opts wopts = au_io_write_opts_default();
  wopts.format = ofmt, wopts.meta = meta, wopts.geometric_type = "Spherical";
  if (a->neuro.has_radius) {
    if (!(Pw = malloc(n3 * sizeof *Pw))) {
      rc = cli_fail(a->out, AU_E_NOMEM, NULL);
      goto done;
    }
    for (size_t i = 0; i < n3; i++) Pw[i] = a->neuro.radius * P[i];
  }
  rc = cli_publish(a->out, m, Pw ? Pw : P, &wopts, a->report, &info, &stages[nst]);
  if (rc != EXIT_OK) {
    if (a->neuro.distortion) unlink(a->neuro.distortion);
    goto done;
  }

  if (!a->quiet)
    fprintf(stderr, "authalic: sphere: V=%d F=%d steps=%d folds=%d mean|r-1|=%.3g vertex|log r|=%.3g time=%.2fs%s\n",
            m->nv, m->nf, rep.flow.steps, fin.folds, fin.r_mean_abs_dev, fin.vertex_logr_mean_abs,
            cli_now() - t_start,
            rep.retry == 2 ? " (lantern retry kept)" : rep.retry == 1 ? " (lantern retry discarded)" : "");
  rc = EXIT_OK;

done:
  cli_progress_end(&prog);
  free(P);
  free(Pinit);
  free(density);
  free(Pw);
  au_io_meta_free(&meta);
  au_topo_free(&topo);
  au_mesh_free(&m);
  return rc;
}

int cli_cmd_sphere(int argc, char **argv) {
  sphere_args a;
  memset(&a, 0, sizeof a);
  a.neuro.radius = 1;
  int rc = parse_sphere(argc, argv, &a);
  return rc >= 0 ? rc : run_sphere(&a);
}
