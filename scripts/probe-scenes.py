#!/usr/bin/env python3
"""Writes random probe scenes: two bodies, one passing the other while it turns.

    scripts/probe-scenes.py OUT_DIR [--seed S] [--count N] [--steps K] [--files-only] [--heavy]
    ./build/bench/verify_report OUT_DIR/*.json --every 5 --rows

Body B (a shape spec or a file of ../shared/data) turns about its box centre while that centre
moves on a line past A's (static, turned at random); the line misses A's centre by a random
fraction of the two bodies' box radii, from 0 (straight through) to 1.2 (mostly apart). B's
poses go to a pose table (OUT_DIR/NAME.poses.csv, one row per step), so the turn is about the
centre whatever the file's origin. The seed is printed and kept in each scene's name: the same
seed writes the same scenes.
"""
import argparse
import json
import math
import os
import random
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.normpath(os.path.join(ROOT, "..", "shared", "data"))

# Files of ../shared/data that hold one body each (or a few, named NAME/k by the scene).
FILES = [
    "step/screw.step",
    "step/linkrods.step",
    "step/pr2ct.stp",
    "step/bug24283_spheres.stp",
    "step/bug28414_bug_toroidal_surface.stp",
    "step/OCC26308-Face.stp",
    "step/bug29478.stp",
    "iges/OCC26138_Torus.igs",
    "iges/OCC8842_cylinder_Ideas.igs",
    "mesh/cube.ply",
    "mesh/shape.stl",
]
# Larger parts (--heavy): a horn of 110 faces, a turbine's open shell, a hammer of 45 trimmed
# faces, an assembly of 18 solids, a triangulated torus.
HEAVY_FILES = [
    "step/bug27693_cornetta-step.stp",
    "step/ec_turbine-A.stp",
    "iges/hammer.iges",
    "step/as1-oc-214-mat.stp",
    "step/OCC22459-TEST2.stp",
    "mesh/mesh.modifier.PGPRemesh.torus.ply",
]


def bodies_box(target, binary):
    """Body count, and centre and half-diagonal of the union of the boxes `extremal info` gives."""
    out = subprocess.run([binary, "info", target, "--json"], check=True, capture_output=True,
                         text=True).stdout
    boxes = [b["bbox"] for b in json.loads(out)["bodies"]]
    lo = [min(b[i] for b in boxes) for i in range(3)]
    hi = [max(b[3 + i] for b in boxes) for i in range(3)]
    centre = [(lo[i] + hi[i]) / 2 for i in range(3)]
    radius = 0.5 * math.sqrt(sum((hi[i] - lo[i]) ** 2 for i in range(3)))
    return len(boxes), centre, radius


def box_of(target, binary):
    """Centre and half-diagonal of the union of the boxes `extremal info` gives."""
    return bodies_box(target, binary)[1:]


def random_shape(rng, size):
    """A shape entry of about `size` (box radius)."""
    kind = rng.choice(["sphere", "ellipsoid", "torus", "cylinder", "plane"])
    s = size
    if kind == "sphere":
        r = s * rng.uniform(0.3, 1.0)
        return {"type": "sphere", "radius": r}, [0, 0, 0]
    if kind == "ellipsoid":
        axes = [s * rng.uniform(0.2, 0.8) for _ in range(3)]
        return {"type": "ellipsoid", "axes": axes}, [0, 0, 0]
    if kind == "torus":
        major = s * rng.uniform(0.4, 0.8)
        minor = major * rng.uniform(0.15, 0.6)
        return {"type": "torus", "major": major, "minor": minor}, [0, 0, 0]
    if kind == "cylinder":
        r = s * rng.uniform(0.1, 0.5)
        h = s * rng.uniform(0.5, 1.6)
        return {"type": "cylinder", "radius": r, "height": h}, [0, 0, h / 2]
    w, h = s * rng.uniform(0.8, 1.6), s * rng.uniform(0.8, 1.6)
    return {"type": "plane", "size": [w, h]}, [0, 0, 0]


def random_unit(rng):
    while True:
        v = [rng.gauss(0, 1) for _ in range(3)]
        n = math.sqrt(sum(x * x for x in v))
        if n > 1e-3:
            return [x / n for x in v]


def quat_mul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return [aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw]


def quat_axis_angle(axis, angle):
    s = math.sin(angle / 2)
    return [math.cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s]


def rotate(q, v):
    p = quat_mul(quat_mul(q, [0.0] + list(v)), [q[0], -q[1], -q[2], -q[3]])
    return p[1:]


def random_quat(rng):
    return quat_axis_angle(random_unit(rng), rng.uniform(0, math.pi))


def body_entry(rng, name, pick, size_hint, binary):
    """A scene body entry (pose filled in later), its box centre (body frame) and radius."""
    if pick == "shape":
        shape, _ = random_shape(rng, size_hint)
        entry = {"name": name, "shape": shape}
        # The box centre and radius from the shape itself (sizes chosen above are bounds).
        centre, radius = box_of(shape_spec(shape), binary)
        return entry, centre, radius
    path = os.path.join(DATA, pick)
    centre, radius = box_of(path, binary)
    return {"name": name, "file": path}, centre, radius


