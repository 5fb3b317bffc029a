"""Cancellation: Ctrl-C (KeyboardInterrupt), a CancellationToken and a Dask cancel stop the long calls.

Each case runs the call in a child interpreter, sends SIGINT once the child says the call is
running, and checks that the child saw KeyboardInterrupt from inside the call (not after it ran to
the end: the calls take tens of seconds here) and left no file in its folder. The latency (signal
to exit) is printed, not asserted (docs/explanation/performance.md has the measured figures).
"""
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import gyrocomp

CHILD_PRELUDE = textwrap.dedent("""
    import sys, time
    import gyrocomp
    def run(call):
        print("READY", flush=True)
        t0 = time.monotonic()
        try:
            call()
        except KeyboardInterrupt:
            print("INTERRUPTED %.3f" % (time.monotonic() - t0), flush=True)
            sys.exit(0)
        print("FINISHED %.3f" % (time.monotonic() - t0), flush=True)
        sys.exit(1)
""")

# process on 5 M samples (50 000 s at 100 Hz, the paper's chamber run): VMD alone takes ~25 s.
PROCESS_5M = CHILD_PRELUDE + textwrap.dedent("""
    sim = gyrocomp.simulate(fs_hz=100.0, seed=1, duration_s=50000.0)
    assert sim.rate_dps.shape == (5000000,)
    run(lambda: gyrocomp.run_parallel_model(sim.rate_dps, sim.temp_c, sim.fs_hz))
""")

# fit --model cs-svr on a heat-cool run (both directions: the kernel model is fitted).
FIT_CS_SVR = CHILD_PRELUDE + textwrap.dedent("""
    sim = gyrocomp.simulate(fs_hz=5.0, seed=1, profile=dict(kind="heat-cool"))
    run(lambda: gyrocomp.fit_drift_model(sim.temp_c, sim.rate_dps, sim.fs_hz, model="cs-svr"))
""")


def interrupt_child(tmp_path, script, delay_s):
    path = tmp_path / "child.py"
    path.write_text(script)
    env = dict(os.environ)
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(gyrocomp.__file__)))  # the gyrocomp imported here
    env["PYTHONPATH"] = os.pathsep.join([package_root] + [p for p in [env.get("PYTHONPATH")] if p])
    proc = subprocess.Popen([sys.executable, str(path)], cwd=tmp_path, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()
        assert line.strip() == "READY", line + proc.stderr.read()
        time.sleep(delay_s)  # well inside the call
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=120)
        latency = time.monotonic() - sent
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    print(f"SIGINT -> exit: {latency:.3f} s; child: {out.strip()}")
    assert proc.returncode == 0, out + err
    assert out.startswith("INTERRUPTED"), out + err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["child.py"]  # nothing left behind


def test_ctrl_c_stops_process_on_5m_samples(tmp_path):
    interrupt_child(tmp_path, PROCESS_5M, 2.0)


def test_ctrl_c_stops_fit_cs_svr(tmp_path):
    interrupt_child(tmp_path, FIT_CS_SVR, 1.5)


def test_a_token_set_from_another_thread_raises_cancelled():
    sim = gyrocomp.simulate(fs_hz=5.0, seed=1, profile=dict(kind="heat-cool"))
    token = gyrocomp.CancellationToken()
    timer = threading.Timer(0.5, token.cancel)
    timer.start()
    try:
        with pytest.raises(gyrocomp.Cancelled):
            gyrocomp.fit_drift_model(sim.temp_c, sim.rate_dps, sim.fs_hz, model="cs-svr", cancel=token)
    finally:
        timer.cancel()
    x = np.random.default_rng(1).normal(size=3000)
    token = gyrocomp.CancellationToken()
    token.cancel()
    for call in (lambda: gyrocomp.sample_entropy(x, cancel=token), lambda: gyrocomp.compute_allan(x, 100.0, cancel=token),
                 lambda: gyrocomp.vmd(x, num_modes=2, cancel=token)):
        with pytest.raises(gyrocomp.Cancelled):
            call()
    # An unset token changes nothing.
    a = gyrocomp.sample_entropy(x)
    b = gyrocomp.sample_entropy(x, cancel=gyrocomp.CancellationToken())
    assert a.a_matches == b.a_matches and a.b_matches == b.b_matches


# ---- Dask -------------------------------------------------------------------------------------

DASK_RESULTS = {}  # filled by the task (an in-process cluster: the same interpreter)


def _dask_fit_task(label, temp_c, rate_dps, fs_hz):
    import gyrocomp as g
    DASK_RESULTS[label] = "started"
    with g.dask.cancel_with_task() as token:
        try:
            g.fit_drift_model(temp_c, rate_dps, fs_hz, model="cs-svr", cancel=token)
            DASK_RESULTS[label] = "finished"
        except g.Cancelled:
            DASK_RESULTS[label] = ("cancelled", time.monotonic())
    return 1


def test_a_dask_cancel_stops_a_running_fit():
    distributed = pytest.importorskip("distributed", reason="dask.distributed is not installed (python3-distributed)")
    sim = gyrocomp.simulate(fs_hz=5.0, seed=1, profile=dict(kind="heat-cool"))
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        temp_c, rate_dps = client.scatter([sim.temp_c, sim.rate_dps])
        future = client.submit(_dask_fit_task, "fit", temp_c, rate_dps, sim.fs_hz, pure=False)
        deadline = time.monotonic() + 60
        while DASK_RESULTS.get("fit") != "started" and time.monotonic() < deadline:
            time.sleep(0.01)
        assert DASK_RESULTS.get("fit") == "started"
        time.sleep(1.0)  # inside the cuckoo search (it takes tens of seconds)
        sent = time.monotonic()
        future.cancel()
        while DASK_RESULTS.get("fit") == "started" and time.monotonic() < deadline:
            time.sleep(0.01)
        result = DASK_RESULTS.get("fit")
    assert isinstance(result, tuple) and result[0] == "cancelled", result
    print(f"Dask cancel -> gyrocomp.Cancelled in the task: {result[1] - sent:.3f} s")


def test_cancel_with_task_outside_dask_is_a_plain_token():
    with gyrocomp.dask.cancel_with_task() as token:
        assert isinstance(token, gyrocomp.CancellationToken) and not token.cancelled
