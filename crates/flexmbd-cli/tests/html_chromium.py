#!/usr/bin/env python3
"""The HTML reports of `flexmbd view` in headless Chromium (docs/visualisation.md).

Usage: html_chromium.py [OUTDIR]

Writes reports with `$FLEXMBD view …` (default `cargo run --release -p flexmbd-cli --`) into
OUTDIR (default: a temporary directory), opens each in headless Chromium (`$CHROMIUM`, default
the first of chromium, chromium-browser, google-chrome on PATH) from a file:// URL, and checks:

- the page reaches its ready state with no JavaScript error: the page's own record (window
  errors, unhandled rejections and console.error, counted in <body data-errors>) read with
  --dump-dom, and no console message at all in Chromium's log (--enable-logging=stderr);
- the expected content (motions, modes, fields, load steps, Table 1 row, the lines of the
  designer's language: for the 12-truss's motion the wires `flexmbd check --json` suggests) in
  the status element;
- a screenshot: the canvas is not blank (enough pixels off the background, enough colours);
- animation: the motion of the 12-truss at phase 0.25 and 0.75 (opposite extremes) gives
  different pictures, while phase 0 and 0.5 (both the reference configuration) give the same
  picture; the same for a mode, and two load steps of a static run differ;
- a simulation (the pendulum of examples/pendulum.toml, `--analysis simulate`): one frame per
  output time, the time shown, the drawn tip at the model's geometry at t = 0 and, at t = 0.5 s,
  where an independent integration of the rigid bar's equation θ'' = −(3g/2L) sin θ puts it;
  the time slider moves the tip, playing advances the time, the pictures at two times differ;
- every control (selectors, sliders, buttons, views, clicks on the canvas, keys) works without
  error, in a copy of each report with a small script added that operates them;
- a broken page (invalid data) is reported as an error, so the checks above can fail;
- the page of a design study (`flexmbd study`, docs/studies.md): a 2 × 2 grid over two
  parameters of examples/folded_sheet_guide_param.toml gives a page with no console message, one
  row per variant with the grid's values and status ok, one inlined plot per varying figure of
  merit and parameter with a marker per variant, and a screenshot that is not blank.

Only the Python standard library is used (the PNG decoder is below). Screenshots are kept in
OUTDIR for a look.
"""
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
WIDTH, HEIGHT = 1280, 800
BACKGROUND = (244, 246, 249)  # scene background of viewer.js (0xf4f6f9)
FAILURES = []
PASSED = []


def fail(msg):
    FAILURES.append(msg)
    print("FAIL " + msg, flush=True)


def ok(msg):
    PASSED.append(msg)
    print("ok   " + msg, flush=True)


# --- PNG -------------------------------------------------------------------------------------

def read_png(path):
    """(width, height, rows of (r, g, b) tuples) of an 8-bit, non-interlaced PNG."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG file")
    pos, idat, w = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or interlace != 0 or ctype not in (2, 6):
                raise ValueError(f"{path}: unsupported PNG (depth {depth}, type {ctype})")
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev, i = [], bytearray(stride), 0
    for _ in range(h):
        ftype = raw[i]
        line = bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if ftype == 1:
                line[x] = (line[x] + a) & 255
            elif ftype == 2:
                line[x] = (line[x] + b) & 255
            elif ftype == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif ftype == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[x] = (line[x] + pred) & 255
        rows.append([tuple(line[x:x + 3]) for x in range(0, stride, bpp)])
        prev = line
    return w, h, rows


def crop(img, rect):
    w, h, rows = img
    x0, y0, cw, ch = rect
    x1, y1 = min(w, x0 + cw), min(h, y0 + ch)
    return [row[x0:x1] for row in rows[y0:y1]]


def canvas_stats(pixels):
    """(fraction of pixels off the background, number of distinct colours at 4 bits/channel)."""
    total = off = 0
    colours = set()
    for row in pixels:
        for p in row:
            total += 1
            if sum(abs(p[k] - BACKGROUND[k]) for k in range(3)) > 30:
                off += 1
            colours.add((p[0] >> 4, p[1] >> 4, p[2] >> 4))
    return off / max(total, 1), len(colours)


def difference(a, b):
    """Fraction of pixels that differ by more than a little between two crops."""
    total = diff = 0
    for ra, rb in zip(a, b):
        for p, q in zip(ra, rb):
            total += 1
            if sum(abs(p[k] - q[k]) for k in range(3)) > 40:
                diff += 1
    return diff / max(total, 1)


# --- Chromium --------------------------------------------------------------------------------

def chromium():
    exe = os.environ.get("CHROMIUM")
    if exe:
        return exe
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    sys.exit("html_chromium.py: no Chromium found (apt-get install chromium, or set $CHROMIUM)")


def browse(page, fragment, out, profile, screenshot=None):
    """Open page#fragment headless; return (DOM text, console lines of Chromium's log)."""
    args = [
        chromium(), "--headless", "--no-sandbox", "--hide-scrollbars",
        "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
        f"--window-size={WIDTH},{HEIGHT}", "--virtual-time-budget=30000",
        f"--user-data-dir={profile}", "--no-first-run", "--disable-extensions",
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--no-pings", "--disable-default-apps", "--enable-logging=stderr", "--v=0",
    ]
    args += [f"--screenshot={screenshot}"] if screenshot else ["--dump-dom"]
    url = "file://" + os.path.abspath(page) + ("#" + fragment if fragment else "")
    r = subprocess.run(args + [url], capture_output=True, text=True, timeout=180)
    console = [l for l in r.stderr.splitlines() if ":CONSOLE" in l]
    if r.returncode != 0:
        fail(f"{os.path.basename(page)}#{fragment}: chromium exit {r.returncode}: {r.stderr[-2000:]}")
    return r.stdout, console


