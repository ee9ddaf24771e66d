"""python3 -m authalic - the `authalic` program's map commands, through the Python binding.

    python3 -m authalic sphere|disk|annulus|square|torus|circles IN OUT [options]
    python3 -m authalic COMMAND --help | --version

The same options, messages and exit statuses as the program (0 ok, also with warnings; 2 bad usage
or bad input, with one error line; 1 internal or numerical failure). OUT and the report are
written only when the whole run succeeded; an interrupted run (Ctrl-C) removes its temporary file
and dies by the signal, as the program does.
"""
import ctypes
import errno
import json
import math
import os
import signal
import stat
import sys
import time

import authalic
from authalic import _lib

EXIT_OK, EXIT_INTERNAL, EXIT_USAGE = 0, 1, 2
COMMANDS = ("sphere", "disk", "annulus", "square", "torus", "circles")

# name -> (metavar or None for a flag, commands, help); the program's option table, in its order.
OPTIONS = [
    ("report", "R.json", COMMANDS, "write a JSON report: metrics of the result and of the initial map, per-step "
                                   "errors, stage times, warnings"),
    ("steps", "K", COMMANDS, "most advection steps, 1..512 (default 60)"),
    ("tol", "T", COMMANDS, "stop when the vertex mean |log area ratio| is below T, T >= 0 (default: 0.002 on the "
                           "sphere, 0.003 on planar targets)"),
    ("density", "FILE", COMMANDS, "prescribed density: one positive number per vertex (or per face) of IN, in "
                                  "order: text (whitespace-separated), a FreeSurfer curv or a GIfTI "
                                  ".shape.gii/.func.gii file; domain area is proportional to density x surface area"),
    ("boundary", "MODE", ("disk", "annulus", "square", "circles"), "slide (default): boundary vertices slide along the domain's boundary "
                                       "(square: corners fixed); fixed: the initial map's boundary is kept"),
    ("inner-radius", "R", ("annulus",), "radius of the inner circle, 0 < R < 1 (default: the conformal modulus's)"),
    ("outer-loop", "WHICH", ("annulus",), "the loop mapped to the unit circle: longer (default), shorter, or the "
                                          "index of a vertex on it"),
    ("outer", "V", ("circles",), "a vertex on the loop mapped to the unit circle (default: a vertex of the longest "
                                 "loop)"),
    ("aspect", "W:H", ("square",), "map onto the rectangle of width to height W:H (the longer side 1; default 1:1): "
                                   "the square's equal-area map stretched, which keeps it equal area"),
    ("corners", "I,J,K,L", ("square",), "boundary vertices (0-based) for the corners: I goes to (0,0), the others "
                                        "to (1,0), (1,1), (0,1) in the order they follow I along the boundary"),
    ("restore-shapes", "F", ("sphere",), "while the spherical areas are driven, aim each step's shear a fraction F "
                                         "(0..1, default 0.1; 0: off) back at the surface's triangle shapes"),
    ("refine-faces", None, COMMANDS, "once the vertex cells meet the tolerance, go on refining the triangles' areas "
                                     "as long as it helps at all"),
    ("angles", "N", COMMANDS, "N steps (1..50) towards the map of least Dirichlet energy with the vertex cells held "
                              "at their areas"),
    ("refine-mesh", "SURF", ("sphere",), "split the map's long edges where a chord triangle cannot shrink to its "
                                         "share, with new vertices on the input's edges, and flow again (at most "
                                         "twice the faces, see --refine-budget); OUT gets the refined mesh's map, SURF "
                                         "its surface, SURF.parents.txt one line per new vertex: its number, its "
                                         "parents' numbers (0-based) and t, the vertex being (1 - t) parent1 + t "
                                         "parent2"),
    ("refine-budget", "K", ("sphere",), "with --refine-mesh: at most K times the input's faces instead of twice (K "
                                        "above 1, at most %d), or auto: 2x, then 3x and 4x while the refined "
                                        "map's per-face mean |r-1| is over 0.02 or its vertex error over 0.005 "
                                        "(the first that meets both is kept, else the lowest per-face)"
                                        % _lib.AU_REFINE_MAX_FACES),
    ("start", "S", ("sphere",), "conformal (default): the balanced conformal map, which squeezes protrusions "
                                "exponentially; multilevel: coarse-to-fine, the mesh simplified to a few hundred "
                                "vertices, mapped, and its vertices brought back level by level inside their rings "
                                "(docs/coarse-to-fine.md); the report's \"start\" says which ran"),
    ("no-balance", None, ("sphere",), "skip the Moebius balancing of the conformal start"),
    ("spherical-areas", None, ("sphere",), "equalize the spherical triangles' areas and skip the chord polish: the "
                                           "map `texture` and `sample` make for themselves (closer texture areas; "
                                           "param-eval's chord figures are higher)"),
    ("lattice", "SHAPE", ("torus",), "conformal (default): the conformal modulus's lattice, area 1; square: the unit "
                                     "square's"),
    ("init-only", None, COMMANDS, "stop after the initial (conformal or harmonic) map, for comparison"),
    ("format", "F", COMMANDS[:4], "write OUT as obj, off, ply, freesurfer (binary triangle surface, big-endian, float32) "
                              "or gifti (.gii; gzip-compressed for a .gii.gz name); default: by OUT's extension, and "
                              "an OUT with none (lh.sphere.authalic) gets the input's format"),
    ("radius", "R", ("sphere",), "write the sphere with radius R, 1e-30 <= R <= 1e30 (FreeSurfer and HCP spheres: 100); "
                                 "the metrics and the report are those of the unit sphere (default 1)"),
    ("distortion", "FILE", COMMANDS, "per-vertex areal distortion log2(map area share / surface area share) of the "
                                     "barycentric vertex cells (HCP's convention): a FreeSurfer curv file, or GIfTI "
                                     "when FILE ends in .gii (e.g. .shape.gii)"),
    ("quiet", None, COMMANDS, "no progress and no summary on stderr (errors and warnings remain)"),
    ("help", None, COMMANDS, "this text"),
]
# In the program's order of checking (cmd_map.c): the first one given is named.
FLOW_ONLY = ("steps", "tol", "density", "refine-faces", "refine-mesh", "restore-shapes", "angles", "spherical-areas",
             "boundary", "refine-budget")


