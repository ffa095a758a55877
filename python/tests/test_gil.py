"""evaluate() releases the GIL: Python code keeps running while it works, and
two Python threads evaluating at once get what each gets alone.

Measured without wall-clock comparisons (which a loaded machine makes flaky):
the main thread ticks in a pure-Python loop while another thread is inside
evaluate(); if evaluate held the GIL, the loop would stall for the whole call,
so the longest pause between ticks is compared with the call's duration."""
import threading
import time

import numpy as np

import sodaevo
from conftest import DAINTY

PROBLEM = {"frames": 8000, "settle_frames": 100}


def creatures(count):
    seed = sodaevo.creature(sodaevo.Model.load(DAINTY))
    return [sodaevo.mutate(seed, k) for k in range(count)]


def test_python_runs_while_evaluate_works():
    models = creatures(128)
    span = []

    def work():
        t0 = time.perf_counter()
        sodaevo.evaluate(models, PROBLEM, replicas=8, threads=1)
        span.extend([t0, time.perf_counter()])

    # The main thread ticks (a Python loop, which needs the GIL) from before the
    # worker starts until it is done.
    ticks = []
    worker = threading.Thread(target=work)
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    t0, t1 = span
    points = [t0] + [t for t in ticks if t0 < t < t1] + [t1]
    longest = max(b - a for a, b in zip(points, points[1:]))
    # evaluate() takes a good fraction of a second; with the GIL held no tick
    # could fall inside it (longest == its duration). Released, the pauses are
    # the sleep, the interpreter's switch interval (5 ms) and the OS scheduler's.
    assert t1 - t0 > 0.1
    assert longest < 0.5 * (t1 - t0), (longest, t1 - t0)


def test_two_python_threads_evaluate_at_once():
    models = creatures(12)
    alone = sodaevo.evaluate(models, PROBLEM, replicas=4, threads=1)
    results = [None, None]

    def work(k):
        results[k] = sodaevo.evaluate(models, PROBLEM, replicas=4, threads=1)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r in results:
        assert np.array_equal(r.fitness, alone.fitness) and np.array_equal(r.sd, alone.sd)