def status(dom):
    """Attributes of the status element, the error count and the error text."""
    m = re.search(r'<div id="status"([^>]*)>', dom)
    attrs = dict(re.findall(r'([\w-]+)="([^"]*)"', m.group(1))) if m else {}
    e = re.search(r'<body[^>]*data-errors="(\d+)"', dom)
    errors = int(e.group(1)) if e else -1
    t = re.search(r'<pre id="errors"[^>]*>(.*?)</pre>', dom, re.S)
    title = re.search(r"<title>(.*?)</title>", dom, re.S)
    return attrs, errors, (t.group(1).strip() if t else ""), (title.group(1) if title else "")


def open_page(page, fragment, out, profile, expect):
    """Load page#fragment: no errors, ready, the expected attributes. Returns the status."""
    name = f"{os.path.basename(page)}#{fragment}"
    dom, console = browse(page, fragment, out, profile)
    attrs, errors, text, title = status(dom)
    good = True
    if errors != 0 or text or title.startswith("ERROR"):
        fail(f"{name}: errors in the page ({errors}): {text or title}")
        good = False
    if console:
        fail(f"{name}: console messages: {console}")
        good = False
    if attrs.get("data-state") != "ready":
        fail(f"{name}: not ready: {attrs}")
        good = False
    for k, v in expect.items():
        got = attrs.get(k)
        if callable(v) and not v(got) or not callable(v) and got != v:
            fail(f"{name}: {k} = {got!r}, expected {v if not callable(v) else 'a match'}")
            good = False
    if good:
        ok(f"{name}: ready, no errors, {attrs.get('data-triangles')} triangles")
    return attrs


def shot(page, fragment, out, profile, tag, rect):
    png = os.path.join(out, tag + ".png")
    browse(page, fragment, out, profile, screenshot=png)
    if not os.path.exists(png):
        fail(f"{tag}: no screenshot")
        return None
    img = read_png(png)
    if (img[0], img[1]) != (WIDTH, HEIGHT):
        fail(f"{tag}: screenshot is {img[0]}x{img[1]}, expected {WIDTH}x{HEIGHT}")
    return crop(img, rect)


def canvas_rect(attrs):
    """The middle of the canvas, clear of the overlays (heading and colour bar at the top, legend
    at the bottom left), where the model is drawn: blank there means nothing was rendered."""
    try:
        x, y, w, h = (int(v) for v in attrs["data-canvas"].split(","))
    except (KeyError, ValueError):
        fail(f"no canvas rectangle in {attrs}")
        x, y, w, h = 0, 0, WIDTH - 360, HEIGHT
    if w < 200 or h < 200:
        fail(f"canvas too small: {w}x{h}")
    w, h = min(w, WIDTH - x), min(h, HEIGHT - y)
    return (x + int(0.3 * w), y + int(0.12 * h), int(0.55 * w), int(0.68 * h))


