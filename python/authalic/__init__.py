"""authalic - equal-area (authalic) maps of triangle meshes, from Python.

A thin binding (ctypes, numpy) over libauthalic.so.1, the C library of the `authalic` program. A
triangle mesh (V, F) is mapped onto the unit sphere (closed genus-0 meshes), the unit disk or the
unit square (one boundary loop) or an annulus (two boundary loops), so that every part of the
surface gets its fair share of the domain's area, with no triangle folded; a closed genus-1 mesh goes
onto a flat torus (the plane modulo a lattice), with seamless per-corner texture coordinates.

    import authalic
    V, F = authalic.read_mesh("bunny.obj")          # float64 (nv, 3), int32 (nf, 3), 0-based
    S, info = authalic.sphere(V, F)                 # S: float64 (nv, 3), unit vectors
    print(info["steps"], info["metrics"]["folds"], info["metrics"]["vertex_logr_mean_abs"])
    authalic.write_mesh("bunny_sphere.obj", S, F)
    UV, info = authalic.disk(*authalic.read_mesh("face.obj"), boundary="slide")
    m = authalic.metrics(V, F, S, domain="sphere")  # the same numbers as info["metrics"]

Functions (each with its own manual: help(authalic.sphere)):
    read_mesh, write_mesh           files (.obj .off .ply .stl in; .obj .off .ply out)
    sphere, disk, annulus, square   the maps: (positions, info)
    torus                           the flat torus: (VT, FT, info), per-corner coordinates
    map_mesh                        any target, everything au_map returns (a MapResult)
    metrics                         the distortion of any map, under param-eval's key names
    version, blas_threads           the library's version; OpenBLAS's thread count

Arrays. Vertices: any real or integer array of shape (nv, 3) that numpy can convert, in any memory
order (views, Fortran order, float32, int64 ...); faces: integers of shape (nf, 3), 0-based,
counter-clockwise seen from outside (int64 is checked to fit in 32 bits). Inputs are never modified
(they are converted to C-ordered float64 / int32 copies only when they are not already so); every
returned array is a fresh numpy array that owns its memory.

Errors. Every failure raises authalic.Error (its .status is the library's au_status value, .name
its enum name such as "AU_E_FOLD", str() the library's one-line message). A fault of the input - a
bad file, a mesh of the wrong topology, a bad density, an array of the wrong shape, an option out
of range - raises authalic.BadInputError, a subclass of both authalic.Error and ValueError. Library
warnings (the tolerance not reached, unreferenced vertices) are issued as authalic.AuthalicWarning
through the warnings module, and are also listed in info["warnings"].

Threads and interrupts. The GIL is released while a map runs, so two threads may map two meshes at
once. A map started from the main thread runs in a helper thread while the main thread waits:
Ctrl-C (KeyboardInterrupt, or any exception a signal handler raises) sets the map's cancel flag, the
map stops at its next step, everything it allocated is freed, and the exception is raised in the
caller. A map started from another thread runs in that thread (Python handles signals in the main
thread only): to make Ctrl-C stop it, let the main thread wait on a threading.Event the worker sets
when done, in a loop with a timeout (`while not done.wait(0.1): pass`: the kernel may hand SIGINT
to another thread, and an untimed wait would not see it; and not Thread.join, which Python 3.11
may get wrong when interrupted) and, on KeyboardInterrupt, have the progress callable return True.

Thread settings and bit-identity with the program. CHOLMOD's OpenMP regions and OpenBLAS's threads
read OMP_THREAD_LIMIT and OPENBLAS_NUM_THREADS when those libraries are loaded. The `authalic`
program runs with both set to 1 (faster on two cores), and a library caller gets the program's map
bit for bit only under the same settings. So importing this package does, before numpy and
libauthalic are loaded, os.environ.setdefault("OMP_THREAD_LIMIT", "1") and
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1"): values you set yourself are kept. If numpy (whose
Debian build loads the same OpenBLAS) was imported before authalic, OpenBLAS has already started
with its own thread count; maps are still valid, but may then differ from the program's in the last
bits, and are slower (bunny: 17.7 s against 6 s on a loaded two-core machine, max |difference|
2.3e-5); importing authalic then warns (AuthalicWarning). For bit-identity and speed, import
authalic first, or set the variables before starting Python, or call authalic.blas_threads(1)
(which sets OpenBLAS's thread count for the whole process, numpy's products included).

Library. The package loads libauthalic.so.1 from $AUTHALIC_LIBRARY if set, else from the path
recorded by `make python` (authalic/_config.py), else from ../../build of a source checkout, else
through the dynamic linker's search. At import the size of every public C struct it lays out is
compared with au_struct_size of the loaded library; a mismatch fails the import with ImportError.

Command line: `python3 -m authalic sphere|disk|annulus|square|torus IN OUT [options]` behaves like the
`authalic` program (same options, exit status 0 ok, 2 bad usage or bad input, 1 other failures).
"""
import os as _os
import sys as _sys

# Before numpy and libauthalic (and so OpenBLAS and libgomp) are loaded: see the docstring above.
_BLAS_LOADED_BEFORE = "numpy" in _sys.modules and "OPENBLAS_NUM_THREADS" not in _os.environ
_os.environ.setdefault("OMP_THREAD_LIMIT", "1")
_os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import ctypes as _ct  # noqa: E402
import json as _json  # noqa: E402
import math as _math  # noqa: E402
import numbers as _numbers  # noqa: E402
import threading as _threading  # noqa: E402
import time as _time  # noqa: E402
import warnings as _warnings  # noqa: E402

import numpy as _np  # noqa: E402

from . import _lib  # noqa: E402

_L = _lib.load()

__version__ = _L.au_version().decode()
__all__ = ["Error", "BadInputError", "AuthalicWarning", "MapResult", "read_mesh", "read_values", "write_mesh", "sphere", "disk",
           "annulus", "square", "torus", "circles", "atlas", "map_mesh", "metrics", "version", "blas_threads"]

_INT_MIN, _INT_MAX = -2 ** 31, 2 ** 31 - 1


# ---------------------------------------------------------------- errors


class Error(Exception):
    """A failure reported by libauthalic (or found by the binding before calling it).

    Attributes:
        status: the library's au_status value (negative), or None for a check made in Python.
        name:   the status's enum name ("AU_E_FOLD", "AU_E_NONMANIFOLD_EDGE", ...), or None.
    str(error) is the library's one-line message ("edge (12, 40) is shared by 3 faces").
    """

    def __init__(self, message, status=None, name=None):
        super().__init__(message)
        self.status = status
        self.name = name


class BadInputError(Error, ValueError):
    """A fault of the input: an unreadable or malformed file, a mesh of the wrong topology for the
    target, non-finite coordinates, a bad density, an array of the wrong shape or type, or an option
    out of its range. A subclass of both authalic.Error and ValueError."""


class AuthalicWarning(UserWarning):
    """A warning of the library: the result is usable (the tolerance was not reached, some vertices
    are used by no face). The same text is in info["warnings"]."""


