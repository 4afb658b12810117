"""Bad input raises extremal.InvalidInput (a ValueError) naming the file, key or argument, with
the command's own message where the command reads the same input."""

import pickle

import numpy as np
import pytest

import extremal
from conftest import write_scene


def raises(match):
    return pytest.raises(extremal.InvalidInput, match=match)


def test_invalid_input_is_a_value_error_that_survives_pickling():
    assert issubclass(extremal.InvalidInput, ValueError)
    with raises("sphere radius") as e:
        extremal.sphere(-1.0)
    copy = pickle.loads(pickle.dumps(e.value))  # as Dask sends a worker's error back
    assert type(copy) is extremal.InvalidInput and str(copy) == str(e.value)


def test_files_and_units(tmp_path):
    missing = tmp_path / "nowhere.step"
    with raises(str(missing)):
        extremal.read_model(missing)
    junk = tmp_path / "junk.step"
    junk.write_text("this is not a STEP file\n")
    with raises(str(junk)):
        extremal.read_model(junk)
    with raises("^path: expected a path"):
        extremal.read_model(42)
    with raises("^units: unknown unit 'furlong'"):
        extremal.read_model(junk, units="furlong")
    with raises("^file_units: unknown unit"):
        extremal.read_model(junk, file_units="")


def test_shapes_name_the_size():
    with raises("^extremal.torus: torus minor radius must be finite and > 0, got 0"):
        extremal.torus(2.0, 0.0)
    with raises("cylinder height"):
        extremal.cylinder(1.0, float("nan"))


def test_distance_names_its_arguments():
    a, b = extremal.sphere(1.0), extremal.sphere(0.5)
    with raises(r"^pose_b: expected 3 numbers \(x, y, z\) or 7 .*got shape \(5,\)"):
        extremal.distance(a, b, pose_b=[1, 2, 3, 4, 5])
    with raises(r"^pose_b\[1\]: not a finite number"):
        extremal.distance(a, b, pose_b=[1, float("inf"), 3])
    with raises("^pose_a: .*quaternion"):
        extremal.distance(a, b, pose_a=[0, 0, 0, 0, 0, 0, 0])
    with raises("^pose_a: expected numbers, got a string"):
        extremal.distance(a, b, pose_a="1,2,3")
    with raises("^b: expected an extremal.Body, a Model or a list of bodies, got str"):
        extremal.distance(a, "sphere:1")
    with raises(r"^a\[1\]: expected an extremal.Body"):
        extremal.distance([a, 3], b)
    with raises("^a: an empty list of bodies"):
        extremal.distance([], b)
    with raises("^tolerance: must be finite and > 0, got 0"):
        extremal.distance(a, b, pose_b=[3, 0, 0], tolerance=0)
    with raises("^max_cells: only with signed=True"):
        extremal.distance(a, b, pose_b=[3, 0, 0], max_cells=10)


def test_trackers_name_their_arguments():
    a, b = extremal.sphere(1.0), extremal.sphere(0.5)
    with raises("^gain: must be finite and >= 0"):
        extremal.Tracker(a, b, gain=-1)
    with raises("^integrator: expected 'euler' or 'rk4', got 'leapfrog'"):
        extremal.Tracker(a, b, integrator="leapfrog")
    with raises("^threshold: must be finite and > 0"):
        extremal.Tracker(a, b, threshold=0.0)
    tracker = extremal.Tracker(a, b)
    with raises("^dt: must be finite and > 0, got -0.1"):
        tracker.step(0.0, None, None, [3, 0, 0], None, -0.1)
    with raises(r"^twist_b: expected 6 numbers \(vx, vy, vz, wx, wy, wz\), got shape \(3,\)"):
        tracker.step(0.0, None, None, [3, 0, 0], [1, 0, 0], 0.01)
    with raises(r"^pairs\[0\]: body index out of range \(2 bodies\)"):
        extremal.SceneTracker([a, b], [(0, 2)])
    with raises(r"^pairs\[0\]\[1\]: no body named 'C'"):
        extremal.SceneTracker([a, b], [("sphere", "C")])
    with raises("^pairs: no pair of bodies to watch"):
        extremal.SceneTracker([a, b], [])
    with raises("^bodies: a scene needs at least two bodies"):
        extremal.SceneTracker([a], "all")


def test_bad_steps_leave_a_tracker_as_it_was():
    a, b = extremal.sphere(1.0), extremal.sphere(0.5)
    times = np.arange(5) * 0.1
    poses_b = np.array([[4 - t, 0, 0, 1, 0, 0, 0] for t in times])
    bad = poses_b.copy()
    bad[3, 3:] = 0.0  # a zero quaternion at the fourth step
    still = np.tile([0.0, 0, 0, 1, 0, 0, 0], (5, 1))
    tracker, fresh = extremal.Tracker(a, b), extremal.Tracker(a, b)
    with raises(r"^poses\[3\]\[1\]: .*quaternion"):
        tracker.track(times, still, bad)
    with raises(r"^times\[2\]: times must increase"):
        tracker.track([0, 0.1, 0.1], still[:3], poses_b[:3])
    with raises(r"^poses: expected shape \(5, 2, 7\)"):
        extremal.SceneTracker([a, b]).track(times, np.zeros((5, 3, 7)))
    np.testing.assert_array_equal(tracker.track(times, still, poses_b)["params"],
                                  fresh.track(times, still, poses_b)["params"])


def test_scene_errors_are_the_commands(cli, tmp_path):
    # An unknown key, a missing file, a bad pose table row: the message names the scene file
    # and the JSON path (or the file and line), word for word as `extremal report` says it.
    good_body = {"name": "A", "shape": {"type": "sphere", "radius": 1}}
    cases = {
        "key.json": {"time": {"end": 1, "step": 0.1},
                     "bodies": [good_body, {"name": "B", "shape": {"type": "sphere", "radius": 1},
                                            "colour": "red"}]},
        "file.json": {"time": {"end": 1, "step": 0.1},
                      "bodies": [good_body, {"name": "B", "file": "missing.step"}]},
        "table.json": {"time": {"end": 1, "step": 0.1},
                       "bodies": [good_body, {"name": "B", "shape": {"type": "point"},
                                              "motion": {"type": "table", "file": "poses.csv"}}]},
    }
    (tmp_path / "poses.csv").write_text("t,x,y,z,qw,qx,qy,qz\n0,3,0,0,1,0,0,0\n1,3,0,0,1,0,0\n")
    expected = {"key.json": "bodies[1].colour", "file.json": "bodies[1].file",
                "table.json": "poses.csv:3"}
    for name, scene in cases.items():
        path = write_scene(tmp_path / name, scene)
        with raises(str(path)) as e:
            extremal.report(path)
        assert expected[name] in str(e.value)
        code, _, err = cli("report", path, "--quiet")
        assert code == 1 and err.strip() == "extremal report: " + str(e.value)
    with raises(str(tmp_path / "none.json")):
        extremal.report(tmp_path / "none.json")
    with raises("^scene: expected a path"):
        extremal.report(7)
