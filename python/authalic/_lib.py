"""_lib.py - libauthalic.so.1 through ctypes: finding and loading the library, the public structs
laid out as in include/authalic.h (checked against au_struct_size at load), and the prototypes.

Nothing here is public; the package's __init__ is the interface. The environment defaults that
make the library's maps match the `authalic` program's bit for bit are set by __init__ before this
module loads the library (see the package docstring).
"""
import ctypes
import os

c_int, c_double, c_char, c_char_p, c_void_p, c_size_t = (
    ctypes.c_int, ctypes.c_double, ctypes.c_char, ctypes.c_char_p, ctypes.c_void_p, ctypes.c_size_t)
P_double, P_int = ctypes.POINTER(c_double), ctypes.POINTER(c_int)

AU_MAX_WARNINGS = 8
AU_MAX_STEPS = 512
AU_MAX_ANGLE_STEPS = 50
AU_REFINE_MAX_FACES = 16
AU_REFINE_AUTO = -1.0
# au_io_format
AU_IO_FORMAT_AUTO, AU_IO_FORMAT_OBJ, AU_IO_FORMAT_OFF, AU_IO_FORMAT_PLY, AU_IO_FORMAT_STL = 0, 1, 2, 3, 4
AU_IO_FORMAT_FREESURFER, AU_IO_FORMAT_GIFTI = 5, 6
AU_OUTER_LONGER, AU_OUTER_SHORTER = -1, -2
AU_E_ARG, AU_E_CANCELLED = -2, -7
TARGETS = {"sphere": 0, "disk": 1, "annulus": 2, "square": 3, "torus": 4, "circles": 5}
AU_LATTICES = {"conformal": 0, "square": 1}
DOMAINS = {"sphere": 0, "plane": 1}

# int (*au_progress_fn)(void *user, int step, int max_steps, double err)
PROGRESS_FN = ctypes.CFUNCTYPE(c_int, c_void_p, c_int, c_int, c_double)


class Msg(ctypes.Structure):
    _fields_ = [("text", c_char * 512)]


class Mesh(ctypes.Structure):
    _fields_ = [("nv", c_int), ("nf", c_int), ("X", P_double), ("F", P_int)]


class WriteOpts(ctypes.Structure):
    _fields_ = [("uv", P_double), ("precision", c_int), ("nvt", c_int), ("vt", P_double), ("Ft", P_int),
                ("format", c_int), ("meta", c_void_p), ("geometric_type", c_char_p), ("radius", c_double)]


class ReportExtra(ctypes.Structure):
    _fields_ = [("input", c_char_p), ("output", c_char_p), ("tool", c_char_p),
                ("t_read", c_double), ("t_validate", c_double), ("t_write", c_double),
                ("warnings", ctypes.POINTER(c_char_p)), ("nwarnings", c_int)]


class Options(ctypes.Structure):
    _fields_ = [("max_steps", c_int), ("tol", c_double), ("refine_faces", c_int), ("angle_steps", c_int),
                ("vertex_density", P_double), ("face_density", P_double), ("restore_shapes", c_double),
                ("balance", c_int), ("init_only", c_int), ("boundary", c_int), ("inner_radius", c_double),
                ("outer_loop", c_int), ("corners", c_int * 4), ("progress", PROGRESS_FN), ("user", c_void_p),
                ("cancel", P_int), ("expert", c_void_p), ("lattice", c_int), ("refine_mesh", c_int),
                ("measure_start", c_int), ("refine_max_faces", c_double), ("spherical_areas", c_int),
                ("aspect", c_double),
                ("start", c_int)]


# The au_metrics fields in order; the doubles among them are named here once.
METRIC_FIELDS = [
    ("nv", c_int), ("nf", c_int), ("domain", c_int),
    ("upsilon_mean_abs", c_double), ("upsilon_std", c_double), ("upsilon_max_abs", c_double),
    ("upsilon_p95_abs", c_double), ("upsilon_p99_abs", c_double), ("upsilon_wmean_abs", c_double),
    ("lambda_mean", c_double), ("lambda_std", c_double), ("lambda_max", c_double), ("lambda_p95", c_double),
    ("logr_mean_abs", c_double), ("r_std", c_double), ("r_mean_abs_dev", c_double), ("r_cv", c_double),
    ("authalic_energy", c_double), ("vertex_logr_mean_abs", c_double), ("vertex_logr_max_abs", c_double),
    ("angle_diff_mean_deg", c_double), ("sph_r_mean_abs_dev", c_double), ("sph_r_cv", c_double),
    ("sph_vertex_logr_mean_abs", c_double), ("sphere_radius_max_dev", c_double),
    ("chord_floor_faces", c_int), ("chord_floor_excess", c_double), ("folds", c_int), ("excluded", c_int),
    ("surface_area", c_double), ("domain_area", c_double),
]