def _raise(status, msg):
    """Raise the exception for a negative status with the message buffer msg (an _lib.Msg)."""
    text = msg.text.decode("utf-8", "replace") if msg is not None else ""
    if not text:
        text = _L.au_status_str(status).decode()
    name = _L.au_status_name(status).decode()
    bad = _L.au_status_is_input_error(status) or status == _lib.AU_E_ARG
    raise (BadInputError if bad else Error)(text, status, name)


def _bad(text):
    raise BadInputError(text)


def version():
    """The version of the loaded libauthalic, "MAJOR.MINOR.PATCH" (au_version); also
    authalic.__version__. The JSON report of a map names the same version under "version"."""
    return __version__


def blas_threads(n=None):
    """Get, or set and get, the number of threads of the OpenBLAS that libauthalic (and Debian's
    numpy) uses; None when the library does not use OpenBLAS.

    n: None to only ask; else a whole number >= 1 (openblas_set_num_threads). This is process-wide:
    numpy's matrix products use the same OpenBLAS. Maps match the `authalic` program's bit for bit
    with one thread, which importing authalic before numpy arranges (OPENBLAS_NUM_THREADS=1); if
    numpy came first, blas_threads(1) restores it.
    """
    try:
        get, put = _L.openblas_get_num_threads, _L.openblas_set_num_threads
    except AttributeError:
        return None
    get.restype, get.argtypes = _ct.c_int, []
    put.restype, put.argtypes = None, [_ct.c_int]
    if n is not None:
        if isinstance(n, bool) or not isinstance(n, _numbers.Integral) or n < 1:
            _bad("blas_threads %r: expected a whole number >= 1" % (n,))
        put(int(n))
    return get()


if _BLAS_LOADED_BEFORE and (blas_threads() or 1) > 1:
    _warnings.warn("numpy was imported before authalic, so OpenBLAS already runs %d threads: maps are slower and "
                   "may differ from the `authalic` program's in the last bits. Import authalic first, set "
                   "OPENBLAS_NUM_THREADS=1, or call authalic.blas_threads(1)." % blas_threads(),
                   AuthalicWarning, stacklevel=2)


# ---------------------------------------------------------------- arrays in and out


def _real_array(a, name, cols, n=None):
    """a as a C-ordered float64 (n, 3) array (2 columns padded with zeros when cols allows it),
    converted only if needed; never a view that could be written through."""
    try:
        x = _np.asarray(a)
    except Exception as e:  # e.g. ragged lists
        _bad("%s: cannot be read as an array (%s)" % (name, e))
    if x.dtype.kind not in "fiu":
        _bad("%s: expected real numbers, got dtype %s" % (name, x.dtype))
    if x.ndim != 2 or x.shape[1] not in cols:
        _bad("%s: expected an array of shape (n, %s), got shape %s" % (name, " or ".join(map(str, cols)), x.shape))
    if n is not None and x.shape[0] != n:
        _bad("%s: %d rows; expected %d (one per vertex)" % (name, x.shape[0], n))
    if x.shape[0] > _INT_MAX:
        _bad("%s: too many rows (%d)" % (name, x.shape[0]))
    if x.shape[1] == 2 and 3 in cols:
        y = _np.zeros((x.shape[0], 3))
        y[:, :2] = x
        return y
    return _np.ascontiguousarray(x, dtype=_np.float64)


def _faces(F, name="F"):
    """F as a C-ordered int32 (nf, 3) array; integer values that do not fit in 32 bits, and
    non-integer values, are refused rather than wrapped."""
    try:
        x = _np.asarray(F)
    except Exception as e:
        _bad("%s: cannot be read as an array (%s)" % (name, e))
    if x.ndim != 2 or x.shape[1] != 3:
        _bad("%s: expected an array of shape (nf, 3), got shape %s" % (name, x.shape))
    if x.shape[0] > _INT_MAX:
        _bad("%s: too many faces (%d)" % (name, x.shape[0]))
    if x.dtype.kind == "f":
        if not _np.all(_np.isfinite(x)) or not _np.all(x == _np.floor(x)):
            _bad("%s: face indices must be whole numbers" % name)
    elif x.dtype.kind not in "iu":
        _bad("%s: expected integer face indices, got dtype %s" % (name, x.dtype))
    if x.dtype != _np.intc and x.size:
        lo, hi = x.min(), x.max()
        if lo < _INT_MIN or hi > _INT_MAX:
            bad = lo if lo < _INT_MIN else hi
            _bad("face index %d out of range" % bad)
    return _np.ascontiguousarray(x, dtype=_np.intc)


def _pd(a):
    return a.ctypes.data_as(_lib.P_double)


def _pi(a):
    return a.ctypes.data_as(_lib.P_int)


def _copy(ptr, shape, dtype):
    """A numpy copy of n C values at ptr (None for a NULL pointer)."""
    if not ptr:
        return None
    return _np.ctypeslib.as_array(ptr, shape).astype(dtype, copy=True)


# ---------------------------------------------------------------- files


def read_mesh(path):
    """Read a triangle mesh file.

    path: a .obj, .off, .ply (ASCII or binary) or .stl file, GIfTI (.gii, .gii.gz) or a FreeSurfer
        surface (lh.white, found by its magic number whatever the name); str, bytes or os.PathLike.
    Returns (V, F): V float64 array of shape (nv, 3), F int32 array of shape (nf, 3), 0-based, in the
    file's order. Polygons with more than three corners are refused, not triangulated; nothing is
    repaired.
    Raises BadInputError (missing or unreadable file, unknown format, malformed or truncated
    file, empty mesh, face index out of range, bad face) or Error (out of memory).
    """
    m = _ct.POINTER(_lib.Mesh)()
    msg = _lib.Msg()
    st = _L.au_mesh_read(_os.fsencode(path), _ct.byref(m), _ct.byref(msg))
    try:
        if st < 0:
            _raise(st, msg)
        mm = m.contents
        V = _copy(mm.X, (mm.nv, 3), _np.float64) if mm.nv else _np.zeros((0, 3))
        F = _copy(mm.F, (mm.nf, 3), _np.int32) if mm.nf else _np.zeros((0, 3), _np.int32)
        return V, F
    finally:
        _L.au_mesh_free(_ct.byref(m))


def read_values(path):
    """Read per-vertex (or per-face) values: a FreeSurfer curv file (lh.sulc, lh.thickness), GIfTI
    (.shape.gii, .func.gii, .gii.gz: its one data array that is not a mesh) or text (numbers separated
    by blanks, commas or line ends, `#` starting a comment line), as the program's --density reads them.
    Returns a float64 array, in the file's order. Raises BadInputError (missing, unreadable, malformed,
    truncated or empty file, a value that is not finite) or Error.
    """
    out = _ct.POINTER(_ct.c_double)()
    n = _ct.c_int(0)
    msg = _lib.Msg()
    st = _L.au_io_read_scalars(_os.fsencode(path), 0, _ct.byref(out), _ct.byref(n), _ct.byref(msg))
    try:
        if st < 0:
            _raise(st, msg)
        return _copy(out, (n.value,), _np.float64)
    finally:
        _L.au_free(out)


