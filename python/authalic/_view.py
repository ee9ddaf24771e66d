"""_view.py - authalic.view: the `authalic view` page of a surface and its map (au_view_html).

The page is one self-contained HTML file (three.js inlined, nothing fetched when it opens); in a
notebook the returned View shows itself in an isolated frame (_repr_html_).
"""
import ctypes as _ct
import html as _html

import numpy as _np

from . import _L, _bad, _faces, _raise, _real_array, _lib

P_double, P_int, c_int, c_double, c_char_p = _lib.P_double, _lib.P_int, _ct.c_int, _ct.c_double, _ct.c_char_p


class _ViewInput(_ct.Structure):
    _fields_ = [("nv", c_int), ("nf", c_int), ("X", P_double), ("F", P_int), ("P", P_double), ("nvt", c_int),
                ("vt", P_double), ("Ft", P_int), ("attr", P_double), ("attr_name", c_char_p), ("title", c_char_p),
                ("steps", c_int), ("seconds", c_double)]


if _L.au_struct_size(b"au_view_input") != _ct.sizeof(_ViewInput):
    raise ImportError("authalic: au_view_input is %d bytes in the library but %d in this package: the library and "
                      "the package are from different versions" % (_L.au_struct_size(b"au_view_input"),
                                                                   _ct.sizeof(_ViewInput)))
_L.au_view_html.restype = c_int
_L.au_view_html.argtypes = [_ct.POINTER(_ViewInput), _ct.POINTER(_ct.c_void_p), _ct.POINTER(_ct.c_size_t),
                            _ct.POINTER(_lib.Msg)]


class View:
    """The page of authalic.view: .html (str); .save(path) writes it; a notebook shows it."""

    __slots__ = ("html",)

    def __init__(self, html):
        self.html = html

    def save(self, path):
        """Write the page to path (UTF-8)."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.html)

    def _repr_html_(self):
        # In its own frame: the page's full-window layout and its key bindings stay off the notebook.
        return ('<iframe srcdoc="%s" style="width:100%%;height:600px;border:0" '
                'sandbox="allow-scripts allow-downloads"></iframe>' % _html.escape(self.html, quote=True))

    def __repr__(self):
        return "<authalic.View %d bytes>" % len(self.html)


def _ptr(a, t):
    return a.ctypes.data_as(_ct.POINTER(t)) if a is not None else None


def view(V=None, F=None, P=None, vt=None, Ft=None, attr=None, attr_name=None, title=None, info=None, result=None):
    """The interactive page of the surface (V, F) and its map, as a View (.html, .save(path)).

    The map: P (nv, 3) at the vertices, on a sphere about the origin (a globe) or with z = 0 (flat;
    (nv, 2) is taken as z = 0), or vt (nvt, 2) with Ft (nf, 3), per-corner plane coordinates (flat;
    tiled 3 x 3 when they tile the plane, as a torus map's do). result: a MapResult instead of V, F,
    P / vt, Ft, info (V and F may then be None). attr: one value per vertex to colour by (attr_name
    names it). info: a map's report (dict) whose steps and time are shown with the figures. The page
    shows the per-face log r and Lambda of metrics(), the figures of the report.
    Raises BadInputError (bad arrays, both or neither of P and vt) or Error.
    """
    if result is not None:
        V, F, info = result.X, result.F, result.info
        if result.vt is not None:
            vt, Ft = result.vt, result.Ft
        else:
            P = result.P
    Va, Fa = _real_array(V, "V", (3,)), _faces(F)
    nv, nf = Va.shape[0], Fa.shape[0]
    if (P is None) == (vt is None):
        _bad("view: give the map as P, or as vt with Ft (exactly one of them)")
    Pa = vta = Fta = None
    if P is not None:
        Pa = _real_array(P, "P", (2, 3), nv)  # two columns come back with z = 0
    else:
        if Ft is None:
            _bad("view: vt needs Ft")
        vta, Fta = _real_array(vt, "vt", (2,)), _faces(Ft, "Ft")
        if Fta.shape != Fa.shape:
            _bad("view: Ft has %d rows, F %d" % (Fta.shape[0], nf))
    aa = None
    if attr is not None:
        aa = _np.ascontiguousarray(_np.asarray(attr, dtype=_np.float64).reshape(-1))
        if aa.shape[0] != nv:
            _bad("view: attr has %d values for %d vertices" % (aa.shape[0], nv))
    vin = _ViewInput()
    vin.nv, vin.nf, vin.X, vin.F = nv, nf, _ptr(Va, c_double), _ptr(Fa, c_int)
    vin.P = _ptr(Pa, c_double)
    if vta is not None:
        vin.nvt, vin.vt, vin.Ft = vta.shape[0], _ptr(vta, c_double), _ptr(Fta, c_int)
    vin.attr = _ptr(aa, c_double)
    vin.attr_name = (attr_name or "attribute").encode() if aa is not None else None
    vin.title = title.encode() if title else None
    info = info or {}
    vin.steps = int(info.get("steps", -1)) if isinstance(info.get("steps"), int) else -1
    total = (info.get("time") or {}).get("total") if isinstance(info.get("time"), dict) else None
    vin.seconds = float(total) if isinstance(total, (int, float)) else -1.0
    out, n, msg = _ct.c_void_p(), _ct.c_size_t(), _lib.Msg()
    st = _L.au_view_html(_ct.byref(vin), _ct.byref(out), _ct.byref(n), _ct.byref(msg))
    if st < 0:
        _raise(st, msg)
    try:
        text = _ct.string_at(out, n.value).decode("utf-8")
    finally:
        _L.au_free(out)
    return View(text)
