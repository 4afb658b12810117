#!/usr/bin/env python3
"""The HTML report in a real browser: Debian's chromium, headless, with software WebGL
(SwiftShader), opens `extremal report SCENE -o OUT.html` from a file: URL, for the demo and for
the 153 pairs of as1 standing still (bench/scenes/as1_all_pairs.json, the shared data set).

Fails when the page records an error (its collector counts uncaught errors, rejected promises,
failed loads and console.error in <html data-errors>; chromium's log is searched for uncaught
errors too), when the summary table lacks a pair of the demo or shows another class than the
known one (as1: than the JSON report's), when a page reaches 20 MB, or when the 3D canvas did
not draw: in a screenshot, the canvas's commonest colour must be its background, and its pixels
show both bodies' colours. A control
page with a script that throws must be caught, so the error check cannot pass vacuously.

Exit 77 (ctest: skipped) only when chromium is not installed.

    test_html_report.py --extremal build/cli/extremal --source-dir . --work-dir DIR
                        [--screenshot-out docs/images/html-report-demo.png]
"""
import argparse
import collections
import html.parser
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

# The demo's pairs and their known classes (data/demo/demo.json, "clearance": 2): the ellipsoids
# pass 1.66 mm apart at their closest, the ellipsoid dips 0.080 mm into the bracket at t = 3 s.
EXPECTED = {"A - B": "clearance", "A - bracket": "clash"}
WINDOW = (1280, 900)
BACKGROUND = (0xEE, 0xF1, 0xF5)  # #view-box in cli/Html_report.css
MAX_BYTES = 20 * 1000 * 1000  # a report stays under 20 MB
# Clicks the demo's row of A - B (scene pair 0) once the page has drawn its first pair.
CLICK_A_B = """<script>
var poll = setInterval(function () {
  if (document.documentElement.getAttribute('data-view') !== 'drawn') return;
  clearInterval(poll);
  document.querySelector('#summary tbody tr[data-pair="0"]').click();
}, 50);
</script>"""


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def chromium_command(chromium, profile, extra, url):
    return [chromium, "--headless", "--no-sandbox", "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader", "--disable-quic", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync",
            "--force-device-scale-factor=1", "--window-size=%d,%d" % WINDOW,
            "--user-data-dir=" + profile, "--enable-logging=stderr", "--v=0",
            "--virtual-time-budget=20000"] + extra + [url]


def run_chromium(chromium, work, extra, page):
    profile = tempfile.mkdtemp(prefix="profile-", dir=work)  # a new, empty one each run
    try:
        done = subprocess.run(chromium_command(chromium, profile, extra, "file://" + page),
                              capture_output=True, text=True, timeout=180)
    finally:
        shutil.rmtree(profile, ignore_errors=True)
    if done.returncode != 0:
        fail("chromium exited %d: %s" % (done.returncode, done.stderr[-2000:]))
    return done


class Page(html.parser.HTMLParser):
    """The <html> attributes, #page-errors, and the summary table's rows (their cells' text)."""

    def __init__(self):
        super().__init__()
        self.root = {}
        self.errors_text = ""
        self.rows = []
        self._in_errors = self._in_summary = self._in_body = False
        self._cell = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "html":
            self.root = a
        elif a.get("id") == "page-errors":
            self._in_errors = True
        elif tag == "table" and a.get("id") == "summary":
            self._in_summary = True
        elif self._in_summary and tag == "tbody":
            self._in_body = True
        elif self._in_body and tag == "tr":
            self.rows.append([])
        elif self._in_body and tag == "td":
            self._cell = ""

    def handle_endtag(self, tag):
        if tag == "div":
            self._in_errors = False
        elif tag == "td" and self._cell is not None:
            self.rows[-1].append(self._cell.strip())
            self._cell = None
        elif tag == "tbody":
            self._in_body = False
        elif tag == "table":
            self._in_summary = False

    def handle_data(self, data):
        if self._in_errors:
            self.errors_text += data
        if self._cell is not None:
            self._cell += data