class Usage(Exception):
    """A usage error: printed as one line with a pointer to --help; exit status 2."""


class BadFile(Exception):
    """A bad auxiliary input file (the density): printed as one line; exit status 2."""


def usage_text(cmd):
    lines = ["usage: python3 -m authalic %s IN OUT [options]" % cmd, "",
             ("Maps the closed genus-1 mesh IN onto a flat torus with equal area and writes it to OUT (.obj: the "
              "surface with seamless per-corner vt),") if cmd == "torus" else
             "Maps the triangle mesh IN onto the %s with equal area and writes the map to OUT (.obj .off .ply .gii,"
             " or FreeSurfer),"
             % {"sphere": "unit sphere", "disk": "unit disk", "annulus": "annulus of outer radius 1",
                "square": "unit square", "circles": "unit disk with a round hole for each boundary loop but one"}[cmd],
             "as `authalic %s` does (see help(authalic.%s) for the method)." % (cmd, cmd), "",
             "options of %s:" % cmd]
    for name, meta, cmds, text in OPTIONS:
        if cmd in cmds:
            head = "  --%s%s" % (name, " " + meta if meta else "")
            lines.append("%-22s%s" % (head, text) if len(head) < 22 else head + "\n" + " " * 22 + text)
    return "\n".join(lines) + "\n"


def parse(argv):
    """(command, IN, OUT, {option: value}) from argv (without the program name)."""
    if not argv:
        raise Usage("no command given")
    cmd = argv[0]
    if cmd not in COMMANDS:
        raise Usage(("unknown option '%s'" if cmd.startswith("-") else "unknown command '%s'") % cmd)
    known = {name: meta for name, meta, cmds, _ in OPTIONS if cmd in cmds}
    pos, vals, dashdash, i = [], {}, False, 1
    while i < len(argv):
        s = argv[i]
        i += 1
        if dashdash or not s.startswith("-") or s == "-":
            if len(pos) >= 2:
                raise Usage("unexpected extra argument '%s'" % s)
            pos.append(s)
            continue
        if s == "--":
            dashdash = True
            continue
        name = s[2:] if s.startswith("--") else ("help" if s == "-h" else None)
        if name not in known:
            raise Usage("unknown option '%s'" % s)
        if name == "help":
            sys.stdout.write(usage_text(cmd))
            raise SystemExit(EXIT_OK)
        v = ""
        if known[name] is not None:
            if i >= len(argv):
                raise Usage("option '%s' needs a value" % s)
            v = argv[i]
            i += 1
            if name in ("report", "density", "refine-mesh", "distortion") and not v:
                raise Usage("option '%s' needs a file name" % s)
        if name in vals:
            raise Usage("option '%s' given twice" % s)
        vals[name] = v
    if len(pos) < 2:
        raise Usage("missing input and output files" if not pos else "missing output file")
    if not pos[0] or not pos[1]:
        raise Usage("empty file name")
    given = [k for k in FLOW_ONLY if k in vals]
    if "init-only" in vals and given:
        raise Usage("--init-only runs no advection: --%s does not apply" % given[0])
    if "refine-budget" in vals and "refine-mesh" not in vals:
        raise Usage("--refine-budget applies to --refine-mesh, which is not given")
    if "refine-mesh" in vals and "density" in vals:
        raise Usage("--refine-mesh does not take --density (the new vertices and faces would have none)")
    if "refine-mesh" in vals and "spherical-areas" in vals:
        raise Usage("--refine-mesh does not take --spherical-areas (spherical triangles have no chord floor to refine)")
    return cmd, pos[0], pos[1], vals


