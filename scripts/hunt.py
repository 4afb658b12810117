#!/usr/bin/env python3
"""The certificate hunt: seeded random scenes over every body kind, every row checked.

    scripts/hunt.py OUT_DIR --seeds S[,S...] [--count N] [--steps K] [--heavy P]
                    [--hours H] [--occt-samples M] [--timeout T] [--log FILE]
                    [--doctor lower_bound|value|sign]
    scripts/hunt.sh HOURS [SEED]           # the long run (fresh seeds until the time is up)

Each seed S writes N scenes (scene k drawn from random.Random(S * 1000 + k), so a seed and an
index name a scene for good) into OUT_DIR/S/, each of 2 to 4 scene entries drawn from every
body kind the project reads: shape specs (sphere, ellipsoid, torus, cylinder, plane, point),
files written beside the scene (a B-spline curve and a bicubic sheet as OBJ free-form, closed
and open triangle meshes as PLY) and the files of ../shared/data (STEP and IGES solids, open
sheets and face sets, files of several bodies, meshes open and closed). The entries move by
every motion the scene format has (static, twist, keyframes, a pose table), pass near each
other (some through, some apart), and the scene watches all pairs or a list (sometimes an
entry of several bodies with itself), sometimes with a threshold (`farther` rows), audits,
RK4, substeps or a looser error budget. --heavy P: the chance that an entry is one of the
larger parts (a horn of 110 faces, a turbine's shell, a hammer, the as1 assembly, a remeshed
torus, the spider mesh).

Every row of every pair is checked by build/bench/verify_report (--every 1: finite numbers,
lower bounds at or below the reference's upper bound, the separating-plane bound, the sign
against evidence, apart distances, depths where a reference exists; docs/checking.md), each
scene alone under --timeout seconds. Then up to --occt-samples of its apart rows (a seeded
sample) go to build/bench/occt_crosscheck, against OpenCASCADE's BRepExtrema_DistShapeShape.

The log (--log, default OUT_DIR/hunt.log) gets a line per scene and, for each wrong row, its
reproducer: the scene file, t, the pair, the check, what was expected and what the row read,
and the command that replays it. A scene whose check crashes (a signal, or the run threw) or
passes the timeout is logged as such. The last lines sum up: seeds, scenes, pairs, rows checked
per check, wrong rows per class, OpenCASCADE rows. OUT_DIR/summary.json holds the same.
--doctor passes verify_report's self-test on (rows made wrong before they are judged; the
apart rows BRepExtrema sees are the doctored ones): tests/hunt/check_hunt.py shows each way is
caught. Exit code 0 when no row is wrong and nothing crashed, 3 otherwise (timeouts alone: 0, listed).
"""
import argparse
import importlib.util
import json
import math
import os
import random
import signal
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.normpath(os.path.join(ROOT, "..", "shared", "data"))

_spec = importlib.util.spec_from_file_location("probe_scenes", os.path.join(ROOT, "scripts", "probe-scenes.py"))
probe = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(probe)
quat_mul, quat_axis_angle, rotate = probe.quat_mul, probe.quat_axis_angle, probe.rotate
random_unit, random_quat = probe.random_unit, probe.random_quat

# Files of ../shared/data by kind (a file of several bodies is also a compound).
SOLIDS = ["step/screw.step", "step/linkrods.step", "step/pr2ct.stp",
          "iges/OCC8842_cylinder_Ideas.igs", "step/bug28414_bug_toroidal_surface.stp",
          "iges/OCC26138_Torus.igs"]
SHEETS = ["step/OCC26308-Face.stp", "step/bug29478.stp", "obj/mesh.source.OBJMeshReader.nurbs.obj"]
COMPOUNDS = ["step/bug24283_spheres.stp", "iges/BUC50025.igs", "step/OCC22459-TEST2.stp"]
MESHES = ["mesh/cube.ply", "mesh/cube_binary.ply", "mesh/shape.stl", "mesh/sphereWithHole.stl"]
HEAVY = ["step/bug27693_cornetta-step.stp", "step/ec_turbine-A.stp", "iges/hammer.iges",
         "step/as1-oc-214-mat.stp", "mesh/mesh.modifier.PGPRemesh.torus.ply",
         "mesh/Spider_binary.stl"]