def uncaught(log):
    """Chromium's log lines of the page's console that report an uncaught error."""
    return [l for l in log.splitlines() if "CONSOLE" in l and ("Uncaught" in l or "Error" in l)]


def read_png(path):
    """(width, height, rows of (r, g, b) tuples) of an 8-bit RGB or RGBA, non-interlaced PNG."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail(path + ": not a PNG")
    at, idat, header = 8, b"", None
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        at += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace:
        fail(path + ": PNG of depth %d, colour type %d, interlace %d" % (depth, colour, interlace))
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * channels
    previous = bytearray(stride)
    rows = []
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            left = line[i - channels] if i >= channels else 0
            up = previous[i]
            corner = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 255
            elif kind == 2:
                line[i] = (line[i] + up) & 255
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - corner
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                line[i] = (line[i] + (left if pa <= pb and pa <= pc else up if pb <= pc else corner)) & 255
        rows.append([tuple(line[x * channels:x * channels + 3]) for x in range(width)])
        previous = line
    return width, height, rows


def check_canvas(png, box):
    """The canvas drew: its commonest colour is the scene's background (a canvas WebGL never
    drew shows black), a share of its pixels is off it, and both bodies' colours are there."""
    width, height, rows = read_png(png)
    x0, y0, w, h = box
    if x0 < 0 or y0 < 0 or x0 + w > width or y0 + h > height or w < 50 or h < 50:
        fail("the canvas %s is not inside the %dx%d screenshot" % (box, width, height))
    # The caption's text over the canvas is left out: its top 40 pixels.
    pixels = [p for y in range(y0 + 40, y0 + h - 2) for p in rows[y][x0 + 2:x0 + w - 2]]
    mode = collections.Counter(pixels).most_common(1)[0][0]
    if max(abs(m - c) for m, c in zip(mode, BACKGROUND)) > 12:
        fail("the 3D canvas's commonest colour is %s, not the scene's background %s: three.js "
             "did not draw it" % (mode, BACKGROUND))
    off = blue = orange = 0
    for r, g, b in pixels:
        if max(abs(r - BACKGROUND[0]), abs(g - BACKGROUND[1]), abs(b - BACKGROUND[2])) > 12:
            off += 1
            if b > r + 40:
                blue += 1
            if r > b + 60:
                orange += 1
    area = len(pixels)
    print("canvas %s: %.1f%% of its pixels drawn, %.1f%% blue (body A), %.1f%% orange (body B)"
          % (box, 100.0 * off / area, 100.0 * blue / area, 100.0 * orange / area))
    if off < 0.05 * area:
        fail("the 3D canvas is (nearly) all background: %d of %d pixels drawn" % (off, area))
    if blue < 0.002 * area or orange < 0.002 * area:
        fail("the 3D canvas lacks a body's colour: %d blue, %d orange pixels" % (blue, orange))