class Metrics(ctypes.Structure):
    _fields_ = METRIC_FIELDS


class Convergence(ctypes.Structure):
    _fields_ = [("steps", c_int), ("converged", c_int), ("undone", c_int), ("err", P_double),
                ("face_err", P_double), ("frac", P_double), ("polish_from", c_int), ("angle_from", c_int),
                ("resolved", c_int), ("start_jump", c_double), ("lantern_retry", c_int),
                ("retry_err", c_double * 2), ("twist_retry", c_int), ("twist_faces", c_int),
                ("twist_err", c_double), ("vertex_polish", c_int), ("polish_sweeps", c_int),
                ("polish_err", c_double * 4), ("staged_retry", c_int), ("staged_stages", c_int),
                ("staged_err", c_double * 2), ("global_polish", c_int), ("global_polish_steps", c_int),
                ("global_polish_err", c_double * 4), ("global_polish_robust", c_double)]


class Result(ctypes.Structure):
    _fields_ = [("target", c_int), ("status", c_int), ("nv", c_int), ("nf", c_int), ("nv_in", c_int),
                ("nf_in", c_int), ("P", P_double), ("P0", P_double), ("X", P_double), ("F", P_int),
                ("uv", P_double), ("metrics", Metrics), ("init_metrics", Metrics), ("conv", Convergence),
                ("init_only", c_int), ("t_check", c_double), ("t_init", c_double), ("t_flow", c_double),
                ("t_metrics", c_double), ("factorizations", ctypes.c_long), ("boundary_dev", c_double),
                ("init_method", c_char_p),
                ("inner_radius", c_double), ("modulus_radius", c_double), ("outer_loop_vertex", c_int),
                ("corners", c_int * 4), ("nsplit", c_int), ("nwarnings", c_int),
                ("warnings", (c_char * 600) * AU_MAX_WARNINGS),
                ("lattice", (c_double * 2) * 2), ("conformal_lattice", (c_double * 2) * 2), ("nvt", c_int),
                ("vt", P_double), ("Ft", P_int), ("nrefined", c_int), ("parent", P_int), ("parent_t", P_double),
                ("init_measured", c_int), ("ncircles", c_int), ("circles", P_double), ("circle_vertex", P_int),
                ("circle_outer", c_int)]


class AtlasOptions(ctypes.Structure):
    _fields_ = [("max_cones", c_int), ("quarter", c_int), ("ncones", c_int), ("cone_v", P_int),
                ("cone_angle", P_double), ("raster", c_int), ("conformal_only", c_int), ("max_steps", c_int)]


class AtlasResult(ctypes.Structure):
    _fields_ = [("nv", c_int), ("nf", c_int), ("F", P_int), ("nvt", c_int), ("vt", P_double), ("Ft", P_int),
                ("ncones", c_int), ("cone_v", P_int), ("cone_angle", P_double), ("ncharts", c_int),
                ("nseams", c_int), ("ncut", c_int), ("seam_rot", P_double), ("seam_rot_dev", c_double),
                ("seam_len_dev", c_double), ("coverage", c_double), ("folds", c_int), ("overlap_texels", ctypes.c_long),
                ("equal_area", c_int), ("flow_steps", c_int), ("face_err_start", c_double), ("face_err", c_double),
                ("genus", c_int), ("nloops", c_int), ("newton_steps", c_int),
                ("metric_err", c_double), ("holonomy_loops", c_int), ("holonomy_cones", c_int),
                ("holonomy_fixed", c_int),
                ("holonomy_dev", c_double), ("holonomy_len_change", c_double), ("t_check", c_double),
                ("t_cones", c_double), ("t_metric", c_double), ("t_layout", c_double), ("t_flow", c_double), ("status", c_int), ("nwarnings", c_int), ("warnings", (c_char * 512) * 4)]


STRUCTS = {"au_msg": Msg, "au_mesh": Mesh, "au_write_opts": WriteOpts, "au_report_extra": ReportExtra,
           "au_options": Options, "au_metrics": Metrics, "au_convergence": Convergence, "au_result": Result,
           "au_atlas_options": AtlasOptions, "au_atlas_result": AtlasResult}


def _candidates():
    """Where to look for the library, in order: $AUTHALIC_LIBRARY; the path `make python` recorded in
    _config.py; the build tree of a source checkout (python/authalic -> ../../build); then the
    dynamic linker's own search (LD_LIBRARY_PATH, ldconfig) by SONAME."""
    env = os.environ.get("AUTHALIC_LIBRARY")
    if env:
        return [env], True
    found = []
    try:
        from . import _config  # written by `make python`
        found.append(_config.LIBRARY)
    except ImportError:
        pass
    here = os.path.dirname(os.path.abspath(__file__))
    found.append(os.path.join(here, "..", "..", "build", "libauthalic.so.1"))
    found.append("libauthalic.so.1")
    return found, False


