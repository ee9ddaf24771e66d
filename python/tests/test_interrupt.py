"""test_interrupt.py - Ctrl-C during a long map: a child Python is sent SIGINT in the middle of a map;
the map is cancelled (it stops within a step), KeyboardInterrupt is raised in the caller, no thread
is left running, the library maps again afterwards, and the process exits cleanly. `python -m
authalic` interrupted likewise dies by SIGINT and leaves neither OUT nor a temporary file."""
import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from conftest import DATA, QUICK, ROOT, SHARED

HERE = os.path.dirname(os.path.abspath(__file__))
PY = sys.executable

# A mesh whose map takes long (tol 0 runs all 512 steps): bunny, or the star subdivided.
LOAD = textwrap.dedent("""
    import os, sys, threading, time
    sys.path[:0] = [%r, %r]
    import authalic
    from conftest import subdivide
    bunny = os.path.join(%r, "meshes", "bunny.obj")
    if os.path.exists(bunny) and not %r:
        V, F = authalic.read_mesh(bunny)
    else:
        V, F = authalic.read_mesh(os.path.join(%r, "bumpy_star.obj"))
        V, F = subdivide(V, F)
    small = authalic.read_mesh(os.path.join(%r, "bumpy_star.obj"))
""") % (os.path.join(ROOT, "python"), HERE, SHARED, QUICK, DATA, DATA)

CHILD = LOAD + textwrap.dedent("""
    def progress(k, n, err):
        print("step", k, flush=True)
    try:
        authalic.sphere(V, F, tol=0, steps=512, progress=progress)
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("interrupted", time.monotonic(), flush=True)
    print("threads", threading.active_count(), flush=True)
    S, info = authalic.sphere(*small, steps=3)
    print("again", info["folds"], flush=True)
""")


def wait_for(stream, word, proc, timeout):
    """Read lines until one starts with word; returns the lines read."""
    lines, t0 = [], time.monotonic()
    while time.monotonic() - t0 < timeout:
        line = stream.readline()
        if not line:
            break
        lines.append(line)
        if line.startswith(word) or word in line:
            return lines
    proc.kill()
    pytest.fail("no %r from the child: %s" % (word, "".join(lines)))


def test_sigint_cancels_a_map_in_the_main_thread():
    p = subprocess.Popen([PY, "-c", CHILD], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        wait_for(p.stdout, "step", p, 300)
        t_sig = time.monotonic()
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=300)
    finally:
        p.kill()
    assert p.returncode == 0, (p.returncode, out, err)
    assert "finished" not in out and "interrupted" in out, out
    t_stop = float(out.split("interrupted", 1)[1].split()[0])
    assert t_stop - t_sig < 60, "the map went on for %.1f s after SIGINT" % (t_stop - t_sig)
    assert "threads 1\n" in out and "again 0\n" in out, out
    assert "Traceback" not in err and "Exception ignored" not in err, err


def test_sigint_cancels_a_map_waited_for_by_the_main_thread():
    # The user's own worker thread maps; the main thread waits on it, gets KeyboardInterrupt and
    # cancels the map through the progress callable's return value. (It waits on an Event with a
    # timeout, not on Thread.join, which Python 3.11 can get wrong when interrupted: see _wait.)
    child = LOAD + textwrap.dedent("""
        stop, done = threading.Event(), threading.Event()
        res = []
        def progress(k, n, err):
            print("step", k, flush=True)
            return stop.is_set()
        def work():
            try:
                authalic.sphere(V, F, tol=0, steps=512, progress=progress)
                res.append("finished")
            except authalic.Error as e:
                res.append(e.name)
            done.set()
        t = threading.Thread(target=work)
        t.start()
        try:
            while not done.wait(0.1):  # timed: a SIGINT the kernel hands to another thread is seen too
                pass
        except KeyboardInterrupt:
            stop.set()
            done.wait()
            t.join()
            print("interrupted", res, flush=True)
        print("threads", threading.active_count(), flush=True)
    """)
    p = subprocess.Popen([PY, "-c", child], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        wait_for(p.stdout, "step", p, 300)
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=300)
    finally:
        p.kill()
    assert p.returncode == 0, (out, err)
    assert "interrupted ['AU_E_CANCELLED']" in out and "threads 1\n" in out, out


def test_sigint_during_python_m_authalic(tmp_path):
    src = os.path.join(SHARED, "meshes", "bunny.obj")
    if QUICK or not os.path.exists(src):
        src = os.path.join(DATA, "bumpy_star.obj")
    out = tmp_path / "out.obj"
    env = dict(os.environ, PYTHONPATH=os.path.join(ROOT, "python"))
    p = subprocess.Popen([PY, "-m", "authalic", "sphere", src, str(out), "--tol", "0", "--steps", "512",
                          "--report", str(tmp_path / "r.json")], stderr=subprocess.PIPE, text=True, env=env)
    try:
        wait_for(p.stderr, "authalic: step", p, 300)  # a progress line: the map is under way
        p.send_signal(signal.SIGINT)
        _, err = p.communicate(timeout=300)
    finally:
        p.kill()
    assert p.returncode == -signal.SIGINT, (p.returncode, err)
    assert "Traceback" not in err, err
    assert os.listdir(tmp_path) == [], os.listdir(tmp_path)
