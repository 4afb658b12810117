#!/usr/bin/env python3
"""Runs `extremal report` on the scenes of bench/scenes that have a closed form (README there)
and prints, per scene, the run time and the largest |distance - closed form| over all rows,
with the row. Usage: scripts/check-closed-forms.py [EXTREMAL_BINARY] (default
build/cli/extremal). bench/RESULTS.md quotes it ("Bodies that overlap", "The own-basin
watch")."""
import csv
import math
import os
import subprocess
import sys
import tempfile
import time

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
exe = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build", "cli", "extremal")
def spun_support(t):
    """ellipsoid_spinning_through_plane.json: h(z) = |D R^T z| of the ellipsoid (1.5, 1, 0.6)
    turned pi/4 about x, then spun at w = (1.5, 2, 0.7) for t seconds (R = exp([w] t) R0)."""
    w = (1.5, 2.0, 0.7)
    speed = math.sqrt(sum(c * c for c in w))
    n = [c / speed for c in w]
    a, cos_a, sin_a = speed * t, math.cos(speed * t), math.sin(speed * t)
    # Row 2 of exp([n] a) (Rodrigues), then of that times R0 (pi/4 about x).
    row = [(1 - cos_a) * n[2] * n[0] - sin_a * n[1], (1 - cos_a) * n[2] * n[1] + sin_a * n[0],
           cos_a + (1 - cos_a) * n[2] * n[2]]
    r0 = math.sqrt(0.5)
    row = [row[0], r0 * (row[1] + row[2]), r0 * (row[2] - row[1])]
    return math.sqrt(sum((row[k] * d) ** 2 for k, d in enumerate((1.5, 1.0, 0.6))))


closed_forms = [
    ("shaft_in_bore.json", lambda t: -3.0),                            # radial way out
    ("balls_start_deep.json", lambda t: math.hypot(1.5, 0.5 * t) - 2.0),  # |c| - 2
    ("ball_through_ball.json", lambda t: abs(-2.0 + 40.0 * t) - 1.3),  # |c| - 1.3
    # The ring's inner circle (radius 2) to the rod's axis, less the rod's radius.
    ("rod_across_ring.json", lambda t: 2.0 - abs(-1.0 + t) - 0.5),
    # The plane z = 0 to the tilted ellipsoid's top, c_z + sqrt(a^2 sin^2 + c^2 cos^2).
    ("ellipsoid_under_plane.json",
     lambda t: 1.5 - math.sqrt(2.25 * math.sin(1.2) ** 2 + 0.25 * math.cos(1.2) ** 2)),
    ("balls_spinning_near_contact.json", lambda t: 0.001),
    # Entered from above: c_z - h until out below, then -(c_z + h); h its support along z.
    ("ellipsoid_spinning_through_plane.json",
     lambda t: (lambda c, h: c - h if c + h > 0.0 else -(c + h))(2.0 - 2.0 * t, spun_support(t))),
]
with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "rows.csv")
    for scene, exact in closed_forms:
        start = time.time()
        subprocess.run([exe, "report", os.path.join(root, "bench", "scenes", scene), "-o", out,
                        "--quiet"], check=True)
        seconds = time.time() - start
        rows = list(csv.DictReader(open(out)))
        errors = [abs(float(r["distance"]) - exact(float(r["t"]))) for r in rows]
        k = max(range(len(rows)), key=lambda i: errors[i])
        inside = sum(float(r["distance"]) < 0.0 for r in rows)
        print("%-34s %6.2f s  max error %.3g (t = %s: %s, exact %.6g)  rows inside %d" %
              (scene, seconds, errors[k], rows[k]["t"], rows[k]["distance"],
               exact(float(rows[k]["t"])), inside))
