#!/usr/bin/env python3
"""Runs the same scenes with two builds of `extremal` and compares their report rows.

    scripts/compare-builds.py OLD_BUILD NEW_BUILD [--mode identical|bounds] [--work DIR]
                              [--sets demo,bench,probe] [--scene FILE ...] [--timeout S]

OLD_BUILD and NEW_BUILD are build trees (their cli/extremal is run). The scenes: the demo
(data/demo/demo.json), every scene of bench/scenes, and the probe sets of bench/RESULTS.md
("Random probe scenes": seeds 1 to 5, written by scripts/probe-scenes.py into WORK/probe),
or only the --scene files given. Each scene's JSON report is written by both builds
(WORK/old, WORK/new) and compared row by row, and summary by summary. Fields whose name ends in
`time_us` (step and audit times) are never compared.

Modes:
  identical  (for changes that must not change behaviour) every row and summary byte for byte
             equal, but for timing fields.
  bounds     (for changes that change digits) every row of one build within the certified
             bounds of the other's: apart rows' intervals [lower_bound, distance] overlap (each
             distance is a real pair's, so an upper bound; each lower bound is certified);
             rows without a bound (contact, penetrating) within the error budget; a status
             changed only from `uncertified`.

Exit code 0 when every scene agrees, 3 when some row differs, 1 on bad input or a failed run.
"""
import argparse
import glob
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The probe sets of bench/RESULTS.md, "Random probe scenes": (seed, count, steps, flags).
PROBE_SETS = [
    (1, 12, 51, []),
    (2, 30, 51, []),
    (3, 40, 51, []),
    (4, 30, 51, ["--files-only"]),
    (5, 12, 41, ["--heavy"]),
]

# The budget a `bounds` comparison allows rows without a certified bound (the default error
# budget, Body_pair_options::tolerance: 1e-9 absolute or relative).
BUDGET = 1e-9


def strip_timing(x):
    if isinstance(x, dict):
        return {k: strip_timing(v) for k, v in x.items() if not k.endswith("time_us")}
    if isinstance(x, list):
        return [strip_timing(v) for v in x]
    return x


def probe_scenes(work, binary):
    out = []
    for seed, count, steps, flags in PROBE_SETS:
        folder = os.path.join(work, "probe", "s%d" % seed)
        if not glob.glob(os.path.join(folder, "*.json")):
            subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "probe-scenes.py"), folder,
                            "--seed", str(seed), "--count", str(count), "--steps", str(steps),
                            "--binary", binary] + flags, check=True, stdout=subprocess.DEVNULL)
        out += sorted(glob.glob(os.path.join(folder, "*.json")))
    return out


def run_report(build, scene, out, timeout):
    binary = os.path.join(build, "cli", "extremal")
    if os.path.exists(out) and os.path.getmtime(out) > os.path.getmtime(binary):
        return True  # (kept from an earlier run with this binary)
    try:
        p = subprocess.run([binary, "report", scene, "-o", out, "--quiet"], capture_output=True,
                           text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        print("  %s: timed out after %g s with %s" % (scene, timeout, build))
        return False
    if p.returncode != 0:
        print("  %s: %s exited %d: %s" % (scene, binary, p.returncode, p.stderr.strip()[:300]))
        return False
    return True


def row_key(r):
    return "t=%r %s-%s" % (r["t"], r["body_a"], r["body_b"])


def within_bounds(a, b):
    """Whether rows a and b (old, new) agree within their certified bounds; a reason if not."""
    sa, sb = a["status"], b["status"]
    if sa != sb and sa != "uncertified":
        return "status %s -> %s" % (sa, sb)
    da, db = a["distance"], b["distance"]
    if not (isinstance(db, (int, float)) and math.isfinite(db)):
        return "distance %r" % db
    la, lb = a.get("lower_bound"), b.get("lower_bound")
    if la is not None and lb is not None:
        slack = 4 * sys.float_info.epsilon * max(abs(da), abs(db), 1.0)
        if db < la - slack or da < lb - slack:
            return "intervals [%r, %r] and [%r, %r] disjoint" % (la, da, lb, db)
        return None
    if abs(da - db) > BUDGET * max(1.0, abs(da)):
        return "distance %r -> %r (no bound: beyond the budget)" % (da, db)
    return None


def compare(old_path, new_path, mode):
    old = strip_timing(json.load(open(old_path)))
    new = strip_timing(json.load(open(new_path)))
    problems = []
    if len(old["rows"]) != len(new["rows"]):
        return ["%d rows -> %d rows" % (len(old["rows"]), len(new["rows"]))]
    for a, b in zip(old["rows"], new["rows"]):
        if row_key(a) != row_key(b):
            problems.append("row %s -> %s" % (row_key(a), row_key(b)))
        elif mode == "identical":
            if a != b:
                diff = [k for k in sorted(set(a) | set(b)) if a.get(k) != b.get(k)]
                problems.append("%s: %s" % (row_key(a), ", ".join(
                    "%s %r -> %r" % (k, a.get(k), b.get(k)) for k in diff)))
        else:
            why = within_bounds(a, b)
            if why:
                problems.append("%s: %s" % (row_key(a), why))
    if mode == "identical":
        for k in sorted(set(old) | set(new)):
            if k != "rows" and old.get(k) != new.get(k):
                problems.append("%s differs" % k)
    return problems


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("old_build")
    ap.add_argument("new_build")
    ap.add_argument("--mode", choices=["identical", "bounds"], default="identical")
    ap.add_argument("--work", default="/tmp/compare-builds")
    ap.add_argument("--sets", default="demo,bench,probe")
    ap.add_argument("--scene", nargs="*", default=[])
    ap.add_argument("--timeout", type=float, default=1800)
    args = ap.parse_args()
    for b in (args.old_build, args.new_build):
        if not os.access(os.path.join(b, "cli", "extremal"), os.X_OK):
            ap.error("%s: no cli/extremal in this build tree" % b)
    scenes = list(args.scene)
    if not scenes:
        sets = args.sets.split(",")
        if "demo" in sets:
            scenes.append(os.path.join(ROOT, "data", "demo", "demo.json"))
        if "bench" in sets:
            scenes += sorted(glob.glob(os.path.join(ROOT, "bench", "scenes", "*.json")))
        if "probe" in sets:
            scenes += probe_scenes(args.work, os.path.join(args.old_build, "cli", "extremal"))
    failed = differing = rows = 0
    for scene in scenes:
        tag = os.path.relpath(scene, ROOT).replace(os.sep, "_").replace("..", "up")
        outs = []
        for side, build in (("old", args.old_build), ("new", args.new_build)):
            folder = os.path.join(args.work, side)
            os.makedirs(folder, exist_ok=True)
            outs.append(os.path.join(folder, tag))
            if not run_report(build, scene, outs[-1], args.timeout):
                outs = None
                break
        if outs is None:
            failed += 1
            continue
        problems = compare(outs[0], outs[1], args.mode)
        n = len(json.load(open(outs[0]))["rows"])
        rows += n
        if problems:
            differing += 1
            print("DIFFERS %s (%d rows): %d problems" % (scene, n, len(problems)))
            for p in problems[:10]:
                print("    " + p)
        else:
            print("same    %s (%d rows)" % (scene, n))
    print("%d scenes, %d rows: %d differ, %d failed to run (mode %s)" %
          (len(scenes), rows, differing, failed, args.mode))
    return 1 if failed else 3 if differing else 0


if __name__ == "__main__":
    sys.exit(main())