def write_mesh(path, V, F, uv=None, precision=17, vt=None, Ft=None):
    """Write a triangle mesh file, atomically.

    path: .obj, .off or .ply (ASCII); the format follows the extension.
    V: vertex positions, shape (nv, 3), or (nv, 2) for a planar map (written with z = 0).
    F: faces, shape (nf, 3), 0-based indices into V.
    uv: optional per-vertex texture coordinates, shape (nv, 2), written as OBJ `vt` lines (ignored
        by the other formats). The planar maps' texture coordinates in [0,1]^2 are
        MapResult.uv; for disk() and annulus() output they are (UV + 1) / 2.
    vt, Ft: per-corner texture coordinates instead of uv (OBJ only), both or neither: vt float (nvt, 2)
        written as `vt` lines, Ft integers (nf, 3), 0-based rows of vt, written as `f v/vt`; what
        torus() returns.
    precision: significant digits, 1..17 (17, the default, reads back exactly).
    The file is written under a temporary name beside path and renamed over it when complete, so a
    failure leaves neither a partial file nor a clobbered old one.
    Raises BadInputError (bad arrays, unknown extension, unwritable path) or Error.
    """
    Va = _real_array(V, "V", (2, 3))
    Fa = _faces(F)
    if Va.shape[0] == 0 or Fa.shape[0] == 0:
        _bad("write_mesh: empty mesh (%d vertices, %d faces)" % (Va.shape[0], Fa.shape[0]))
    o = _L.au_write_opts_default()
    if not isinstance(precision, _numbers.Integral) or not 1 <= precision <= 17:
        _bad("precision %r: expected a whole number from 1 to 17" % (precision,))
    o.precision = int(precision)
    ua = vta = Fta = None
    if uv is not None:
        ua = _real_array(uv, "uv", (2,), Va.shape[0])
        o.uv = _pd(ua)
    if (vt is None) != (Ft is None):
        _bad("write_mesh: vt and Ft go together")
    if vt is not None:
        if uv is not None:
            _bad("write_mesh: uv or vt/Ft, not both")
        vta = _real_array(vt, "vt", (2,))
        Fta = _faces(Ft, "Ft")
        if Fta.shape[0] != Fa.shape[0]:
            _bad("Ft: %d rows; F has %d" % (Fta.shape[0], Fa.shape[0]))
        if Fta.size and (Fta.min() < 0 or Fta.max() >= vta.shape[0]):
            _bad("Ft: an index is outside vt's %d rows" % vta.shape[0])
        o.nvt, o.vt, o.Ft = vta.shape[0], _pd(vta), _pi(Fta)
    msg = _lib.Msg()
    st = _L.au_mesh_write(_os.fsencode(path), Va.shape[0], _pd(Va), Fa.shape[0], _pi(Fa), _ct.byref(o),
                          _ct.byref(msg))
    if st < 0:
        _raise(st, msg)


# ---------------------------------------------------------------- metrics

# The report's metric keys (param-eval's names) and their au_metrics fields, in the report's order
# (common/au_report.c); the sphere-only ones are left out for planar maps, as in the report.
_METRIC_KEYS = [(k, k) for k in (
    "upsilon_mean_abs", "upsilon_std", "upsilon_max_abs", "upsilon_p95_abs", "upsilon_p99_abs", "upsilon_wmean_abs",
    "lambda_mean", "lambda_std", "lambda_max", "lambda_p95", "logr_mean_abs", "r_std", "r_mean_abs_dev", "r_cv",
    "authalic_energy", "vertex_logr_mean_abs", "vertex_logr_max_abs", "surface_area")] + [
    ("domain_area_sum", "domain_area"), ("angle_diff_mean_deg", "angle_diff_mean_deg")]
_SPHERE_KEYS = ["sph_r_mean_abs_dev", "sph_r_cv", "sph_vertex_logr_mean_abs", "sphere_radius_max_dev",
                "chord_floor_excess"]


def _finite_or_none(x):
    return x if _math.isfinite(x) else None


def _metrics_dict(m):
    sphere = m.domain == _lib.DOMAINS["sphere"]
    d = {"domain": "sphere" if sphere else "plane"}
    for key, field in _METRIC_KEYS:
        d[key] = _finite_or_none(getattr(m, field))
    if sphere:
        for key in _SPHERE_KEYS:
            d[key] = _finite_or_none(getattr(m, key))
    d["folds"] = m.folds
    d["excluded_faces"] = m.excluded
    if sphere:
        d["chord_floor_faces"] = m.chord_floor_faces
    return d


def metrics(V, F, P, domain=None, per_face=False):
    """The distortion of the map V -> P, under the names and definitions of param-eval.

    V: surface positions, shape (nv, 3).  F: faces, shape (nf, 3).
    P: the map, shape (nv, 3) on the sphere, or (nv, 2) / (nv, 3) with z ignored in the plane.
    domain: "sphere", or "plane" (also accepted: "disk", "annulus", "square"); None (default): as
        param-eval detects it, the plane when P has two columns or every z is 0, else the sphere.
    per_face: also return the per-face Upsilon and Lambda arrays (NaN for excluded faces).
    Per face, J is the affine map from the domain triangle (the chord triangle on the sphere) to
    the surface triangle, the surface scaled to the domain's total area; gmax >= gmin are its
    singular values; Upsilon = ln(gmax gmin) (area), Lambda = ln(gmax / gmin) (angle); r = domain
    share / surface share. Faces whose domain or surface area is <= 1e-14 of the total are excluded.
    Returns a dict with the keys of info["metrics"] in a map's report: "domain", upsilon_*,
    lambda_*, logr_mean_abs, r_std, r_mean_abs_dev (mean |r - 1|), r_cv (std/mean of r),
    authalic_energy, vertex_logr_mean_abs, vertex_logr_max_abs, surface_area, domain_area_sum,
    angle_diff_mean_deg, folds, excluded_faces, and on the sphere sph_r_mean_abs_dev, sph_r_cv,
    sph_vertex_logr_mean_abs, sphere_radius_max_dev, chord_floor_excess, chord_floor_faces
    (non-finite values are None, as null in the JSON report); with per_face, also "upsilon" and
    "lambda" (float64 arrays of shape (nf,)).
    Raises BadInputError (bad arrays, unknown domain, zero total area) or Error.
    """
    if domain is None:  # param-eval looks at the vertices the faces use
        Pz, Fz = _real_array(P, "P", (2, 3)), _faces(F)
        used = _np.unique(Fz) if Fz.size else _np.zeros(0, _np.int64)
        used = used[(used >= 0) & (used < Pz.shape[0])]
        domain = "plane" if not Pz[used, 2].any() else "sphere"
    if domain not in ("sphere", "plane", "disk", "annulus", "square"):
        _bad("domain %r: expected 'sphere' or 'plane'" % (domain,))
    dom = _lib.DOMAINS["sphere" if domain == "sphere" else "plane"]
    Va = _real_array(V, "V", (2, 3))
    Fa = _faces(F)
    Pa = _real_array(P, "P", (2, 3) if dom else (3,), Va.shape[0])
    nf = Fa.shape[0]
    if nf == 0:
        _bad("metrics: the mesh has no faces")
    if Fa.min() < 0 or Fa.max() >= Va.shape[0]:
        _bad("face index %d out of range (%d vertices)" % (Fa.min() if Fa.min() < 0 else Fa.max(), Va.shape[0]))
    out = _lib.Metrics()
    ups = lam = None
    if per_face:
        ups, lam = _np.empty(nf), _np.empty(nf)
    msg_status = _L.au_metrics_compute(Va.shape[0], nf, _pd(Va), _pd(Pa), _pi(Fa), dom, _ct.byref(out),
                                       _pd(ups) if per_face else None, _pd(lam) if per_face else None)
    if msg_status < 0:
        _raise(msg_status, None)
    d = _metrics_dict(out)
    if per_face:
        d["upsilon"], d["lambda"] = ups, lam
    return d