def not_blank(tag, pixels, min_off=0.02, min_colours=12):
    off, colours = canvas_stats(pixels)
    if off < min_off or colours < min_colours:
        fail(f"{tag}: canvas looks blank: {100 * off:.2f} % drawn, {colours} colours")
    else:
        ok(f"{tag}: {100 * off:.1f} % of the canvas drawn, {colours} colours")


def moves(tag, a, b, min_diff=0.003):
    d = difference(a, b)
    if d < min_diff:
        fail(f"{tag}: the pictures do not differ ({100 * d:.3f} % of pixels)")
    else:
        ok(f"{tag}: {100 * d:.2f} % of the pixels change")


def same(tag, a, b, max_diff=0.0005):
    d = difference(a, b)
    if d > max_diff:
        fail(f"{tag}: the pictures should be the same, {100 * d:.3f} % of pixels differ")
    else:
        ok(f"{tag}: same picture ({100 * d:.4f} % of pixels differ)")


# --- the reports -----------------------------------------------------------------------------

# Injected into a copy of a report: works every control once (all animations and colourings,
# every load step, play, sliders, views, keys) after the page is ready and clicks a 9 × 5 grid
# over the canvas in the iso view, counting the clicks that selected an element; then writes the
# counts into <body data-exercised data-selected>. Errors land in the page's own record like any
# other.
EXERCISE = """<script>
(function () {
  function go() {
    var st = document.getElementById('status');
    if (!st || st.getAttribute('data-state') === 'loading') { setTimeout(go, 50); return; }
    var n = 0;
    function fire(el, type) { el.dispatchEvent(new Event(type, { bubbles: true })); n++; }
    function each(id, type, values) {
      var el = document.getElementById(id);
      if (!el) return;
      values(el).forEach(function (v) { el.value = v; fire(el, type); });
    }
    var options = function (el) { return Array.prototype.map.call(el.options, function (o) { return o.value; }); };
    each('sel-item', 'change', options);
    each('sel-color', 'change', options);
    each('rng-step', 'input', function (el) {
      var v = []; for (var k = 0; k <= Number(el.max); k++) v.push(String(k)); return v;
    });
    each('rng-phase', 'input', function () { return ['0.1', '0.6']; });
    each('rng-time', 'input', function (el) { return ['0', String(Math.floor(Number(el.max) / 2)), el.max]; });
    each('rng-speed', 'input', function (el) { return [el.min, el.max]; });
    var energy = document.getElementById('sim-energy');
    if (energy) {
      var er = energy.getBoundingClientRect();
      energy.dispatchEvent(new MouseEvent('click', { bubbles: true, clientX: er.left + 0.6 * er.width, clientY: er.top + er.height / 2 }));
      n++;
    }
    each('rng-amp', 'input', function () { return ['2', '0.5']; });
    ['chk-ghost', 'chk-ghost', 'btn-play', 'btn-prev', 'btn-next', 'btn-play'].forEach(function (id) {
      var el = document.getElementById(id); if (el) { el.click(); n++; }
    });
    document.querySelectorAll('button[data-view]').forEach(function (b) { b.click(); n++; });
    document.querySelector('button[data-view=iso]').click();
    var cv = document.querySelector('#canvas-host canvas');
    var r = cv.getBoundingClientRect();
    var hits = 0;
    for (var i = 1; i < 10; i++) {
      for (var j = 3; j < 8; j++) {
        cv.dispatchEvent(new MouseEvent('click', { bubbles: true, clientX: r.left + r.width * i / 10, clientY: r.top + r.height * j / 10 }));
        n++;
        if (document.querySelector('#selection b')) hits++;
      }
    }
    [' ', 'ArrowLeft', 'ArrowRight', ' '].forEach(function (key) {
      window.dispatchEvent(new KeyboardEvent('keydown', { key: key })); n++;
    });
    setTimeout(function () {
      document.body.setAttribute('data-exercised', String(n));
      document.body.setAttribute('data-selected', String(hits));
    }, 1000);
  }
  go();
})();
</script>
"""


