#!/usr/bin/env python3
"""`extremal report` writes the same JSON whatever `--threads` and from run to run: byte for
byte, but for the timing fields (every key ending in `time_us`).

The scenes: bench scenes that run in seconds (among them as1_all_pairs, 153 pairs), and a hunt
set written at test time by scripts/probe-scenes.py with fixed seeds (shapes and files of the
shared data set), run both one scene at a time and as one scene of all their pairs, so that the
pairs' threads interleave. One batch per run: `--threads 1` twice, then 2 and 8; every scene's
report of each run is compared with the first run's. Fails on any difference (naming the
scene, run and first differing row), on a failed run, and when a control (a copy of a report
with one digit changed) is not caught.

    test_report_determinism.py --extremal build/cli/extremal --source-dir . --work-dir DIR
"""
import argparse
import glob
import json
import os
import subprocess
import sys

# Bench scenes of a few seconds each (bench/scenes).
BENCH = [
    "as1_all_pairs.json",
    "ball_over_as1.json",
    "balls_spinning_near_contact.json",
    "ellipsoid_spinning_through_plane.json",
    "pin_in_fillet_slide.json",
    "rod_across_ring.json",
    "screw_through_plane_tilted.json",
]
# The hunt set: (seed, count, steps) of scripts/probe-scenes.py, and the scenes of it left out
# for their running time (probe_1_4: linkrods against a trimmed sheet, 10 s alone).
PROBE = (1, 12, 31)
PROBE_SLOW = {"probe_1_4.json"}
# `--threads` of each run; the first is the reference.
RUNS = [1, 1, 2, 8]


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def strip_timing(x):
    if isinstance(x, dict):
        return {k: strip_timing(v) for k, v in x.items() if not k.endswith("time_us")}
    if isinstance(x, list):
        return [strip_timing(v) for v in x]
    return x


def canonical(path):
    """The report without its timing fields, as text: the same doubles give the same text, and
    any other difference (a digit, -0 for 0, an integer for a double, key order) shows."""
    with open(path) as f:
        report = json.load(f, object_pairs_hook=lambda pairs: dict(pairs))
    return json.dumps(strip_timing(report), separators=(",", ":"), allow_nan=True)


def first_difference(ref, other):
    """Where two canonical reports first differ: a row index and both rows, or a summary."""
    a, b = json.loads(ref), json.loads(other)
    rows_a, rows_b = a.get("rows", []), b.get("rows", [])
    for i, (x, y) in enumerate(zip(rows_a, rows_b)):
        if json.dumps(x) != json.dumps(y):
            return "row %d:\n    %s\n    %s" % (i, json.dumps(x), json.dumps(y))
    if len(rows_a) != len(rows_b):
        return "%d rows against %d" % (len(rows_a), len(rows_b))
    for key in sorted(set(a) | set(b)):
        if json.dumps(a.get(key)) != json.dumps(b.get(key)):
            return "key %r:\n    %s\n    %s" % (key, json.dumps(a.get(key))[:400],
                                                json.dumps(b.get(key))[:400])
    return "(text only)"


def combined_scene(probes, folder):
    """One scene holding every probe scene's two bodies as a pair of its own (A_k, B_k), their
    pose tables beside it."""
    bodies, pairs, time = [], [], None
    for k, path in enumerate(probes):
        with open(path) as f:
            s = json.load(f)
        time = time or s["time"]
        if s["time"] != time:
            fail("%s: a time range unlike the other probe scenes'" % path)
        names = []
        for b in s["bodies"]:
            b = dict(b)
            b["name"] = "%s_%d" % (b["name"], k)
            names.append(b["name"])
            bodies.append(b)
        pairs.append(names)
    scene = {"units": "mm", "time": time, "bodies": bodies, "pairs": pairs}
    out = os.path.join(folder, "probe_all_pairs.json")
    with open(out, "w") as f:
        json.dump(scene, f, indent=1)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--extremal", required=True)
    ap.add_argument("--source-dir", required=True)
    ap.add_argument("--work-dir", required=True)
    args = ap.parse_args()
    work = os.path.abspath(args.work_dir)
    os.makedirs(work, exist_ok=True)

    seed, count, steps = PROBE
    probe_dir = os.path.join(work, "probe")
    for old in glob.glob(os.path.join(probe_dir, "*")):
        os.remove(old)
    subprocess.run([sys.executable, os.path.join(args.source_dir, "scripts", "probe-scenes.py"),
                    probe_dir, "--seed", str(seed), "--count", str(count), "--steps", str(steps),
                    "--binary", args.extremal], check=True, stdout=subprocess.DEVNULL)
    probes = sorted(p for p in glob.glob(os.path.join(probe_dir, "probe_*.json"))
                    if os.path.basename(p) not in PROBE_SLOW)
    if len(probes) != count - len(PROBE_SLOW):
        fail("probe-scenes.py wrote %d scenes, expected %d" % (len(probes), count - len(PROBE_SLOW)))
    scenes = [os.path.join(args.source_dir, "bench", "scenes", s) for s in BENCH]
    scenes += probes + [combined_scene(probes, probe_dir)]

    # One batch per run: out.TAG.json per scene, TAG the scene's file name.
    reports = []
    for k, threads in enumerate(RUNS):
        folder = os.path.join(work, "run%d" % k)
        os.makedirs(folder, exist_ok=True)
        for old in glob.glob(os.path.join(folder, "*.json")):
            os.remove(old)
        p = subprocess.run([args.extremal, "report"] + scenes +
                           ["-o", os.path.join(folder, "out.json"), "--quiet",
                            "--threads", str(threads)], capture_output=True, text=True)
        if p.returncode != 0:
            fail("run %d (--threads %d) exited %d: %s" % (k, threads, p.returncode, p.stderr[-2000:]))
        outs = sorted(glob.glob(os.path.join(folder, "out.*.json")))
        if len(outs) != len(scenes):
            fail("run %d wrote %d reports for %d scenes" % (k, len(outs), len(scenes)))
        reports.append({os.path.basename(o): canonical(o) for o in outs})
        print("run %d: --threads %d, %d reports" % (k, threads, len(outs)))

    rows = sum(len(json.loads(text)["rows"]) for text in reports[0].values())
    if rows < 1000:
        fail("only %d rows in all: the scenes did not run" % rows)
    differences = []
    for k in range(1, len(RUNS)):
        for name, ref in reports[0].items():
            if reports[k][name] != ref:
                differences.append("%s, run %d (--threads %d) against run 0 (--threads %d): %s" %
                                   (name, k, RUNS[k], RUNS[0], first_difference(ref, reports[k][name])))

    # The control: a copy of a report with one digit of one distance changed must differ.
    control = os.path.join(work, "control.json")
    with open(os.path.join(work, "run0", "out.rod_across_ring.json")) as f:
        text = f.read()
    at = text.index('"distance":', text.index('"rows"')) + len('"distance":')
    end = at
    while text[end] not in ",}":
        end += 1
    digit = end - 1 if text[end - 1].isdigit() else text.index("e", at) - 1
    text = text[:digit] + ("1" if text[digit] != "1" else "2") + text[digit + 1:]
    with open(control, "w") as f:
        f.write(text)
    if canonical(control) == reports[0]["out.rod_across_ring.json"]:
        fail("control: a report with a changed distance compared equal")

    for line in differences:
        print("DIFFERS: " + line)
    if differences:
        fail("%d reports differ" % len(differences))
    print("%d scenes, %d rows, identical over --threads %s" %
          (len(scenes), rows, ", ".join(str(t) for t in RUNS)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
