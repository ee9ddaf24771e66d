/* cmd_disk.c - `authalic disk | annulus | square IN OUT`: open meshes onto planar domains (the unit
 * disk, an annulus with outer radius 1, the unit square); argv[0] says which. */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "au_advect.h"
#include "au_disk.h"
#include "cli.h"

enum { CMD_DISK, CMD_ANNULUS, CMD_SQUARE };

static const char *const cmd_names[] = {"disk", "annulus", "square"};
static const char *const cmd_helps[] = {"authalic disk --help", "authalic annulus --help", "authalic square --help"};

static void print_help(int cmd) {
  au_disk_opts d = au_disk_opts_default();
  if (cmd == CMD_DISK)
    printf("usage: authalic disk IN OUT [options]\n\n"
           "Maps the triangle mesh IN, which must have one boundary loop (a topological disk), onto the\n"
           "unit disk so that every vertex cell keeps its share of the surface area. The boundary stays on\n"
           "the unit circle and slides along it during the flow.\n\n");
  else if (cmd == CMD_ANNULUS)
    printf("usage: authalic annulus IN OUT [options]\n\n"
           "Maps the triangle mesh IN, which must have two boundary loops (a topological annulus), onto\n"
           "an annulus centred at the origin with outer radius 1 so that every vertex cell keeps its share\n"
           "of the surface area. Both loops slide along their circles during the flow.\n\n");
  else
    printf("usage: authalic square IN OUT [options]\n\n"
           "Maps the triangle mesh IN, which must have one boundary loop, onto the unit square [0,1]^2 so\n"
           "that every vertex cell keeps its share of the surface area (Zou et al. 2011, sec. 4.1). Four\n"
           "boundary vertices go to the corners and stay there; the others slide along their sides.\n"
           "Triangles whose three vertices would land on one side are split first: the new vertices\n"
           "(edge midpoints) come after the input's vertices in OUT, the new faces after its faces.\n\n");
  printf("IN may also be a FreeSurfer surface or GIfTI (.gii, .gii.gz); OUT (.obj .off .ply .gii .gii.gz,\n"
         "another name: IN's format) has the input's vertices in the input's order and its faces, with\n"
         "positions (u, v, 0); an .obj also gets `vt` texture coordinates in [0,1]^2%s. Progress and a\n"
         "summary line go to stderr; OUT and the report are written only when the whole run succeeded.\n\n",
         cmd == CMD_SQUARE ? " (u, v)" : " ((u+1)/2, (v+1)/2)");
  printf("options of %s:\n"
         "  --report R.json     write a JSON report: metrics of the result and of the initial map,\n"
         "                      per-step errors, stage times, warnings\n"
         "  --steps K           most advection steps, 1..%d (default %d)\n"
         "  --tol T             stop when the vertex mean |log area ratio| is below T, T >= 0 (default %g)\n"
         "  --boundary MODE     slide (default): boundary vertices slide along the %s;\n"
         "                      fixed: the initial map's boundary is kept\n"
         "  --refine-faces      once the vertex cells meet the tolerance, go on refining the triangles'\n"
         "                      areas as long as it helps at all, down to a per-face mean |r-1| of %g\n"
         "                      (default: while it gains %g%% in 4 steps, down to %g), on the flow's\n"
         "                      ordinary schedule also where the mesh resolves the start well\n"
         "  --angles N          after the flow, N steps (1..%d) towards the map of least Dirichlet\n"
         "                      energy with the vertex cells held at their areas: less angle distortion\n"
         "                      and vertex cells within about 1e-4, the triangles' areas held near theirs\n",
         cmd_names[cmd], AU_ADVECT_MAX_STEPS, d.flow.max_steps, d.flow.tol,
         cmd == CMD_SQUARE ? "sides, corners fixed" : cmd == CMD_DISK ? "circle" : "circles", au_advect_opts_default().face_tol,
         100 * d.flow.face_gain, d.flow.face_tol, AU_ANGLE_STEPS_MAX);
  if (cmd == CMD_ANNULUS)
    printf("  --inner-radius R    radius of the inner circle, 0 < R < 1 (default: the conformal modulus's)\n"
           "  --outer-loop WHICH  the loop mapped to the unit circle: longer (default), shorter, or the\n"
           "                      index of a vertex on it\n");
  if (cmd == CMD_SQUARE)
    printf("  --corners I,J,K,L   boundary vertices (0-based) for the corners: I goes to (0,0), the others\n"
           "                      to (1,0), (1,1), (0,1) in the order they follow I along the boundary\n"
           "                      (default: the most corner-like vertices near the arc-length quarters)\n");
  printf("  --init-only         stop after the initial (harmonic, near-conformal) map, for comparison\n"
         "  --quiet             no progress and no summary on stderr (errors and warnings remain)\n");
  cli_print_neuro_options(0);
  printf("  --help              this text\n");
}