def exercise(page, out, profile, clicks_select=True):
    """Work every control of a copy of the page; no error may appear. With clicks_select, some
    click on the canvas must select an element."""
    with open(page, encoding="utf-8") as f:
        text = f.read()
    copy = os.path.join(out, "exercise_" + os.path.basename(page))
    with open(copy, "w", encoding="utf-8") as f:
        f.write(text.replace("</body>", EXERCISE + "</body>", 1))
    dom, console = browse(copy, "", out, profile)
    attrs, errors, etext, title = status(dom)
    m = re.search(r'data-exercised="(\d+)"', dom)
    n = int(m.group(1)) if m else 0
    if errors != 0 or console or attrs.get("data-state") != "ready" or n < 10:
        fail(f"{os.path.basename(page)}: controls: {n} actions, errors {errors}: {etext or title} {console}")
    else:
        sel = re.search(r'data-selected="(\d+)"', dom)
        hits = int(sel.group(1)) if sel else 0
        if hits == 0 and clicks_select:
            fail(f"{os.path.basename(page)}: no click on the canvas selected an element")
        else:
            ok(f"{os.path.basename(page)}: {n} control actions without error;"
               f" {hits} of 45 clicks on the canvas selected an element")


# Injected into a copy of a simulation report: lets it play for a second of (virtual) time and
# records the frame reached, then moves the time slider to the first and the last output time
# and records the drawn tip position (status data-tip) and time after each move.
SLIDE = """<script>
(function () {
  function go() {
    var st = document.getElementById('status');
    if (!st || st.getAttribute('data-state') === 'loading') { setTimeout(go, 50); return; }
    var body = document.body;
    var frames = 0;
    // playing: wait until the shown output advances, counting animation frames (the viewer
    // advances its clock in them), at most 600: not timers, whose (virtual) time runs on
    // while a loaded machine renders no frame at all, so that a wait of 10 s of it ended once
    // before the first frame was drawn; then record where it got to and after how many frames
    function played(next) {
      if (Number(st.getAttribute('data-frame')) > 0 || frames >= 600) { next(); return; }
      frames += 1;
      requestAnimationFrame(function () { played(next); });
    }
    setTimeout(function () { played(function () {
      body.setAttribute('data-played-to', st.getAttribute('data-frame'));
      body.setAttribute('data-played-frames', String(frames));
      var r = document.getElementById('rng-time');
      function slide(v, tag, next) {
        r.value = v;
        r.dispatchEvent(new Event('input', { bubbles: true }));
        setTimeout(function () {
          body.setAttribute('data-tip-' + tag, st.getAttribute('data-tip'));
          body.setAttribute('data-time-' + tag, st.getAttribute('data-time'));
          if (next) next();
        }, 300);
      }
      slide('0', 'first', function () { slide(r.max, 'last', function () { body.setAttribute('data-slid', '1'); }); });
    }); }, 1000);
  }
  go();
})();
</script>
"""


def pendulum_reference():
    """From examples/pendulum.toml's geometry and gravity: the pin, the tip at t = 0, the bar's
    length and g."""
    import tomllib
    with open(os.path.join(ROOT, "examples", "pendulum.toml"), "rb") as f:
        m = tomllib.load(f)
    pin, tip = m["nodes"]["pin"], m["nodes"]["tip"]
    g = -m["static"]["gravity"][2]
    length = math.dist(pin, tip)
    return pin, tip, length, g


def rigid_bar_tip(t_end, steps=20000):
    """The tip of a uniform rigid bar pinned at one end at time t_end, released from rest at the
    file's position: θ'' = −(3g/2L) sin θ (θ from the downward vertical, in the x-z plane), by
    the classical Runge–Kutta method."""
    pin, tip, length, g = pendulum_reference()
    theta = math.atan2(tip[0] - pin[0], -(tip[2] - pin[2]))
    omega, k, h = 0.0, 1.5 * g / length, t_end / steps
    f = lambda th, om: (om, -k * math.sin(th))
    for _ in range(steps):
        a1 = f(theta, omega)
        a2 = f(theta + h / 2 * a1[0], omega + h / 2 * a1[1])
        a3 = f(theta + h / 2 * a2[0], omega + h / 2 * a2[1])
        a4 = f(theta + h * a3[0], omega + h * a3[1])
        theta += h / 6 * (a1[0] + 2 * a2[0] + 2 * a3[0] + a4[0])
        omega += h / 6 * (a1[1] + 2 * a2[1] + 2 * a3[1] + a4[1])
    return [pin[0] + length * math.sin(theta), pin[1], pin[2] - length * math.cos(theta)]


def near(tag, got, expected, tol):
    """A position "x,y,z" (a status attribute) within tol of expected."""
    try:
        p = [float(v) for v in got.split(",")]
    except (AttributeError, ValueError):
        fail(f"{tag}: no position ({got!r})")
        return
    d = math.dist(p, expected)
    if d > tol:
        fail(f"{tag}: {p}, expected {expected} (off by {d:.2e})")
    else:
        ok(f"{tag}: {[round(v, 4) for v in p]} within {d:.1e} of {[round(v, 4) for v in expected]}")


