"""Long runs release the GIL and stop on Ctrl-C."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time

import rocking_stones as rs

# The run installs Python's own Ctrl-C handler: a Python started with SIGINT ignored (as a
# background job of a shell without job control starts it) would otherwise never see the signal.
LONG_DROP = """
import signal, sys, rocking_stones as rs
signal.signal(signal.SIGINT, signal.default_int_handler)
a = rs.analyze(rs.generate("pebble", n=400, seed=1))
print("ready", flush=True)
rs.drop(a, n=10**6, seed=1, size=0.01)
"""


def test_ctrl_c_stops_a_long_drop_quickly():
    # -X faulthandler: if the run does not stop, SIGABRT makes it print where its threads are.
    cmd = [sys.executable, "-X", "faulthandler", "-c", LONG_DROP]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "ready"
    time.sleep(1.0)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    try:
        _, err = p.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        p.send_signal(signal.SIGABRT)
        try:
            _, err = p.communicate(timeout=10)
        except subprocess.TimeoutExpired:
            p.kill()
            _, err = p.communicate()
        raise AssertionError(f"the drop run did not stop on SIGINT; where it was:\n{err}")
    waited = time.monotonic() - sent
    assert "KeyboardInterrupt" in err, err
    assert waited < 5.0, f"stopped {waited:.1f} s after Ctrl-C"


def test_drops_release_the_gil():
    a = rs.analyze(rs.generate("pebble", n=300, seed=2))
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    start = time.monotonic()
    rs.drop(a, n=300, seed=1, threads=1, size=0.01)
    elapsed = time.monotonic() - start
    done.set()
    t.join()
    # The counting thread ran while the drops did (≈ one tick per ms; with the GIL held by the
    # drops it could not have run at all).
    assert elapsed > 0.2, f"the run was too short to tell ({elapsed:.2f} s)"
    assert len(ticks) >= 20, (len(ticks), elapsed)


def test_progress_is_reported_and_can_stop_a_run():
    a = rs.analyze(rs.generate("box"))
    seen = []
    d = rs.drop(a, n=300, seed=1, size=0.01, progress=lambda done, total: seen.append((done, total)))
    assert seen and seen[-1] == (300, 300) and all(t == 300 for _, t in seen)
    assert [x for x, _ in seen] == sorted(x for x, _ in seen)
    assert d.drops == 300

    class Stop(Exception):
        pass

    def stop(done, total):
        raise Stop

    try:
        rs.drop(a, n=10**6, seed=1, size=0.01, progress=stop)
    except Stop:
        pass
    else:
        raise AssertionError("the exception raised by progress should stop the run")


def test_thread_count_follows_rayon_num_threads():
    code = "import rocking_stones as rs; print(rs.num_threads())"
    for n in ("1", "3"):
        out = subprocess.run([sys.executable, "-c", code], env={**os.environ, "RAYON_NUM_THREADS": n},
                             capture_output=True, text=True, check=True)
        assert out.stdout.strip() == n