def check_report(extremal, chromium, work, scene, expected, screenshot_out=None):
    """Writes the scene's HTML and JSON reports and checks the page in the browser. `expected`:
    the known classes by pair, or None to take the JSON report's."""
    stem = os.path.splitext(os.path.basename(scene))[0]
    page = os.path.join(work, stem + ".html")
    report = os.path.join(work, stem + ".json")
    for out in (page, report):
        done = subprocess.run([extremal, "report", scene, "-o", out, "--quiet"],
                              capture_output=True, text=True, timeout=600)
        if done.returncode != 0:
            fail("extremal report -o %s exited %d: %s" % (out, done.returncode, done.stderr))
    with open(report) as f:
        json_classes = {s["body_a"] + " - " + s["body_b"]: s["class"]
                        for s in json.load(f)["summary"]}
    if expected is not None and json_classes != expected:
        fail("%s: the JSON report's classes %s, expected %s" % (stem, json_classes, expected))
    size = os.path.getsize(page)
    if size >= MAX_BYTES:
        fail("%s: the page has %d bytes, over %d" % (stem, size, MAX_BYTES))

    # The page as the browser left it.
    done = run_chromium(chromium, work, ["--dump-dom"], page)
    dom = Page()
    dom.feed(done.stdout)
    if dom.root.get("data-errors") != "0" or dom.errors_text.strip():
        fail("%s: the page recorded errors (%s): %s"
             % (stem, dom.root.get("data-errors"), dom.errors_text))
    if uncaught(done.stderr):
        fail("%s: chromium logged: %s" % (stem, "\n".join(uncaught(done.stderr))))
    if dom.root.get("data-view") != "drawn":
        fail("%s: the 3D view was not drawn: data-view=%r" % (stem, dom.root.get("data-view")))
    table = {row[1]: row[2] for row in dom.rows if len(row) > 2}
    if table != json_classes or len(dom.rows) != len(json_classes):
        fail("%s: the summary table (%d rows) differs from the report's classes: %s, not %s"
             % (stem, len(dom.rows), table, json_classes))
    print("%s: %d bytes, no errors, 3D view drawn after %s ms, %d pairs in the table%s"
          % (stem, size, dom.root.get("data-ready-ms"), len(table),
             (" " + str(table)) if len(table) < 5 else ""))

    # The canvas drew the worst pair's bodies.
    png = os.path.join(work, stem + ".png")
    run_chromium(chromium, work, ["--screenshot=" + png], page)
    box = [int(v) for v in dom.root.get("data-canvas", "").split(",")]
    check_canvas(png, box)
    if screenshot_out:
        shutil.copyfile(png, screenshot_out)
    return page


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--extremal", required=True)
    parser.add_argument("--source-dir", required=True)
    parser.add_argument("--work-dir", required=True)
    parser.add_argument("--screenshot-out", help="also copy the demo's screenshot here (docs)")
    args = parser.parse_args()

    chromium = shutil.which("chromium")
    if not chromium:
        print("SKIP: chromium is not installed (scripts/setup.sh installs it)")
        return 77
    work = os.path.abspath(args.work_dir)
    os.makedirs(work, exist_ok=True)
    demo = check_report(args.extremal, chromium, work,
                        os.path.join(args.source_dir, "data", "demo", "demo.json"), EXPECTED,
                        args.screenshot_out)
    # 153 pairs of a real assembly (the shared data set, docs/test-data.md): under 20 MB.
    check_report(args.extremal, chromium, work,
                 os.path.join(args.source_dir, "bench", "scenes", "as1_all_pairs.json"), None)

    # Selecting another pair: a click on the demo's A - B row once the view is drawn.
    clicked = os.path.join(work, "clicked.html")
    with open(demo) as f:
        text = f.read()
    with open(clicked, "w") as f:
        f.write(text.replace("</body>", CLICK_A_B + "</body>", 1))
    done = run_chromium(chromium, work, ["--dump-dom"], clicked)
    dom = Page()
    dom.feed(done.stdout)
    if dom.root.get("data-errors") != "0" or dom.root.get("data-selected") != "0":
        fail("after a click on A - B: data-errors=%r, data-selected=%r: %s"
             % (dom.root.get("data-errors"), dom.root.get("data-selected"), dom.errors_text))
    png = os.path.join(work, "clicked.png")
    run_chromium(chromium, work, ["--screenshot=" + png], clicked)
    check_canvas(png, [int(v) for v in dom.root.get("data-canvas", "").split(",")])
    print("a click on A - B selects it and draws it")

    # Control: the same page with a script that throws must be caught.
    control = os.path.join(work, "control.html")
    with open(demo) as f:
        text = f.read()
    with open(control, "w") as f:
        f.write(text.replace("</body>", "<script>undefined.x;</script></body>", 1))
    done = run_chromium(chromium, work, ["--dump-dom"], control)
    dom = Page()
    dom.feed(done.stdout)
    if dom.root.get("data-errors") in (None, "0"):
        fail("a page that throws was not caught: data-errors=%r" % dom.root.get("data-errors"))
    print("control: a throwing script is caught (%s)" % dom.errors_text.strip())
    print("1 passed, 0 failed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