# Numbers are read by the C library's strtol and strtod, as the program reads them (cli_parse_int,
# cli_parse_nonneg): Python's int and float take other spellings (1_5, non-ASCII digits) and refuse
# some of C's (leading blanks, 0x4), and the two programs must accept the same arguments.
_libc = ctypes.CDLL(None, use_errno=True)
_libc.strtol.restype, _libc.strtol.argtypes = ctypes.c_long, [ctypes.c_char_p, ctypes.POINTER(ctypes.c_char_p), ctypes.c_int]
_libc.strtod.restype, _libc.strtod.argtypes = ctypes.c_double, [ctypes.c_char_p, ctypes.POINTER(ctypes.c_char_p)]


def c_number(v, integer):
    """The whole string v read by strtol (base 10) or strtod, or None (empty, trailing text, out of
    range)."""
    b = os.fsencode(v)
    if not b or b"\0" in b:
        return None
    buf, end = ctypes.create_string_buffer(b), ctypes.c_char_p()
    ctypes.set_errno(0)
    x = _libc.strtol(buf, ctypes.byref(end), 10) if integer else _libc.strtod(buf, ctypes.byref(end))
    used = ctypes.cast(end, ctypes.c_void_p).value - ctypes.addressof(buf)
    return None if used != len(b) or ctypes.get_errno() == errno.ERANGE else x


def whole(name, v, lo, hi):
    x = c_number(v, True)
    if x is not None and lo <= x <= hi:
        return x
    raise Usage("--%s '%s': expected a whole number from %d to %d" % (name, v, lo, hi))


def nonneg(name, v, hi=None, what=None):
    x = c_number(v, False)
    if x is not None and math.isfinite(x) and x >= 0 and (hi is None or x <= hi):
        return x
    raise Usage("--%s '%s': %s" % (name, v, what or "expected a finite number >= 0"))