# ---------------------------------------------------------------- maps


class MapResult:
    """Everything a map returns (map_mesh).

    P:        float64 (nv, 3): the map (unit vectors on the sphere; (u, v, 0) in the plane).
    P0:       float64 (nv, 3): the initial (conformal or harmonic) map.
    X:        float64 (nv, 3): surface positions (the input's, then the square's or refine_mesh's split
              midpoints).
    F:        int32 (nf, 3): faces (the input's, re-oriented where they disagreed with their neighbours
              (status "AU_W_REORIENTED"), then the square's split faces; with refine_mesh the refined
              mesh's faces).
    uv:       planar targets: float64 (nv, 2) texture coordinates in [0,1]^2 ((u+1)/2, (v+1)/2 for
              disk and annulus; (u, v) for the square); None on the sphere and the torus.
    vt, Ft, lattice: the torus's: vt float64 (nvt, 2) per-corner coordinates in the plane, Ft int32
              (nf, 3) each corner's row of vt, lattice float64 (2, 2) the basis a1 = lattice[0],
              a2 = lattice[1] (determinant 1); None for the other targets.
    nv_in, nf_in: the input's counts: rows [0, nv_in) of P and X, [0, nf_in) of F are the input's.
    info:     the JSON report as a dict (see sphere()).
    status:   "AU_OK", "AU_W_NOT_CONVERGED", "AU_W_UNREFERENCED" or "AU_W_REORIENTED".
    warnings: the library's warnings (list of str).
    inner_radius, modulus_radius, outer_loop_vertex: the annulus's; corners (4 vertex indices for
              (0,0), (1,0), (1,1), (0,1)) and nsplit: the square's; boundary_dev: planar targets'
              largest distance of the boundary from the domain's boundary; init_method: "cotan" or
              "meanvalue" for planar targets and the torus (the torus also "compressed"); the sphere's
              start, "conformal" or "multilevel".
    parent, parent_t: the sphere with refine_mesh=True: int32 (nv - nv_in, 2) and float64 (nv - nv_in,):
              new vertex nv_in + k lies at (1 - parent_t[k]) X[parent[k, 0]] + parent_t[k] X[parent[k, 1]]
              (a parent may itself be new, with a smaller number); None without refinement.
    """

    __slots__ = ("target", "P", "P0", "X", "F", "uv", "nv_in", "nf_in", "info", "status", "warnings",
                 "inner_radius", "modulus_radius", "outer_loop_vertex", "corners", "nsplit", "boundary_dev",
                 "init_method", "vt", "Ft", "lattice", "parent", "parent_t", "circles", "circle_vertex")

    def __repr__(self):
        return "<authalic.MapResult %s nv=%d nf=%d status=%s steps=%s folds=%s>" % (
            self.target, self.P.shape[0], self.F.shape[0], self.status, self.info.get("steps"),
            self.info.get("metrics", {}).get("folds"))


def _collect(res, target, extra):
    """Copy a result out of the library (the caller frees it)."""
    r = res.contents
    nv, nf = r.nv, r.nf
    out = MapResult()
    out.target = target
    out.P = _copy(r.P, (nv, 3), _np.float64)
    out.P0 = _copy(r.P0, (nv, 3), _np.float64)
    out.X = _copy(r.X, (nv, 3), _np.float64)
    out.F = _copy(r.F, (nf, 3), _np.int32)
    out.uv = _copy(r.uv, (nv, 2), _np.float64)
    out.vt = _copy(r.vt, (r.nvt, 2), _np.float64) if target == "torus" else None
    out.Ft = _copy(r.Ft, (nf, 3), _np.int32) if target == "torus" else None
    out.lattice = _np.array([[r.lattice[0][0], r.lattice[0][1]], [r.lattice[1][0], r.lattice[1][1]]]) \
        if target == "torus" else None
    out.nv_in, out.nf_in = r.nv_in, r.nf_in
    out.status = _L.au_status_name(r.status).decode()
    out.warnings = [r.warnings[k].value.decode("utf-8", "replace") for k in range(r.nwarnings)]
    out.inner_radius, out.modulus_radius, out.outer_loop_vertex = r.inner_radius, r.modulus_radius, r.outer_loop_vertex
    out.corners, out.nsplit, out.boundary_dev = list(r.corners), r.nsplit, r.boundary_dev
    out.init_method = r.init_method.decode() if r.init_method else None
    out.circles = _copy(r.circles, (r.ncircles, 3), _np.float64) if r.ncircles > 0 else None
    out.circle_vertex = _copy(r.circle_vertex, (r.ncircles,), _np.int32) if r.ncircles > 0 else None
    out.parent = _copy(r.parent, (r.nrefined, 2), _np.int32) if r.nrefined > 0 else None
    out.parent_t = _copy(r.parent_t, (r.nrefined,), _np.float64) if r.nrefined > 0 else None
    js = _ct.POINTER(_ct.c_char)()
    msg = _lib.Msg()
    st = _L.au_result_json(res, _ct.byref(extra) if extra is not None else None, _ct.byref(js), _ct.byref(msg))
    if st < 0:
        _raise(st, msg)
    try:
        out.info = _json.loads(_ct.string_at(js).decode("utf-8"))
    finally:
        _L.au_free(js)
    return out


class _Bar:
    """progress=True: a tqdm bar on stderr when python3-tqdm is installed, else one line redrawn on
    a terminal (a line a second otherwise), as the program draws it."""

    def __init__(self, target):
        self.target, self.bar, self.drawn, self.t_last = target, None, False, 0.0
        try:
            import tqdm
            self.tqdm = tqdm.tqdm
        except ImportError:
            self.tqdm = None

    def __call__(self, step, max_steps, err):
        if self.tqdm is not None:
            if self.bar is None:
                self.bar = self.tqdm(total=max_steps, desc="authalic " + self.target, unit="step", file=_sys.stderr)
            if self.bar.total != max_steps:
                self.bar.total = max_steps
            self.bar.set_postfix_str("err %.3e" % err, refresh=False)
            self.bar.update(step - self.bar.n)
            return
        if _sys.stderr.isatty():
            _sys.stderr.write("\rauthalic: step %d/%d  err %.3e " % (step, max_steps, err))
            self.drawn = True
        elif _time.monotonic() - self.t_last >= 1.0:
            _sys.stderr.write("authalic: step %d/%d  err %.3e\n" % (step, max_steps, err))
            self.t_last = _time.monotonic()
        _sys.stderr.flush()

    def close(self):
        if self.bar is not None:
            self.bar.close()
        elif self.drawn:
            _sys.stderr.write("\n")
            _sys.stderr.flush()


def _int_opt(name, v, lo, hi):
    if isinstance(v, bool) or not isinstance(v, _numbers.Integral) or not lo <= v <= hi:
        _bad("%s %r: expected a whole number from %d to %d" % (name, v, lo, hi))
    return int(v)


