"""Bodies and the certified one-shot distance: shapes, a STEP part, known answers (two spheres
in closed form, the box of pr2ct.stp), and the same answers as `extremal distance`."""

import math

import numpy as np
import pytest

import extremal


def quaternion(axis, angle):
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    return [math.cos(angle / 2), *(math.sin(angle / 2) * axis)]


def spec(numbers):
    return ",".join(repr(float(x)) for x in numbers)


def test_shapes_give_bodies():
    s = extremal.sphere(2.0)
    assert (s.name, s.face_count, s.curve_count, s.is_point) == ("sphere", 1, 0, False)
    np.testing.assert_allclose(s.bbox(), [[-2, -2, -2], [2, 2, 2]], atol=1e-9)
    e = extremal.ellipsoid(3, 2, 1.5, name="A")
    assert e.name == "A" and e.face_kinds == ["ellipsoid"]
    np.testing.assert_allclose(e.bbox(), [[-3, -2, -1.5], [3, 2, 1.5]], atol=1e-9)
    np.testing.assert_allclose(extremal.torus(3, 1).bbox(), [[-4, -4, -1], [4, 4, 1]], atol=1e-9)
    c = extremal.cylinder(1, 4)
    assert c.face_count == 3  # the side and two caps
    np.testing.assert_allclose(c.bbox(), [[-1, -1, 0], [1, 1, 4]], atol=1e-9)
    np.testing.assert_allclose(extremal.plane(2, 3).bbox(), [[-1, -1.5, 0], [1, 1.5, 0]], atol=1e-12)
    p = extremal.point()
    assert p.is_point and p.face_count == 0
    np.testing.assert_array_equal(s.placement, [0, 0, 0, 1, 0, 0, 0])


def test_read_model_reads_a_step_box(shared_data):
    m = extremal.read_model(shared_data / "step" / "pr2ct.stp")
    assert m.format.startswith("STEP") and m.unit == "mm" and m.file_unit == "millimetre"
    assert len(m) == 1 and m[0] is m.bodies[0] and [b.name for b in m] == [m[0].name]
    box = m[0]
    assert box.face_count == 6 and box.edge_count == 12
    assert box.face_kinds == ["plane"] * 6
    np.testing.assert_allclose(box.bbox(), [[0, 0, 0], [200, 200, 200]], atol=1e-6)
    # The same file in centimetres: lengths a tenth.
    cm = extremal.read_model(shared_data / "step" / "pr2ct.stp", units="cm")
    np.testing.assert_allclose(cm[0].bbox(), [[0, 0, 0], [20, 20, 20]], atol=1e-7)


@pytest.mark.parametrize("ra, rb, ca, cb", [
    (1.0, 0.5, [0, 0, 0], [3, 0, 0]),
    (2.0, 0.7, [1, -2, 0.5], [4.5, 1.25, -3]),
    (0.3, 5.0, [-10, 4, 2], [-10, 4, 9]),
])
def test_two_spheres_in_closed_form(ra, rb, ca, cb):
    ca, cb = np.array(ca, float), np.array(cb, float)
    # Turned frames: the answer is the same for balls about their origins.
    pose_a = [*ca, *quaternion([1, 2, 3], 0.7)]
    pose_b = [*cb, *quaternion([-1, 0, 2], 2.1)]
    r = extremal.distance(extremal.sphere(ra), extremal.sphere(rb), pose_a, pose_b, tolerance=1e-12)
    u = (cb - ca) / np.linalg.norm(cb - ca)
    d = np.linalg.norm(cb - ca) - ra - rb
    assert r.status == "converged" and r.certified
    assert r.distance == pytest.approx(d, abs=1e-11)
    assert r.lower_bound <= d + 1e-12 and r.upper_bound >= d - 1e-12
    assert r.upper_bound - r.lower_bound <= 1e-12 + 1e-15 * abs(d)
    np.testing.assert_allclose(r.point_a, ca + ra * u, atol=1e-6)
    np.testing.assert_allclose(r.point_b, cb - rb * u, atol=1e-6)
    np.testing.assert_allclose(r.normal, u, atol=1e-6)
    np.testing.assert_allclose(r.point_b - r.point_a, r.distance * r.normal, atol=1e-9)
    assert (r.face_a, r.face_b) == (0, 0) and (r.body_a, r.body_b) == ("sphere", "sphere")
    assert r.element_a["kind"] == "face" and not r.signed and r.overlap is None


def test_overlapping_spheres_read_zero_or_their_depth():
    a, b = extremal.sphere(1.0), extremal.sphere(0.5)
    plain = extremal.distance(a, b, pose_b=(1.2, 0.0, 0.0))
    assert plain.status == "intersecting" and plain.distance == 0.0
    s = extremal.distance(a, b, pose_b=(1.2, 0.0, 0.0), signed=True)
    # Convex bodies: minus the minimum translation distance, 1 + 0.5 - 1.2.
    assert s.status == "penetrating" and s.overlap == "surfaces_meet" and s.depth == "translation"
    assert s.distance == pytest.approx(-0.3, abs=1e-8)
    assert s.lower_bound <= -0.3 + 1e-12 <= s.upper_bound + 2e-12
    np.testing.assert_allclose(s.normal, [1, 0, 0], atol=1e-6)
    assert s.closed_a and s.closed_b
    # A ball inside another: the winding number finds it.
    inner = extremal.distance(extremal.sphere(5.0), b, pose_b=(1, 1, 0), signed=True)
    assert inner.overlap == "b_inside_a"
    assert inner.distance == pytest.approx(math.sqrt(2) - 5.5, abs=1e-8)
    # Apart, signed or not, the same certified distance.
    apart = extremal.distance(a, b, pose_b=(3, 0, 0), signed=True)
    assert apart.status == "converged" and apart.overlap == "none" and apart.depth is None
    assert apart.distance == pytest.approx(1.5, abs=1e-9)