# Generated beside the scene: (kind, writer below).
GENERATED = ["curve", "sheet_obj", "closed_mesh", "convex_mesh", "open_mesh"]
SHAPES = ["sphere", "ellipsoid", "torus", "cylinder", "plane", "point"]
SHAPE_WEIGHTS = [3, 2, 1, 2, 2, 2]  # balls and points have reference depths of their own
# Entries of several bodies paired with themselves only up to this many bodies (the pairs among
# them grow as its square).
MAX_SELF_PAIR_BODIES = 7
# The fewest steps a scene of many pairs is cut to (--rows).
MIN_STEPS = 6

# The checks verify_report runs, and the kind of defect each shows.
CHECK_CLASS = {
    "finite": "NaN", "lower_bound": "false lower bound", "support_plane": "wrong value",
    "apart_sign": "wrong sign", "overlap_sign": "wrong sign",
    "reference_evidence": "reference disagrees with evidence", "apart_value": "wrong value",
    "convex_value": "wrong value", "closed_form_depth": "wrong value",
    "ball_depth": "wrong value", "point_depth": "wrong value", "sheet_plane_depth": "wrong value",
}

_info_cache = {}


def file_info(path, binary):
    """Body count, box centre and half diagonal (file frame) of a file, from `extremal info`."""
    if path not in _info_cache:
        _info_cache[path] = probe.bodies_box(path, binary)
    return _info_cache[path]


# ---- bodies written beside the scene ---------------------------------------------------------

def write_curve(rng, path, size):
    """A cubic B-spline curve (OBJ free-form `curv`), clamped, 5 to 7 control points."""
    n = rng.randint(5, 7)
    pts = [[size * rng.uniform(-1, 1) for _ in range(3)] for _ in range(n)]
    inner = sorted(rng.uniform(0.1, 0.9) for _ in range(n - 4))
    knots = [0.0] * 4 + inner + [1.0] * 4
    with open(path, "w") as f:
        for p in pts:
            f.write("v %r %r %r\n" % tuple(p))
        f.write("cstype bspline\ndeg 3\n")
        f.write("curv 0 1 %s\n" % " ".join(str(i + 1) for i in range(n)))
        f.write("parm u %s\nend\n" % " ".join(repr(k) for k in knots))
    return [0.0, 0.0, 0.0], size * math.sqrt(3)


def write_sheet_obj(rng, path, size):
    """An open bicubic Bezier sheet (OBJ free-form `surf`), a bumpy square of side 2 size."""
    bump = rng.uniform(0.05, 0.6) * size
    with open(path, "w") as f:
        for j in range(4):          # v
            for i in range(4):      # u varies fastest
                x = size * (-1 + 2 * i / 3) + rng.uniform(-0.1, 0.1) * size
                y = size * (-1 + 2 * j / 3) + rng.uniform(-0.1, 0.1) * size
                f.write("v %r %r %r\n" % (x, y, rng.uniform(-bump, bump)))
        f.write("cstype bezier\ndeg 3 3\n")
        f.write("surf 0 1 0 1 %s\n" % " ".join(str(i + 1) for i in range(16)))
        f.write("parm u 0 1\nparm v 0 1\nend\n")
    return [0.0, 0.0, 0.0], size * math.sqrt(2) * 1.1 + bump


def icosphere():
    """The unit icosahedron subdivided once: 42 vertices, 80 triangles, outward."""
    t = (1 + math.sqrt(5)) / 2
    v = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t],
         [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    v = [[x / math.sqrt(1 + t * t) for x in p] for p in v]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    mid = {}

    def midpoint(a, b):
        key = (min(a, b), max(a, b))
        if key not in mid:
            p = [(v[a][i] + v[b][i]) / 2 for i in range(3)]
            n = math.sqrt(sum(x * x for x in p))
            v.append([x / n for x in p])
            mid[key] = len(v) - 1
        return mid[key]

    out = []
    for a, b, c in faces:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    return v, out


def write_ply(path, vertices, triangles):
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                "property float z\nelement face %d\nproperty list uchar int vertex_indices\n"
                "end_header\n" % (len(vertices), len(triangles)))
        for p in vertices:
            f.write("%.9g %.9g %.9g\n" % tuple(p))
        for t in triangles:
            f.write("3 %d %d %d\n" % t)