def map_kwargs(cmd, vals):
    """The keyword arguments of authalic.map_mesh from the parsed options."""
    kw = {}
    if "steps" in vals:
        kw["steps"] = whole("steps", vals["steps"], 1, _lib.AU_MAX_STEPS)
    if "tol" in vals:
        kw["tol"] = nonneg("tol", vals["tol"])
    if "angles" in vals:
        kw["angles"] = whole("angles", vals["angles"], 1, _lib.AU_MAX_ANGLE_STEPS)
    if "restore-shapes" in vals:
        kw["restore_shapes"] = nonneg("restore-shapes", vals["restore-shapes"], 1, "expected a number from 0 to 1")
    kw["refine_faces"] = "refine-faces" in vals
    if "refine-mesh" in vals:
        kw["refine_mesh"] = True
    if "refine-budget" in vals:
        v = vals["refine-budget"]
        k = "auto" if v == "auto" else c_number(v, False)
        if k is None or (k != "auto" and not (1 < k <= _lib.AU_REFINE_MAX_FACES)):
            raise Usage("--refine-budget '%s': expected auto or a number above 1 and at most %d"
                        % (v, _lib.AU_REFINE_MAX_FACES))
        kw["refine_budget"] = k
    kw["init_only"] = "init-only" in vals
    if "no-balance" in vals:
        kw["balance"] = False
    if "start" in vals:
        if vals["start"] not in ("conformal", "multilevel"):
            raise Usage("--start '%s': expected conformal or multilevel" % vals["start"])
        kw["start"] = vals["start"]
    if "spherical-areas" in vals:
        kw["spherical_areas"] = True
    if "boundary" in vals:
        if vals["boundary"] not in ("slide", "fixed"):
            raise Usage("--boundary '%s': expected slide or fixed" % vals["boundary"])
        kw["boundary"] = vals["boundary"]
    if "inner-radius" in vals:
        r = nonneg("inner-radius", vals["inner-radius"], 1, "expected a number between 0 and 1 (exclusive)")
        if not 0 < r < 1:
            raise Usage("--inner-radius '%s': expected a number between 0 and 1 (exclusive)" % vals["inner-radius"])
        kw["inner_radius"] = r
    if "outer-loop" in vals:
        v = vals["outer-loop"]
        if v in ("longer", "shorter"):
            kw["outer_loop"] = v
        else:
            try:
                kw["outer_loop"] = whole("outer-loop", v, 0, 2 ** 31 - 1)
            except Usage:
                raise Usage("--outer-loop '%s': expected longer, shorter or a vertex index" % v) from None
    if "lattice" in vals:
        if vals["lattice"] not in _lib.AU_LATTICES:
            raise Usage("--lattice '%s': expected conformal or square" % vals["lattice"])
        kw["lattice"] = vals["lattice"]
    if "outer" in vals:
        kw["outer"] = whole("outer", vals["outer"], 0, 2 ** 31 - 1)
    if "aspect" in vals:
        wh = [c_number(x, False) for x in vals["aspect"].split(":")]
        if len(wh) != 2 or not all(x is not None and x > 0 for x in wh) or not math.isfinite(wh[0] / wh[1]) \
                or not wh[0] / wh[1] > 0:
            raise Usage("--aspect '%s': expected W:H with two positive numbers" % vals["aspect"])
        kw["aspect"] = (wh[0], wh[1])
    if "corners" in vals:
        parts = vals["corners"].split(",")
        try:
            if len(parts) != 4:
                raise Usage("")
            kw["corners"] = [whole("corners", p, 0, 2 ** 31 - 1) for p in parts]
        except Usage:
            raise Usage("--corners '%s': expected four vertex indices I,J,K,L" % vals["corners"]) from None
    return kw


def same_file(a, b):
    """The same string, the same file when both exist, or else the same name in the same directory (a
    file not made yet: out.obj and ./out.obj); two links to one file not made yet are one too."""
    a, b = out_target(a), out_target(b)
    if a == b:
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:
        pass
    try:
        (da, na), (db, nb) = os.path.split(a), os.path.split(b)
        return bool(na) and na == nb and os.path.samefile(da or ".", db or ".")
    except OSError:
        return False


def parents_name(surf):
    return surf + ".parents.txt"


def out_target(path):
    """The file a write to path replaces: path, or the file a symbolic link names (the link stays), as
    the program and the library's writers do."""
    p = authalic._L.au_output_target(os.fsencode(path))
    if not p:
        raise MemoryError()
    try:
        return os.fsdecode(ctypes.string_at(p))
    finally:
        authalic._L.au_free(p)


def temp_name(path):
    """A temporary name beside path that keeps its extension, as the program's."""
    d, base = os.path.split(path)
    return os.path.join(d, ".authalic-%d-%s" % (os.getpid(), base))


def output_format(out, forced, in_format):
    """OUT's format as the program picks it (cli_output_format): --format, else OUT's extension, else
    the input's."""
    f = forced if forced != _lib.AU_IO_FORMAT_AUTO else authalic._L.au_io_format_of_name(os.fsencode(out))
    if f == _lib.AU_IO_FORMAT_AUTO:
        f = in_format
    if f in (_lib.AU_IO_FORMAT_AUTO, _lib.AU_IO_FORMAT_STL):
        raise Usage("output '%s' has no extension of a format that can be written and the input is %s "
                    "(use .obj, .off, .ply, .gii or --format)" % (out, authalic._L.au_io_format_name(f).decode()))
    return f


