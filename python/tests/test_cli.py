"""test_cli.py - `python -m authalic`: the program's map commands through the binding: the same OUT
byte for byte and the same report keys and metrics as the program, exit statuses 0/1/2 with one
error line, nothing written on failure."""
import json
import os
import stat
import subprocess
import sys

import pytest

import authalic
import authalic.__main__ as cli_main
from conftest import DATA, ROOT, cli

PY = sys.executable
STAR = os.path.join(DATA, "bumpy_star.obj")
DISK = os.path.join(DATA, "disk_bump.obj")


def run_py(*args):
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "python"))
    return subprocess.run([PY, "-m", "authalic"] + [str(a) for a in args], capture_output=True, text=True, env=env)


def keys(d, prefix=""):
    out = set()
    for k, v in d.items():
        out.add(prefix + k)
        if isinstance(v, dict):
            out |= keys(v, prefix + k + ".")
    return out


@pytest.mark.parametrize("cmd, src, opts", [("sphere", STAR, []), ("disk", DISK, ["--steps", "6"]),
                                            ("square", DISK, ["--boundary", "fixed"]),
                                            ("sphere", STAR, ["--spherical-areas"])])
def test_same_output_and_report_as_the_program(tmp_path, cmd, src, opts):
    prog = cli()
    a = subprocess.run([prog, cmd, src, tmp_path / "c.obj", "--report", tmp_path / "c.json"] + opts,
                       capture_output=True, text=True)
    b = run_py(cmd, src, tmp_path / "p.obj", "--report", tmp_path / "p.json", *opts)
    assert a.returncode == 0 and b.returncode == 0, (a.stderr, b.stderr)
    assert (tmp_path / "c.obj").read_bytes() == (tmp_path / "p.obj").read_bytes()
    ra, rb = json.loads((tmp_path / "c.json").read_text()), json.loads((tmp_path / "p.json").read_text())
    assert keys(ra) == keys(rb)
    for k in ("metrics", "initial_metrics", "convergence", "steps", "V", "F", "folds", "warnings", "command"):
        assert ra.get(k) == rb.get(k), k
    assert rb["input"] == src and rb["output"] == str(tmp_path / "p.obj")
    # The summary lines agree but for the time.
    cut = lambda s: s.strip().splitlines()[-1].rsplit(" time=", 1)[0]  # noqa: E731
    assert cut(a.stderr) == cut(b.stderr)