def load():
    """Load libauthalic and declare its prototypes; raise ImportError naming what was tried, or
    naming the struct whose size differs from the library's (a header/library mismatch)."""
    paths, explicit = _candidates()
    lib, errors = None, []
    for p in paths:
        if os.sep in p and not os.path.exists(p) and not explicit:
            errors.append("%s: no such file" % p)
            continue
        try:
            lib = ctypes.CDLL(p)
            break
        except OSError as e:
            errors.append(str(e))
    if lib is None:
        raise ImportError("authalic: cannot load libauthalic.so.1 (set AUTHALIC_LIBRARY to its path, or run "
                          "`make python`): " + "; ".join(errors))
    lib.au_struct_size.restype = c_size_t
    lib.au_struct_size.argtypes = [c_char_p]
    for name, cls in STRUCTS.items():
        theirs = lib.au_struct_size(name.encode())
        if theirs != ctypes.sizeof(cls):
            raise ImportError("authalic: %s is %d bytes in %s but %d in this package: the library and the "
                              "package are from different versions" % (name, theirs, lib._name, ctypes.sizeof(cls)))

    def proto(name, restype, *argtypes):
        f = getattr(lib, name)
        f.restype, f.argtypes = restype, list(argtypes)

    P_msg, PP_result, PP_mesh = ctypes.POINTER(Msg), ctypes.POINTER(ctypes.POINTER(Result)), ctypes.POINTER(
        ctypes.POINTER(Mesh))
    proto("au_version", c_char_p)
    proto("au_status_str", c_char_p, c_int)
    proto("au_status_name", c_char_p, c_int)
    proto("au_status_is_input_error", c_int, c_int)
    proto("au_free", None, c_void_p)
    proto("au_options_default", Options)
    proto("au_target_defaults", None, c_int, P_int, P_double)
    proto("au_map", c_int, P_double, c_int, P_int, c_int, c_int, ctypes.POINTER(Options), PP_result, P_msg)
    proto("au_result_free", None, PP_result)
    proto("au_result_json", c_int, ctypes.POINTER(Result), ctypes.POINTER(ReportExtra),
          ctypes.POINTER(ctypes.POINTER(c_char)), P_msg)
    proto("au_mesh_read", c_int, c_char_p, PP_mesh, P_msg)
    proto("au_mesh_free", None, PP_mesh)
    proto("au_io_read_scalars", c_int, c_char_p, c_int, ctypes.POINTER(P_double), P_int, P_msg)
    proto("au_io_read_meta", c_int, c_char_p, PP_mesh, ctypes.POINTER(c_void_p), P_msg)
    proto("au_io_meta_free", None, ctypes.POINTER(c_void_p))
    proto("au_io_meta_format", c_int, c_void_p)
    proto("au_io_format_of_name", c_int, c_char_p)
    proto("au_io_format_parse", c_int, c_char_p)
    proto("au_io_format_name", c_char_p, c_int)
    proto("au_io_write_scalars", c_int, c_char_p, c_int, P_double, c_int, c_void_p, P_msg)
    proto("au_metrics_vertex_distortion", c_int, c_int, c_int, P_double, P_double, P_int, c_int, P_double, P_int)
    proto("au_metrics_vertex_distortion_vt", c_int, c_int, c_int, P_double, P_int, c_int, P_double, P_int, P_double,
          P_int)
    proto("au_output_target", c_void_p, c_char_p)
    proto("au_write_opts_default", WriteOpts)
    proto("au_mesh_write", c_int, c_char_p, c_int, P_double, c_int, P_int, ctypes.POINTER(WriteOpts), P_msg)
    proto("au_mesh_can_write", c_int, c_char_p)
    proto("au_write_text", c_int, c_char_p, c_char_p, c_size_t, P_msg)
    PP_atlas = ctypes.POINTER(ctypes.POINTER(AtlasResult))
    proto("au_atlas_options_default", AtlasOptions)
    proto("au_atlas", c_int, P_double, c_int, P_int, c_int, ctypes.POINTER(AtlasOptions), PP_atlas, P_msg)
    proto("au_atlas_result_free", None, PP_atlas)
    proto("au_atlas_result_json", c_int, ctypes.POINTER(AtlasResult), c_double, c_double,
          ctypes.POINTER(ctypes.POINTER(c_char)), P_msg)
    proto("au_metrics_compute", c_int, c_int, c_int, P_double, P_double, P_int, c_int, ctypes.POINTER(Metrics),
          P_double, P_double)
    return lib
