#!/usr/bin/env python3
"""Drives a report.html's comparison viewer in headless Chromium and checks what it shows.

    python3 scripts/report_browser.py REPORT.html [--shots DIR]       # the checks (exit 1 on a failure)
    python3 scripts/report_browser.py REPORT.html… --measure N [--csv F]   # size and load time, N rounds

The checks press keys and click as a reader does, through the DevTools protocol on a pipe (no
network, no package beyond Python's standard library), and read the answer from the DOM and from
screenshot pixels: after each key or click the stage shows the chosen method's picture; the zoom
panel shows, pixel for pixel, the same crop of two methods' shaded images, upscaled without
smoothing; chart points answer hover and open their method; the page logs nothing to the console,
throws nothing and requests nothing but itself. The last line is `N passed, M failed`.
"""

import argparse
import base64
import json
import os
import shutil
import statistics
import struct
import subprocess
import sys
import tempfile
import time
import zlib

WIDTH, HEIGHT = 1400, 1000


def decode_png(data):
    """(width, height, rows of RGB tuples) of an 8- or 16-bit gray, RGB or RGBA PNG."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, head = 8, b"", None
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            head = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    w, h, depth, colour, _, _, interlace = head
    assert interlace == 0 and depth in (8, 16) and colour in (0, 2, 4, 6), f"PNG kind {depth}-bit colour {colour}"
    channels = {0: 1, 2: 3, 4: 2, 6: 4}[colour]
    bpp = channels * depth // 8
    stride = w * bpp
    raw = zlib.decompress(idat)
    prev = bytearray(stride)
    rows = []
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if f == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 255
        elif f == 2:
            for i in range(stride):
                line[i] = (line[i] + prev[i]) & 255
        elif f == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + prev[i]) >> 1)) & 255
        elif f == 4:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                b = prev[i]
                c = prev[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pred) & 255
        prev = line
        step = depth // 8
        samples = line[::step]  # the high byte of 16-bit samples: what a browser shows
        px = [tuple(samples[i:i + channels]) for i in range(0, len(samples), channels)]
        if colour in (0, 4):
            px = [(p[0], p[0], p[0]) for p in px]
        else:
            px = [p[:3] for p in px]
        rows.append(px)
    return w, h, rows


def png_of_uri(uri):
    assert uri.startswith("data:image/png;base64,"), uri[:40]
    return decode_png(base64.b64decode(uri.split(",", 1)[1]))


class Browser:
    """Headless Chromium over --remote-debugging-pipe: commands on fd 3, answers and events on fd 4."""

    def __init__(self, chrome):
        to_chrome_r, self._to_chrome = os.pipe()
        self._from_chrome, from_chrome_w = os.pipe()
        self.profile = tempfile.mkdtemp(prefix="report-browser-")

        def fds():
            os.dup2(to_chrome_r, 3)
            os.dup2(from_chrome_w, 4)

        flags = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run", "--disable-extensions", f"--user-data-dir={self.profile}",
                 "--host-resolver-rules=MAP * ~NOTFOUND", "--force-color-profile=srgb", "--hide-scrollbars",
                 f"--window-size={WIDTH},{HEIGHT}", "--remote-debugging-pipe", "about:blank"]
        self.proc = subprocess.Popen([chrome] + flags, preexec_fn=fds, pass_fds=(3, 4), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(to_chrome_r)
        os.close(from_chrome_w)
        self._buf = b""
        self._id = 0
        self.events = []
        self.session = None
        targets = self.call("Target.getTargets")["targetInfos"]
        page = next(t for t in targets if t["type"] == "page")
        self.session = self.call("Target.attachToTarget", targetId=page["targetId"], flatten=True)["sessionId"]
        for domain in ("Page", "Runtime", "Log", "Network"):
            self.call(domain + ".enable")
        self.call("Emulation.setDeviceMetricsOverride", width=WIDTH, height=HEIGHT, deviceScaleFactor=1, mobile=False)

    def _read(self, deadline):
        while b"\0" not in self._buf:
            if time.time() > deadline:
                raise TimeoutError("Chromium did not answer")
            chunk = os.read(self._from_chrome, 1 << 20)
            if not chunk:
                raise RuntimeError("Chromium closed the pipe")
            self._buf += chunk
        msg, self._buf = self._buf.split(b"\0", 1)
        return json.loads(msg)

    def call(self, method, timeout=120, **params):
        self._id += 1
        msg = {"id": self._id, "method": method, "params": params}
        if self.session and not method.startswith("Target."):
            msg["sessionId"] = self.session
        os.write(self._to_chrome, json.dumps(msg).encode() + b"\0")
        deadline = time.time() + timeout
        while True:
            m = self._read(deadline)
            if m.get("id") == self._id:
                if "error" in m:
                    raise RuntimeError(f"{method}: {m['error']}")
                return m.get("result", {})
            if "method" in m:
                self.events.append(m)

    def wait_event(self, name, timeout=120):
        deadline = time.time() + timeout
        for i, e in enumerate(self.events):
            if e["method"] == name:
                return self.events.pop(i)
        while True:
            m = self._read(deadline)
            if m.get("method") == name:
                return m
            if "method" in m:
                self.events.append(m)

    def open(self, path):
        self.call("Page.navigate", url="file://" + os.path.abspath(path))
        self.wait_event("Page.loadEventFired")

    def eval(self, expression):
        r = self.call("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in r:
            raise RuntimeError(f"{expression[:80]}: {r['exceptionDetails']}")
        return r["result"].get("value")

    def key(self, key):
        codes = {"ArrowRight": 39, "ArrowLeft": 37, "Escape": 27}
        params = {"key": key, "windowsVirtualKeyCode": codes.get(key, ord(key.upper()[0]))}
        if len(key) == 1:
            params["text"] = key
            params["code"] = ("Digit" + key) if key.isdigit() else ("Key" + key.upper() if key.isalpha() else "")
        else:
            params["code"] = key
        self.call("Input.dispatchKeyEvent", type="keyDown", **params)
        self.call("Input.dispatchKeyEvent", type="keyUp", **{k: v for k, v in params.items() if k != "text"})

    def mouse(self, x, y, click=True):
        self.call("Input.dispatchMouseEvent", type="mouseMoved", x=x, y=y)
        if click:
            self.call("Input.dispatchMouseEvent", type="mousePressed", x=x, y=y, button="left", clickCount=1)
            self.call("Input.dispatchMouseEvent", type="mouseReleased", x=x, y=y, button="left", clickCount=1)

    def settle(self):
        # Two animation frames: the viewer redraws in one.
        self.eval("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")

    def shot(self, rect=None, path=None):
        """PNG bytes of the viewport, or of `rect` (x, y, w, h in page coordinates)."""
        params = {"format": "png"}
        if rect:
            x, y, w, h = rect
            params["clip"] = {"x": x, "y": y, "width": w, "height": h, "scale": 1}
        data = base64.b64decode(self.call("Page.captureScreenshot", **params)["data"])
        if path:
            with open(path, "wb") as f:
                f.write(data)
        return data

    def problems(self):
        """Console messages, exceptions, log errors and requests for anything but the page itself."""
        self.settle()
        out = []
        for e in self.events:
            m, p = e["method"], e.get("params", {})
            if m == "Runtime.consoleAPICalled":
                out.append(f"console.{p['type']}: {[a.get('value', a.get('description')) for a in p.get('args', [])]}")
            elif m == "Runtime.exceptionThrown":
                out.append(f"exception: {p['exceptionDetails'].get('text')} {p['exceptionDetails'].get('exception', {}).get('description', '')}")
            elif m == "Log.entryAdded" and p["entry"]["level"] in ("error", "warning"):
                out.append(f"log {p['entry']['level']}: {p['entry']['text']} {p['entry'].get('url', '')}")
            elif m == "Network.requestWillBeSent":
                url = p["request"]["url"]
                if not url.startswith(("data:", "file:")):
                    out.append(f"request: {url}")
            elif m == "Network.loadingFailed":
                out.append(f"failed load: {p.get('errorText')}")
        return out

    def close(self):
        try:
            self.call("Browser.close", timeout=10)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        shutil.rmtree(self.profile, ignore_errors=True)


class Checks:
    def __init__(self):
        self.passed, self.failed = 0, 0

    def check(self, ok, what):
        if ok:
            self.passed += 1
            print(f"ok: {what}")
        else:
            self.failed += 1
            print(f"FAIL: {what}")
        return ok


VIEWER = "document.querySelectorAll('.viewer.live')[{v}]"


def state(b, v):
    return b.eval(f"(() => {{ const r = {VIEWER.format(v=v)}; return [r.dataset.current, r.dataset.layer, r.dataset.overlay, r.dataset.crop]; }})()")


def shown_is(b, v, label, layer):
    """Whether the stage shows `label`'s `layer` picture: the stage image is that figure's image."""
    js = f"""(() => {{
      const r = {VIEWER.format(v=v)};
      const item = [...r.querySelectorAll(':scope > .v-item')].find(i => i.dataset.label === {json.dumps(label)});
      const fig = item && item.querySelector('figure[data-layer={json.dumps(layer)}] img');
      return !!fig && r.querySelector('.v-stage .v-img').src === fig.src;
    }})()"""
    return b.eval(js)


def rect(b, selector_js, inner=False):
    """Page coordinates (x, y, w, h) of an element, then its viewport (x, y), after scrolling it
    into view; `inner`: of its content, inside the border."""
    return b.eval(f"""(() => {{ const e = {selector_js}; e.scrollIntoView({{block: 'center'}});
      const r = e.getBoundingClientRect();
      const [dx, dy, w, h] = {'true' if inner else 'false'} ? [e.clientLeft, e.clientTop, e.clientWidth, e.clientHeight] : [0, 0, r.width, r.height];
      return [r.left + dx + scrollX, r.top + dy + scrollY, w, h, r.left + dx, r.top + dy]; }})()""")


def choose(b, v, k):
    """Item k of viewer v: by its number key where one reaches it, else by clicking its name."""
    if k <= 9:
        b.key(str(k))
        return
    _, _, pw, ph, px, py = rect(b, f"{VIEWER.format(v=v)}.querySelectorAll('.v-pick')[{k}]")
    b.mouse(px + pw / 2, py + ph / 2)


def crop_pixels(png, x0, y0, side):
    _, _, rows = png
    return [row[x0:x0 + side] for row in rows[y0:y0 + side]]


def upscaled_matches(shot_png, crop, scale):
    """Largest channel difference between a screenshot and `crop` upscaled `scale` times, nearest."""
    w, h, rows = shot_png
    worst = 0
    for y in range(h):
        src = crop[y // scale]
        out = rows[y]
        for x in range(w):
            a, b = out[x], src[x // scale]
            worst = max(worst, abs(a[0] - b[0]), abs(a[1] - b[1]), abs(a[2] - b[2]))
    return worst


def most_different_spot(a, b, side):
    """Top-left of the side × side window (on a coarse grid) where two pictures differ the most."""
    w, h, ra = a
    _, _, rb = b
    best, at = -1, (0, 0)
    for y0 in range(0, h - side + 1, side // 2):
        for x0 in range(0, w - side + 1, side // 2):
            d = 0
            for y in range(y0, y0 + side, 2):
                pa, pb = ra[y], rb[y]
                for x in range(x0, x0 + side, 2):
                    d += abs(pa[x][0] - pb[x][0]) + abs(pa[x][1] - pb[x][1]) + abs(pa[x][2] - pb[x][2])
            if d > best:
                best, at = d, (x0, y0)
    return at, best


def run_checks(b, html, shots):
    c = Checks()
    b.open(html)
    b.settle()
    counted = b.eval("document.querySelectorAll('.viewer').length")
    live = b.eval("Number(document.documentElement.dataset.viewers || -1)")
    c.check(counted > 0 and live == counted, f"the script made every viewer live ({live} of {counted})")
    if shots:
        b.shot(path=os.path.join(shots, "at-rest.png"))
    # A compare's viewer: the reference and methods with shaded images (a failure gallery has none).
    methods = b.eval("!!document.querySelector('.viewer.live > .v-item[data-reference] + .v-item figure[data-layer=shaded]')")
    if methods:
        methods_viewer(b, c, shots)
    else:
        print("(no compare viewer on this page: the per-viewer checks only)")
    other_viewers(b, c, counted, 1 if methods else 0, shots)
    problems = b.problems()
    c.check(not problems, "no console message, exception, failed load or request: " + ("; ".join(problems) or "none"))
    return c


def methods_viewer(b, c, shots):
    """The compare viewer (the first on the page): keys, clicks, the overlay, the zoom, the charts."""
    labels = b.eval(f"[...{VIEWER.format(v=0)}.querySelectorAll(':scope > .v-item')].map(i => i.dataset.label)")
    c.check(labels[0] == "reference" and len(labels) >= 3, f"the main viewer lists the reference and the methods: {labels}")
    cur = state(b, 0)
    c.check(cur[0] == labels[1] and shown_is(b, 0, labels[1], "shaded"), f"at rest it shows the first method's shaded image ({cur})")
    rect(b, VIEWER.format(v=0))
    # Keys go to the viewer most in view until one is clicked.
    steps = [("2", labels[2], "shaded"), ("0", "reference", "shaded"), ("ArrowRight", labels[1], "shaded"),
             ("v", labels[1], "visibility"), ("e", labels[1], "abs_error"), ("ArrowLeft", "reference", "shaded"),
             ("1", labels[1], "abs_error"), ("s", labels[1], "shaded")]
    for key, label, layer in steps:
        b.key(key)
        b.settle()
        cur = state(b, 0)
        c.check(cur[0] == label and cur[1] == layer and shown_is(b, 0, label, layer), f"key {key!r}: the stage shows {label} / {layer} (DOM says {cur[:2]})")
    b.key("o")
    b.settle()
    over = b.eval(f"""(() => {{ const r = {VIEWER.format(v=0)}; const item = [...r.querySelectorAll(':scope > .v-item')][1];
      const o = r.querySelector('.v-over'); return !r.querySelector('.v-overclip').hidden && o.src === item.querySelector('figure[data-layer=abs_error] img').src; }})()""")
    c.check(state(b, 0)[2] == "on" and over, "key 'o': the method's |error| map lies over its shaded image")
    b.key("o")
    # A click on a method's name.
    pick = len(labels) - 1
    _, _, w, h, x, y = rect(b, f"{VIEWER.format(v=0)}.querySelectorAll('.v-pick')[{pick}]")
    b.mouse(x + w / 2, y + h / 2)
    b.settle()
    c.check(state(b, 0)[0] == labels[pick] and shown_is(b, 0, labels[pick], "shaded"), f"a click on {labels[pick]!r} shows it")
    if shots:
        b.shot(path=os.path.join(shots, "switched.png"))

    # The zoom: the crop around the place where two methods differ most, the same pixels in both.
    uri = lambda label: b.eval(f"""[...{VIEWER.format(v=0)}.querySelectorAll(':scope > .v-item')].find(i => i.dataset.label === {json.dumps(label)}).querySelector('figure[data-layer=shaded] img').src""")
    a_label, b_label = labels[1], labels[-1]
    pa, pb = png_of_uri(uri(a_label)), png_of_uri(uri(b_label))
    side = int(state(b, 0)[3].split(",")[2])
    (x0, y0), diff = most_different_spot(pa, pb, side)
    c.check(diff > 0, f"{a_label} and {b_label} differ around ({x0}, {y0}), so the zoom can tell them apart")
    sx, sy, sw, sh, vx, vy = rect(b, f"{VIEWER.format(v=0)}.querySelector('.v-stage .v-img')")
    scale = sw / pa[0]
    cx, cy = x0 + side / 2, y0 + side / 2
    b.mouse(vx + cx * scale, vy + cy * scale)
    b.settle()
    crop = [int(v) for v in state(b, 0)[3].split(",")]
    # The viewer's own rule: the crop centred on the clicked pixel, kept inside the picture.
    u, v = (cx * scale) / sw, (cy * scale) / sw
    want_x = max(0, min(pa[0] - side, round(u * pa[0] - side / 2)))
    want_y = max(0, min(pa[1] - side, round(v * pa[0] - side / 2)))
    c.check(abs(crop[0] - want_x) <= 1 and abs(crop[1] - want_y) <= 1, f"the click fixed the crop at the clicked pixel: {crop[:2]} (expected {want_x}, {want_y})")
    zoom = crop[3]
    for label, png, name in ((a_label, pa, "zoomed-a.png"), (b_label, pb, "zoomed-b.png")):
        choose(b, 0, labels.index(label))
        b.settle()
        now = state(b, 0)
        c.check(now[0] == label and [int(v) for v in now[3].split(",")] == crop, f"switching to {label} keeps the crop {crop[:3]}")
        zx, zy, zw, zh, _, _ = rect(b, f"{VIEWER.format(v=0)}.querySelector('.v-zoom')", inner=True)
        shot = decode_png(b.shot((zx, zy, zw, zh), os.path.join(shots, name) if shots else None))
        worst = upscaled_matches(shot, crop_pixels(png, crop[0], crop[1], crop[2]), zoom)
        other = pb if png is pa else pa
        apart = upscaled_matches(shot, crop_pixels(other, crop[0], crop[1], crop[2]), zoom)
        c.check(shot[0] == crop[2] * zoom and worst == 0, f"the zoom shows {label}'s pixels {crop[0]}..{crop[0] + crop[2] - 1} × {crop[1]}..{crop[1] + crop[2] - 1} at {zoom}×, nearest-neighbour (largest difference {worst})")
        c.check(apart > 0, f"and not the other method's (difference {apart})")
    # The strip shows every method's crop at once: the first method's cell is its own pixels.
    sx, sy, sw, sh, _, _ = rect(b, f"{VIEWER.format(v=0)}.querySelectorAll('.v-strip canvas')[1]", inner=True)
    strip = decode_png(b.shot((sx, sy, sw, sh)))
    factor = strip[0] // crop[2]
    c.check(factor >= 1 and upscaled_matches(strip, crop_pixels(pa, crop[0], crop[1], crop[2]), factor) == 0, f"the strip's cell of {a_label} shows the same crop")
    if shots:
        b.shot(path=os.path.join(shots, "zoomed.png"))

    # Chart points: a tooltip on hover and focus, and a click opens the method in the viewer.
    hits = b.eval("document.querySelectorAll('svg .hit').length")
    if c.check(hits > 0, f"the charts carry {hits} answering points"):
        target = b.eval("document.querySelector('svg .hit').dataset.label")
        hx, hy, hw, hh, vx, vy = rect(b, "document.querySelector('svg .hit')")
        b.mouse(vx + hw / 2, vy + hh / 2, click=False)
        b.settle()
        tip = b.eval("(() => { const t = document.querySelector('.v-tip'); return t && !t.hidden ? t.textContent : ''; })()")
        c.check(target in tip and "RMSE" in tip and "FLIP" in tip and " map" in tip and " ms" in tip, f"hovering a point shows its figures: {tip!r}")
        if shots:
            b.shot(path=os.path.join(shots, "chart-hover.png"))
        b.mouse(vx + hw / 2, vy + hh / 2)
        b.settle()
        c.check(state(b, 0)[0] == target, f"clicking the point of {target} opens it in the viewer")
        b.eval("document.querySelectorAll('svg .hit')[1].focus()")
        b.settle()
        second = b.eval("document.querySelectorAll('svg .hit')[1].dataset.label")
        tip = b.eval("(() => { const t = document.querySelector('.v-tip'); return t && !t.hidden ? t.textContent : ''; })()")
        c.check(second in tip, f"focusing a point shows its figures: {tip!r}")
        titles = b.eval("[...document.querySelectorAll('svg .hit')].every(h => h.querySelector('title') && h.querySelector('title').textContent.includes('RMSE'))")
        c.check(titles, "every point also has a <title>, which a reader without scripts shows")



def other_viewers(b, c, counted, first, shots):
    """Every other viewer (failure gallery, per-region pictures) switches by key after a click in it."""
    for v in range(first, counted):
        lab = b.eval(f"[...{VIEWER.format(v=v)}.querySelectorAll(':scope > .v-item')].map(i => [i.dataset.label, i.hasAttribute('data-reference')])")
        x, y, w, h, vx, vy = rect(b, f"{VIEWER.format(v=v)}.querySelector('.v-caption')")
        b.mouse(vx + 2, vy + 2)
        base = 0 if lab[0][1] else 1
        k = min(len(lab) - 1, 2)
        b.key(str(k + base))
        b.settle()
        cur = state(b, v)
        name = b.eval(VIEWER.format(v=v) + ".getAttribute('aria-label')")
        c.check(cur[0] == lab[k][0] and shown_is(b, v, lab[k][0], cur[1]), f"viewer {v + 1} ({name}): key {k + base} shows {lab[k][0]}")
        if shots and v == first:
            b.shot(path=os.path.join(shots, f"viewer-{v + 1}.png"))


SCROLL_TO_IMAGES = """(async () => {
  const frame = () => new Promise(r => requestAnimationFrame(r));
  const to = document.querySelector('.viewer') || [...document.querySelectorAll('h2')].find(h => h.textContent === 'Images');
  const t = performance.now();
  to.scrollIntoView();
  for (let i = 0; i < 3; i++) await frame();
  return performance.now() - t;
})()"""


def load_once(chrome, html):
    """(load event, DOMContentLoaded, first frames drawn, images shown) in ms on the page's clock,
    in a fresh browser; the last is the time from scrolling to the images (the first viewer, or the
    Images heading of a page without one) to three frames later, when the viewer has drawn its zoom
    and every method's crop."""
    b = Browser(chrome)
    try:
        b.open(html)
        nav = b.eval("JSON.parse(JSON.stringify(performance.getEntriesByType('navigation')[0]))")
        b.settle()
        drawn = b.eval("performance.now()")
        shown = b.eval(SCROLL_TO_IMAGES)
        problems = b.problems()
        if problems:
            print("problems:", problems)
        return nav["loadEventEnd"], nav["domContentLoadedEventEnd"], drawn, shown
    finally:
        b.close()


