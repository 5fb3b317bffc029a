#!/usr/bin/env python3
"""Time from a Ctrl-C to the end of a gyrocomp Python call: the Python rows of the table
"Cancellation" in docs/explanation/performance.md.

    PYTHONPATH=build/python bench/cancel_latency.py child process 2      # SIGINT 2 s into run_parallel_model (5 M samples)
    PYTHONPATH=build/python bench/cancel_latency.py child fit 3          # SIGINT 3 s into fit_drift_model(cs-svr)
    PYTHONPATH=build/python bench/cancel_latency.py stage entropy 0.5   # SIGINT 0.5 s into a stage of run_parallel_model

child: a child interpreter simulates the record (process: 50 000 s at 100 Hz; fit: the heat-cool
profile at 5 Hz), prints READY and runs the call; SIGINT is sent DELAY s after READY and the time
to the child's exit is printed, with the stage it was in and the files left in its (empty) folder.
stage: SIGINT is sent to this process DELAY s after the stage's first progress call (vmd, entropy,
drift-fit, bandwidth); the time to the KeyboardInterrupt is printed. Timing only: the assertions
are in python/tests/test_cancel.py.
"""
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time

CHILD = r"""
import sys
import gyrocomp
kind = sys.argv[1]
stage = ["(before the first progress call)"]
def prog(s, f):
    stage[0] = s
if kind == "process":
    sim = gyrocomp.simulate(fs_hz=100.0, seed=1, duration_s=50000.0)
    call = lambda: gyrocomp.run_parallel_model(sim.rate_dps, sim.temp_c, sim.fs_hz, progress=prog)
else:
    sim = gyrocomp.simulate(fs_hz=5.0, seed=1, profile=dict(kind="heat-cool"))
    call = lambda: gyrocomp.fit_drift_model(sim.temp_c, sim.rate_dps, sim.fs_hz, model="cs-svr", progress=prog)
print("READY", flush=True)
try:
    call()
    print("FINISHED", flush=True)
except KeyboardInterrupt:
    print("KeyboardInterrupt in", stage[0], flush=True)
"""


def child(kind, delay):
    with tempfile.TemporaryDirectory() as folder:
        script = os.path.join(folder, "..", os.path.basename(folder) + "_child.py")
        with open(script, "w") as f:
            f.write(CHILD)
        try:
            env = dict(os.environ)  # PYTHONPATH made absolute: the child runs in `folder`
            env["PYTHONPATH"] = os.pathsep.join(os.path.abspath(p) for p in env.get("PYTHONPATH", "").split(os.pathsep) if p)
            p = subprocess.Popen([sys.executable, script, kind], stdout=subprocess.PIPE, text=True, cwd=folder, env=env)
            assert p.stdout.readline().strip() == "READY"
            time.sleep(delay)
            sent = time.monotonic()
            p.send_signal(signal.SIGINT)
            out = p.communicate()[0].strip()
            latency = time.monotonic() - sent
            print(f"{kind}: SIGINT {delay} s in -> exit {p.returncode} after {latency:.3f} s; {out}; "
                  f"files left: {os.listdir(folder)}")
        finally:
            os.remove(script)


def stage(name, delay):
    import gyrocomp
    sim = gyrocomp.simulate(fs_hz=100.0, seed=1, duration_s=50000.0)
    sent = []

    def fire():
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)

    armed = []

    def prog(s, fraction):
        if s == name and not armed:
            armed.append(threading.Timer(delay, fire))
            armed[0].start()

    try:
        gyrocomp.run_parallel_model(sim.rate_dps, sim.temp_c, sim.fs_hz, progress=prog)
        print(f"{name}: finished before the signal")
    except KeyboardInterrupt:
        print(f"run_parallel_model, 5 M samples, SIGINT {delay} s into '{name}': "
              f"KeyboardInterrupt {time.monotonic() - sent[0]:.3f} s after the signal")


if __name__ == "__main__":
    if len(sys.argv) != 4 or sys.argv[1] not in ("child", "stage"):
        sys.exit(__doc__)
    (child if sys.argv[1] == "child" else stage)(sys.argv[2], float(sys.argv[3]))