def shape_spec(shape):
    t = shape["type"]
    if t == "sphere":
        return "sphere:%r" % shape["radius"]
    if t == "ellipsoid":
        return "ellipsoid:%r,%r,%r" % tuple(shape["axes"])
    if t == "torus":
        return "torus:%r,%r" % (shape["major"], shape["minor"])
    if t == "cylinder":
        return "cylinder:%r,%r" % (shape["radius"], shape["height"])
    return "plane:%r,%r" % tuple(shape["size"])


def write_scene(rng, out_dir, name, steps, files_only, heavy, binary):
    files = FILES + HEAVY_FILES if heavy else FILES
    choices = files if files_only else files + ["shape"] * 4
    pick_a, pick_b = rng.choice(choices), rng.choice(choices)
    if heavy and pick_a not in HEAVY_FILES and pick_b not in HEAVY_FILES:
        pick_a = rng.choice(HEAVY_FILES)
    if pick_a == "shape" and pick_b == "shape":
        pick_b = rng.choice(files)
    # A file fixes the scale; a shape follows the other body's.
    size = 5.0
    if pick_a != "shape":
        size = box_of(os.path.join(DATA, pick_a), binary)[1]
    elif pick_b != "shape":
        size = box_of(os.path.join(DATA, pick_b), binary)[1]
    a, ca, ra = body_entry(rng, "A", pick_a, size, binary)
    b, cb, rb = body_entry(rng, "B", pick_b, size, binary)

    # A static, turned about its box centre, which sits at the origin.
    qa = random_quat(rng)
    pa = [-x for x in rotate(qa, ca)]
    a["pose"] = {"position": pa, "quaternion": qa}
    a["motion"] = {"type": "static"}

    # B's centre passes the origin on a line that misses it by `miss`, from 1.6 (ra + rb)
    # before to as far after, while B turns about its centre at up to 1.5 rad/s.
    u = random_unit(rng)
    side = random_unit(rng)
    side = [side[i] - sum(side[j] * u[j] for j in range(3)) * u[i] for i in range(3)]
    n = math.sqrt(sum(x * x for x in side)) or 1.0
    side = [x / n for x in side]
    reach = ra + rb
    miss = rng.uniform(0.0, 1.2) * reach
    start = [1.6 * reach * u[i] + miss * side[i] for i in range(3)]
    travel = [-3.2 * reach * u[i] for i in range(3)]
    axis = random_unit(rng)
    rate = rng.uniform(0.0, 1.5)
    qb0 = random_quat(rng)
    duration = 2.0
    step = duration / (steps - 1)
    table = os.path.join(out_dir, name + ".poses.csv")
    with open(table, "w") as f:
        f.write("t,x,y,z,qw,qx,qy,qz\n")
        for k in range(steps):
            t = k * step
            q = quat_mul(quat_axis_angle(axis, rate * t), qb0)
            c = [start[i] + travel[i] * t / duration for i in range(3)]
            rc = rotate(q, cb)
            p = [c[i] - rc[i] for i in range(3)]
            f.write("%r,%r,%r,%r,%r,%r,%r,%r\n" % (t, p[0], p[1], p[2], q[0], q[1], q[2], q[3]))
    b["pose"] = {"position": [start[i] - rotate(qb0, cb)[i] for i in range(3)], "quaternion": qb0}
    b["motion"] = {"type": "table", "file": os.path.basename(table)}
    scene = {"units": "mm", "time": {"start": 0, "end": duration, "step": step},
             "bodies": [a, b], "pairs": [["A", "B"]]}
    path = os.path.join(out_dir, name + ".json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path, pick_a, pick_b, miss / reach


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out_dir")
    ap.add_argument("--seed", type=int, default=None)
    ap.add_argument("--count", type=int, default=10)
    ap.add_argument("--steps", type=int, default=101)
    ap.add_argument("--files-only", action="store_true", help="both bodies from ../shared/data")
    ap.add_argument("--heavy", action="store_true",
                    help="one body at least from the larger parts (cornetta, turbine, hammer, as1, ...)")
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "cli", "extremal"))
    args = ap.parse_args()
    if args.steps < 2 or args.count < 1:
        ap.error("--steps must be at least 2 and --count at least 1")
    seed = args.seed if args.seed is not None else random.SystemRandom().randrange(1 << 30)
    print("seed %d" % seed)
    os.makedirs(args.out_dir, exist_ok=True)
    for k in range(args.count):
        rng = random.Random(seed * 1000 + k)
        name = "probe_%d_%d" % (seed, k)
        path, pa, pb, miss = write_scene(rng, args.out_dir, name, args.steps, args.files_only,
                                         args.heavy, args.binary)
        print("%s: %s against %s, miss %.2f of the box radii" % (path, pa, pb, miss))
    return 0


if __name__ == "__main__":
    sys.exit(main())