def measure(chrome, pages, runs, csv=None, labels=()):
    """Median load figures of each page over `runs` rounds, the pages interleaved round by round
    (so they see the same machine load), each load in a fresh browser; `csv`: a row per page."""
    figures = {p: [] for p in pages}
    for r in range(runs):
        for p in pages:
            figures[p].append(load_once(chrome, p))
            load, dcl, drawn, shown = figures[p][-1]
            print(f"  round {r + 1}: {p}: load {load:.0f} ms, DOMContentLoaded {dcl:.0f} ms, drawn {drawn:.0f} ms, images shown {shown:.0f} ms")
    version = subprocess.run([chrome, "--version"], capture_output=True, text=True).stdout.strip()
    for i, p in enumerate(pages):
        size = os.path.getsize(p)
        imgs = open(p, encoding="utf-8").read().count("<img ")
        load, dcl, drawn, shown = (statistics.median(f[k] for f in figures[p]) for k in range(4))
        print(f"{p}: {size} bytes ({size / 2**20:.2f} MiB), {imgs} <img>; median of {runs}: load event {load:.0f} ms, "
              f"DOMContentLoaded {dcl:.0f} ms, first frames drawn {drawn:.0f} ms, images shown {shown:.0f} ms after the scroll "
              f"(performance clock, headless {version})")
        if csv:
            new = not os.path.exists(csv)
            with open(csv, "a", encoding="utf-8") as f:
                if new:
                    f.write("report,bytes,img,runs,load_ms,dom_content_loaded_ms,drawn_ms,images_shown_ms,browser\n")
                label = labels[i] if i < len(labels) else p
                f.write(f"{label},{size},{imgs},{runs},{load:.0f},{dcl:.0f},{drawn:.0f},{shown:.0f},{version}\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("html", nargs="+", help="the report (several with --measure: measured interleaved)")
    ap.add_argument("--shots", help="folder for the screenshots (at rest, switched, zoomed)")
    ap.add_argument("--measure", type=int, default=0, help="only measure: size and median load time over N fresh loads")
    ap.add_argument("--csv", help="with --measure: append a row (report, bytes, medians) to this CSV file")
    ap.add_argument("--labels", default="", help="with --csv: the rows' names for the reports, comma-separated")
    ap.add_argument("--chrome", default=os.environ.get("CHROMIUM", "chromium"))
    args = ap.parse_args()
    if not shutil.which(args.chrome):
        sys.exit(f"error: {args.chrome} not found: apt-get install -y chromium (bash scripts/setup.sh installs it)")
    if args.measure:
        measure(args.chrome, args.html, args.measure, args.csv, [l for l in args.labels.split(",") if l])
        return
    if len(args.html) != 1:
        sys.exit("error: the checks take one report")
    if args.shots:
        os.makedirs(args.shots, exist_ok=True)
    b = Browser(args.chrome)
    try:
        c = run_checks(b, args.html[0], args.shots)
    finally:
        b.close()
    print(f"{c.passed} passed, {c.failed} failed")
    sys.exit(1 if c.failed else 0)


if __name__ == "__main__":
    main()