def check_outputs(src, out, report, surf=None, density=None, distortion=None):
    if same_file(src, out):
        raise Usage("output '%s' is the input file; refusing to overwrite it" % out)
    if report and same_file(report, src):
        raise Usage("report '%s' is the input file" % report)
    if report and same_file(report, out):
        raise Usage("report '%s' is the output file" % report)
    if density and (same_file(density, out) or (report and same_file(density, report))):
        raise Usage("--density '%s' is also an output file; refusing to overwrite it" % density)
    if authalic._L.au_io_format_of_name(os.fsencode(out)) == _lib.AU_IO_FORMAT_STL:
        raise Usage("cannot write '%s' files (output '%s'; use .obj, .off, .ply, .gii or --format)" %
                    (out[out.rindex("."):], out))
    if distortion and any(o and same_file(distortion, o) for o in (src, out, report, density)):
        raise Usage("--distortion '%s' is also another input or output file" % distortion)
    if surf:
        for f in (surf, parents_name(surf)):
            if any(o and same_file(f, o) for o in (src, out, report, density)):
                raise Usage("--refine-mesh '%s': %s is also another input or output file" %
                            (surf, "it" if f == surf else f))
        if authalic._L.au_io_format_of_name(os.fsencode(surf)) == _lib.AU_IO_FORMAT_STL:
            raise Usage("--refine-mesh '%s': cannot write that extension (use .obj, .off, .ply or .gii)" % surf)
    for path, what in ((out, "output"), (report, "report"), (distortion, "--distortion"), (surf, "--refine-mesh"),
                       (surf and parents_name(surf), "--refine-mesh's parents file")):
        if not path:
            continue
        if os.path.isdir(path):
            raise Usage("%s '%s' is a directory" % (what, path))
        if os.path.exists(path) and not os.path.isfile(path):
            raise Usage("%s '%s' is not a regular file (a device, FIFO or socket); give a file name" % (what, path))
        try:
            os.stat(path)
        except OSError as e:
            if e.errno == errno.ELOOP:
                raise Usage("%s '%s': too many levels of symbolic links" % (what, path)) from None
        d = os.path.dirname(path)
        if d and not os.path.isdir(d):
            raise Usage("%s '%s': directory '%s' does not exist" % (what, path, d))


def fail(path, text, bad):
    """The one error line; returns the exit status."""
    if text.startswith(path + ":"):
        sys.stderr.write("authalic: error: %s\n" % text)
    else:
        sys.stderr.write("authalic: error: %s: %s\n" % (path, text))
    return EXIT_USAGE if bad else EXIT_INTERNAL


def read_density(path, nv, nf):
    """The program's --density: text, FreeSurfer curv or GIfTI values (authalic.read_values), nv or nf
    of them, each positive; its messages."""
    try:
        with open(path, "rb"):
            pass
    except OSError as e:
        raise BadFile("%s: cannot open the density file: %s" % (path, e.strerror)) from None
    try:
        vals = authalic.read_values(path)
    except authalic.Error as e:
        raise BadFile(str(e) if str(e).startswith(path + ":") else "%s: %s" % (path, e)) from None
    for k, x in enumerate(vals):
        if not x > 0:
            raise BadFile("%s: value %d ('%g') is not a positive finite number" % (path, k + 1, x))
    if len(vals) not in (nv, nf):
        raise BadFile("%s: %d values; the mesh has %d vertices and %d faces" % (path, len(vals), nv, nf))
    return vals


class Progress:
    """The program's progress display: one line redrawn on a terminal, else a line a second after
    the first second."""

    def __init__(self):
        self.t0 = self.t_last = time.monotonic()
        self.tty = sys.stderr.isatty()
        self.drawn = False

    def __call__(self, step, max_steps, err):
        t = time.monotonic()
        if t - self.t0 <= 1.0 and not self.tty:
            return
        if self.tty:
            sys.stderr.write("\rauthalic: step %d/%d  err %.3e " % (step, max_steps, err))
            self.drawn = True
        elif t - self.t_last >= 1.0:
            sys.stderr.write("authalic: step %d/%d  err %.3e\n" % (step, max_steps, err))
            self.t_last = t
        sys.stderr.flush()

    def end(self):
        if self.drawn:
            sys.stderr.write("\n")
        self.drawn = False