def write_closed_mesh(rng, path, size, convex):
    """A closed mesh of 80 triangles: an icosphere scaled per axis (convex), or with its
    vertices moved in and out along their rays (star-shaped, not convex)."""
    v, tris = icosphere()
    axes = [size * rng.uniform(0.4, 1.0) for _ in range(3)]
    out = []
    for p in v:
        r = 1.0 if convex else rng.uniform(0.6, 1.0)
        out.append([axes[i] * p[i] * r for i in range(3)])
    write_ply(path, out, tris)
    return [0.0, 0.0, 0.0], math.sqrt(sum(a * a for a in axes))


def write_open_mesh(rng, path, size):
    """An open height field of 6 x 6 cells (72 triangles)."""
    n = 6
    amp = rng.uniform(0.05, 0.5) * size
    v = [[size * (-1 + 2 * i / n), size * (-1 + 2 * j / n), rng.uniform(-amp, amp)]
         for j in range(n + 1) for i in range(n + 1)]
    tris = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            tris += [(a, a + 1, a + n + 2), (a, a + n + 2, a + n + 1)]
    write_ply(path, v, tris)
    return [0.0, 0.0, 0.0], size * math.sqrt(2) + amp


def random_shape(rng, kind, size):
    """A shape entry of about `size`, its box centre and half diagonal (body frame)."""
    s = size
    if kind == "point":
        return {"type": "point"}, [0, 0, 0], 0.0
    if kind == "sphere":
        r = s * rng.uniform(0.2, 1.0)
        return {"type": "sphere", "radius": r}, [0, 0, 0], r * math.sqrt(3)
    if kind == "ellipsoid":
        axes = [s * rng.uniform(0.15, 0.9) for _ in range(3)]
        return {"type": "ellipsoid", "axes": axes}, [0, 0, 0], math.sqrt(sum(a * a for a in axes))
    if kind == "torus":
        major = s * rng.uniform(0.4, 0.9)
        minor = major * rng.uniform(0.15, 0.6)
        r = major + minor
        return {"type": "torus", "major": major, "minor": minor}, [0, 0, 0], math.sqrt(2 * r * r + minor * minor)
    if kind == "cylinder":
        r = s * rng.uniform(0.1, 0.6)
        h = s * rng.uniform(0.4, 1.8)
        return {"type": "cylinder", "radius": r, "height": h}, [0, 0, h / 2], math.sqrt(2 * r * r + h * h / 4)
    w, h = s * rng.uniform(0.6, 2.0), s * rng.uniform(0.6, 2.0)
    return {"type": "plane", "size": [w, h]}, [0, 0, 0], 0.5 * math.sqrt(w * w + h * h)


# ---- scenes -----------------------------------------------------------------------------------

def pick_kind(rng, heavy):
    if heavy > 0 and rng.random() < heavy:
        return "heavy"
    return rng.choices(["shape", "generated", "solid", "sheet", "compound", "mesh"],
                       weights=[5, 3, 3, 2, 2, 2])[0]


def make_entry(rng, out_dir, name, kind, size, binary, heavy):
    """A body entry (no pose or motion yet), its box centre (entry frame), half diagonal, body
    count and what it is (a shape's type, a written file's kind, or the data file's kind)."""
    if kind == "shape":
        shape, centre, radius = random_shape(rng, rng.choices(SHAPES, weights=SHAPE_WEIGHTS)[0], size)
        return {"name": name, "shape": shape}, centre, radius, 1, shape["type"]
    if kind == "generated":
        g = rng.choice(GENERATED)
        ext = "obj" if g in ("curve", "sheet_obj") else "ply"
        fname = "%s.%s.%s" % (name, g, ext)
        path = os.path.join(out_dir, fname)
        s = size * rng.uniform(0.3, 1.0)
        if g == "curve":
            centre, radius = write_curve(rng, path, s)
        elif g == "sheet_obj":
            centre, radius = write_sheet_obj(rng, path, s)
        elif g == "open_mesh":
            centre, radius = write_open_mesh(rng, path, s)
        else:
            centre, radius = write_closed_mesh(rng, path, s, g == "convex_mesh")
        return {"name": name, "file": fname}, centre, radius, 1, g
    files = {"solid": SOLIDS, "sheet": SHEETS, "compound": COMPOUNDS, "mesh": MESHES,
             "heavy": HEAVY}[kind]
    path = os.path.join(DATA, rng.choice(files))
    count, centre, radius = file_info(path, binary)
    return {"name": name, "file": path}, centre, radius, count, kind


