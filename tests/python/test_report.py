"""extremal.report: the rows and summary `extremal report` writes, as NumPy columns, lists of
str and a dict."""

import csv
import json

import numpy as np
import pytest

import extremal
from conftest import SOURCE_DIR, write_scene

DEMO = SOURCE_DIR / "data" / "demo" / "demo.json"


def command_report(cli, scene, out):
    code, _, err = cli("report", scene, "-o", out, "--quiet")
    assert code == 0, err
    return out


def test_the_demo_reads_as_the_command_writes_it(cli, tmp_path):
    rep = extremal.report(DEMO)
    data = json.loads(command_report(cli, DEMO, tmp_path / "demo.json").read_text())
    rows = data["rows"]
    assert len(rep) == len(rows) == 2 * 601
    assert rep.scene == str(DEMO) and rep.units == "mm" and rep.time == data["time"]
    assert rep.pairs == [("A", "B"), ("A", "bracket")]
    assert list(rep.columns) == list(extremal.Report.NUMERIC)
    np.testing.assert_array_equal(rep.t, [r["t"] for r in rows])
    np.testing.assert_array_equal(rep["distance"], [r["distance"] for r in rows])
    np.testing.assert_array_equal(np.stack([rep.ax, rep.ay, rep.az], 1), [r["point_a"] for r in rows])
    np.testing.assert_array_equal(np.stack([rep.nx, rep.ny, rep.nz], 1), [r["normal"] for r in rows])
    np.testing.assert_array_equal(np.stack([rep.ua, rep.va, rep.ub, rep.vb], 1),
                                  [r["params"] for r in rows])
    assert rep.face_b.dtype == np.int64 and list(rep.face_b) == [r["face_b"] for r in rows]
    assert rep.body_b == [r["body_b"] for r in rows] and rep.status == [r["status"] for r in rows]
    assert rep.detail == [r["detail"] for r in rows]
    # The same summaries but for the step times, which differ from run to run.
    def timeless(summary):
        return {k: v for k, v in summary.items() if not k.endswith("time_us")}
    assert {k: timeless(s) for k, s in rep.summary.items()} == \
        {(s["body_a"], s["body_b"]): timeless(s) for s in data["summary"]}
    for times in [rep.step_time_us] + [s["step_time_us"] for s in rep.summary.values()]:
        assert 0 <= times["median"] <= times["p99"] <= times["max"] and times["mean"] <= times["max"]
    # README: A - bracket is in contact from t = 2.82 s and penetrates at most 0.080 mm.
    s = rep.summary[("A", "bracket")]
    assert s["contact"] and 2.7 < s["contact"][0]["start"] < 2.9
    assert 0.07 < s["deepest_penetration"] < 0.09
    assert min(d for d, b in zip(rep.distance, rep.body_b) if b == "bracket") < 0
    # The CSV's numbers are the same doubles (17 digits).
    with open(command_report(cli, DEMO, tmp_path / "demo.csv"), newline="") as f:
        table = list(csv.DictReader(f))
    for name in ("t", "distance", "bx", "nz", "vb"):
        np.testing.assert_array_equal(rep[name], [float(r[name]) for r in table])
    assert rep.status == [r["status"] for r in table] and rep.detail == [r["detail"] for r in table]


def test_a_pair_beyond_the_threshold_has_one_farther_row(cli, tmp_path):
    # B passes A and leaves: beyond the threshold it gets one 'farther' row when it goes there.
    scene = write_scene(tmp_path / "pass.json", {
        "time": {"start": 0, "end": 2, "step": 0.02},
        "bodies": [
            {"name": "A", "shape": {"type": "sphere", "radius": 1}},
            {"name": "B", "shape": {"type": "sphere", "radius": 0.5},
             "pose": {"position": [-6, 1.8, 0]},
             "motion": {"type": "twist", "velocity": [6, 0, 0]}}],
        "threshold": 2})
    rep = extremal.report(scene, threads=2)
    assert rep.status.count("farther") == 2  # once going out of reach at the start, once leaving
    assert rep.status[0] == "farther" and rep.status[-1] == "farther"
    steps = 101
    assert len(rep) < steps
    s = rep.summary[("A", "B")]
    assert s["rows"] == steps and s["tracked_rows"] == len(rep) - 2
    assert abs(s["min_distance"] - 0.3) < 1e-9 and abs(s["min_time"] - 1.0) < 1e-9
    assert s["farther"] and s["contact"] == [] and s["deepest_penetration"] is None
    data = json.loads(command_report(cli, scene, tmp_path / "command.json").read_text())
    assert rep.status == [r["status"] for r in data["rows"]]
    np.testing.assert_array_equal(rep.distance, [r["distance"] for r in data["rows"]])


def test_every_writes_every_nth_steps_rows_and_summarises_them_all(cli, tmp_path):
    # 601 steps, every 7th: steps 0, 7, ..., 595 (86 of them) and the last, 600.
    full = extremal.report(DEMO)
    rep = extremal.report(DEMO, every=7)
    steps = list(range(0, 601, 7)) + [600]
    t = full.t[::2]  # two pairs a step, in scene order
    np.testing.assert_array_equal(rep.t[::2], t[steps])
    np.testing.assert_array_equal(rep.distance, full.distance.reshape(601, 2)[steps].ravel())

    def timeless(summary):
        return {k: {n: v for n, v in s.items() if not n.endswith("time_us")}
                for k, s in summary.items()}
    assert timeless(rep.summary) == timeless(full.summary)
    data = json.loads(command_report(cli, DEMO, tmp_path / "every.json").read_text())
    assert len(data["rows"]) == len(full)
    code, _, err = cli("report", DEMO, "-o", tmp_path / "every7.json", "--every", 7, "--quiet")
    assert code == 0, err
    assert [r["t"] for r in json.loads((tmp_path / "every7.json").read_text())["rows"]] == list(rep.t)
    for bad in (0, -1, 1.5, True):
        with pytest.raises(extremal.InvalidInput, match="every"):
            extremal.report(DEMO, every=bad)