def summary(cmd, r, seconds, spherical=False):
    m = r.info["metrics"]
    head = "authalic: %s: V=%d F=%d steps=%d folds=%d mean|r-1|=%.3g vertex|log r|=%.3g" % (
        cmd, r.P.shape[0], r.F.shape[0], r.info["steps"], m["folds"], m["r_mean_abs_dev"] or math.nan,
        m["vertex_logr_mean_abs"] or math.nan)
    if cmd == "torus":
        (a, b), (c, d) = r.lattice
        sys.stderr.write("%s lattice=(%.6g,%.6g),(%.6g,%.6g) vt=%d start=%s time=%.2fs\n" % (
            head, a, b, c, d, r.vt.shape[0], r.init_method or "?", seconds))
        return
    if cmd == "sphere":
        conv = r.info["convergence"]
        lr, tw, vp = conv.get("lantern_retry"), conv.get("twisted_start"), conv.get("vertex_polish")
        sr, gp = conv.get("staged_retry"), conv.get("global_polish")
        parts = ([("lantern retry skipped: it would repeat the first flow" if lr.get("skipped")
               else "lantern retry kept" if lr["kept"] else "lantern retry discarded")] if lr else []) + \
            ([("twisted start: the conformal one folded" if tw.get("conformal_start_folded")
               else "twisted start kept" if tw["kept"] else "twisted start discarded")] if tw else []) + \
            ([("staged retry kept" if sr["kept"] else "staged retry discarded")] if sr else []) + \
            ([("vertex polish kept" if vp["kept"] else "vertex polish discarded")] if vp else []) + \
            ([("global polish kept" if gp["kept"] else "global polish discarded")] if gp else [])
        tail = " (%s)" % "; ".join(parts) if parts else ""
        if spherical:
            head += " sph|r-1|=%.3g sph vertex|log r|=%.3g" % (m["sph_r_mean_abs_dev"] or math.nan,
                                                               m["sph_vertex_logr_mean_abs"] or math.nan)
        sys.stderr.write("%s time=%.2fs%s\n" % (head, seconds, tail))
        return
    extra = ""
    if cmd == "annulus":
        extra = " inner_radius=%.6g modulus_radius=%.6g" % (r.inner_radius, r.modulus_radius)
    elif cmd == "square":
        extra = " corners=%d,%d,%d,%d split=%d" % (tuple(r.corners) + (r.nsplit,))
    elif cmd == "circles":
        extra = " circles=%d" % len(r.circles)
    sys.stderr.write("%s boundary_dev=%.2g%s start=%s time=%.2fs\n" % (head, r.boundary_dev, extra,
                                                                        r.init_method or "?", seconds))


def read_input(path):
    """(V, F, meta): the mesh and what its file carries besides (au_io_read_meta; the caller frees meta
    with au_io_meta_free)."""
    m, meta, msg = ctypes.POINTER(_lib.Mesh)(), ctypes.c_void_p(), _lib.Msg()
    st = authalic._L.au_io_read_meta(os.fsencode(path), ctypes.byref(m), ctypes.byref(meta), ctypes.byref(msg))
    try:
        if st < 0:
            authalic._raise(st, msg)
        mm = m.contents
        V = authalic._copy(mm.X, (mm.nv, 3), authalic._np.float64)
        F = authalic._copy(mm.F, (mm.nf, 3), authalic._np.int32)
        return V, F, meta
    finally:
        authalic._L.au_mesh_free(ctypes.byref(m))


def write_map(path, V, F, fmt, meta, geometric_type, radius, uv=None, vt=None, Ft=None):
    """au_mesh_write with the program's write options: the format, the input's metadata, the GIfTI
    GeometricType, the radius."""
    np = authalic._np
    w = authalic._L.au_write_opts_default()
    Va, Fa = np.ascontiguousarray(V, np.float64), np.ascontiguousarray(F, np.int32)
    keep = [Va, Fa]
    if uv is not None:
        keep.append(np.ascontiguousarray(uv, np.float64))
        w.uv = authalic._pd(keep[-1])
    if vt is not None:
        keep += [np.ascontiguousarray(vt, np.float64), np.ascontiguousarray(Ft, np.int32)]
        w.nvt, w.vt, w.Ft = keep[-2].shape[0], authalic._pd(keep[-2]), authalic._pi(keep[-1])
    w.format, w.meta, w.radius = fmt, meta, radius
    w.geometric_type = geometric_type.encode() if geometric_type else None
    msg = _lib.Msg()
    st = authalic._L.au_mesh_write(os.fsencode(path), Va.shape[0], authalic._pd(Va), Fa.shape[0], authalic._pi(Fa),
                                   ctypes.byref(w), ctypes.byref(msg))
    if st < 0:
        authalic._raise(st, msg)


def write_distortion(path, r, cmd, meta):
    """The program's --distortion file (cli_write_distortion): log2 of each vertex cell's share of the
    domain over its share of the surface, as curv or GIfTI."""
    np = authalic._np
    X, F = np.ascontiguousarray(r.X, np.float64), np.ascontiguousarray(r.F, np.int32)
    d = np.zeros(X.shape[0])
    if cmd == "torus":
        vt, Ft = np.ascontiguousarray(r.vt, np.float64), np.ascontiguousarray(r.Ft, np.int32)
        st = authalic._L.au_metrics_vertex_distortion_vt(X.shape[0], F.shape[0], authalic._pd(X), authalic._pi(F),
                                                         vt.shape[0], authalic._pd(vt), authalic._pi(Ft),
                                                         authalic._pd(d), None)
    else:
        P = np.ascontiguousarray(r.P, np.float64)
        if P.shape[1] == 2:
            P = np.ascontiguousarray(np.column_stack([P, np.zeros(P.shape[0])]))
        st = authalic._L.au_metrics_vertex_distortion(X.shape[0], F.shape[0], authalic._pd(X), authalic._pd(P),
                                                      authalic._pi(F), _lib.DOMAINS["sphere" if cmd == "sphere" else "plane"],
                                                      authalic._pd(d), None)
    msg = _lib.Msg()
    if st >= 0:
        st = authalic._L.au_io_write_scalars(os.fsencode(path), X.shape[0], authalic._pd(d), F.shape[0], meta,
                                             ctypes.byref(msg))
    if st < 0:
        authalic._raise(st, msg)