def simulation_checks(page, out, profile):
    """The pendulum report: frames, times, the drawn tip at two times, slider and playback."""
    pin, tip0, length, g = pendulum_reference()
    tip_end = rigid_bar_tip(0.5)
    a = open_page(page, "paused=1&step=0", out, profile, {
        "data-frames": "51", "data-animations": "0", "data-time": "0", "data-frame": "0",
        "data-fields": lambda v: v is not None and {"sigma1", "speed"} <= set(v.split())})
    near("pendulum t = 0: drawn tip at the model's tip", a.get("data-tip"), tip0, 1e-6)
    b = open_page(page, "paused=1&step=50", out, profile, {
        "data-time": lambda v: v is not None and abs(float(v) - 0.5) < 1e-12})
    near("pendulum t = 0.5 s: drawn tip where the rigid bar's equation puts it",
         b.get("data-tip"), tip_end, 2e-3 * length)
    r = canvas_rect(a)
    first = shot(page, "paused=1&step=0", out, profile, "pendulum_t0", r)
    mid = shot(page, "paused=1&step=25", out, profile, "pendulum_t025", r)
    last = shot(page, "paused=1&step=50", out, profile, "pendulum_t050", r)
    if first and mid and last:
        not_blank("pendulum t = 0.25 s", mid, min_off=0.005, min_colours=8)
        moves("pendulum t = 0 vs t = 0.5 s", first, last)
        moves("pendulum t = 0.25 vs t = 0.5 s", mid, last)
    # the slider, and playing
    with open(page, encoding="utf-8") as f:
        text = f.read()
    copy = os.path.join(out, "slide_" + os.path.basename(page))
    with open(copy, "w", encoding="utf-8") as f:
        f.write(text.replace("</body>", SLIDE + "</body>", 1))
    dom, console = browse(copy, "", out, profile)
    attrs, errors, etext, title = status(dom)
    body = dict(re.findall(r'(data-[\w-]+)="([^"]*)"', re.search(r'<body (data-errors="[^>]*)>', dom).group(1)))
    if errors != 0 or console or body.get("data-slid") != "1":
        fail(f"{os.path.basename(copy)}: errors {errors}: {etext or title} {console} {body}")
        return
    played = int(body.get("data-played-to", "0"))
    if played > 0:
        ok(f"pendulum: playing reached output {played} in {body.get('data-played-frames')} frames")
    else:
        fail(f"pendulum: playing did not advance ({body})")
    near("pendulum slider at the first output: tip", body.get("data-tip-first"), tip0, 1e-6)
    near("pendulum slider at the last output: tip", body.get("data-tip-last"), tip_end, 2e-3 * length)
    if body.get("data-time-first") != "0" or abs(float(body.get("data-time-last", "nan")) - 0.5) > 1e-12:
        fail(f"pendulum slider: times {body.get('data-time-first')}, {body.get('data-time-last')}")
    else:
        ok("pendulum slider: t = 0 and t = 0.5 s shown")


def flexmbd():
    exe = os.environ.get("FLEXMBD")
    return [exe] if exe else ["cargo", "run", "--quiet", "--release", "-p", "flexmbd-cli", "--"]


def view(out, name, model, *args):
    path = os.path.join(out, name + ".html")
    # --force: a folder given on the command line may hold the reports of an earlier run
    cmd = flexmbd() + ["--force", "view", os.path.join(ROOT, "examples", model + ".toml"), "-o", path, *args]
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=900)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed: {r.stderr}")
    size = os.path.getsize(path)
    ok(f"{name}.html written ({size} bytes)")
    return path


# the study: two thicknesses and two angles of sheet 2 (the values are the grid's, independent
# of flexmbd: the records must carry exactly these)
STUDY_T = (0.2e-3, 0.25e-3)
STUDY_ANGLE = (200.0, 220.0)