def _real_opt(name, v, lo, hi, lo_open=False, hi_open=False):
    ok = isinstance(v, _numbers.Real) and not isinstance(v, bool) and _math.isfinite(v)
    ok = ok and (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)
    if not ok:
        _bad("%s %r: expected a number %s %g%s" % (name, v, ">" if lo_open else ">=", lo,
                                                   "" if hi == _math.inf else " and %s %g" % ("<" if hi_open else "<=", hi)))
    return float(v)


_PLANAR_ONLY = {"boundary": "disk, annulus, square and circles", "inner_radius": "annulus", "outer_loop": "annulus",
                "outer": "circles", "aspect": "square",
                "corners": "square", "restore_shapes": "sphere", "balance": "sphere", "lattice": "torus",
                "refine_mesh": "sphere", "refine_budget": "sphere", "spherical_areas": "sphere", "start": "sphere"}
_APPLIES = {"boundary": ("disk", "annulus", "square", "circles"), "inner_radius": ("annulus",),
            "outer_loop": ("annulus",), "outer": ("circles",), "aspect": ("square",),
            "corners": ("square",), "restore_shapes": ("sphere",), "balance": ("sphere",), "lattice": ("torus",),
            "refine_mesh": ("sphere",), "refine_budget": ("sphere",), "spherical_areas": ("sphere",),
            "start": ("sphere",)}


def _flag_opt(name, v):
    """A keyword that is True or False (None: not given, False); anything else (1, "no", an array) is
    refused rather than read by its truth value."""
    if v is not None and v is not True and v is not False:
        _bad("%s %r: expected True or False" % (name, v))
    return v is True


def _options(target, nv, nf, steps, tol, density, angles, refine_faces, init_only, extra):
    """au_options from the keyword arguments, checked with the keywords' names; also returns the
    density array (to keep it alive during the call)."""
    for k, v in extra.items():
        if k not in _APPLIES:
            raise TypeError("unexpected keyword argument %r" % k)
        if target not in _APPLIES[k] and v is not None:
            _bad("%s: applies to the %s map only" % (k, _PLANAR_ONLY[k]))
    o = _L.au_options_default()
    flow_given = []
    if steps is not None:
        o.max_steps = _int_opt("steps", steps, 1, _lib.AU_MAX_STEPS)
        flow_given.append("steps")
    if tol is not None:
        o.tol = _real_opt("tol", tol, 0, _math.inf)
        flow_given.append("tol")
    if angles:
        o.angle_steps = _int_opt("angles", angles, 0, _lib.AU_MAX_ANGLE_STEPS)
        flow_given.append("angles")
    if _flag_opt("refine_faces", refine_faces):
        o.refine_faces = 1
        flow_given.append("refine_faces")
    o.init_only = 1 if _flag_opt("init_only", init_only) else 0
    d = None
    if density is not None:
        try:
            d = _np.ascontiguousarray(density, dtype=_np.float64)
        except (TypeError, ValueError) as e:
            _bad("density: cannot be read as an array of numbers (%s)" % e)
        if d.ndim != 1 or d.shape[0] not in (nv, nf):
            _bad("density: %s values; the mesh has %d vertices and %d faces" % (
                d.shape[0] if d.ndim == 1 else "shape %s:" % (d.shape,), nv, nf))
        if d.shape[0] == nv:  # as the program: nv values are per vertex, even when nv == nf
            o.vertex_density = _pd(d)
        else:
            o.face_density = _pd(d)
        flow_given.append("density")
    v = extra.get("restore_shapes")
    if v is not None:
        o.restore_shapes = _real_opt("restore_shapes", v, 0, 1)
        flow_given.append("restore_shapes")
    v = extra.get("balance")
    if v is not None:
        o.balance = 1 if _flag_opt("balance", v) else 0
    v = extra.get("boundary")
    if v is not None:
        if v not in ("slide", "fixed"):
            _bad("boundary %r: expected 'slide' or 'fixed'" % (v,))
        o.boundary = 0 if v == "slide" else 1
        flow_given.append("boundary")
    v = extra.get("inner_radius")
    if v is not None:
        o.inner_radius = _real_opt("inner_radius", v, 0, 1, True, True)
    v = extra.get("outer_loop")
    if v is not None:
        if v == "longer":
            o.outer_loop = _lib.AU_OUTER_LONGER
        elif v == "shorter":
            o.outer_loop = _lib.AU_OUTER_SHORTER
        elif isinstance(v, _numbers.Integral) and not isinstance(v, bool) and 0 <= v <= _INT_MAX:
            o.outer_loop = int(v)
        else:
            _bad("outer_loop %r: expected 'longer', 'shorter' or a vertex index" % (v,))
    if _flag_opt("refine_mesh", extra.get("refine_mesh")):
        o.refine_mesh = 1
        flow_given.append("refine_mesh")
    v = extra.get("refine_budget")
    if v is not None:
        if not extra.get("refine_mesh"):
            _bad("refine_budget: applies with refine_mesh=True only")
        if isinstance(v, str) and v == "auto":
            o.refine_max_faces = _lib.AU_REFINE_AUTO
        elif (isinstance(v, _numbers.Real) and not isinstance(v, bool) and _math.isfinite(v)
              and 1 < v <= _lib.AU_REFINE_MAX_FACES):
            o.refine_max_faces = float(v)
        else:
            _bad("refine_budget %r: expected 'auto' or a number > 1 and <= %d" % (v, _lib.AU_REFINE_MAX_FACES))
    if _flag_opt("spherical_areas", extra.get("spherical_areas")):
        o.spherical_areas = 1
        flow_given.append("spherical_areas")
    v = extra.get("start")
    if v is not None:
        if not isinstance(v, str) or v not in ("conformal", "multilevel"):
            _bad("start %r: expected 'conformal' or 'multilevel'" % (v,))
        o.start = 1 if v == "multilevel" else 0
    v = extra.get("lattice")
    if v is not None:
        if v not in _lib.AU_LATTICES:
            _bad("lattice %r: expected 'conformal' or 'square'" % (v,))
        o.lattice = _lib.AU_LATTICES[v]
    v = extra.get("outer")
    if v is not None:
        if not (isinstance(v, _numbers.Integral) and not isinstance(v, bool) and 0 <= v <= _INT_MAX):
            _bad("outer %r: expected a vertex index" % (v,))
        o.outer_loop = int(v)
    v = extra.get("aspect")
    if v is not None:
        w = list(v) if isinstance(v, (list, tuple)) else [v, 1]
        if len(w) != 2 or not all(isinstance(x, _numbers.Real) and not isinstance(x, bool) and _math.isfinite(x) and x > 0
                                  for x in w) or not (_math.isfinite(w[0] / w[1]) and w[0] / w[1] > 0):
            _bad("aspect %r: expected a positive width / height, or (W, H)" % (v,))
        o.aspect = float(w[0]) / float(w[1])
    v = extra.get("corners")
    if v is not None:
        c = list(v) if isinstance(v, (list, tuple, _np.ndarray)) else []
        if len(c) != 4 or not all(isinstance(x, _numbers.Integral) and not isinstance(x, bool) and 0 <= x <= _INT_MAX
                                  for x in c):
            _bad("corners %r: expected four vertex indices" % (v,))
        o.corners[:] = [int(x) for x in c]
    if init_only and flow_given:
        _bad("init_only runs no advection: %s do%s not apply" % (", ".join(flow_given),
                                                                  "es" if len(flow_given) == 1 else ""))
    return o, d


