"""Trackers stepped from Python: two spheres in closed form through contact, the seed's
ellipsoids against the certified solver at every step, a STEP body placed in its file, and a
scene of three bodies, stepped one call a step and many steps a call."""

import math

import numpy as np
import pytest

import extremal


def qmul(p, q):
    w1, x1, y1, z1 = p
    w2, x2, y2, z2 = q
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def turned(q0, w, t):
    """The quaternion of exp([w]x t) R(q0): a frame turning at the world angular velocity w."""
    w = np.asarray(w, float)
    angle = np.linalg.norm(w) * t
    if angle == 0:
        return np.asarray(q0, float)
    axis = w / np.linalg.norm(w)
    return qmul([math.cos(angle / 2), *(math.sin(angle / 2) * axis)], q0)


def rotation(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


# The demo's ellipsoids A (3, 2, 1.5) and B (2, 1.2, 1): both turning, B drifting towards A.
QA = [0.9233805169, 0.1025978352, 0.3077935056, 0.2051956704]
QB = [0.8677218313, -0.2169304578, 0.1084652289, 0.4338609156]
WA, WB = [0.2, -0.1, 0.3], [-0.1, 0.3, 0.2]
PB, VB = np.array([7.5, 1, 0.5]), np.array([-0.35, 0.1, 0.05])


def ellipsoid_motion(t):
    pose_a = np.array([0, 0, 0, *turned(QA, WA, t)])
    pose_b = np.array([*(PB + VB * t), *turned(QB, WB, t)])
    return pose_a, np.array([0, 0, 0, *WA]), pose_b, np.array([*VB, *WB])


def test_two_spheres_through_contact_in_closed_form():
    tracker = extremal.Tracker(extremal.sphere(1.0), extremal.sphere(0.5))
    dt, statuses = 0.01, set()
    for k in range(161):
        t = k * dt
        centre = np.array([4 - 2 * t, 1.0, 0.0])  # B moves at -2 along x, spinning about z
        r = tracker.step(t, None, None, [*centre, *turned([1, 0, 0, 0], [0, 0, 1], t)],
                         [-2, 0, 0, 0, 0, 1], dt)
        u = centre / np.linalg.norm(centre)
        d = np.linalg.norm(centre) - 1.5
        assert r.time == t
        assert r.distance == pytest.approx(d, abs=1e-12), t
        np.testing.assert_allclose(r.point_a, u, atol=1e-9)
        np.testing.assert_allclose(r.point_b, centre - 0.5 * u, atol=1e-9)
        np.testing.assert_allclose(r.normal, u, atol=1e-9)
        assert (r.face_a, r.face_b) == (0, 0) and not r.solved
        assert r.status == ("penetrating" if d < -1e-9 else "tracking" if d > 1e-9 else "contact")
        statuses.add(r.status)
    assert statuses == {"tracking", "penetrating"}


def test_the_seeds_ellipsoids_against_the_certified_solver():
    A, B = extremal.ellipsoid(3, 2, 1.5), extremal.ellipsoid(2, 1.2, 1)
    tracker = extremal.Tracker(A, B, gain=100)
    dt, worst = 0.01, 0.0
    for k in range(120):
        t = k * dt
        pose_a, twist_a, pose_b, twist_b = ellipsoid_motion(t)
        r = tracker.step(t, pose_a, twist_a, pose_b, twist_b, dt)
        ref = extremal.distance(A, B, pose_a, pose_b, tolerance=1e-11)
        assert ref.certified
        assert ref.lower_bound - 1e-9 <= r.distance <= ref.upper_bound + 1e-9, t
        worst = max(worst, abs(r.distance - ref.distance))
        # The witnesses lie on the ellipsoids, d along the normal.
        for p, pose, axes in ((r.point_a, pose_a, (3, 2, 1.5)), (r.point_b, pose_b, (2, 1.2, 1))):
            local = rotation(pose[3:]).T @ (p - pose[:3])
            assert np.sum((local / axes) ** 2) == pytest.approx(1.0, abs=1e-9)
        np.testing.assert_allclose(r.point_b - r.point_a, r.distance * r.normal, atol=1e-9)
    assert worst < 1e-9  # 2.2e-15 measured


def test_a_step_body_sits_where_its_file_places_it(shared_data):
    # bug24283_spheres.stp: two unit spheres, the second placed off the file's origin. Turning
    # the file's frame about z carries that sphere round a circle; its twist is the frame's.
    model = extremal.read_model(shared_data / "step" / "bug24283_spheres.stp")
    far = model[1]
    c0 = np.array(far.placement[:3])
    assert np.linalg.norm(c0) > 1
    probe = np.array([4.0, -1.0, 0.5])
    tracker = extremal.Tracker(far, extremal.sphere(0.5))
    w, dt = np.array([0, 0, 2.0]), 0.005
    for k in range(200):
        t = k * dt
        q = turned([1, 0, 0, 0], w, t)
        centre = rotation(q) @ c0
        r = tracker.step(t, [0, 0, 0, *q], [0, 0, 0, *w], probe, None, dt)
        assert r.distance == pytest.approx(np.linalg.norm(probe - centre) - 1.5, abs=1e-8), t
        np.testing.assert_allclose(r.point_a, centre + (probe - centre) / np.linalg.norm(probe - centre),
                                   atol=1e-6)


def test_a_scene_tracker_steps_its_pairs_as_trackers_do():
    bodies = [extremal.ellipsoid(3, 2, 1.5, name="A"), extremal.ellipsoid(2, 1.2, 1, name="B"),
              extremal.sphere(0.8, name="C")]
    scene = extremal.SceneTracker(bodies, "all", gain=100)
    assert scene.pairs == [(0, 1), (0, 2), (1, 2)]
    named = extremal.SceneTracker(bodies, [("A", "C"), (1, 2)])
    assert named.pairs == [(0, 2), (1, 2)]
    steps, dt = 60, 0.01
    times = np.arange(steps) * dt
    poses = np.zeros((steps, 3, 7))
    twists = np.zeros((steps, 3, 6))
    for i, t in enumerate(times):
        pa, va, pb, vb = ellipsoid_motion(t)
        poses[i] = [pa, pb, [-1.0 + 0.5 * t, -4.0, 0.2, 1, 0, 0, 0]]
        twists[i] = [va, vb, [0.5, 0, 0, 0, 0, 0]]
    out = scene.track(times, poses, twists)
    assert out["distance"].shape == (steps, 3) and out["point_a"].shape == (steps, 3, 3)
    assert out["params"].shape == (steps, 3, 4) and out["status"].shape == (steps, 3)
    np.testing.assert_array_equal(out["time"], times)
    # One Tracker per pair, stepped one call a step with track's steps (the times' intervals,
    # the last one again): the same numbers.
    dts = [*np.diff(times), times[-1] - times[-2]]
    for k, (a, b) in enumerate(scene.pairs):
        tracker = extremal.Tracker(bodies[a], bodies[b], gain=100)
        for i, t in enumerate(times):
            r = tracker.step(t, poses[i, a], twists[i, a], poses[i, b], twists[i, b], dts[i])
            assert r.distance == out["distance"][i, k]
            np.testing.assert_array_equal(r.point_a, out["point_a"][i, k])
            np.testing.assert_array_equal(r.params, out["params"][i, k])
            assert (r.status, r.face_b, r.solved) == (out["status"][i, k], out["face_b"][i, k],
                                                      out["solved"][i, k])
    assert set(out["status"].ravel()) <= {"tracking", "boundary"}
    # And step() on the scene: a PairReport per pair.
    again = extremal.SceneTracker(bodies, "all", gain=100)
    reports = again.step(times[0], poses[0], twists[0], dts[0])
    assert [r.distance for r in reports] == list(out["distance"][0])


def test_track_of_a_pair_gives_columns():
    tracker = extremal.Tracker(extremal.sphere(1.0), extremal.sphere(0.5))
    times = np.linspace(0.0, 1.0, 11)
    poses_b = np.array([[4 - 2 * t, 1.0, 0.0] for t in times])  # x, y, z: unturned
    twists_b = np.tile([-2.0, 0, 0, 0, 0, 0], (11, 1))
    out = tracker.track(times, np.zeros((11, 3)), poses_b, None, twists_b)
    assert out["distance"].shape == (11,) and out["point_b"].shape == (11, 3)
    np.testing.assert_allclose(out["distance"], np.linalg.norm(poses_b, axis=1) - 1.5, atol=1e-12)
    assert list(out["status"]) == ["tracking"] * 11 and list(out["degeneracy"]) == [""] * 11


def test_a_threshold_reports_far_pairs_as_farther():
    tracker = extremal.Tracker(extremal.sphere(1.0), extremal.sphere(1.0), threshold=2.0)
    far = tracker.step(0.0, None, None, [10, 0, 0], [-10, 0, 0, 0, 0, 0], 0.5)
    assert far.status == "farther" and 0 < far.distance <= 8.0
    near = tracker.step(0.5, None, None, [3.5, 0, 0], [-10, 0, 0, 0, 0, 0], 0.01)
    assert near.status == "tracking" and near.distance == pytest.approx(1.5, abs=1e-9)


def test_trackers_read_like_a_scene_report(tmp_path):
    # The same two bodies and motions as a scene file: Python's poses are the scene's motion to
    # rounding, so the rows agree to rounding.
    from conftest import write_scene
    scene = write_scene(tmp_path / "ellipsoids.json", {
        "time": {"start": 0, "end": 1.0, "step": 0.01},
        "bodies": [
            {"name": "A", "shape": {"type": "ellipsoid", "axes": [3, 2, 1.5]},
             "pose": {"position": [0, 0, 0], "quaternion": QA},
             "motion": {"type": "twist", "angular_velocity": WA}},
            {"name": "B", "shape": {"type": "ellipsoid", "axes": [2, 1.2, 1]},
             "pose": {"position": list(PB), "quaternion": QB},
             "motion": {"type": "twist", "velocity": list(VB), "angular_velocity": WB}}],
        "tracker": {"gain": 100}})
    rep = extremal.report(scene)
    tracker = extremal.Tracker(extremal.ellipsoid(3, 2, 1.5), extremal.ellipsoid(2, 1.2, 1), gain=100)
    for i, t in enumerate(rep.t):
        r = tracker.step(t, *ellipsoid_motion(t), 0.01)
        assert r.distance == pytest.approx(rep.distance[i], abs=1e-10)
        assert r.status == rep.status[i] and r.face_a == rep.face_a[i]