def run(cmd, src, out, vals):
    t_start = time.monotonic()
    quiet = "quiet" in vals
    report = vals.get("report")
    kw = map_kwargs(cmd, vals)
    surf, distortion = vals.get("refine-mesh"), vals.get("distortion")
    forced = _lib.AU_IO_FORMAT_AUTO
    if "format" in vals:
        forced = authalic._L.au_io_format_parse(os.fsencode(vals["format"]))
        if forced == _lib.AU_IO_FORMAT_AUTO:
            raise Usage("--format '%s': expected obj, off, ply, freesurfer or gifti" % vals["format"])
    radius = 0.0
    if "radius" in vals:
        radius = nonneg("radius", vals["radius"], 1e30, "expected a number from 1e-30 to 1e30")
        if not radius >= 1e-30:
            raise Usage("--radius '%s': expected a number from 1e-30 to 1e30" % vals["radius"])
    check_outputs(src, out, report, surf, vals.get("density"), distortion)
    if cmd == "torus" and not out.lower().endswith(".obj"):
        raise Usage("%s: the torus map is written as .obj (its seamless `vt` need OBJ)" % out)
    t0 = time.monotonic()
    try:
        V, F, meta = read_input(src)
    except authalic.Error as e:
        return fail(src, str(e), isinstance(e, authalic.BadInputError))
    try:
        return run_with(cmd, src, out, vals, kw, V, F, meta, forced, radius, t0, t_start)
    finally:
        authalic._L.au_io_meta_free(ctypes.byref(meta))