class _Call:
    """One map's shared state between the caller and the thread running au_map."""

    def __init__(self, progress, target):
        self.cancel = _ct.c_int(0)
        self.exc = None          # an exception raised by the progress callable (re-raised by the caller)
        self.outcome = None      # (status, message text, MapResult or None)
        self.bar = _Bar(target) if progress is True else None
        self.user = self.bar if self.bar is not None else (progress if callable(progress) else None)
        if progress not in (None, False, True) and not callable(progress):
            _bad("progress %r: expected True, False or a callable (step, max_steps, error)" % (progress,))
        self.fn = _lib.PROGRESS_FN(self._progress) if self.user is not None else None

    def _progress(self, _user, step, max_steps, err):
        # Runs with the GIL re-acquired, once per step; any exception cancels the map.
        try:
            if self.cancel.value:
                return 1
            return 1 if self.user(step, max_steps, err) else 0
        except BaseException as e:  # noqa: B902 - handed to the caller, which re-raises it
            self.exc = e
            return 1


def _run_map(Va, Fa, tcode, o, call, target, extra, keep, done=None):
    """au_map and the copy of its result; the outcome goes to call. keep holds arrays o points
    into (the density), alive until au_map has returned. done (an Event) is set at the very end."""
    try:
        res = _ct.POINTER(_lib.Result)()
        msg = _lib.Msg()
        st = _L.au_map(_pd(Va), Va.shape[0], _pi(Fa), Fa.shape[0], tcode, _ct.byref(o), _ct.byref(res),
                       _ct.byref(msg))
        try:
            out = _collect(res, target, extra) if st >= 0 else None
            call.outcome = (st, msg, out)
        except BaseException as e:  # noqa: B902 - e.g. MemoryError while copying, re-raised by the caller
            call.outcome = (st, msg, None)
            call.exc = call.exc or e
        finally:
            _L.au_result_free(_ct.byref(res))
    finally:
        del keep
        if done is not None:
            done.set()


def _wait(thread, done, call):
    """Wait, in the main thread, for the map's thread to set done. The wait polls in short sleeps, so
    a signal is seen within 0.05 s; an exception its handler raises (KeyboardInterrupt) sets the
    cancel flag and the wait goes on until the map has stopped; the first such exception is
    returned. No lock is waited on where the exception can land: not Thread.join (in Python 3.11 a
    join interrupted by KeyboardInterrupt can mark a running thread as stopped), and not done.wait,
    an Event's condition lock (suspected: one CI run waited 300 s for `python -m
    authalic` to end after a SIGINT, with done.wait here; 25 runs of that test here did not repeat
    it)."""
    pending = None
    while not done.is_set():
        try:
            _time.sleep(0.05)
        except BaseException as e:  # noqa: B902 - re-raised by the caller once the map has stopped
            call.cancel.value = 1
            if pending is None:
                pending = e
    try:
        thread.join()  # it has nothing left to do but end
    except BaseException as e:  # noqa: B902
        if pending is None:
            pending = e
    return pending


def map_mesh(V, F, target, steps=None, tol=None, density=None, angles=0, refine_faces=False, progress=False,
             init_only=False, _report_extra=None, _stacklevel=2, **kwargs):
    """Map the mesh (V, F) onto target and return everything the library computed (a MapResult).

    target: "sphere", "disk", "annulus", "square" or "torus". The other arguments are those of
    sphere(), disk(), annulus(), square() and torus(), whose manuals say more; the target-specific
    keywords (restore_shapes, balance, refine_mesh, refine_budget, spherical_areas, start; boundary; inner_radius, outer_loop;
    corners; lattice) are accepted for their targets only. Use this rather than square() when the square may split edges (MapResult.F then
    has more faces than F, and MapResult.X the split midpoints).

    refine_mesh (sphere): True to split the map's long edges where a chord triangle cannot shrink to its
    share (long, thin limbs), with new vertices on the input's edges, and flow again, as the program's
    --refine-mesh: MapResult.X and F are then the refined mesh, P its map, parent and parent_t where
    each new vertex lies; the input's mesh stands (with a warning) when no refinement does better.
    refine_budget (with refine_mesh): at most this many times the input's faces, 1 < K <= 16 (None:
    2), or "auto": 2x, then 3x and 4x while the refined map's per-face mean |r - 1| is over 0.02 or
    its vertex error over 0.005, the first that meets both kept (a warning lists the budgets tried);
    long, thin limbs meet those at 2x (limbs4, coil) or 3x (limbs8, tpose), docs/sphere.md.
    """
    if target not in _lib.TARGETS:
        _bad("target %r: expected 'sphere', 'disk', 'annulus', 'square', 'torus' or 'circles'" % (target,))
    Va = _real_array(V, "V", (3,))
    Fa = _faces(F)
    o, dens = _options(target, Va.shape[0], Fa.shape[0], steps, tol, density, angles, refine_faces, init_only, kwargs)
    call = _Call(progress, target)
    o.cancel = _ct.pointer(call.cancel)
    if call.fn is not None:
        o.progress = call.fn
    tcode = _lib.TARGETS[target]
    pending = None
    try:
        if _threading.current_thread() is _threading.main_thread():
            done = _threading.Event()
            t = _threading.Thread(target=_run_map, args=(Va, Fa, tcode, o, call, target, _report_extra, dens, done),
                                  name="authalic-map")
            t.start()
            pending = _wait(t, done, call)
        else:
            _run_map(Va, Fa, tcode, o, call, target, _report_extra, dens)
    finally:
        if call.bar is not None:
            call.bar.close()
    if pending is not None:
        raise pending
    st, msg, out = call.outcome
    if call.exc is not None:
        raise call.exc
    if st < 0:
        _raise(st, msg)
    for w in out.warnings:
        _warnings.warn(w, AuthalicWarning, stacklevel=_stacklevel)
    return out


_COMMON_DOC = """
    V: vertex positions, shape (nv, 3), any real dtype and memory order (not modified).
    F: faces, shape (nf, 3), 0-based integer indices, counter-clockwise seen from outside.
    steps: the most advection steps, 1..512 (None: the target's default, 60).
    tol: stop when the vertex-level mean |ln(area ratio)| is at most tol, >= 0 (None: the target's
        default, 2e-3 on the sphere, 3e-3 on planar targets).
    density: None (equal area), or a prescribed density, positive and finite: nv values (per vertex;
        also when nv == nf, as the program reads --density) or nf values (per face). The domain area
        of a vertex's cell (a face) is proportional to density x its surface area.
    angles: 0..50 angle steps after the flow: steps towards the map of least Dirichlet energy with
        the vertex cells held at their areas (less angle distortion, vertex cells near 1e-4, the
        triangles' areas held near theirs). 0 (default): none.
    refine_faces: after the vertex cells meet tol, go on refining the triangles' areas as long as it
        helps at all (several times the time for about half the per-face error).
    progress: False (default) nothing; True a progress bar on stderr (tqdm if installed, else a
        plain line); or a callable f(step, max_steps, error) called once per step (error: the
        per-face mean |r - 1|); a true return value cancels the map (Error, status AU_E_CANCELLED),
        an exception it raises cancels the map and is re-raised. It runs with the GIL held while
        the map waits: keep it cheap.
    init_only: stop after the initial (conformal or harmonic) map (then steps, tol, density,
        angles, refine_faces and the flow's keywords must be left out)."""