@pytest.mark.parametrize("args, words", [
    ([], "no command"),
    (["cube", STAR, "o.obj"], "unknown command"),
    (["sphere"], "missing input"),
    (["sphere", STAR], "missing output"),
    (["sphere", STAR, "o.obj", "--steps", "0"], "--steps"),
    (["sphere", STAR, "o.obj", "--tol", "x"], "--tol"),
    (["sphere", STAR, "o.obj", "--corners", "1,2,3,4"], "unknown option"),
    (["sphere", STAR, "o.obj", "--steps", "3", "--steps", "4"], "twice"),
    (["sphere", STAR, "o.obj", "--init-only", "--steps", "3"], "--init-only"),
    (["sphere", STAR, "o.obj", "--init-only", "--spherical-areas"], "--spherical-areas does not apply"),
    (["sphere", STAR, "o.obj", "--spherical-areas", "--refine-mesh", "s.obj"], "--refine-mesh does not take --spherical-areas"),
    (["sphere", STAR, "o.stl"], "cannot write"),
    (["sphere", STAR, "o.obj", "--radius", "1e39"], "from 1e-30 to 1e30"),
    (["sphere", STAR, "o.obj", "--radius", "1e-50"], "from 1e-30 to 1e30"),
    (["sphere", STAR, "o.obj", "--format", "stl"], "--format 'stl'"),
    (["sphere", STAR, "o.obj", "--distortion", STAR], "--distortion"),
    (["sphere", STAR, "o.obj", "--report", "/dev/null"], "not a regular file"),
    (["sphere", STAR, STAR], "input file"),
    (["sphere", "missing.obj", "o.obj"], "missing.obj"),
    (["sphere", DISK, "o.obj"], "boundary"),
    (["disk", STAR, "o.obj"], "closed mesh"),
    (["square", DISK, "o.obj", "--corners", "0,1,2,3"], "--corners"),
    (["annulus", DISK, "o.obj", "--inner-radius", "1"], "--inner-radius"),
    (["sphere", STAR, "o.obj", "--density", "missing.txt"], "density"),
    (["sphere", STAR, "o.obj", "--refine-budget", "3"], "--refine-budget applies to --refine-mesh"),
    (["sphere", STAR, "o.obj", "--refine-mesh", "s.obj", "--refine-budget", "1"], "--refine-budget '1'"),
    (["sphere", STAR, "o.obj", "--refine-mesh", STAR], "also another input or output file"),
    (["sphere", STAR, "o.obj", "--refine-mesh", "o.obj"], "also another input or output file"),
    (["sphere", STAR, "o.obj", "--refine-mesh", "s.stl"], "cannot write that extension"),
    (["disk", DISK, "o.obj", "--refine-mesh", "s.obj"], "unknown option"),
])
def test_bad_usage_and_input_exit_2_with_one_line(tmp_path, args, words):
    args = [str(tmp_path / a) if a in ("o.obj", "o.xyz", "s.obj", "s.xyz", "missing.obj", "missing.txt") else a
            for a in args]
    r = run_py(*args)
    assert r.returncode == 2, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("authalic: error: ") and words in lines[0], r.stderr
    assert not [p for p in os.listdir(tmp_path) if not p.startswith("missing")]


@pytest.mark.parametrize("budget", ["2.5", "auto"])
def test_refine_mesh_same_files_as_the_program(tmp_path, budget):
    """--refine-mesh SURF --refine-budget K: OUT, SURF and SURF.parents.txt byte for byte the program's."""
    src = os.path.join(DATA, "limbs4.obj")
    a = subprocess.run([cli(), "sphere", src, tmp_path / "c.obj", "--refine-mesh", tmp_path / "cs.obj",
                        "--refine-budget", budget, "--quiet"], capture_output=True, text=True)
    b = run_py("sphere", src, tmp_path / "p.obj", "--refine-mesh", tmp_path / "ps.obj", "--refine-budget", budget,
               "--quiet")
    assert a.returncode == 0 and b.returncode == 0, (a.stderr, b.stderr)
    for c, p in (("c.obj", "p.obj"), ("cs.obj", "ps.obj"), ("cs.obj.parents.txt", "ps.obj.parents.txt")):
        assert (tmp_path / c).read_bytes() == (tmp_path / p).read_bytes(), c
    V, F = authalic.read_mesh(src)
    X, F2 = authalic.read_mesh(str(tmp_path / "ps.obj"))
    rows = [line.split() for line in (tmp_path / "ps.obj.parents.txt").read_text().splitlines()]
    # Refined within the budget: every new vertex has a line, the new vertices numbered on from the input's.
    assert F.shape[0] < F2.shape[0] <= (4 if budget == "auto" else 2.5) * F.shape[0]
    assert [int(r[0]) for r in rows] == list(range(V.shape[0], X.shape[0]))
    assert a.stderr == b.stderr


def test_refine_mesh_outputs_checked_before_the_run(tmp_path):
    """SURF under another name for OUT, and a parents file that is a directory: refused before the run,
    nothing written; a user's earlier SURF is left as it was."""
    (tmp_path / "s.obj").write_text("user")
    (tmp_path / "s.obj.parents.txt").mkdir()
    for surf, words in ((str(tmp_path) + "/./o.obj", "also another input or output file"),
                        (tmp_path / "s.obj", "parents file")):
        r = run_py("sphere", STAR, tmp_path / "o.obj", "--refine-mesh", surf)
        assert r.returncode == 2 and words in r.stderr and r.stderr.count("\n") == 1, r.stderr
    assert sorted(os.listdir(tmp_path)) == ["s.obj", "s.obj.parents.txt"]
    assert (tmp_path / "s.obj").read_text() == "user"


