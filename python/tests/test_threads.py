"""test_threads.py - the GIL is released while a map runs: two threads map two meshes at once, each
getting the map it gets alone, and Python code runs beside a map."""
import os
import threading
import time

import numpy as np

import authalic
from conftest import DATA


def test_two_threads_map_two_meshes_at_once(star):
    Vd, Fd = authalic.read_mesh(os.path.join(DATA, "disk_bump.obj"))
    opts = dict(tol=0, steps=25)  # both run all their steps, so the two flows surely overlap
    alone = [authalic.sphere(*star, **opts)[0], authalic.disk(Vd, Fd, **opts)[0]]
    spans = [[None, None], [None, None]]
    out = [None, None]
    errors = []
    barrier = threading.Barrier(2)

    def job(k):
        def progress(step, n, err):  # first and last step seen, per job
            t = time.monotonic()
            spans[k][0] = spans[k][0] or t
            spans[k][1] = t
        try:
            barrier.wait()
            out[k] = (authalic.sphere(*star, progress=progress, **opts) if k == 0 else
                      authalic.disk(Vd, Fd, progress=progress, **opts))[0]
        except BaseException as e:  # noqa: B902 - reported below
            errors.append(e)

    threads = [threading.Thread(target=job, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    assert np.array_equal(out[0], alone[0]) and np.array_equal(out[1], alone[1])
    # The two flows overlapped in time: each one's steps began before the other's ended.
    (a0, a1), (b0, b1) = spans
    assert a0 < b1 and b0 < a1, spans


def test_python_runs_while_a_map_runs(star):
    done = threading.Event()
    result = []

    def job():
        result.append(authalic.sphere(*star, steps=30, tol=0)[1])
        done.set()
    t = threading.Thread(target=job)
    t.start()
    spins = 0
    while not done.is_set():
        spins += 1  # would barely move if the map held the GIL
    t.join()
    assert result and result[0]["folds"] == 0
    assert spins > 10000, spins


def test_the_main_thread_map_leaves_no_thread_behind(star):
    before = threading.active_count()
    authalic.sphere(*star, steps=2)
    assert threading.active_count() == before


def test_numpy_imported_first_warns_and_blas_threads_repairs():
    import subprocess
    import sys
    from conftest import ROOT
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS", "OMP_THREAD_LIMIT")}
    env["PYTHONPATH"] = os.path.join(ROOT, "python")
    code = ("import warnings; warnings.simplefilter('always')\n"
            "import numpy, authalic\n"
            "n = authalic.blas_threads(); print('before', n); print('after', authalic.blas_threads(1))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    if "before 1\n" in r.stdout:  # a one-core machine: OpenBLAS starts with one thread anyway
        return
    assert "AuthalicWarning" in r.stderr and "blas_threads(1)" in r.stderr and "after 1\n" in r.stdout
    # Imported first, authalic sets one thread and says nothing.
    r = subprocess.run([sys.executable, "-W", "always", "-c", "import authalic, numpy; print(authalic.blas_threads())"],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 0 and r.stdout == "1\n" and not r.stderr, (r.stdout, r.stderr)