def pose_json(q, centre_world, centre_body):
    rc = rotate(q, centre_body)
    return [centre_world[i] - rc[i] for i in range(3)]


def write_scene(rng, out_dir, name, steps, rows, heavy, binary):
    n_entries = rng.choices([2, 3, 4], weights=[4, 4, 2])[0]
    kinds = [pick_kind(rng, heavy) for _ in range(n_entries)]
    # The scene's size: the first file's, else a random one.
    size = None
    entries = []
    for k, kind in enumerate(kinds):
        name_k = "E%d" % k
        if size is None and kind in ("solid", "sheet", "compound", "mesh", "heavy"):
            entry, centre, radius, count, what = make_entry(rng, out_dir, name + "_" + name_k, kind, 1.0,
                                                            binary, heavy)
            size = max(radius, 1e-3)
        else:
            entry, centre, radius, count, what = None, None, None, None, None
        entries.append([kind, entry, centre, radius, count, what])
    if size is None:
        size = rng.choice([1.0, 5.0, 50.0])
    for k, e in enumerate(entries):
        if e[1] is None:
            e[1], e[2], e[3], e[4], e[5] = make_entry(rng, out_dir, name + "_E%d" % k, e[0], size,
                                                      binary, heavy)
        e[1]["name"] = "E%d" % k
    names = ["E%d" % k for k in range(len(entries))]
    counts = [e[4] for e in entries]
    total = sum(counts)
    if rng.random() < 0.5 and total <= 8:
        pairs = "all"
        n_pairs = total * (total - 1) // 2
    else:
        pairs = []
        for i in range(len(names)):
            for j in range(i + 1, len(names)):
                if rng.random() < 0.7 and counts[i] * counts[j] <= 24:
                    pairs.append([names[i], names[j]] if rng.random() < 0.5 else [names[j], names[i]])
            if 2 <= counts[i] <= MAX_SELF_PAIR_BODIES and rng.random() < 0.4:
                pairs.append([names[i], names[i]])
        if not pairs:
            i, j = sorted(sorted(range(len(names)), key=lambda x: counts[x])[:2])
            pairs.append([names[i], names[j]])
        n_pairs = sum(counts[names.index(x)] * counts[names.index(y)] if x != y else
                      counts[names.index(x)] * (counts[names.index(x)] - 1) // 2 for x, y in pairs)
    # Fewer steps for many pairs: about `rows` rows per scene.
    steps = max(MIN_STEPS, min(steps, rows // max(1, n_pairs)))
    start = rng.choice([0.0, 0.0, 0.0, 1.5])
    duration = 2.0
    end = start + duration
    step = duration / (steps - 1)
    bodies = []
    motions = []
    for k, (kind, entry, cb, rb, count, _) in enumerate(entries):
        reach = rb + size
        q0 = random_quat(rng)
        motion = "static" if k == 0 and rng.random() < 0.6 else rng.choice(
            ["static", "twist", "keyframes", "table", "table"])
        # The centre passes the origin (at time tc) on a line missing it by `miss`.
        u = random_unit(rng)
        side = random_unit(rng)
        side = [side[i] - sum(side[j] * u[j] for j in range(3)) * u[i] for i in range(3)]
        ns = math.sqrt(sum(x * x for x in side)) or 1.0
        side = [x / ns for x in side]
        miss = (rng.uniform(0.0, 0.7) if rng.random() < 0.8 else rng.uniform(0.7, 1.1)) * reach
        tc = start + duration * rng.uniform(0.3, 0.7)
        speed = rng.uniform(1.5, 3.5) * reach / duration
        centre_at = lambda t: [miss * side[i] + speed * (t - tc) * u[i] for i in range(3)]
        axis = random_unit(rng)
        rate = rng.uniform(0.0, 2.0)
        if motion == "static":
            c = [rng.uniform(0.0, 0.3) * reach * x for x in random_unit(rng)]
            entry["pose"] = {"position": pose_json(q0, c, cb), "quaternion": q0}
            entry["motion"] = {"type": "static"}
        elif motion == "twist":
            # About the entry's origin: keep the turn's swing of the centre below its box.
            lever = math.sqrt(sum(x * x for x in cb))
            rate = min(rate, 0.5 * max(rb, 1e-9) / max(lever, 1e-9) / duration)
            w = [rate * x for x in axis]
            c0 = centre_at(start)
            p0 = pose_json(q0, c0, cb)
            entry["pose"] = {"position": p0, "quaternion": q0}
            entry["motion"] = {"type": "twist", "velocity": [speed * x for x in u],
                               "angular_velocity": w}
        else:
            if motion == "keyframes":
                times = sorted(set([start] + [start + duration * rng.random() for _ in range(rng.randint(1, 3))] + [end]))
            else:
                times = [start + i * step for i in range(steps)]
            frames = []
            for t in times:
                q = quat_mul(quat_axis_angle(axis, rate * (t - start)), q0)
                if motion == "keyframes":
                    q = quat_mul(quat_axis_angle(random_unit(rng), rng.uniform(0, 0.8)), q)
                frames.append((t, pose_json(q, centre_at(t), cb), q))
            if motion == "keyframes":
                entry["motion"] = {"type": "keyframes", "keyframes": [
                    {"t": t, "position": p, "quaternion": q} for t, p, q in frames]}
            else:
                table = "%s_%s.poses.csv" % (name, entry["name"])
                with open(os.path.join(out_dir, table), "w") as f:
                    f.write("t,x,y,z,qw,qx,qy,qz\n")
                    for t, p, q in frames:
                        f.write("%r,%r,%r,%r,%r,%r,%r,%r\n" % (t, p[0], p[1], p[2], q[0], q[1], q[2], q[3]))
                entry["motion"] = {"type": "table", "file": table}
        bodies.append(entry)
        motions.append(motion)
    scene = {"units": "mm", "time": {"start": start, "end": end, "step": step}, "bodies": bodies,
             "pairs": pairs}
    if rng.random() < 0.2:
        scene["threshold"] = size * rng.uniform(0.1, 1.0)
    tracker = {}
    if rng.random() < 0.2:
        tracker["audit_every"] = rng.randint(3, 15)
    if rng.random() < 0.1:
        tracker["integrator"] = "rk4"
    if rng.random() < 0.1:
        tracker["substeps"] = 2
    if tracker:
        scene["tracker"] = tracker
    if rng.random() < 0.15:
        scene["tolerance"] = {"absolute": 1e-6 * size, "relative": 1e-6}
    path = os.path.join(out_dir, name + ".json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    what = ", ".join(
        "%s %s%s (%s)" % (b["name"], entries[k][5],
                          " " + os.path.basename(b["file"]) if "file" in b else "", motions[k])
        for k, b in enumerate(bodies))
    return path, what, [e[5] for e in entries]


# ---- running the checks -----------------------------------------------------------------------

def run(cmd, timeout):
    """(returncode or 'timeout', stdout, stderr, seconds); the process group is ended on timeout."""
    t0 = time.time()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         start_new_session=True)
    try:
        out, err = p.communicate(timeout=timeout)
        return p.returncode, out, err, time.time() - t0
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, err = p.communicate()
        return "timeout", out, err, time.time() - t0


class Tally:
    def __init__(self):
        self.seeds = []
        self.scenes = 0
        self.pairs = 0
        self.rows = 0
        self.checks = {}
        self.wrong_rows = 0
        self.wrong_by_class = {}
        self.wrong = []  # reproducer dicts
        self.crashes = []
        self.timeouts = []
        self.failing_seeds = set()
        self.occt = {"checked": 0, "wrong": 0, "occt_above": 0, "skipped": 0, "failed": 0,
                     "uncertified_above": 0, "max_row_above": 0.0}
        self.seconds = 0.0
        self.kinds = {}  # scene entries drawn, by what they are
        # Apart rows reading `uncertified` (judged from below only) and the largest amount one
        # reads above the reference, with where.
        self.uncertified = {"rows": 0, "max_excess": 0.0, "where": None}


    def as_json(self):
        return {k: (sorted(v) if isinstance(v, set) else v) for k, v in self.__dict__.items()}


def check_scene(args, scene, seed, index, log, tally, rng):
    vjson = scene[:-5] + ".verify.json"
    doctor = ["--doctor", args.doctor] if args.doctor else []
    cmd = [args.verify, scene, "--every", "1", "--rows", "--seconds", str(args.reference_seconds),
           "--json", vjson] + doctor
    rc, out, err, secs = run(cmd, args.timeout)
    tally.scenes += 1
    if rc == "timeout":
        tally.timeouts.append({"seed": seed, "scene": scene, "seconds": args.timeout})
        log("  seed %d scene %d: TIMEOUT after %.0f s (%s)" % (seed, index, secs, scene))
        return
    if rc not in (0, 3) or not os.path.exists(vjson):
        kind = "signal %d" % -rc if isinstance(rc, int) and rc < 0 else "exit %s" % rc
        tally.crashes.append({"seed": seed, "scene": scene, "how": kind, "stderr": err.strip()[-2000:]})
        tally.failing_seeds.add(seed)
        log("  seed %d scene %d: CRASH (%s): %s\n    replay: %s" % (seed, index, kind, err.strip()[-500:],
                                                                    " ".join(cmd[:2] + ["--every", "1", "--rows"] + doctor)))
        return
    with open(vjson) as f:
        result = json.load(f)["scenes"][0]
    rows = 0
    wrong = 0
    for p in result["pairs"]:
        tally.pairs += 1
        rows += p["rows"]
        wrong += p["wrong"]
        if p.get("uncertified_rows", 0):
            tally.uncertified["rows"] += p["uncertified_rows"]
            if p["max_uncertified_excess"] > tally.uncertified["max_excess"]:
                tally.uncertified["max_excess"] = p["max_uncertified_excess"]
                tally.uncertified["where"] = "%s t=%r %s - %s" % (
                    scene, p["t_max_uncertified_excess"], p["body_a"], p["body_b"])
        for name, (judged, failed) in p["checks"].items():
            c = tally.checks.setdefault(name, [0, 0])
            c[0] += judged
            c[1] += failed
    tally.rows += rows
    tally.wrong_rows += wrong
    classes = {}
    for w in result["wrong_rows"]:
        classes[w["class"]] = classes.get(w["class"], 0) + 1
        tally.wrong_by_class[w["class"]] = tally.wrong_by_class.get(w["class"], 0) + 1
        w["seed"] = seed
        w["index"] = index
        w["replay"] = " ".join([os.path.relpath(args.verify, ROOT), scene, "--at", repr(w["t"]), "--rows"] + doctor)
        tally.wrong.append(w)
    line = "  seed %d scene %d: %d pairs, %d rows checked, %d wrong%s (%.1f s)" % (
        seed, index, len(result["pairs"]), rows, wrong,
        " (" + ", ".join("%d %s" % (n, c) for c, n in sorted(classes.items())) + ")" if classes else "",
        secs)
    log(line)
    for w in result["wrong_rows"]:
        log("    WRONG (%s) %s: %s t=%r %s - %s: got %r (%s%s), expected %r in [%r, %r] "
            "(reference %s, %s; evidence %s)\n      replay: %s" % (
                w["class"], w["check"], scene, w["t"], w["body_a"], w["body_b"], w["got"],
                w["status"], ", " + w["detail"] if w["detail"] else "", w["expected"], w["lower"],
                w["upper"], w["reference_status"], w["overlap"], w["evidence"], w["replay"]))
    if wrong:
        tally.failing_seeds.add(seed)
    # The OpenCASCADE cross-check on a sample of the apart rows.
    apart = result["apart_rows"]
    if args.occt_samples > 0 and apart and os.path.exists(args.occt):
        sample = rng.sample(apart, min(args.occt_samples, len(apart)))
        rjson = scene[:-5] + ".occt-rows.json"
        ojson = scene[:-5] + ".occt.json"
        with open(rjson, "w") as f:
            json.dump({"rows": sample}, f)
        rc, out, err, secs = run([args.occt, scene, rjson, "--json", ojson], args.timeout)
        if rc == "timeout":
            tally.occt["failed"] += 1
            log("    occt: timeout after %.0f s" % secs)
        elif rc not in (0, 3) or not os.path.exists(ojson):
            tally.occt["failed"] += 1
            log("    occt: failed (exit %s): %s\n      replay: %s %s %s" % (
                rc, err.strip()[-300:], os.path.relpath(args.occt, ROOT), scene, rjson))
        else:
            with open(ojson) as f:
                o = json.load(f)
            tally.occt["checked"] += o["checked"]
            tally.occt["wrong"] += o["wrong"]
            tally.occt["occt_above"] += o["occt_above"]
            tally.occt["skipped"] += sum(o["skipped"].values())
            tally.occt["max_row_above"] = max(tally.occt["max_row_above"], o["max_row_above"])
            tally.occt["uncertified_above"] += o.get("uncertified_above", 0)
            log("    occt: %d apart rows against BRepExtrema, %d wrong, %d skipped%s" % (
                o["checked"], o["wrong"], sum(o["skipped"].values()),
                " (" + "; ".join("%d %s" % (n, w) for w, n in o["skipped"].items()) + ")" if o["skipped"] else ""))
            for r in o["rows"]:
                if r["verdict"] != "ok":
                    tally.failing_seeds.add(seed)
                    rep = {"seed": seed, "index": index, "scene": scene, "t": r["t"],
                           "body_a": r["body_a"], "body_b": r["body_b"], "check": "occt",
                           "class": "wrong value (BRepExtrema)", "got": r["distance"],
                           "expected": r["occt"], "verdict": r["verdict"],
                           "replay": "%s %s %s" % (os.path.relpath(args.occt, ROOT), scene, rjson)}
                    tally.wrong.append(rep)
                    tally.wrong_by_class[rep["class"]] = tally.wrong_by_class.get(rep["class"], 0) + 1
                    log("    WRONG (BRepExtrema) %s t=%r %s - %s: row %r, lower bound %r, BRepExtrema %r: %s\n"
                        "      replay: %s" % (scene, r["t"], r["body_a"], r["body_b"], r["distance"],
                                              r["lower_bound"], r["occt"], r["verdict"], rep["replay"]))


def summary_lines(tally):
    lines = ["seeds: %s" % " ".join(str(s) for s in tally.seeds),
             "entries drawn: " + ", ".join("%s %d" % (k, v) for k, v in sorted(tally.kinds.items())),
             "scenes %d, body pairs %d, rows checked %d, wrong rows %d, crashes %d, timeouts %d, "
             "%.0f s" % (tally.scenes, tally.pairs, tally.rows, tally.wrong_rows, len(tally.crashes),
                         len(tally.timeouts), tally.seconds),
             "checks (judged/wrong): " + ", ".join(
                 "%s %d/%d" % (k, v[0], v[1]) for k, v in sorted(tally.checks.items())),
             "wrong rows by class: " + (", ".join("%s %d" % (k, v) for k, v in sorted(tally.wrong_by_class.items()))
                                        or "none"),
             "BRepExtrema: %d apart rows, %d wrong, %d where it is above the row (missed the minimum), "
             "%d uncertified rows above it, %d skipped, %d runs failed or timed out; row - BRepExtrema "
             "at most %.3g (certified rows)" % (
                 tally.occt["checked"], tally.occt["wrong"], tally.occt["occt_above"],
                 tally.occt["uncertified_above"], tally.occt["skipped"], tally.occt["failed"],
                 tally.occt["max_row_above"]),
             "uncertified apart rows (judged from below only): %d, at most %.3g above the reference%s" % (
                 tally.uncertified["rows"], tally.uncertified["max_excess"],
                 " (%s)" % tally.uncertified["where"] if tally.uncertified["where"] else ""),
             "failing seeds: %s" % (" ".join(str(s) for s in sorted(tally.failing_seeds)) or "none"),
             "timeouts: %s" % (" ".join("%d:%s" % (t["seed"], os.path.basename(t["scene"])) for t in tally.timeouts) or "none")]
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out_dir")
    ap.add_argument("--seeds", default=None, help="comma-separated seeds (default: one random)")
    ap.add_argument("--hours", type=float, default=None,
                    help="go on with the next seeds (the last given plus 1, 2, ...) until this time is up")
    ap.add_argument("--count", type=int, default=6, help="scenes per seed")
    ap.add_argument("--steps", type=int, default=31, help="steps per scene")
    ap.add_argument("--rows", type=int, default=200,
                    help="rows per scene: scenes of many pairs get fewer steps (at least %d)" % MIN_STEPS)
    ap.add_argument("--heavy", type=float, default=0.0, help="chance of a larger part per entry")
    ap.add_argument("--occt-samples", type=int, default=3, help="apart rows per scene for BRepExtrema")
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds per scene's check")
    ap.add_argument("--reference-seconds", type=float, default=20.0,
                    help="time limit of each reference query (verify_report --seconds)")
    ap.add_argument("--doctor", choices=["lower_bound", "value", "sign"], default=None,
                    help="the checks' self-test: verify_report makes rows wrong before judging them "
                         "(and the apart rows sent to BRepExtrema are the doctored ones)")
    ap.add_argument("--log", default=None)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    args = ap.parse_args()
    if args.steps < 2 or args.count < 1:
        ap.error("--steps must be at least 2 and --count at least 1")
    binary = os.path.join(args.build, "cli", "extremal")
    args.verify = os.path.join(args.build, "bench", "verify_report")
    args.occt = os.path.join(args.build, "bench", "occt_crosscheck")
    for b in (binary, args.verify):
        if not os.path.exists(b):
            ap.error("%s not built" % b)
    seeds = [int(s) for s in args.seeds.split(",")] if args.seeds else [random.SystemRandom().randrange(1 << 30)]
    os.makedirs(args.out_dir, exist_ok=True)
    log_path = args.log or os.path.join(args.out_dir, "hunt.log")
    logf = open(log_path, "a")

    def log(s):
        print(s, flush=True)
        logf.write(s + "\n")
        logf.flush()

    tally = Tally()
    t0 = time.time()
    deadline = t0 + 3600 * args.hours if args.hours is not None else None
    log("hunt: %s, %d scenes per seed, %d steps, heavy %.2f, BRepExtrema %d rows per scene, seeds from %s%s" % (
        time.strftime("%Y-%m-%d %H:%M:%S"), args.count, args.steps, args.heavy, args.occt_samples,
        seeds[0], ", for %.2f h" % args.hours if args.hours is not None else ""))
    queue = list(seeds)
    while queue:
        seed = queue.pop(0)
        tally.seeds.append(seed)
        seed_dir = os.path.join(args.out_dir, str(seed))
        os.makedirs(seed_dir, exist_ok=True)
        log("seed %d" % seed)
        for k in range(args.count):
            if deadline is not None and time.time() > deadline:
                break
            rng = random.Random(seed * 1000 + k)
            name = "hunt_%d_%d" % (seed, k)
            path, what, kinds = write_scene(rng, seed_dir, name, args.steps, args.rows, args.heavy, binary)
            for kind in kinds:
                tally.kinds[kind] = tally.kinds.get(kind, 0) + 1
            log("  seed %d scene %d: %s: %s" % (seed, k, path, what))
            check_scene(args, path, seed, k, log, tally, random.Random(seed * 1000 + k + 1))
        if deadline is not None and time.time() < deadline and not queue:
            queue.append(seed + 1)
    tally.seconds = time.time() - t0
    log("---- summary")
    for line in summary_lines(tally):
        log(line)
    with open(os.path.join(args.out_dir, "summary.json"), "w") as f:
        json.dump(tally.as_json(), f, indent=1)
    return 3 if tally.wrong or tally.crashes else 0


if __name__ == "__main__":
    sys.exit(main())