def study_checks(out, profile):
    failed_before = len(FAILURES)
    folder = os.path.join(out, "study")
    path = os.path.join(out, "study.toml")
    model = os.path.join(ROOT, "examples", "folded_sheet_guide_param.toml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(
            "[study]\nname = \"html check\"\n"
            f"model = {json.dumps(model)}\n"
            "analyses = [\"check\", \"modes\"]\nmodes = 4\n"
            "[parameters]\n"
            f"t = {{ values = [{STUDY_T[0]!r}, {STUDY_T[1]!r}] }}\n"
            f"angle = {{ values = [{STUDY_ANGLE[0]!r}, {STUDY_ANGLE[1]!r}] }}\n"
        )
    cmd = flexmbd() + ["--force", "--quiet", "study", path, "--out", folder, "--jobs", "2"]
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=900)
    if r.returncode != 0:
        fail(f"{' '.join(cmd)}: exit {r.returncode}: {r.stderr[-2000:]}")
        return
    page = os.path.join(folder, "study.html")
    dom, console = browse(page, "", out, profile)
    if console:
        fail(f"study.html: console messages: {console}")
    rows = re.findall(r"<tr(?: class=\"failed\")?><td>(\d+)</td>(.*?)</tr>", dom, re.S)
    grid = [(t, a) for t in STUDY_T for a in STUDY_ANGLE]
    if len(rows) != len(grid):
        fail(f"study.html: {len(rows)} variant rows, expected {len(grid)}")
    for (variant, rest) in rows:
        cells = re.findall(r"<td[^>]*>(.*?)</td>", rest, re.S)
        want = grid[int(variant)] if int(variant) < len(grid) else None
        got = tuple(float(c) for c in cells[:2]) if len(cells) >= 3 else None
        if want is None or got is None or any(abs(g - w) > 1e-5 * abs(w) for g, w in zip(got, want)):
            fail(f"study.html: variant {variant} has parameters {got}, expected {want}")
        elif cells[2] != "ok":
            fail(f"study.html: variant {variant} status {cells[2]!r}: {cells[-1]}")
    svgs = re.findall(r"<svg.*?</svg>", dom, re.S)
    titles = re.findall(r"<h3>(.*?)</h3>", dom)
    plots = sorted(os.listdir(os.path.join(folder, "plots")))
    if not svgs or len(svgs) != len([p for p in plots if p.endswith(".svg")]):
        fail(f"study.html: {len(svgs)} inlined plots, plots/ holds {plots}")
    thin = [i for i, svg in enumerate(svgs) if svg.count("<circle") < len(grid)]
    if thin:
        fail(f"study.html: plots {thin} have fewer than {len(grid)} markers")
    if len(FAILURES) == failed_before:
        ok(f"study.html: {len(rows)} variants, {len(svgs)} plots of {len(titles)} figures of merit")
    png = os.path.join(out, "study_page.png")
    browse(page, "", out, profile, screenshot=png)
    if os.path.exists(png):
        w, h, pixels = read_png(png)
        not_blank("study.html", crop((w, h, pixels), (0, 0, w, h)), min_off=0.01, min_colours=4)
    else:
        fail("study.html: no screenshot")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="flexmbd-html-")
    os.makedirs(out, exist_ok=True)
    profile = tempfile.mkdtemp(prefix="flexmbd-chromium-")
    try:
        run(out, profile)
    finally:
        shutil.rmtree(profile, ignore_errors=True)
    print(f"screenshots in {out}")
    print(f"html_chromium: {len(PASSED)} passed, {len(FAILURES)} failed")
    if FAILURES:
        sys.exit(1)