typedef struct disk_args {
  int cmd;
  const char *in, *out, *report;
  int steps, has_steps, has_tol, has_boundary, quiet, init_only, refine_faces;
  int angles; /* --angles N, 0 if not given */
  double tol;
  au_disk_boundary boundary;
  double inner_radius;
  int has_inner;
  int outer_mode; /* 0 longer, 1 shorter, 2 vertex */
  int outer_vertex, has_outer;
  int corners[4], has_corners;
  cli_neuro_args neuro; /* --format, --distortion */
} disk_args;

/* Four comma-separated whole numbers >= 0; 0 on success. */
static int parse_corners(const char *s, int c[4]) {
  const char *p = s;
  for (int q = 0; q < 4; q++) {
    char buf[32];
    const char *e = strchr(p, ',');
    size_t n = e ? (size_t)(e - p) : strlen(p);
    if ((q < 3) != (e != NULL) || n == 0 || n >= sizeof buf) return -1;
    memcpy(buf, p, n);
    buf[n] = '\0';
    if (cli_parse_int(buf, 0, 2147483647L, &c[q])) return -1;
    p = e ? e + 1 : p + n;
  }
  return 0;
}

static int parse_disk(int argc, char **argv, disk_args *a) {
  const char *help = cmd_helps[a->cmd];
  int npos = 0, dashdash = 0;
  for (int i = 1; i < argc; i++) {
    const char *s = argv[i];
    if (dashdash || s[0] != '-' || s[1] == '\0') {
      if (npos == 0) a->in = s;
      else if (npos == 1) a->out = s;
      else return cli_usage_error(help, "unexpected extra argument '%s'", s);
      npos++;
      continue;
    }
    if (strcmp(s, "--") == 0) {
      dashdash = 1;
    } else if (strcmp(s, "--help") == 0 || strcmp(s, "-h") == 0) {
      print_help(a->cmd);
      return EXIT_OK;
    } else if (strcmp(s, "--quiet") == 0) {
      if (a->quiet++) return cli_usage_error(help, "option '%s' given twice", s);
    } else if (strcmp(s, "--init-only") == 0) {
      if (a->init_only++) return cli_usage_error(help, "option '%s' given twice", s);
    } else if (strcmp(s, "--refine-faces") == 0) {
      if (a->refine_faces++) return cli_usage_error(help, "option '%s' given twice", s);
    } else if (strcmp(s, "--report") == 0 || strcmp(s, "--steps") == 0 || strcmp(s, "--tol") == 0 ||
               strcmp(s, "--boundary") == 0 || strcmp(s, "--angles") == 0 || (a->cmd == CMD_ANNULUS && strcmp(s, "--inner-radius") == 0) ||
               (a->cmd == CMD_ANNULUS && strcmp(s, "--outer-loop") == 0) ||
               (a->cmd == CMD_SQUARE && strcmp(s, "--corners") == 0)) {
      if (i + 1 >= argc) return cli_usage_error(help, "option '%s' needs a value", s);
      const char *v = argv[++i];
      if (strcmp(s, "--report") == 0) {
        if (a->report) return cli_usage_error(help, "option '%s' given twice", s);
        if (!*v) return cli_usage_error(help, "option '--report' needs a file name");
        a->report = v;
      } else if (strcmp(s, "--steps") == 0) {
        if (a->has_steps++) return cli_usage_error(help, "option '%s' given twice", s);
        if (cli_parse_int(v, 1, AU_ADVECT_MAX_STEPS, &a->steps))
          return cli_usage_error(help, "--steps '%s': expected a whole number from 1 to %d", v, AU_ADVECT_MAX_STEPS);
      } else if (strcmp(s, "--angles") == 0) {
        if (a->angles) return cli_usage_error(help, "option '%s' given twice", s);
        if (cli_parse_int(v, 1, AU_ANGLE_STEPS_MAX, &a->angles))
          return cli_usage_error(help, "--angles '%s': expected a whole number from 1 to %d", v, AU_ANGLE_STEPS_MAX);
      } else if (strcmp(s, "--tol") == 0) {
        if (a->has_tol++) return cli_usage_error(help, "option '%s' given twice", s);
        if (cli_parse_nonneg(v, &a->tol)) return cli_usage_error(help, "--tol '%s': expected a finite number >= 0", v);
      } else if (strcmp(s, "--boundary") == 0) {
        if (a->has_boundary++) return cli_usage_error(help, "option '%s' given twice", s);
        if (strcmp(v, "slide") == 0) a->boundary = AU_DISK_SLIDE;
        else if (strcmp(v, "fixed") == 0) a->boundary = AU_DISK_FIXED;
        else return cli_usage_error(help, "--boundary '%s': expected slide or fixed", v);
      } else if (strcmp(s, "--inner-radius") == 0) {
        if (a->has_inner++) return cli_usage_error(help, "option '%s' given twice", s);
        if (cli_parse_nonneg(v, &a->inner_radius) || !(a->inner_radius > 0 && a->inner_radius < 1))
          return cli_usage_error(help, "--inner-radius '%s': expected a number between 0 and 1 (exclusive)", v);
      } else if (strcmp(s, "--outer-loop") == 0) {
        if (a->has_outer++) return cli_usage_error(help, "option '%s' given twice", s);
        if (strcmp(v, "longer") == 0) a->outer_mode = 0;
        else if (strcmp(v, "shorter") == 0) a->outer_mode = 1;
        else if (cli_parse_int(v, 0, 2147483647L, &a->outer_vertex) == 0) a->outer_mode = 2;
        else return cli_usage_error(help, "--outer-loop '%s': expected longer, shorter or a vertex index", v);
      } else {
        if (a->has_corners++) return cli_usage_error(help, "option '%s' given twice", s);
        if (parse_corners(v, a->corners))
          return cli_usage_error(help, "--corners '%s': expected four vertex indices I,J,K,L", v);
      }
    } else {
      int k = cli_parse_neuro(help, argc, argv, &i, 0, &a->neuro);
      if (k < 0) return EXIT_USAGE;
      if (k == 0) return cli_usage_error(help, "unknown option '%s'", s);
    }
  }
  if (npos < 2) return cli_usage_error(help, npos == 0 ? "missing input and output files" : "missing output file");
  if (!*a->in || !*a->out) return cli_usage_error(help, "empty file name");
  if (a->init_only && (a->has_steps || a->has_tol || a->has_boundary || a->refine_faces || a->angles))
    return cli_usage_error(help, "--init-only runs no advection: --steps, --tol, --boundary, --refine-faces and --angles "
                                 "do not apply");
  int rc = cli_check_outputs(help, a->in, a->out, a->report);
  const char *d = a->neuro.distortion;
  if (!rc && d && (cli_same_file(d, a->in) || cli_same_file(d, a->out) || (a->report && cli_same_file(d, a->report))))
    rc = cli_usage_error(help, "--distortion '%s' is also another input or output file", d);
  if (!rc && d) rc = cli_check_writable_path(help, d, "--distortion");
  return rc ? rc : -1;
}

