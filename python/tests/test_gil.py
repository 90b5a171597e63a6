"""The GIL is released while tessella works, so other Python threads make progress."""

import sys
import threading
import time

import pytest

import tessella
from conftest import icosphere

WORK = {
    "refine": lambda v, f: tessella.refine(v, f, v, scheme="pn", level=48),
    "refine-png1": lambda v, f: tessella.refine(v, f, v, scheme="png1", level=48),
    # Opening the device, the GPU work and the wait for it (lavapipe where there is no GPU).
    "refine-gpu": lambda v, f: tessella.refine(v, f, v, scheme="pn", level=48, backend="gpu"),
    "quality": lambda v, f: tessella.quality(v, f, v, scheme="png1", level=96),
}


@pytest.mark.parametrize("work", WORK)
def test_another_thread_runs_python_code_during_the_work(work):
    v, f = icosphere(2)
    stamps = {}
    started = threading.Event()

    def worker():
        started.set()
        stamps["start"] = time.perf_counter()
        WORK[work](v, f)
        stamps["end"] = time.perf_counter()

    old = sys.getswitchinterval()
    # With a huge switch interval a thread gives up the GIL only when it blocks or releases it
    # itself: the main thread can run while the worker is inside refine only if refine
    # released the GIL. Without the release every main-thread stamp falls after "end".
    sys.setswitchinterval(1000.0)
    try:
        t = threading.Thread(target=worker)
        t.start()
        started.wait()
        ours = [time.perf_counter() for _ in range(2000)]
        t.join()
    finally:
        sys.setswitchinterval(old)
    assert stamps["start"] < ours[0]
    assert ours[-1] < stamps["end"], f"the main thread could not run while {work} was working"