def run(out, profile):
    twelve = view(out, "twelve_truss", "twelve_truss")
    six = view(out, "folded_sheet_guide_6", "folded_sheet_guide_6")
    stroke = view(out, "parallel_leaf_stroke", "parallel_leaf_stroke", "--analysis", "static", "--steps", "8")
    modes = view(out, "paper_dynamic_6_sheets", "paper_dynamic_6_sheets", "--analysis", "modes", "--count", "4")
    sim = view(out, "pendulum_simulate", "pendulum", "--analysis", "simulate", "--t-end", "0.5",
               "--output-step", "0.01")

    # 12-truss: one motion, one self-stress, Table 1 row 2; the motion animates, drawn with
    # the wires `flexmbd check` suggests to remove it (its top joint is in no body: no twist)
    r = subprocess.run(flexmbd() + ["check", os.path.join(ROOT, "examples", "twelve_truss.toml"), "--json"],
                       cwd=ROOT, capture_output=True, text=True, timeout=900)
    wires = len(json.loads(r.stdout)["wire_suggestions"][0]["wires"])
    if wires == 0:
        fail("twelve_truss: `flexmbd check` suggests no wire for its motion")
    a = open_page(twelve, "item=0&phase=0.25&paused=1", out, profile, {
        "data-animations": "1", "data-fields": "self_stress_1", "data-table1-row": "2",
        "data-elements": "12", "data-item": "0", "data-screw-lines": str(wires)})
    rect = canvas_rect(a)
    p25 = shot(twelve, "item=0&phase=0.25&paused=1", out, profile, "twelve_phase025", rect)
    p75 = shot(twelve, "item=0&phase=0.75&paused=1", out, profile, "twelve_phase075", rect)
    p0 = shot(twelve, "item=0&phase=0&paused=1", out, profile, "twelve_phase000", rect)
    p50 = shot(twelve, "item=0&phase=0.5&paused=1", out, profile, "twelve_phase050", rect)
    if p25 and p75 and p0 and p50:
        not_blank("twelve_truss motion 1", p25)
        moves("twelve_truss motion 1, phase 0.25 vs 0.75", p25, p75)
        moves("twelve_truss motion 1, phase 0 vs 0.25", p0, p25)
        same("twelve_truss motion 1, phase 0 vs 0.5 (both the reference)", p0, p50)

    # six folded sheets: over-constrained, no motion, one self-stress through every sheet
    a = open_page(six, "paused=1", out, profile, {
        "data-animations": "0", "data-fields": "self_stress_1", "data-table1-row": "3",
        "data-elements": "13", "data-color": "self_stress_1"})
    s1 = shot(six, "paused=1", out, profile, "six_self_stress", canvas_rect(a))
    st = shot(six, "paused=1&color=type", out, profile, "six_element_type", canvas_rect(a))
    if s1 and st:
        not_blank("folded_sheet_guide_6 self-stress", s1)
        not_blank("folded_sheet_guide_6 element type", st)
        moves("folded_sheet_guide_6 colour by self-stress vs element type", s1, st)

    # static stroke: 9 frames, stress fields; the first and last steps differ
    a = open_page(stroke, "paused=1&step=8", out, profile, {
        "data-frames": "9", "data-animations": "0",
        "data-fields": lambda v: v is not None and "max_stress" in v.split()})
    r = canvas_rect(a)
    first = shot(stroke, "paused=1&step=0", out, profile, "stroke_step0", r)
    last = shot(stroke, "paused=1&step=8", out, profile, "stroke_step8", r)
    if first and last:
        not_blank("parallel_leaf_stroke step 8", last)
        moves("parallel_leaf_stroke step 0 vs step 8", first, last)

    # modes: 4 modes with frequencies, strain-energy colouring; mode 1 animates
    a = open_page(modes, "item=0&phase=0.25&paused=1", out, profile, {
        "data-animations": "4", "data-fields": "strain_energy", "data-item": "0"})
    r = canvas_rect(a)
    m25 = shot(modes, "item=0&phase=0.25&paused=1", out, profile, "modes_mode1_phase025", r)
    m75 = shot(modes, "item=0&phase=0.75&paused=1", out, profile, "modes_mode1_phase075", r)
    if m25 and m75:
        not_blank("paper_dynamic_6_sheets mode 1", m25)
        moves("paper_dynamic_6_sheets mode 1, phase 0.25 vs 0.75", m25, m75)

    # simulation: frames at the output times, the tip over time, slider and playback
    simulation_checks(sim, out, profile)

    # every control once, on every report
    for page in (twelve, six, stroke, modes):
        exercise(page, out, profile)
    # the pendulum is one thin bar, which a 9 × 5 grid of clicks can miss
    exercise(sim, out, profile, clicks_select=False)

    # the page of a design study
    study_checks(out, profile)

    # a broken page must be reported: the checks above can fail
    with open(twelve, encoding="utf-8") as f:
        text = f.read()
    broken = os.path.join(out, "broken.html")
    with open(broken, "w", encoding="utf-8") as f:
        f.write(text.replace('"format":1,', '"format":1,,', 1))
    dom, console = browse(broken, "", out, profile)
    attrs, errors, etext, title = status(dom)
    if errors >= 1 and attrs.get("data-state") == "error" and title.startswith("ERROR") and console:
        ok(f"broken.html: the error is reported ({etext.splitlines()[0] if etext else title})")
    else:
        fail(f"broken.html: the error was not reported: errors={errors}, {attrs}, {console}")


if __name__ == "__main__":
    main()
