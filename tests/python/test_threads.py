"""Heavy calls release the GIL: two threads' calls run at once, and both answers are right.

How it is seen without timing anything: with a switch interval of 1000 s, a thread that holds
the GIL keeps it until it blocks or a C++ call releases it. The main thread waits for the
worker to start; it can run again while the worker's call is still inside C++ only if that
call released the GIL, and the worker cannot mark its call done without the GIL back, which
the main thread keeps until it blocks in its own call. So `not done` read by the main thread
right after waking says the calls overlapped."""

import contextlib
import sys
import threading

import numpy as np
import pytest

import extremal
from conftest import SOURCE_DIR


@contextlib.contextmanager
def long_switch_interval():
    before = sys.getswitchinterval()
    sys.setswitchinterval(1000.0)
    try:
        yield
    finally:
        sys.setswitchinterval(before)


def overlapped(work, main_work):
    """Runs work() in a thread and main_work() here once it has started; returns whether the
    main thread ran while work() was still in its call, and both results."""
    started = threading.Event()
    state = {"done": False}

    def worker():
        started.set()
        state["result"] = work()
        state["done"] = True

    with long_switch_interval():
        thread = threading.Thread(target=worker)
        thread.start()
        started.wait()
        during = not state["done"]
        mine = main_work()
        thread.join()
    return during, state["result"], mine


@pytest.fixture(scope="module")
def parts(shared_data):
    return (extremal.read_model(shared_data / "step" / "linkrods.step"),
            extremal.read_model(shared_data / "step" / "screw.step"))


def test_two_threads_measure_at_once(parts):
    linkrods, screw = parts
    ellipsoid = extremal.ellipsoid(3, 2, 1.5)

    def first():  # a signed query, a fraction of a second: the ellipsoid cuts the part
        return extremal.distance(linkrods, ellipsoid, pose_b=(5, 3, 1), signed=True)

    def second():
        return extremal.distance(screw, linkrods, pose_b=(-20, 0, 8), tolerance=1e-12)

    expected = first(), second()
    during, a, b = overlapped(first, second)
    assert during, "the main thread did not run while the other thread's distance call ran"
    for got, want in zip((a, b), expected):
        assert got.distance == want.distance and got.status == want.status
        assert (got.lower_bound, got.upper_bound) == (want.lower_bound, want.upper_bound)
        np.testing.assert_array_equal(got.point_a, want.point_a)
        np.testing.assert_array_equal(got.normal, want.normal)
    assert a.status == "penetrating" and a.distance < 0 and b.status == "converged" and b.distance > 0


def test_two_threads_track_at_once_and_a_tracker_is_not_shared(parts):
    linkrods, _ = parts
    ball = extremal.sphere(0.6)
    times = np.arange(150) * 0.005
    still = np.tile([0.0, 0, 0, 1, 0, 0, 0], (150, 1))
    passing = np.array([[2.0 + 10 * t, 3.2, 2.9] for t in times])
    twists = np.tile([10.0, 0, 0, 0, 0, 0], (150, 1))

    def run(tracker):
        return tracker.track(times, still, passing, None, twists)

    expected = run(extremal.Tracker(linkrods, ball))
    busy = extremal.Tracker(linkrods, ball)
    errors = []

    def main_work():
        try:  # the other thread is inside busy.track: this tracker is not for two threads
            busy.step(0.0, None, None, passing[0], twists[0], 0.005)
        except RuntimeError as e:
            errors.append(str(e))
        return run(extremal.Tracker(linkrods, ball))

    during, a, b = overlapped(lambda: run(busy), main_work)
    assert during
    assert errors and "not shared between threads" in errors[0]
    for got in (a, b):
        np.testing.assert_array_equal(got["distance"], expected["distance"])
        assert list(got["status"]) == list(expected["status"])
    assert expected["distance"].min() > 0


def test_a_report_runs_while_python_does():
    demo = SOURCE_DIR / "data" / "demo" / "demo.json"
    during, rep, _ = overlapped(lambda: extremal.report(demo), lambda: None)
    assert during and len(rep) == 1202