_RETURNS_DOC = """
    info is the dict of the program's --report JSON (au_result_json): "tool", "version", "command",
    "input" and "output" (None), "V", "F", "steps", "converged", "folds", "time" (seconds per stage:
    validate, init, flow, metrics, total; the program adds read and write), "factorizations" (sparse
    factorizations the map made), "metrics" and
    "initial_metrics" (param-eval's keys: upsilon_*, lambda_*, r_mean_abs_dev = mean |r - 1|, r_cv,
    vertex_logr_mean_abs, angle_diff_mean_deg, folds, ...; see metrics()), "convergence" (per-step
    "err", "face_err", "frac", ...) and "warnings".
    Raises BadInputError (a mesh of the wrong topology, non-manifold, zero-area faces, bad density,
    bad arrays or options; str() names the problem, e.g. "edge (12, 40) is shared by 3 faces") or
    Error (a numerical failure, a map that would fold: AU_E_FOLD; cancelled: AU_E_CANCELLED).
    Ctrl-C cancels the map and raises KeyboardInterrupt. Warnings (tolerance not reached) are issued
    as AuthalicWarning. The GIL is released while the map runs."""


def sphere(V, F, steps=None, tol=None, density=None, angles=0, refine_faces=False, progress=False, *,
           restore_shapes=None, balance=True, spherical_areas=False, init_only=False, start=None):
    r = map_mesh(V, F, "sphere", steps, tol, density, angles, refine_faces, progress, init_only, _stacklevel=3,
                 restore_shapes=restore_shapes, balance=None if balance is True else balance,
                 spherical_areas=spherical_areas, start=start)
    return r.P, r.info


sphere.__doc__ = """Map a closed genus-0 triangle mesh onto the unit sphere with equal area.

    S, info = authalic.sphere(V, F)

    Every vertex cell gets its share of the sphere's area (Lie advection from a Moebius-balanced
    conformal start); no triangle is folded (a map that would fold raises Error AU_E_FOLD).
""" + _COMMON_DOC + """
    restore_shapes: while the spherical areas are driven, each step's shear aims this fraction
        (0..1) back at the surface's triangle shapes (None: 0.1; 0: off).
    balance: Moebius-balance the conformal start (default True).
    start: "conformal" (None, the default) or "multilevel": coarse-to-fine, the mesh simplified to a
        few hundred vertices, mapped, and its vertices brought back level by level, each inside its
        ring (docs/coarse-to-fine.md); where it cannot be made, the conformal start is used with a
        warning. info["start"] says which ran.
    spherical_areas: True to equalize the spherical triangles' areas only, with no chord polish: the
        map `authalic texture` and `sample` make for themselves (texels and grid cells lie on the
        sphere). info["metrics"]["sph_r_mean_abs_dev"] and ["sph_vertex_logr_mean_abs"] measure it;
        its chord figures (r_mean_abs_dev, vertex_logr_mean_abs) stay higher on long edges. On long,
        thin limbs the difference is large (data/tpose.obj: spherical 0.0118 / 0.0028, chord 0.53 /
        0.38; docs/sphere.md). False (default): the chord triangles' areas, param-eval's
        headline figures.

    Returns (S, info): S float64 (nv, 3), the map, unit vectors in the order of V (unreferenced
    vertices stay at (0, 0, 1)); with the program's OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1 (the
    package's defaults), S is bit for bit the map `authalic sphere` writes.""" + _RETURNS_DOC


def _planar(target, V, F, steps, tol, density, angles, refine_faces, progress, init_only, **kw):
    r = map_mesh(V, F, target, steps, tol, density, angles, refine_faces, progress, init_only, _stacklevel=4, **kw)
    return r.P[:, :2].copy(), r.info


def disk(V, F, steps=None, tol=None, density=None, angles=0, refine_faces=False, progress=False, *,
         boundary="slide", init_only=False):
    return _planar("disk", V, F, steps, tol, density, angles, refine_faces, progress, init_only,
                   boundary=None if boundary == "slide" else boundary)


def annulus(V, F, steps=None, tol=None, density=None, angles=0, refine_faces=False, progress=False, *,
            boundary="slide", inner_radius=None, outer_loop="longer", init_only=False):
    return _planar("annulus", V, F, steps, tol, density, angles, refine_faces, progress, init_only,
                   boundary=None if boundary == "slide" else boundary, inner_radius=inner_radius,
                   outer_loop=None if outer_loop == "longer" else outer_loop)


def square(V, F, steps=None, tol=None, density=None, angles=0, refine_faces=False, progress=False, *,
           boundary="slide", corners=None, aspect=None, init_only=False):
    return _planar("square", V, F, steps, tol, density, angles, refine_faces, progress, init_only,
                   boundary=None if boundary == "slide" else boundary, corners=corners, aspect=aspect)


def circles(V, F, steps=None, tol=None, density=None, angles=0, refine_faces=False, progress=False, *,
            boundary="slide", outer=None, init_only=False):
    return _planar("circles", V, F, steps, tol, density, angles, refine_faces, progress, init_only,
                   boundary=None if boundary == "slide" else boundary, outer=outer)


_BOUNDARY_DOC = """
    boundary: "slide" (default): boundary vertices slide along the domain's boundary during the flow;
        "fixed": the initial map's boundary is kept."""
_PLANAR_RETURNS = """
    Returns (UV, info): UV float64 (nv, 2), the map's positions (u, v) in the order of V
    (texture coordinates in [0,1]^2 are (UV + 1) / 2 for the disk and annulus, UV itself for the
    square; MapResult.uv from map_mesh has them as the program writes them).""" + _RETURNS_DOC

disk.__doc__ = """Map a triangle mesh with one boundary loop onto the unit disk with equal area.

    UV, info = authalic.disk(V, F)

    The boundary starts by arc length on the unit circle, the interior harmonic; the flow then
    gives every vertex cell its share of the disk's area.
""" + _COMMON_DOC + _BOUNDARY_DOC + "\n" + _PLANAR_RETURNS

annulus.__doc__ = """Map a triangle mesh with two boundary loops onto an annulus with equal area.

    UV, info = authalic.annulus(V, F)

    The annulus is centred at the origin with outer radius 1; both loops slide along their circles.
""" + _COMMON_DOC + _BOUNDARY_DOC + """
    inner_radius: the inner circle's radius, 0 < r < 1 (None: the conformal modulus's).
    outer_loop: the loop mapped to the unit circle: "longer" (default), "shorter", or the index of a
        vertex on it.
""" + _PLANAR_RETURNS

