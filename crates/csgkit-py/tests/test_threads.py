"""The GIL is released while csgkit computes: Python code runs on other threads meanwhile,
and operations on several threads give what they give on one."""

import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np

import csgkit
from conftest import sphere


def test_python_runs_on_other_threads_during_an_operation():
    """The library reports progress from its worker threads, and each report runs the Python
    callback there. Those threads can only run Python while the calling thread does not hold
    the GIL, so callbacks from other threads are Python code run during the operation (with
    the GIL held, the first would wait forever; the join's timeout turns that into a
    failure instead of a hang)."""
    caller = []
    reporters = set()

    def progress(stage, done, total):
        reporters.add(threading.get_ident())

    def work():
        caller.append(threading.get_ident())
        csgkit.union(sphere((0, 0, 0), 1, 4), sphere((0.5, 0.2, 0.1), 1, 4), progress=progress)

    thread = threading.Thread(target=work, daemon=True)
    thread.start()
    thread.join(timeout=300)
    assert not thread.is_alive(), "the operation never finished: the GIL was not released"
    assert reporters - set(caller), "no report came from a worker thread"


def test_concurrent_operations_match_serial_ones():
    pairs = [(sphere((0, 0, 0), 1, 3), sphere((0.3 * k, 0.1, 0), 0.9, 3)) for k in range(1, 5)]
    serial = [csgkit.union(a, b) for a, b in pairs]
    with ThreadPoolExecutor(max_workers=4) as pool:
        parallel = list(pool.map(lambda ab: csgkit.union(*ab), pairs))
    for one, other in zip(serial, parallel):
        np.testing.assert_array_equal(one.vertices, other.vertices)
        np.testing.assert_array_equal(one.faces, other.faces)


def test_ctrl_c_interrupts_an_operation():
    """A KeyboardInterrupt arriving during an operation (here simulated on the main thread,
    as Ctrl-C delivers it) is raised by the operation, long before the operation would have
    finished, and the next operation runs normally."""
    import _thread
    import signal
    import time

    a, b = sphere((0, 0, 0), 1, 6), sphere((0.3, 0.2, 0.1), 1, 6)
    start = time.perf_counter()
    csgkit.union(a, b)
    full = time.perf_counter() - start

    big_a, big_b = sphere((0, 0, 0), 1, 7), sphere((0.3, 0.2, 0.1), 1, 7)
    # A process started in the background (a CI job, `cmd &`) inherits SIGINT ignored, and
    # interrupt_main then does nothing: Python's own handler goes in, as in an interactive run.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.05, _thread.interrupt_main)
    start = time.perf_counter()
    timer.start()
    try:
        csgkit.union(big_a, big_b)
    except KeyboardInterrupt:
        interrupted_after = time.perf_counter() - start
    else:
        raise AssertionError("the operation finished without seeing the interrupt")
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    # The subdivision-7 union is four times the subdivision-6 one's work.
    assert interrupted_after < 2 * full + 0.5, (interrupted_after, full)
    assert csgkit.check(csgkit.union(*cube_pair()))["volume"] == 1.5


def cube_pair():
    from conftest import cube

    return cube(), cube((0.5, 0, 0), (1.5, 1, 1))


def test_a_progress_callback_can_run_an_operation():
    """An operation runs on a worker of the library's thread pool, and so does a progress
    callback it calls; an operation that callback starts runs right there. With one worker
    (RAYON_NUM_THREADS=1, in a fresh interpreter) an operation queued for the pool instead
    would wait for the worker that waits for it; the timeout turns that hang into a
    failure."""
    import os
    import subprocess
    import sys

    script = """
import csgkit
from conftest import cube
inner = []
def progress(stage, done, total):
    if not inner:
        inner.append(csgkit.check(csgkit.union(cube(), cube((0.5, 0, 0), (1.5, 1, 1))))["volume"])
result = csgkit.union(cube(), cube((0, 0.5, 0), (1, 1.5, 1)), progress=progress)
print(inner[0], csgkit.check(result)["volume"])
"""
    here = os.path.dirname(os.path.abspath(__file__))
    done = subprocess.run([sys.executable, "-c", script], cwd=here, capture_output=True, text=True,
                          timeout=120, env={**os.environ, "RAYON_NUM_THREADS": "1"})
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["1.5", "1.5"]