@pytest.mark.parametrize("value", ["0x4", "1_5", " 3", "+3", "3 ", "1e999", "nan", "2.5", "\u0663", "-0", "",
                                   "auto", "AUTO", " auto", "autox"])
def test_numbers_read_as_the_program_reads_them(tmp_path, value):
    """--steps and --refine-budget take the same spellings in both programs (C's strtol and strtod, and
    --refine-budget's auto): with a missing input, a value either is refused by name or lets the run reach
    the input."""
    for opt in (["--steps", value], ["--refine-mesh", tmp_path / "s.obj", "--refine-budget", value]):
        a = subprocess.run([cli(), "sphere", tmp_path / "missing.obj", tmp_path / "o.obj"] + opt, capture_output=True,
                           text=True)
        b = run_py("sphere", tmp_path / "missing.obj", tmp_path / "o.obj", *opt)
        name = opt[-2]
        assert a.returncode == b.returncode == 2, (a.stderr, b.stderr)
        assert (name in a.stderr) == (name in b.stderr), (value, a.stderr, b.stderr)


def test_density_file_and_bad_values(tmp_path):
    V, F = authalic.read_mesh(STAR)
    good, bad = tmp_path / "d.txt", tmp_path / "bad.txt"
    good.write_text("\n".join(["1.5"] * V.shape[0]))
    bad.write_text("1 2 -3")
    assert run_py("sphere", STAR, tmp_path / "o.obj", "--density", good, "--quiet").returncode == 0
    r = run_py("sphere", STAR, tmp_path / "o2.obj", "--density", bad, "--quiet")
    assert r.returncode == 2 and "positive finite" in r.stderr and not (tmp_path / "o2.obj").exists()
    # A value that is no number, or not finite, or no value at all: the program's one line and exit 2.
    for text in ("1 abc 2", "1 inf 2", ""):
        bad.write_text(text)
        a = subprocess.run([cli(), "sphere", STAR, tmp_path / "o3.obj", "--density", bad, "--quiet"],
                           capture_output=True, text=True)
        b = run_py("sphere", STAR, tmp_path / "o3.obj", "--density", bad, "--quiet")
        assert a.returncode == 2 and b.returncode == 2 and b.stderr == a.stderr, (text, a.stderr, b.stderr)
        assert not (tmp_path / "o3.obj").exists()


def test_density_curv_and_gifti_as_the_program(tmp_path):
    """--density in a FreeSurfer curv file and in a GIfTI .shape.gii (written by nibabel): read as the
    program reads them (python -m authalic crashed on the curv file's bytes), the same map byte for
    byte; and read_values gives the file's numbers."""
    nib = pytest.importorskip("nibabel")
    import numpy as np
    V, F = authalic.read_mesh(STAR)
    d = (1 + 0.5 * (V[:, 0] > 0)).astype(np.float32)
    nib.freesurfer.write_morph_data(str(tmp_path / "rh.dens"), d)
    nib.save(nib.gifti.GiftiImage(darrays=[nib.gifti.GiftiDataArray(d, intent="NIFTI_INTENT_SHAPE",
                                                                    datatype="NIFTI_TYPE_FLOAT32")]),
             str(tmp_path / "dens.shape.gii"))
    for name in ("rh.dens", "dens.shape.gii"):
        assert np.array_equal(authalic.read_values(tmp_path / name), d.astype(np.float64))
        a = subprocess.run([cli(), "sphere", STAR, tmp_path / ("c_" + name + ".obj"), "--density", tmp_path / name,
                            "--quiet", "--steps", "4"], capture_output=True, text=True)
        b = run_py("sphere", STAR, tmp_path / ("p_" + name + ".obj"), "--density", tmp_path / name, "--quiet",
                   "--steps", "4")
        assert a.returncode == 0 and b.returncode == 0, (a.stderr, b.stderr)
        assert (tmp_path / ("c_" + name + ".obj")).read_bytes() == (tmp_path / ("p_" + name + ".obj")).read_bytes()
    with pytest.raises(authalic.BadInputError):
        authalic.read_values(tmp_path / "missing.txt")