square.__doc__ = """Map a triangle mesh with one boundary loop onto the unit square [0,1]^2 with equal area.

    UV, info = authalic.square(V, F)

    Four boundary vertices go to the corners and stay there; the others slide along their sides.
    Triangles whose three corners would lie on one side are split first: then the result has more
    vertices than V (their midpoints come after V's), UV has a row for each, and the faces differ
    from F - use map_mesh(V, F, "square") to get them (MapResult.F, MapResult.X); a warning says so.
""" + _COMMON_DOC + _BOUNDARY_DOC + """
    corners: four boundary vertex indices for (0,0), (1,0), (1,1), (0,1) - the first at (0,0), the
        others in the order they follow it along the boundary (None: the most corner-like vertices
        near the arc-length quarters).
    aspect: the rectangle's width / height, or (W, H): the map onto [0, w] x [0, h] with the longer
        side 1 (the square's map stretched: a linear stretch scales every area alike). None: 1.
""" + _PLANAR_RETURNS

circles.__doc__ = """Map a genus-0 triangle mesh with k >= 1 boundary loops onto the unit disk with k - 1
    round holes (a circle domain) with equal area.

    UV, info = authalic.circles(V, F)

    Every boundary vertex slides along its circle, and each hole moves with the flow; a hole's area
    is that of the flat cap over its loop, scaled with the surface. One loop: the disk map.
    info["circles"] lists each loop's circle: {"vertex": a vertex on it, "center": [x, y],
    "radius": r, "outer": True for the unit circle}; map_mesh(V, F, "circles") also gives them as
    MapResult.circles (k, 3: centre x, centre y, radius) and MapResult.circle_vertex.
""" + _COMMON_DOC + _BOUNDARY_DOC + """
    outer: a vertex on the loop mapped to the unit circle (None: the longest loop).
""" + _PLANAR_RETURNS


def torus(V, F, steps=None, tol=None, density=None, angles=0, refine_faces=False, progress=False, *,
          lattice="conformal", init_only=False):
    r = map_mesh(V, F, "torus", steps, tol, density, angles, refine_faces, progress, init_only, _stacklevel=3,
                 lattice=None if lattice == "conformal" else lattice)
    return r.vt, r.Ft, r.info


torus.__doc__ = """Map a closed genus-1 triangle mesh onto a flat torus with equal area.

    VT, FT, info = authalic.torus(V, F)
    authalic.write_mesh("bob_torus.obj", V, F, vt=VT, Ft=FT)   # the surface, with seamless vt

    The flat torus is the plane modulo a lattice of area 1 (info["lattice"]: [[a1x, a1y], [a2x,
    a2y]]). The conformal start needs no cut (a tree-cotree homology basis, harmonic 1-forms, the
    period lattice); the flow keeps every face's corners at their lattice translations, so nothing
    drifts apart. A face across the fundamental domain's edge has its own corner copies: the two
    faces of any edge place its ends at positions that differ by one lattice vector (seamless).
""" + _COMMON_DOC + """
    lattice: "conformal" (default): the conformal modulus's lattice, scaled to determinant 1;
        "square": the unit square (the conformal map composed with a linear map onto it).

    Returns (VT, FT, info): VT float64 (nvt, 2) per-corner texture coordinates in the plane (nvt >=
    nv: row i < nv belongs to vertex i, the rows after it are copies shifted by lattice vectors),
    FT int32 (nf, 3) each corner's row of VT.""" + _RETURNS_DOC


def atlas(V, F, cones=None, quarter=False, max_cones=24):
    """A seamless atlas of a connected orientable triangle mesh of any genus, closed or open.

    VT, FT, info = authalic.atlas(V, F)
    authalic.write_mesh("fertility_atlas.obj", V, F, vt=VT, Ft=FT)

    Cones where the conformal factor is extreme (or the given ones), a flat cone metric by a convex
    conformal solve, a cut through the cones and a homology basis into charts laid out in that metric,
    then an equal-area flow that moves both sides of every seam together, charts split where they would
    overlap, packed into [0,1]^2 at one scale: both sides of every seam match by a rotation and a
    translation, no texel of a 1024 x 1024 raster is covered twice. info["equal_area"] is True when the
    flow brought the per-face mean |r - 1| to 0.02 or below (info["flow"]); where it stalls above that a
    warning says so (docs/atlas.md).

    cones: None (automatic), or a sequence of (vertex, angle in degrees) for interior vertices; on a
        closed surface the curvatures 360 - angle must sum to 360 x Euler characteristic.
    quarter: cone angles and every loop's holonomy in multiples of 90 degrees (every seam a quarter turn).
    max_cones: at most this many automatic cones (1..1000).

    Returns (VT, FT, info): VT float64 (nvt, 2) per-corner texture coordinates in [0,1]^2, FT int32
    (nf, 3) each corner's row of VT, info the report as a dict (cones, charts, seams and their
    rotations, coverage, folds, overlapping texels, times, warnings). Faces that disagreed with their
    neighbours are re-oriented (a warning); FT follows the re-oriented faces' corner order.
    Raises BadInputError (several components, non-manifold or non-orientable mesh, bad cones or
    options) or Error."""
    Va, Fa = _real_array(V, "V", (3,)), _faces(F)
    o = _L.au_atlas_options_default()
    o.max_cones = _int_opt("max_cones", max_cones, 1, 1000)
    o.quarter = _flag_opt("quarter", quarter)
    keep = []
    if cones is not None:
        c = _np.asarray(cones, dtype=_np.float64)
        if c.ndim != 2 or c.shape[1] != 2 or c.shape[0] == 0:
            _bad("cones: expected a sequence of (vertex, angle in degrees) pairs")
        if not _np.all(c[:, 0] == _np.floor(c[:, 0])) or c[:, 0].min() < 0 or c[:, 0].max() >= Va.shape[0]:
            _bad("cones: vertex indices must be whole numbers in 0..%d" % (Va.shape[0] - 1))
        cv = _np.ascontiguousarray(c[:, 0], dtype=_np.intc)
        ca = _np.ascontiguousarray(c[:, 1] * _np.pi / 180)
        keep = [cv, ca]
        o.ncones, o.cone_v, o.cone_angle = cv.shape[0], _pi(cv), _pd(ca)
    r = _ct.POINTER(_lib.AtlasResult)()
    msg = _lib.Msg()
    st = _L.au_atlas(_pd(Va), Va.shape[0], _pi(Fa), Fa.shape[0], _ct.byref(o), _ct.byref(r), _ct.byref(msg))
    del keep
    if st < 0:
        _raise(st, msg)
    try:
        rr = r.contents
        VT = _copy(rr.vt, (rr.nvt, 2), _np.float64)
        FT = _copy(rr.Ft, (rr.nf, 3), _np.int32)
        js = _ct.POINTER(_ct.c_char)()
        if _L.au_atlas_result_json(r, -1.0, -1.0, _ct.byref(js), _ct.byref(msg)) < 0:
            _raise(_lib.AU_E_ARG, msg)
        try:
            info = _json.loads(_ct.string_at(js).decode())
        finally:
            _L.au_free(js)
        for w in info["warnings"]:
            _warnings.warn(w, AuthalicWarning, stacklevel=2)
        return VT, FT, info
    finally:
        _L.au_atlas_result_free(_ct.byref(r))


from ._view import View, view  # noqa: E402,F401  (the page of a map: docs/view.md)
