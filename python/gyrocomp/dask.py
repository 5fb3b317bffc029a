"""Dask: a cancelled Dask task stops the gyrocomp call it is running (docs/guides/python.md).

Dask does not interrupt a running task: ``future.cancel()`` (or dropping the last reference to the
future) only marks it cancelled on its worker, and the task's thread runs on. Inside a task, pass
the token of ``cancel_with_task()`` to the long calls; a watcher thread polls the task's state on
its worker every ``poll_s`` seconds (default 0.05) and cancels the token once the task is no longer
executing, so the call raises ``gyrocomp.Cancelled`` within the library's polling interval::

    def fit_unit(path):
        with gyrocomp.dask.cancel_with_task() as token:
            return gyrocomp.fit_drift_model(temp, rate, fs, model="cs-svr", cancel=token)

Needs dask.distributed (Debian: python3-distributed). Outside a distributed task (the local
threaded / process schedulers, or no Dask at all) the token is a plain CancellationToken that
nothing sets: those schedulers cannot cancel a running task; Ctrl-C in the main thread still
reaches a call made there (KeyboardInterrupt).
"""

import contextlib
import threading

from ._core import CancellationToken

_RUNNING = ("executing", "long-running")


def _current_task():
    """(worker, key) of the distributed task running on this thread, or None."""
    try:
        from distributed import get_worker
        from distributed.worker import thread_state
        worker = get_worker()
        key = thread_state.key
    except (ImportError, ValueError, AttributeError):
        return None
    return worker, key


@contextlib.contextmanager
def cancel_with_task(poll_s=0.05):
    """A CancellationToken that is cancelled when the current Dask task is cancelled."""
    token = CancellationToken()
    task = _current_task()
    if task is None:
        yield token
        return
    worker, key = task
    done = threading.Event()

    def watch():
        while not done.wait(poll_s):
            state = worker.state.tasks.get(key)
            if state is None or state.state not in _RUNNING:
                token.cancel()
                return

    watcher = threading.Thread(target=watch, name="gyrocomp-dask-cancel", daemon=True)
    watcher.start()
    try:
        yield token
    finally:
        done.set()
        watcher.join()