/* The loop index (0 or 1) the user picked for the outer circle, or -1 with an error printed. */
static int pick_outer(const disk_args *a, const au_topo *t) {
  double l0 = t->loop_len ? t->loop_len[0] : t->loop_start[1] - t->loop_start[0];
  double l1 = t->loop_len ? t->loop_len[1] : t->loop_start[2] - t->loop_start[1];
  if (a->outer_mode == 0) return l1 > l0 ? 1 : 0;
  if (a->outer_mode == 1) return l1 > l0 ? 0 : 1;
  for (int l = 0; l < 2; l++)
    for (int k = t->loop_start[l]; k < t->loop_start[l + 1]; k++)
      if (t->loop_vert[k] == a->outer_vertex) return l;
  fprintf(stderr, "authalic: error: %s: --outer-loop: vertex %d is on neither boundary loop\n", a->in, a->outer_vertex);
  return -1;
}

static const char *help_of(int cmd) { return cmd_helps[cmd]; }

static int run_disk(const disk_args *a) {
  const char *name = cmd_names[a->cmd];
  double t_start = cli_now(), t0;
  au_report_stage stages[8];
  int nst = 0, rc = EXIT_INTERNAL;
  cli_warnings warn;
  warn.n = 0;
  au_mesh *m = NULL, *ms = NULL;
  au_topo *topo = NULL, *ts = NULL;
  double *P = NULL, *P0 = NULL, *uv = NULL;
  au_io_meta *meta = NULL;
  au_io_format ofmt = AU_IO_FORMAT_AUTO;
  au_msg msg = {{0}};
  au_status st;
  au_metrics fin, ini;
  cli_progress_state prog;
  cli_progress_init(&prog, a->quiet);

  au_disk_opts opts = au_disk_opts_default();
  if (a->has_steps) opts.flow.max_steps = a->steps;
  if (a->has_tol) opts.flow.tol = a->tol;
  /* --refine-faces lowers the per-face stop to 1e-3 (the planar default, 1e-2, would end it), lets the
   * shear weight go down to 3e-4 once the vertex cells are equal (au_advect_opts.face_shear_tail), and
   * runs the ordinary schedule, as on the sphere (it is for accuracy, not speed). */
  if (a->refine_faces)
    opts.flow.face_gain = 0.02, opts.flow.face_tol = au_advect_opts_default().face_tol, opts.flow.resolved_jump = 0,
    opts.flow.face_shear_tail = 3e-4, opts.flow.angle_switch = 0;
  opts.boundary = a->boundary;
  opts.flow.angle_steps = a->angles;
  if (a->has_inner) opts.inner_radius = a->inner_radius;
  if (!a->quiet) opts.flow.progress = cli_progress, opts.flow.user = &prog;

  au_mesh_expect ex = au_mesh_expect_default();
  ex.loops = a->cmd == CMD_ANNULUS ? 2 : 1, ex.genus = 0, ex.command = name;
  rc = cli_load_meta(a->in, &ex, &m, &topo, &meta, &warn, stages, &nst);
  if (rc >= 0) goto done;
  rc = cli_output_format(help_of(a->cmd), a->out, a->neuro.format, meta, &ofmt);
  if (rc) goto done;
  rc = EXIT_INTERNAL;

  /* The mesh that is mapped: the input, or for the square the input with split edges. */
  const au_mesh *mm = m;
  const au_topo *tt = topo;
  int nsplit = 0;
  if (a->cmd == CMD_ANNULUS) {
    if ((opts.outer_loop = pick_outer(a, topo)) < 0) {
      rc = EXIT_USAGE;
      goto done;
    }
  } else if (a->cmd == CMD_SQUARE) {
    t0 = cli_now();
    int c[4];
    if (a->has_corners) {
      memcpy(c, a->corners, sizeof c);
      st = au_square_order_corners(topo, c, &msg);
      if (st != AU_OK) {
        fprintf(stderr, "authalic: error: %s: --corners: %s\n", a->in, msg.text);
        rc = EXIT_USAGE;
        goto done;
      }
    } else {
      st = au_square_corners(m, topo, c, &msg);
      if (st != AU_OK) {
        /* Too few boundary vertices for four corners: a fault of the input. */
        fprintf(stderr, "authalic: error: %s: %s\n", a->in, msg.text);
        rc = EXIT_USAGE;
        goto done;
      }
    }
    st = au_square_split(m, topo, c, &ms, &nsplit, &msg);
    if (st == AU_OK) st = au_mesh_topology(ms, &ts, &msg);
    if (st != AU_OK) {
      rc = cli_fail(a->in, st, &msg);
      goto done;
    }
    memcpy(opts.corners, c, sizeof c);
    mm = ms, tt = ts;
    if (nsplit)
      cli_warn(&warn, a->in, "split %d edge%s joining vertices of one side; vertices %d..%d are their midpoints", nsplit,
               nsplit == 1 ? "" : "s", m->nv, ms->nv - 1);
    stages[nst++] = (au_report_stage){"split", cli_now() - t0};
  }

  size_t n3 = 3 * (size_t)mm->nv;
  P = malloc(n3 * sizeof *P);
  P0 = malloc(n3 * sizeof *P0);
  uv = malloc(2 * (size_t)mm->nv * sizeof *uv);
  if (!P || !P0 || !uv) {
    rc = cli_fail(a->in, AU_E_NOMEM, NULL);
    goto done;
  }

  au_disk_report rep;
  memset(&rep, 0, sizeof rep);
  if (a->init_only) {
    t0 = cli_now();
    if (a->cmd == CMD_DISK) st = au_disk_init(mm, tt, P, &rep.init, &msg);
    else if (a->cmd == CMD_ANNULUS)
      st = au_annulus_init(mm, tt, opts.outer_loop, opts.inner_radius, P, &rep.inner_radius, &rep.modulus_radius,
                           &rep.init, &msg);
    else st = au_square_init(mm, tt, opts.corners, P, &rep.init, &msg);
    rep.t_init = cli_now() - t0;
    memcpy(rep.corners, opts.corners, sizeof rep.corners);
  } else {
    if (a->cmd == CMD_DISK) st = au_disk_map(mm, tt, &opts, P, P0, &rep, &msg);
    else if (a->cmd == CMD_ANNULUS) st = au_annulus_map(mm, tt, &opts, P, P0, &rep, &msg);
    else st = au_square_map(mm, tt, &opts, P, P0, &rep, &msg);
    cli_progress_end(&prog);
  }
  if (st < 0) {
    rc = cli_fail(a->in, st, &msg);
    goto done;
  }
  if (st == AU_W_NOT_CONVERGED) {
    int k = rep.flow.steps;
    cli_warn(&warn, a->in, "tolerance %g not reached in %d steps (error %.3e)", opts.flow.tol, k, rep.flow.err[k]);
  }
  stages[nst++] = (au_report_stage){"init", rep.t_init};
  stages[nst++] = (au_report_stage){"flow", rep.t_flow};

  t0 = cli_now();
  st = au_metrics_compute(mm->nv, mm->nf, mm->X, P, mm->F, AU_DOMAIN_PLANE, &fin, NULL, NULL);
  if (st == AU_OK && !a->init_only)
    st = au_metrics_compute(mm->nv, mm->nf, mm->X, P0, mm->F, AU_DOMAIN_PLANE, &ini, NULL, NULL);
  if (st != AU_OK) {
    rc = cli_fail(a->in, st, NULL);
    goto done;
  }
  rc = cli_refuse_folds(a->in, &fin, !a->init_only && !rep.flow.converged);
  if (rc >= 0) goto done;
  rc = EXIT_INTERNAL;
  /* Boundary conformance, and the texture coordinates. */
  double bdev = 0;
  for (int i = 0; i < mm->nv; i++) {
    const double *p = P + 3 * i;
    if (a->cmd == CMD_SQUARE) {
      uv[2 * i] = p[0], uv[2 * i + 1] = p[1];
      if (tt->vb[i]) {
        double d = fmin(fmin(fabs(p[0]), fabs(p[0] - 1)), fmin(fabs(p[1]), fabs(p[1] - 1)));
        bdev = fmax(bdev, d);
      }
    } else {
      uv[2 * i] = 0.5 * (p[0] + 1), uv[2 * i + 1] = 0.5 * (p[1] + 1);
    }
  }
  if (a->cmd != CMD_SQUARE)
    for (int l = 0; l < tt->nloops; l++) {
      double want = a->cmd == CMD_DISK || l == opts.outer_loop ? 1.0 : rep.inner_radius;
      for (int k = tt->loop_start[l]; k < tt->loop_start[l + 1]; k++) {
        const double *p = P + 3 * tt->loop_vert[k];
        bdev = fmax(bdev, fabs(hypot(p[0], p[1]) - want));
      }
    }
  if (!(bdev <= 1e-12)) {
    fprintf(stderr, "authalic: error: %s: a boundary vertex is %.3g off the domain's boundary; nothing written\n", a->in, bdev);
    goto done;
  }
  stages[nst++] = (au_report_stage){"metrics", cli_now() - t0};
  stages[nst] = (au_report_stage){"write", 0};
  au_io_write_opts wopts = au_io_write_opts_default();
  wopts.uv = uv, wopts.format = ofmt, wopts.meta = meta, wopts.geometric_type = "Flat";
  /* The distortion file first (its own atomic write), removed again if OUT cannot be published. */
  if (a->neuro.distortion) {
    rc = cli_write_distortion(a->neuro.distortion, mm, P, AU_DOMAIN_PLANE, meta);
    if (rc >= 0) goto done;
  }
  au_report_info info;
  memset(&info, 0, sizeof info);
  info.tool_version = AU_VERSION, info.command = name, info.input = a->in, info.output = a->out;
  info.nv = mm->nv, info.nf = mm->nf;
  info.steps = rep.flow.steps, info.converged = a->init_only ? 0 : rep.flow.converged;
  info.undone = a->init_only ? 0 : rep.flow.undone;
  info.has_schedule = !a->init_only, info.start_jump = rep.flow.start_jump, info.resolved = rep.flow.resolved;
  info.angle_from = a->init_only ? 0 : rep.flow.angle_from;
  info.init = a->init_only ? NULL : &ini, info.final = &fin;
  info.stages = stages, info.nstages = nst + 1;
  info.step_err = a->init_only ? NULL : rep.flow.err, info.step_frac = a->init_only ? NULL : rep.flow.frac;
  info.step_face_err = a->init_only ? NULL : rep.flow.face_err;
  info.warnings = warn.list, info.nwarnings = warn.n;
  rc = cli_publish(a->out, mm, P, &wopts, a->report, &info, &stages[nst]);
  if (rc != EXIT_OK) {
    if (a->neuro.distortion) unlink(a->neuro.distortion);
    goto done;
  }

  if (!a->quiet) {
    char extra[160] = "";
    if (a->cmd == CMD_ANNULUS)
      snprintf(extra, sizeof extra, " inner_radius=%.6g modulus_radius=%.6g", rep.inner_radius, rep.modulus_radius);
    else if (a->cmd == CMD_SQUARE)
      snprintf(extra, sizeof extra, " corners=%d,%d,%d,%d split=%d", rep.corners[0], rep.corners[1], rep.corners[2],
               rep.corners[3], nsplit);
    fprintf(stderr,
            "authalic: %s: V=%d F=%d steps=%d folds=%d mean|r-1|=%.3g vertex|log r|=%.3g boundary_dev=%.2g%s "
            "start=%s time=%.2fs\n",
            name, mm->nv, mm->nf, rep.flow.steps, fin.folds, fin.r_mean_abs_dev, fin.vertex_logr_mean_abs, bdev, extra,
            rep.init == AU_INIT_COTAN ? "cotan" : "meanvalue", cli_now() - t_start);
  }
  rc = EXIT_OK;

done:
  cli_progress_end(&prog);
  free(P), free(P0), free(uv);
  au_io_meta_free(&meta);
  au_topo_free(&ts);
  au_mesh_free(&ms);
  au_topo_free(&topo);
  au_mesh_free(&m);
  return rc;
}

int cli_cmd_disk(int argc, char **argv) {
  disk_args a;
  memset(&a, 0, sizeof a);
  a.cmd = strcmp(argv[0], "annulus") == 0 ? CMD_ANNULUS : strcmp(argv[0], "square") == 0 ? CMD_SQUARE : CMD_DISK;
  int rc = parse_disk(argc, argv, &a);
  return rc >= 0 ? rc : run_disk(&a);
}
