#!/usr/bin/env python3
"""Size and open time of HTML reports (bench/RESULTS.md, "HTML report").

Writes `extremal report SCENE -o OUT.html` for each scene, then opens each page RUNS times in
headless chromium (software WebGL, as tests/browser/test_html_report.py does) with an empty
page as the peer measured in the same run: per page the median wall time of the browser's run
(start to exit, the page loaded and its 3D view drawn) and the median time the page itself
reports from the start of its loading to its first drawn 3D view (<html data-ready-ms>).

    scripts/bench-html-report.py [--runs 5] [SCENE...]   (default: the demo and as1_all_pairs)
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "browser"))
import test_html_report  # noqa: E402  (its chromium command line)


def open_page(chromium, work, page):
    profile = tempfile.mkdtemp(prefix="profile-", dir=work)
    start = time.monotonic()
    done = subprocess.run(test_html_report.chromium_command(chromium, profile, ["--dump-dom"],
                                                            "file://" + page),
                          capture_output=True, text=True, timeout=300)
    wall = time.monotonic() - start
    shutil.rmtree(profile, ignore_errors=True)
    root = re.search(r"<html[^>]*>", done.stdout)
    attrs = dict(re.findall(r'([\w-]+)="([^"]*)"', root.group(0))) if root else {}
    return wall, attrs


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--extremal", default=os.path.join(ROOT, "build", "cli", "extremal"))
    parser.add_argument("scenes", nargs="*", default=[
        os.path.join(ROOT, "data", "demo", "demo.json"),
        os.path.join(ROOT, "bench", "scenes", "as1_all_pairs.json")])
    args = parser.parse_args()
    chromium = shutil.which("chromium")
    if not chromium:
        sys.exit("chromium is not installed (scripts/setup.sh installs it)")
    work = tempfile.mkdtemp(prefix="html-report-bench-")
    pages = []
    empty = os.path.join(work, "empty.html")
    with open(empty, "w") as f:
        f.write("<!DOCTYPE html><html><body></body></html>\n")
    pages.append(("empty page (peer)", empty))
    for scene in args.scenes:
        page = os.path.join(work, os.path.splitext(os.path.basename(scene))[0] + ".html")
        start = time.monotonic()
        subprocess.run([args.extremal, "report", scene, "-o", page, "--quiet"], check=True)
        print("%s: written in %.2f s, %d bytes (%.2f MB)"
              % (os.path.basename(scene), time.monotonic() - start, os.path.getsize(page),
                 os.path.getsize(page) / 1e6))
        pages.append((os.path.basename(page), page))
    walls = {name: [] for name, _ in pages}
    ready = {name: [] for name, _ in pages}
    for _ in range(args.runs):  # interleaved, so load drifts hit every page alike
        for name, page in pages:
            wall, attrs = open_page(chromium, work, page)
            if page != empty and (attrs.get("data-view") != "drawn" or attrs.get("data-errors") != "0"):
                sys.exit("%s did not draw cleanly: %s" % (name, attrs))
            walls[name].append(wall)
            if "data-ready-ms" in attrs:
                ready[name].append(float(attrs["data-ready-ms"]))
    peer = statistics.median(walls[pages[0][0]])
    print("| page | size (MB) | browser run, median of %d (s) | minus the empty page's (s) | "
          "page start to 3D view drawn, median (ms) |" % args.runs)
    print("|---|---|---|---|---|")
    for name, page in pages:
        wall = statistics.median(walls[name])
        print("| %s | %.2f | %.2f | %.2f | %s |"
              % (name, os.path.getsize(page) / 1e6, wall, wall - peer,
                 "%.0f" % statistics.median(ready[name]) if ready[name] else "-"))
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