def test_neuro_outputs_as_the_program(tmp_path):
    """GIfTI and FreeSurfer in and out (written by nibabel): python -m authalic writes what the program
    writes, byte for byte: a GIfTI OUT with the input's AnatomicalStructurePrimary and GeometricType
    Spherical (it had none), an OUT without extension in the input's FreeSurfer format (refused before),
    --radius 100, --distortion, and --refine-mesh SURF as a FreeSurfer surface (the program refused
    SURF without extension) and as GIfTI with the input's metadata (it had none). On limbs4, whose
    refined map beats its input's (on bumpy_star the input's polished map wins and SURF is the input)."""
    nib = pytest.importorskip("nibabel")
    import numpy as np
    V, F = authalic.read_mesh(os.path.join(DATA, "limbs4.obj"))
    meta = {"AnatomicalStructurePrimary": "CortexLeft", "GeometricType": "Anatomical"}
    gii = tmp_path / "lh.white.surf.gii"
    nib.save(nib.gifti.GiftiImage(darrays=[
        nib.gifti.GiftiDataArray(V.astype(np.float32), intent="NIFTI_INTENT_POINTSET", datatype="NIFTI_TYPE_FLOAT32",
                                 meta=meta),
        nib.gifti.GiftiDataArray(F.astype(np.int32), intent="NIFTI_INTENT_TRIANGLE", datatype="NIFTI_TYPE_INT32")]),
        str(gii))
    fs = tmp_path / "lh.white"
    nib.freesurfer.write_geometry(str(fs), V.astype(np.float32), F)
    runs = [(gii, "s.gii", []), (fs, "lh.sphere", ["--radius", "100", "--distortion", "{}.shape.gii"]),
            (fs, "m.obj", ["--refine-mesh", "{}surf"]), (gii, "g.obj", ["--refine-mesh", "{}surf.gii"])]
    for src, out, opts in runs:
        outs = []
        for who in ("c", "p"):
            o = [x.format(tmp_path / (who + "_" + out + "_")) for x in opts]
            args = ["sphere", src, tmp_path / (who + "_" + out), "--quiet"] + o
            r = subprocess.run([cli()] + args, capture_output=True, text=True) if who == "c" else run_py(*args)
            assert r.returncode == 0, r.stderr
            outs.append([tmp_path / (who + "_" + out)] + [o[k + 1] for k in range(len(o)) if opts[k] in (
                "--distortion", "--refine-mesh")])
        for a, b in zip(*outs):
            assert open(a, "rb").read() == open(b, "rb").read(), a
    img = nib.load(str(tmp_path / "p_s.gii"))
    m = dict(img.darrays[0].meta)
    assert m["AnatomicalStructurePrimary"] == "CortexLeft" and m["GeometricType"] == "Spherical"
    S, _ = nib.freesurfer.read_geometry(str(tmp_path / "p_lh.sphere"))
    assert np.allclose(np.linalg.norm(S, axis=1), 100, rtol=1e-6)
    X, Fr = nib.freesurfer.read_geometry(str(tmp_path / "p_m.obj_surf"))
    assert X.shape[0] > V.shape[0] and np.allclose(X[:V.shape[0]], V, atol=1e-5)
    s = nib.load(str(tmp_path / "p_g.obj_surf.gii"))
    m = dict(s.darrays[0].meta)
    assert m["AnatomicalStructurePrimary"] == "CortexLeft" and m["GeometricType"] == "Anatomical"
    assert nib.load(str(tmp_path / "p_lh.sphere_.shape.gii")).darrays[0].data.shape == (V.shape[0],)


@pytest.mark.parametrize("cmd, src, dist", [("disk", DISK, "d.shape.gii"),
                                            ("torus", os.path.join(DATA, "torus_r3.obj"), "d.curv")])