def run_with(cmd, src, out, vals, kw, V, F, meta, forced, radius, t0, t_start):
    quiet = "quiet" in vals
    report = vals.get("report")
    surf, distortion = vals.get("refine-mesh"), vals.get("distortion")
    t_read = time.monotonic() - t0
    in_fmt = authalic._L.au_io_meta_format(meta)
    fmt = _lib.AU_IO_FORMAT_OBJ if cmd == "torus" else output_format(out, forced, in_fmt)
    # SURF as OUT: by its extension, else the input's format (a FreeSurfer lh.white gives one).
    sfmt = None
    if surf:
        sfmt = authalic._L.au_io_format_of_name(os.fsencode(surf))
        if sfmt == _lib.AU_IO_FORMAT_AUTO:
            sfmt = in_fmt
        if sfmt in (_lib.AU_IO_FORMAT_AUTO, _lib.AU_IO_FORMAT_STL):
            raise Usage("--refine-mesh '%s': no extension of a format that can be written and the input is %s "
                        "(use .obj, .off, .ply or .gii)" % (surf, authalic._L.au_io_format_name(sfmt).decode()))
    if "density" in vals:
        try:
            kw["density"] = read_density(vals["density"], V.shape[0], F.shape[0])
        except BadFile as e:
            sys.stderr.write("authalic: error: %s\n" % e)
            return EXIT_USAGE
    extra = _lib.ReportExtra(os.fsencode(src), os.fsencode(out), ("authalic " + authalic.__version__).encode(),
                             t_read, -1.0, -1.0, None, 0)
    prog = None if quiet else Progress()
    import warnings
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", authalic.AuthalicWarning)
            r = authalic.map_mesh(V, F, cmd, progress=prog or False, _report_extra=extra, **kw)
    except authalic.Error as e:
        if prog:
            prog.end()
        if e.status == _lib.AU_E_ARG:  # a bad corner or outer-loop vertex: name the option as a flag
            text = str(e)
            head, sep, rest = text.partition(":")
            return fail(src, "--" + head.replace("_", "-") + sep + rest if sep else text, True)
        return fail(src, str(e), isinstance(e, authalic.BadInputError))
    finally:
        if prog:
            prog.end()
    for w in r.warnings:
        sys.stderr.write("authalic: warning: %s: %s\n" % (src, w))
    # The refined surface and its parents under temporary names (each an atomic write), renamed into
    # place once OUT is: a run that fails later leaves a user's earlier SURF as it was. OUT likewise,
    # renamed into place only when the report is written too.
    # SURF, its parents and the distortion wait under temporary names beside the files they replace
    # until OUT is published, as the program's (cmd_map.c).
    dests = [out_target(surf), out_target(parents_name(surf))] if surf else []
    if distortion:
        dests.append(out_target(distortion))
    temps = [temp_name(d) for d in dests]
    if surf:
        try:
            write_map(temps[0], r.X, r.F, sfmt, meta, None, 0.0)
        except authalic.Error as e:
            return fail(surf, str(e), isinstance(e, authalic.BadInputError))
        nv_in = r.X.shape[0] - (0 if r.parent is None else r.parent.shape[0])
        lines = "".join("%d %d %d %.17g\n" % (nv_in + k, a, b, t) for k, ((a, b), t) in
                        enumerate(zip(r.parent.tolist(), r.parent_t.tolist()))) if r.parent is not None else ""
        msg, data = _lib.Msg(), lines.encode()
        st = authalic._L.au_write_text(os.fsencode(temps[1]), data, len(data), msg)
        if st < 0:
            os.unlink(temps[0])
            return fail(parents_name(surf), msg.text.decode() or "cannot write", authalic._L.au_status_is_input_error(st))
    if distortion:
        try:
            write_distortion(temps[-1], r, cmd, meta)
        except authalic.Error as e:
            for f in temps:
                if os.path.exists(f):
                    os.unlink(f)
            return fail(distortion, str(e), isinstance(e, authalic.BadInputError))
    dest = out_target(out)
    tmp = temp_name(dest)
    try:
        t0 = time.monotonic()
        try:
            if cmd == "torus":  # the surface in `v`, the map in the per-corner `vt`
                write_map(tmp, r.X, r.F, fmt, meta, "Flat", 0.0, vt=r.vt, Ft=r.Ft)
            else:
                write_map(tmp, r.P, r.F, fmt, meta, "Spherical" if cmd == "sphere" else "Flat", radius, uv=r.uv)
        except authalic.Error as e:
            return fail(out, str(e), isinstance(e, authalic.BadInputError))
        try:
            old = os.stat(dest)
            if stat.S_ISREG(old.st_mode):
                os.chmod(tmp, stat.S_IMODE(old.st_mode))
        except OSError:
            pass
        t_write = time.monotonic() - t0
        if report:
            info = r.info
            times = info["time"]
            total = times.pop("total") + t_write
            times["write"], times["total"] = t_write, total
            text = json.dumps(info, indent="\t", allow_nan=False) + "\n"
            msg = _lib.Msg()
            data = text.encode()
            st = authalic._L.au_write_text(os.fsencode(report), data, len(data), msg)
            if st < 0:
                return fail(report, msg.text.decode() or "cannot write the report", authalic._L.au_status_is_input_error(st))
        os.replace(tmp, dest)
        tmp = None
        for t, d in zip(temps, dests):
            os.replace(t, d)
    finally:
        for f in [tmp] + temps:
            if f and os.path.exists(f):
                os.unlink(f)
    if not quiet:
        summary(cmd, r, time.monotonic() - t_start, "spherical-areas" in vals)
    return EXIT_OK


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    cmd = argv[0] if argv and argv[0] in COMMANDS else None
    help_ref = "python3 -m authalic %s--help" % (cmd + " " if cmd else "")
    if argv and argv[0] in ("--help", "-h", "--version"):
        if len(argv) > 1:
            sys.stderr.write("authalic: error: unexpected argument '%s' after '%s' (see `%s`)\n" % (argv[1], argv[0],
                                                                                                  help_ref))
            return EXIT_USAGE
        if argv[0] == "--version":
            print("authalic %s (python %s)" % (authalic.__version__, ".".join(map(str, sys.version_info[:3]))))
        else:
            print(__doc__.strip())
        return EXIT_OK
    try:
        cmd, src, out, vals = parse(argv)
        return run(cmd, src, out, vals)
    except Usage as e:
        sys.stderr.write("authalic: error: %s (see `%s`)\n" % (e, help_ref))
        return EXIT_USAGE
    except KeyboardInterrupt:
        # Die by the signal, as the program does (the temporary was removed on the way out).
        sys.stderr.flush()
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        os.kill(os.getpid(), signal.SIGINT)
        return 130


if __name__ == "__main__":
    sys.exit(main())
