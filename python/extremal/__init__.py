"""Extremal from Python: exact distances between moving NURBS bodies.

Bodies come from CAD and mesh files (read_model) or shapes (sphere, ellipsoid, torus, cylinder,
plane, point). distance() is the certified one-shot distance of `extremal distance`; Tracker
and SceneTracker keep the extremal pair up to date while Python moves the bodies; report() runs
a scene file as `extremal report` does. extremal.batch runs a batch of scenes on a Dask cluster
(it is the only part that imports Dask).

Points are NumPy arrays in world coordinates; a pose is (x, y, z, qw, qx, qy, qz), the body
frame's placement in the world (unit quaternion, w first), or (x, y, z); a twist is (vx, vy, vz,
wx, wy, wz), the world-frame velocity of the frame's origin and its angular velocity, as in the
scene files. Lengths are in the bodies' unit (millimetres unless read otherwise), times in
seconds. Bad input raises extremal.InvalidInput (a ValueError) naming the file, key or argument.
Heavy calls release the GIL. A tracker is not shared between threads: give each its own.

docs/python.md has the whole API with examples.
"""

import json as _json
import os as _os

import numpy as _np

from . import _core
from ._core import (
    Body,
    DistanceResult,
    InvalidInput,
    Model,
    PairReport,
    PreconditionViolation,
    SceneTracker,
    Tracker,
    cylinder,
    distance,
    ellipsoid,
    plane,
    point,
    read_model,
    sphere,
    torus,
)

__version__ = _core.__version__

__all__ = [
    "Body",
    "DistanceResult",
    "InvalidInput",
    "Model",
    "PairReport",
    "PreconditionViolation",
    "Report",
    "SceneTracker",
    "Tracker",
    "cylinder",
    "distance",
    "ellipsoid",
    "plane",
    "point",
    "read_model",
    "report",
    "sphere",
    "torus",
]


class Report:
    """A scene's report, as `extremal report SCENE -o OUT.json` writes it.

    columns: the numeric columns of the CSV, each a NumPy array with one value per row
        (t, distance, ax, ay, az, bx, by, bz, nx, ny, nz as float64; face_a, face_b as int64;
        ua, va, ub, vb, lower_bound as float64; lower_bound is NaN where a row has none: in
        contact or overlapping), also readable as attributes (report.distance) or by
        indexing (report["distance"]).
    body_a, body_b, status, detail: lists of str, one per row.
    summary: dict keyed by (body_a, body_b), one per watched pair: rows, tracked_rows,
        min_distance, min_time, contact, penetration, farther (lists of {"start", "end"}),
        deepest_penetration, deepest_time (None where the pair has none), step_time_us
        ({mean, median, p99, max}: the pair's step times in microseconds, nearest rank, its
        audits excluded), audit_time_us (the same of its audits' times: 0 without audits).
    step_time_us: the scene's step times, {mean, median, p99, max} in microseconds (a step's
        time is the sum of its pairs'), audits excluded; audit_time_us: the audits' times.
    scene, units, time ({start, end, step, steps}), bodies (list of {name, shape | file}),
    pairs (list of (body_a, body_b)).

    Rows are those of the command: a pair beyond the scene's threshold has one 'farther' row
    when it goes there, then none until it comes back; with every=N, the rows of the steps k
    with k % N == 0 and of the last step only (the summary covers every step).
    """

    NUMERIC = ("t", "distance", "ax", "ay", "az", "bx", "by", "bz", "nx", "ny", "nz",
               "face_a", "face_b", "ua", "va", "ub", "vb", "lower_bound")

    def __init__(self, data):
        rows = data["rows"]
        self.scene = data["scene"]
        self.units = data["units"]
        self.time = data["time"]
        self.bodies = data["bodies"]
        self.pairs = [tuple(p) for p in data["pairs"]]

        def floats(values):
            return _np.array([_np.nan if v is None else v for v in values], dtype=_np.float64)

        columns = {"t": floats(r["t"] for r in rows), "distance": floats(r["distance"] for r in rows)}
        for key, names in (("point_a", "ax ay az"), ("point_b", "bx by bz"), ("normal", "nx ny nz")):
            for c, name in enumerate(names.split()):
                columns[name] = floats(r[key][c] for r in rows)
        columns["face_a"] = _np.array([r["face_a"] for r in rows], dtype=_np.int64)
        columns["face_b"] = _np.array([r["face_b"] for r in rows], dtype=_np.int64)
        for c, name in enumerate(("ua", "va", "ub", "vb")):
            columns[name] = floats(r["params"][c] for r in rows)
        columns["lower_bound"] = floats(r["lower_bound"] for r in rows)
        self.columns = {name: columns[name] for name in self.NUMERIC}
        self.body_a = [r["body_a"] for r in rows]
        self.body_b = [r["body_b"] for r in rows]
        self.status = [r["status"] for r in rows]
        self.detail = [r["detail"] for r in rows]
        self.summary = {(s["body_a"], s["body_b"]): s for s in data["summary"]}
        self.step_time_us = data["step_time_us"]
        self.audit_time_us = data["audit_time_us"]

    def __len__(self):
        return len(self.status)

    def __getitem__(self, name):
        return self.columns[name]

    def __getattr__(self, name):
        columns = self.__dict__.get("columns", {})
        if name in columns:
            return columns[name]
        raise AttributeError(f"'Report' object has no attribute {name!r}")

    def __repr__(self):
        return f"<extremal.Report {self.scene!r}: {len(self)} rows, {len(self.pairs)} pairs>"


def report(scene, threads=1, every=1):
    """Runs a scene file (JSON, docs/cli.md) as `extremal report` does and returns its
    Report: the same rows and summary the command writes. threads: the pairs run on this many
    threads (the rows do not depend on it). every: as the command's --every, the rows of every
    N-th step and of the last step only, an integer >= 1 (the summary covers every step).
    Raises extremal.InvalidInput naming the scene file and the JSON path of a bad key, or the
    file that cannot be read. The GIL is released while it runs."""
    try:
        path = _os.fspath(scene)
    except TypeError:
        path = None
    if not isinstance(path, str):
        raise InvalidInput(f"scene: expected a path (str or os.PathLike), got {type(scene).__name__}")
    if isinstance(every, bool) or not isinstance(every, int) or every < 1:
        raise InvalidInput(f"every: must be an integer >= 1, got {every!r}")
    return Report(_json.loads(_core._report_json(path, threads, every)))
