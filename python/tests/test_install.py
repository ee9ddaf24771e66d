"""test_install.py - the package as `make python` installs it (python/install.sh into a temporary
directory here): importable from any directory with no environment variable, loading its own copy
of the library; and the import-time check of the struct layouts against the library."""
import ctypes
import os
import subprocess
import sys

import pytest

import authalic
from authalic import _lib
from conftest import ROOT


def test_installed_package_imports_from_anywhere(tmp_path):
    name = authalic._L._name  # the build's library this suite loaded; the install copies it
    build = os.path.dirname(os.path.abspath(name)) if os.sep in name else os.path.join(ROOT, "build")
    if not os.path.exists(os.path.join(build, "libauthalic.so.1")):
        pytest.skip("no libauthalic.so.1 beside the loaded library")
    dest = tmp_path / "site"
    r = subprocess.run(["sh", os.path.join(ROOT, "python", "install.sh"), sys.executable, build, str(dest)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert sorted(os.listdir(dest)) == ["authalic"]
    env = {k: v for k, v in os.environ.items() if k not in ("AUTHALIC_LIBRARY", "PYTHONPATH")}
    env["PYTHONPATH"] = str(dest)
    code = ("import authalic, sys; V, F = authalic.read_mesh(sys.argv[1]); S, info = authalic.sphere(V, F, steps=2);"
            "print(authalic.__file__); print(authalic._L._name); print(info['V'])")
    r = subprocess.run([sys.executable, "-c", code, os.path.join(ROOT, "data", "bumpy_star.obj")], cwd="/",
                       capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    f, lib, nv = r.stdout.split()
    assert f.startswith(str(dest)) and lib == str(dest / "authalic" / "libauthalic.so.1") and nv == "2562"


def test_struct_layout_mismatch_fails_the_import(monkeypatch):
    class Short(ctypes.Structure):
        _fields_ = [("max_steps", ctypes.c_int)]
    monkeypatch.setitem(_lib.STRUCTS, "au_options", Short)
    with pytest.raises(ImportError, match="au_options is .* bytes"):
        _lib.load()


def test_missing_library_is_named(monkeypatch, tmp_path):
    monkeypatch.setenv("AUTHALIC_LIBRARY", str(tmp_path / "nowhere.so"))
    with pytest.raises(ImportError, match="AUTHALIC_LIBRARY"):
        _lib.load()