def test_the_step_box_against_a_ball_in_closed_form(shared_data):
    box = extremal.read_model(shared_data / "step" / "pr2ct.stp")
    ball = extremal.sphere(10.0)
    # Across the +x face, then across the edge x = y = 200.
    r = extremal.distance(box, ball, pose_b=(250, 100, 120))
    assert r.status == "converged" and r.distance == pytest.approx(40.0, abs=1e-9)
    np.testing.assert_allclose(r.point_a, [200, 100, 120], atol=1e-6)
    np.testing.assert_allclose(r.point_b, [240, 100, 120], atol=1e-6)
    np.testing.assert_allclose(r.normal, [1, 0, 0], atol=1e-9)
    assert r.body_a == box[0].name
    e = extremal.distance(box, ball, pose_b=(230, 240, 100))
    assert e.distance == pytest.approx(40.0, abs=1e-9)  # sqrt(30^2 + 40^2) - 10
    np.testing.assert_allclose(e.point_a, [200, 200, 100], atol=1e-6)
    # The box moved: its pose places the file's frame.
    moved = extremal.distance(box, ball, pose_a=(-50, 0, 0), pose_b=(250, 100, 120))
    assert moved.distance == pytest.approx(90.0, abs=1e-9)
    # A ball through the +x face at x = 190 leaves the box's hull after 200 - 190 + 30 = 40.
    s = extremal.distance(box, extremal.sphere(30.0), pose_b=(190, 100, 120), signed=True)
    assert s.status == "penetrating" and s.overlap == "surfaces_meet" and s.depth == "hull"
    assert s.distance == pytest.approx(-40.0, abs=1e-9)
    np.testing.assert_allclose(s.normal, [1, 0, 0], atol=1e-6)


def test_a_model_of_two_solids_is_a_set(shared_data):
    path = shared_data / "step" / "bug24283_spheres.stp"
    model = extremal.read_model(path)
    assert len(model) == 2
    probe = np.array([3.0, 2.5, -1.0])
    centres = [np.array(b.placement[:3]) for b in model]
    gaps = [np.linalg.norm(probe - c) - 1.0 - 0.25 for c in centres]
    r = extremal.distance(model, extremal.sphere(0.25), pose_b=probe)
    assert r.distance == pytest.approx(min(gaps), abs=1e-9)
    assert r.body_a == model[int(np.argmin(gaps))].name
    # The same as a list of its bodies.
    assert extremal.distance(list(model), extremal.sphere(0.25), pose_b=probe).distance == r.distance


def test_the_same_answers_as_the_command(shared_data, cli_json):
    # The seed's ellipsoids, turned, and a STEP part with curved faces: the command's certified
    # solver and the module's are one, so the answers are the same numbers.
    pose_a = [0.3, -0.2, 0.1, *quaternion([1, 2, 3], 0.7)]
    pose_b = [6.5, 1.0, 0.5, *quaternion([-1, 0, 2], 2.1)]
    j = cli_json("distance", "ellipsoid:3,2,1.5", "ellipsoid:2,1.2,1", "--pose-a", spec(pose_a),
                 "--pose-b", spec(pose_b), "--tolerance", "1e-12")
    r = extremal.distance(extremal.ellipsoid(3, 2, 1.5), extremal.ellipsoid(2, 1.2, 1), pose_a,
                          pose_b, tolerance=1e-12)
    assert j["status"] == r.status == "converged"
    for key in ("distance", "lower_bound", "upper_bound"):
        assert getattr(r, key) == j[key]
    for key in ("point_a", "point_b", "normal"):
        np.testing.assert_array_equal(getattr(r, key), j[key])
    assert (r.face_a, r.face_b) == (j["face_a"], j["face_b"])

    screw = shared_data / "step" / "screw.step"
    pose_b = [-18.0, 0.5, 15.0]
    j = cli_json("distance", screw, "sphere:2", "--pose-b", spec(pose_b))
    # `extremal distance` reads files with a 1e-9 trim band.
    r = extremal.distance(extremal.read_model(screw, trim_tolerance=1e-9), extremal.sphere(2.0),
                          pose_b=pose_b)
    assert r.distance == j["distance"] and r.status == j["status"]
    assert r.body_a == j["body_a"] and r.element_a["kind"] == j["element_a"]["kind"]
    np.testing.assert_array_equal(r.point_a, j["point_a"])
    assert 0 < r.distance < 10

    s = cli_json("distance", "ellipsoid:3,2,1.5", "sphere:1", "--pose-b", "3.5,0.5,0", "--signed")
    r = extremal.distance(extremal.ellipsoid(3, 2, 1.5), extremal.sphere(1), pose_b=(3.5, 0.5, 0),
                          signed=True)
    assert r.distance == s["distance"] < 0 and r.overlap == s["overlap"] and r.depth == s["depth"]
