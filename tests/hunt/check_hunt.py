#!/usr/bin/env python3
"""The certificate hunt's short run (ctest `hunt_short`, label `hunt`), and its self-test.

1. scripts/hunt.py on fixed seeds (7, 36, 4, 3; 3 scenes each, 21 steps): every body kind is
   drawn, every check that must see rows sees some, BRepExtrema checks apart rows, and no row
   is wrong (exit 0).
2. The same hunt with verify_report's --doctor (rows made wrong before they are judged), once
   per way: it must exit 3, the check that catches that way must count wrong rows, and the log
   must give each a replay command; doctored distances sent to BRepExtrema must be caught there
   too. A hunt that cannot see a wrong row fails here.

    tests/hunt/check_hunt.py BUILD_DIR OUT_DIR
"""
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HUNT = os.path.join(ROOT, "scripts", "hunt.py")
SHORT = ["--seeds", "7,36,4,3", "--count", "3", "--steps", "21"]
# What the short run must draw and judge.
KINDS = ["solid", "sheet", "sheet_obj", "compound", "mesh", "closed_mesh", "convex_mesh",
         "open_mesh", "point", "sphere", "curve", "plane", "ellipsoid", "cylinder"]
CHECKS = ["finite", "lower_bound", "support_plane", "apart_sign", "overlap_sign",
          "reference_evidence", "apart_value", "convex_value"]
# Each doctoring and the check that must catch it.
DOCTORED = {"lower_bound": "lower_bound", "value": "apart_value", "sign": "apart_sign"}

failures = []


def expect(ok, what):
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)


def hunt(build, out, args):
    shutil.rmtree(out, ignore_errors=True)
    p = subprocess.run([sys.executable, HUNT, out, "--build", build] + args,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out, "hunt.log")) as f:
        log = f.read()
    return p.returncode, summary, log


def main():
    build, out = sys.argv[1], sys.argv[2]
    occt = os.path.exists(os.path.join(build, "bench", "occt_crosscheck"))

    rc, s, log = hunt(build, os.path.join(out, "short"), SHORT)
    print("\n".join(log.splitlines()[-9:]))
    expect(rc == 0, "short run exits 0 (exit %d)" % rc)
    expect(s["scenes"] == 12 and s["rows"] > 500, "12 scenes, over 500 rows (%d, %d)" % (s["scenes"], s["rows"]))
    expect(s["wrong_rows"] == 0 and not s["wrong"], "no wrong row (%d)" % s["wrong_rows"])
    expect(not s["crashes"] and not s["timeouts"], "no crash, no timeout")
    for k in KINDS:
        expect(s["kinds"].get(k, 0) > 0, "draws %s (%d)" % (k, s["kinds"].get(k, 0)))
    for c in CHECKS:
        expect(s["checks"].get(c, [0, 0])[0] > 0, "check %s judges rows (%d)" % (c, s["checks"].get(c, [0])[0]))
    if occt:
        expect(s["occt"]["checked"] >= 20 and s["occt"]["wrong"] == 0,
               "BRepExtrema checks at least 20 apart rows, none wrong (%d, %d)" % (
                   s["occt"]["checked"], s["occt"]["wrong"]))

    for how, check in DOCTORED.items():
        rc, s, log = hunt(build, os.path.join(out, "doctor-" + how),
                          ["--seeds", "7", "--count", "2", "--steps", "11", "--doctor", how])
        failed = s["checks"].get(check, [0, 0])[1]
        expect(rc == 3, "--doctor %s: exit 3 (exit %d)" % (how, rc))
        expect(failed > 0, "--doctor %s: %s finds wrong rows (%d)" % (how, check, failed))
        expect(("--doctor " + how) in log and "replay: " in log,
               "--doctor %s: the log replays the wrong rows" % how)
        if occt and how == "value":
            expect(s["occt"]["wrong"] > 0, "--doctor value: BRepExtrema finds rows above its "
                   "distance (%d)" % s["occt"]["wrong"])
    if failures:
        print("%d failed: %s" % (len(failures), "; ".join(failures)))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