def test_distortion_as_the_program(tmp_path, cmd, src, dist):
    """--distortion of a planar and of a torus map (per-corner vt): the program's file byte for byte."""
    for who in ("c", "p"):
        args = [cmd, src, tmp_path / (who + ".obj"), "--distortion", tmp_path / (who + dist), "--quiet"]
        r = subprocess.run([cli()] + args, capture_output=True, text=True) if who == "c" else run_py(*args)
        assert r.returncode == 0, r.stderr
    assert (tmp_path / ("c" + dist)).read_bytes() == (tmp_path / ("p" + dist)).read_bytes()
    assert (tmp_path / "c.obj").read_bytes() == (tmp_path / "p.obj").read_bytes()


@pytest.mark.parametrize("who", ["program", "python"])
def test_links_fifos_and_failed_runs(tmp_path, who):
    """Outputs through symbolic links: the link stays and the file it names gets the output (also one
    not made yet); a FIFO as OUT, SURF or --distortion is refused with exit 2 and stays a FIFO; two links
    to one new file are one output; a run that fails at its last write (the report in a directory that
    cannot take files) leaves the link and its old file as they were (the distortion file was deleted
    through the link)."""
    def go(*args):
        a = ["sphere", STAR] + [str(x) for x in args] + ["--quiet"]
        return subprocess.run([cli()] + a, capture_output=True, text=True) if who == "program" else run_py(*a)
    (tmp_path / "old.obj").write_text("old\n")
    os.symlink("old.obj", tmp_path / "out.obj")
    os.symlink("sub/../new.json", tmp_path / "r.json")
    (tmp_path / "sub").mkdir()
    r = go(tmp_path / "out.obj", "--report", tmp_path / "r.json")
    assert r.returncode == 0, r.stderr
    assert os.path.islink(tmp_path / "out.obj") and os.path.islink(tmp_path / "r.json")
    assert (tmp_path / "old.obj").read_text().startswith("#") and "metrics" in (tmp_path / "new.json").read_text()
    os.mkfifo(tmp_path / "fifo")
    for opts in (["fifo"], ["o.obj", "--refine-mesh", "fifo"], ["o.obj", "--distortion", "fifo"]):
        r = go(*[tmp_path / o if not o.startswith("--") else o for o in opts])
        assert r.returncode == 2 and "not a regular file" in r.stderr and len(r.stderr.strip().splitlines()) == 1
        assert stat.S_ISFIFO(os.lstat(tmp_path / "fifo").st_mode)
    os.symlink("same.obj", tmp_path / "a.obj")
    os.symlink("same.obj", tmp_path / "b.obj")
    r = go(tmp_path / "a.obj", "--refine-mesh", tmp_path / "b.obj")
    assert r.returncode == 2 and "another input or output" in r.stderr
    (tmp_path / "d.curv").write_bytes(b"old")
    os.symlink("d.curv", tmp_path / "dlink.curv")
    r = go(tmp_path / "o2.obj", "--distortion", tmp_path / "dlink.curv", "--report", "/proc/r.json")
    assert r.returncode != 0
    assert os.path.islink(tmp_path / "dlink.curv") and (tmp_path / "d.curv").read_bytes() == b"old"
    assert not (tmp_path / "o2.obj").exists()
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []


def test_internal_failure_exits_1(tmp_path, monkeypatch, capsys):
    def fail(*a, **k):
        raise authalic.Error("numerical failure in the solve", -4, "AU_E_NUMERIC")
    monkeypatch.setattr(authalic, "map_mesh", fail)
    rc = cli_main.main(["sphere", STAR, str(tmp_path / "o.obj")])
    err = capsys.readouterr().err
    assert rc == 1 and err.count("\n") == 1 and "numerical failure" in err
    assert not (tmp_path / "o.obj").exists()


def test_help_and_version():
    r = run_py("sphere", "--help")
    assert r.returncode == 0 and "--steps" in r.stdout and "--corners" not in r.stdout
    r = run_py("--version")
    assert r.returncode == 0 and authalic.version() in r.stdout
