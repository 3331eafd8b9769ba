#!/usr/bin/env python3
"""The preview's real-browser test: Debian's chromium, headless, driven over
the DevTools protocol (on a pipe: no extra package), loads web/dist from a
static server on 127.0.0.1 and uses the page as a person would (its
controls, its Render button, its file input). Checks that

- the demo scene gives targets/checksums.txt's checksums and ray counts
  (f32 at packet widths 4 and 1, fixed32, RGB888 and panel RGB565 output);
- SPD scenes (balls-2, gears-1, teapot-1) at both scalars, and an AOV,
  give the checksums and ray counts of the host's `raypack render`;
- the bytes the page received (its output stream) and the pixels on its
  canvas are those checksums;
- a malformed scene shows the CLI's one-line error, with line and column;
  a scene without a camera and one over the preview's capacity are clear
  errors; a render afterwards still works;
- the page stays responsive during a render (a timer on the main thread
  keeps running) and the bands arrive one by one.

    python3 web/test/browser_test.py --dist web/dist --raypack target/debug/raypack --chromium /usr/bin/chromium

With --bench: renders balls-2 with packets of 4 and 1 rays, interleaved,
and prints the page's own render times and rays/s (docs/web.md).
"""
import argparse
import functools
import http.server
import json
import os
import re
import select
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
RENDER_TIMEOUT = 180  # seconds for one render in the page
FAILURES = []


def log(msg):
    print(msg, flush=True)


def check(cond, what):
    log(("ok    " if cond else "FAIL  ") + what)
    if not cond:
        FAILURES.append(what)


# ---------------------------------------------------------------- host side


def fnv1a(data, h=0x811C9DC5):
    for b in data:
        h = ((h ^ b) * 0x01000193) & 0xFFFFFFFF
    return h


BAYER4 = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]]


def quantize(v, bits, x, y):
    """src/render/bands.rs `quantize` with the Bayer 4x4 dither, written again."""
    m = (1 << bits) - 1
    rank = BAYER4[y & 3][x & 3]
    return min(m, (2 * 16 * m * v + (2 * rank + 1) * 255) // (2 * 16 * 255))


def rgb565_stream(rgb, width):
    out = bytearray()
    for i in range(0, len(rgb), 3):
        x, y = (i // 3) % width, (i // 3) // width
        r, g, b = rgb[i], rgb[i + 1], rgb[i + 2]
        p = (quantize(r, 5, x, y) << 11) | (quantize(g, 6, x, y) << 5) | quantize(b, 5, x, y)
        out += bytes((p >> 8, p & 0xFF))
    return bytes(out)


def read_ppm(path):
    data = open(path, "rb").read()
    fields, i = [], 0
    while len(fields) < 4:
        while data[i:i + 1].isspace():
            i += 1
        j = i
        while not data[j:j + 1].isspace():
            j += 1
        fields.append(data[i:j])
        i = j
    if fields[0] != b"P6" or fields[3] != b"255":
        raise ValueError(f"{path}: not an 8-bit P6 PPM")
    w, h = int(fields[1]), int(fields[2])
    return w, h, data[i + 1:i + 1 + 3 * w * h]


def host_render(raypack, scene, width, height, scalar, aov="color"):
    """Checksums and rays of the host CLI's render of `scene`."""
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "out.ppm")
        cmd = [raypack, "render", scene, "--width", str(width), "--height", str(height), "--scalar", scalar,
               "--aov", aov, "-o", out]
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        if r.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)}: {r.stderr.strip()}")
        m = re.search(r"rays: (\d+) primary, (\d+) shadow, (\d+) reflected, (\d+) refracted", r.stderr)
        if not m:
            raise RuntimeError(f"no ray counts in: {r.stderr}")
        w, h, rgb = read_ppm(out)
        rays = [int(v) for v in m.groups()]
        return {"rgb888": fnv1a(rgb), "rgb565": fnv1a(rgb565_stream(rgb, w)), "rays": rays + [sum(rays)]}


def host_error(raypack, name, text):
    """The CLI's error line for a scene file `name` holding `text` (`-`:
    the text on standard input)."""
    with tempfile.TemporaryDirectory() as d:
        if name != "-":
            open(os.path.join(d, name), "wb").write(text)
        r = subprocess.run([raypack, "render", name, "-o", "out.ppm"], cwd=d, input=text if name == "-" else None,
                           capture_output=True, timeout=120)
        r.stderr = r.stderr.decode()
        lines = r.stderr.strip().splitlines()
        if r.returncode != 1 or len(lines) != 1:
            raise RuntimeError(f"expected one error line and exit code 1 from the CLI, got {r.returncode}: {r.stderr}")
        return lines[0]


def demo_checksums():
    """targets/checksums.txt: {scalar: {rgb888, rgb565, rays}}."""
    out = {}
    for line in open(os.path.join(ROOT, "targets", "checksums.txt")):
        f = line.split()
        if len(f) == 3 and not line.startswith("#"):
            out.setdefault(f[0], {})[f[1]] = int(f[2], 0)
    return out


# ---------------------------------------------------------------- browser


class Quiet(http.server.SimpleHTTPRequestHandler):
    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map, ".wasm": "application/wasm",
                      ".js": "text/javascript", ".nff": "text/plain"}

    def log_message(self, *args):
        pass


def serve(directory):
    handler = functools.partial(Quiet, directory=directory)
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server


class Chromium:
    """Headless chromium and the DevTools protocol over
    --remote-debugging-pipe (fd 3: commands in, fd 4: replies out, each
    message JSON ending in a NUL byte)."""

    def __init__(self, exe, profile):
        to_child_r, self.to_child = os.pipe()
        self.from_child, from_child_w = os.pipe()
        # Out of the way of fds 3 and 4, which the child needs.
        a, b = os.dup2(to_child_r, 100), os.dup2(from_child_w, 101)
        os.close(to_child_r)
        os.close(from_child_w)

        def child():
            os.dup2(a, 3)
            os.dup2(b, 4)
            os.close(a)
            os.close(b)

        args = [exe, "--headless", "--remote-debugging-pipe", "--no-sandbox", "--disable-gpu",
                "--disable-dev-shm-usage", "--no-first-run", "--no-default-browser-check", "--disable-extensions",
                "--disable-background-timer-throttling", "--disable-renderer-backgrounding",
                "--disable-backgrounding-occluded-windows", f"--user-data-dir={profile}", "about:blank"]
        self.stderr = open(os.path.join(profile, "chromium.log"), "wb")
        self.proc = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=self.stderr, stderr=self.stderr,
                                     preexec_fn=child, close_fds=False)
        os.close(a)
        os.close(b)
        self.buf = b""
        self.next_id = 0
        self.events = []
        self.session = None

    def send(self, method, params=None, session=True, timeout=60):
        self.next_id += 1
        msg = {"id": self.next_id, "method": method, "params": params or {}}
        if session and self.session:
            msg["sessionId"] = self.session
        os.write(self.to_child, json.dumps(msg).encode() + b"\0")
        deadline = time.monotonic() + timeout
        while True:
            reply = self.read(deadline, method)
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def read(self, deadline, what):
        while b"\0" not in self.buf:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError(f"chromium did not answer {what} in time")
            if self.proc.poll() is not None:
                raise RuntimeError(f"chromium exited with {self.proc.returncode} (see its log)")
            ready, _, _ = select.select([self.from_child], [], [], min(left, 1.0))
            if ready:
                chunk = os.read(self.from_child, 1 << 20)
                if not chunk:
                    raise RuntimeError("chromium closed the DevTools pipe")
                self.buf += chunk
        msg, self.buf = self.buf.split(b"\0", 1)
        return json.loads(msg)

    def open(self, url):
        target = self.send("Target.createTarget", {"url": "about:blank"}, session=False)["targetId"]
        self.session = self.send("Target.attachToTarget", {"targetId": target, "flatten": True},
                                 session=False)["sessionId"]
        self.send("Runtime.enable")
        self.send("Page.enable")
        self.send("DOM.enable")
        self.send("Page.navigate", {"url": url})

    def eval(self, expression, timeout=RENDER_TIMEOUT):
        r = self.send("Runtime.evaluate", {"expression": expression, "awaitPromise": True, "returnByValue": True},
                      timeout=timeout + 30)
        if "exceptionDetails" in r:
            d = r["exceptionDetails"]
            raise RuntimeError(f"in the page: {d.get('exception', {}).get('description') or d.get('text')}")
        return r["result"].get("value")

    def console(self):
        """What the page logged or threw (for failure reports)."""
        out = []
        for e in self.events:
            if e.get("method") == "Runtime.consoleAPICalled":
                out.append(" ".join(str(a.get("value", a.get("description", ""))) for a in e["params"]["args"]))
            elif e.get("method") == "Runtime.exceptionThrown":
                out.append(e["params"]["exceptionDetails"].get("exception", {}).get("description", ""))
        return out

    def close(self):
        try:
            self.send("Browser.close", session=False, timeout=10)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.stderr.close()


# In the page: helpers to wait, to set the controls and to render.
PAGE_JS = r"""
window.__t = {
  sleep: (ms) => new Promise((r) => setTimeout(r, ms)),
  async until(pred, ms, what) {
    const t0 = performance.now();
    while (!pred()) {
      if (performance.now() - t0 > ms) throw new Error(`timed out after ${ms} ms waiting for ${what}`);
      await this.sleep(20);
    }
  },
  set(id, value) {
    const e = document.getElementById(id);
    e.value = String(value);
    e.dispatchEvent(new Event('change'));
  },
  fnv(bytes) {
    let h = 0x811c9dc5;
    for (let i = 0; i < bytes.length; i++) h = Math.imul(h ^ bytes[i], 0x01000193) >>> 0;
    return '0x' + h.toString(16).padStart(8, '0');
  },
  // The canvas pixels as the output format would give them: RGB888 bytes,
  // or for RGB565 the stream expanded as the page shows it.
  canvasMatches(c) {
    const ctx = document.getElementById('image').getContext('2d');
    const px = ctx.getImageData(0, 0, c.width, c.height).data;
    for (let i = 0, n = c.width * c.height; i < n; i++) {
      let want;
      if (c.job.output === 1) {
        const p = (c.stream[2 * i] << 8) | c.stream[2 * i + 1];
        const r = (p >> 11) & 31, g = (p >> 5) & 63, b = p & 31;
        want = [(r << 3) | (r >> 2), (g << 2) | (g >> 4), (b << 3) | (b >> 2)];
      } else {
        want = [c.stream[3 * i], c.stream[3 * i + 1], c.stream[3 * i + 2]];
      }
      if (px[4 * i] !== want[0] || px[4 * i + 1] !== want[1] || px[4 * i + 2] !== want[2] || px[4 * i + 3] !== 255)
        return false;
    }
    return true;
  },
  async render(o, ms) {
    if (o.scene !== undefined) this.set('scene', o.scene);
    if (o.text !== undefined) document.getElementById('text').value = o.text;
    for (const k of ['width', 'height', 'packet', 'scalar', 'output', 'aov']) if (o[k] !== undefined) this.set(k, o[k]);
    const before = window.raypackLast;
    let last = performance.now(), maxGap = 0;
    const timer = setInterval(() => { const t = performance.now(); maxGap = Math.max(maxGap, t - last); last = t; }, 10);
    try {
      document.getElementById('render').click();
      await this.until(() => window.raypackLast !== before && window.raypackLast.finished &&
        ['done', 'error'].includes(document.body.dataset.state), ms, 'the render');
    } finally {
      clearInterval(timer);
    }
    const c = window.raypackLast;
    const out = { state: document.body.dataset.state, error: document.getElementById('error').textContent, maxGap };
    if (out.state !== 'done') return out;
    return Object.assign(out, {
      width: c.width, height: c.height, packet: c.packet, ms: c.ms, rays: c.rays, rgb888: c.rgb888, rgb565: c.rgb565,
      streamFnv: c.streamFnv, streamBytes: c.streamAt, bands: c.bands, totalBands: c.totalBands,
      firstBandBeforeDone: c.progressAt.length > 1 && c.progressAt[0] < c.doneAt - 1,
      checksumText: document.getElementById('checksum').textContent,
      raysText: document.getElementById('rays').textContent,
      canvas: this.canvasMatches(c),
    });
  },
};
true
"""


def render(browser, **o):
    return browser.eval(f"window.__t.render({json.dumps(o)}, {RENDER_TIMEOUT * 1000})")


def hx(v):
    return f"0x{v:08x}"


def check_render(label, got, want, output="rgb888"):
    if got.get("state") != "done":
        check(False, f"{label}: rendered (page says: {got.get('error')})")
        return
    same = (got["rgb888"], got["rgb565"], got["rays"]) == (hx(want["rgb888"]), hx(want["rgb565"]), want["rays"])
    check(same, f"{label}: rgb888 {got['rgb888']} rgb565 {got['rgb565']} rays {got['rays'][4]} "
                f"(host: {hx(want['rgb888'])} {hx(want['rgb565'])} {want['rays'][4]}), {got['ms']:.0f} ms in the page")
    stream = hx(want["rgb565"] if output == "rgb565" else want["rgb888"])
    bpp = 2 if output == "rgb565" else 3
    check(got["streamFnv"] == stream and got["streamBytes"] == got["width"] * got["height"] * bpp,
          f"{label}: the {output} stream the page received hashes to {got['streamFnv']}")
    check(got["canvas"], f"{label}: the canvas shows those pixels")
    check(got["checksumText"].startswith(stream), f"{label}: the page shows checksum {got['checksumText']}")


def wait_ready(browser):
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        state = browser.eval("document.body ? document.body.dataset.state : 'none'", timeout=10)
        if state in ("done", "error"):
            return state
        time.sleep(0.2)
    raise TimeoutError("the page did not finish its first render in 120 s")


def run_tests(browser, raypack):
    demo = demo_checksums()
    for scalar, code, packet in (("f32", 0, 4), ("f32", 0, 1), ("fixed32", 1, 4)):
        want = {k: demo[scalar][k] for k in ("rgb888", "rgb565-bayer4", "rays")}
        got = render(browser, scene="demo", width=160, height=128, packet=packet, scalar=code, output=0, aov=0)
        label = f"demo {scalar} packet {packet} (RGB888) vs targets/checksums.txt"
        if got.get("state") == "done":
            check((got["rgb888"], got["rgb565"], got["rays"][4]) == (hx(want["rgb888"]), hx(want["rgb565-bayer4"]),
                                                                    want["rays"]),
                  f"{label}: rgb888 {got['rgb888']} rgb565 {got['rgb565']} rays {got['rays'][4]}")
            check(got["streamFnv"] == hx(want["rgb888"]) and got["canvas"], f"{label}: stream and canvas")
            check(got["packet"] == (packet if scalar == "f32" else 1), f"{label}: traced packet {got['packet']}")
        else:
            check(False, f"{label}: rendered (page says: {got.get('error')})")
    for scalar, code in (("f32", 0), ("fixed32", 1)):
        got = render(browser, scene="demo", width=160, height=128, packet=4, scalar=code, output=1, aov=0)
        label = f"demo {scalar} panel RGB565 output vs targets/checksums.txt"
        ok = got.get("state") == "done" and got["streamFnv"] == hx(demo[scalar]["rgb565-bayer4"]) and got["canvas"]
        check(ok and got["checksumText"].startswith(hx(demo[scalar]["rgb565-bayer4"])),
              f"{label}: stream {got.get('streamFnv')}, page shows {got.get('checksumText')}")

    size = (120, 90)
    for scene in ("balls-2", "gears-1", "teapot-1"):
        path = os.path.join(ROOT, "tests", "scenes", f"{scene}.nff")
        for scalar, code in (("f32", 0), ("fixed32", 1)):
            want = host_render(raypack, path, *size, scalar)
            for output in ((0, "rgb888"), (1, "rgb565")) if scalar == "f32" else ((0, "rgb888"),):
                got = render(browser, scene=scene, width=size[0], height=size[1], packet=4, scalar=code,
                             output=output[0], aov=0)
                check_render(f"{scene} {scalar} {output[1]} vs the host CLI", got, want, output[1])
    for aov, code in (("normal", 2), ("id", 3), ("depth", 1)):
        path = os.path.join(ROOT, "tests", "scenes", "gears-1.nff")
        want = host_render(raypack, path, *size, "f32", aov)
        got = render(browser, scene="gears-1", width=size[0], height=size[1], packet=4, scalar=0, output=0, aov=code)
        check_render(f"gears-1 f32 AOV {aov} vs the host CLI", got, want)

    # Errors: the CLI's line for a malformed file (through the file input).
    bad = b"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.01\nresolution 64 48\nl 5 5 5\n" \
          b"f 1 0 0 1 0 0 0 1\ns 0 0 0 one\n"
    want = host_error(raypack, "bad.nff", bad)
    check("line 10, column 9" in want, f"the CLI reports line and column: {want}")
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "bad.nff")
        open(path, "wb").write(bad)
        node = browser.send("DOM.getDocument")["root"]["nodeId"]
        node = browser.send("DOM.querySelector", {"nodeId": node, "selector": "#file"})["nodeId"]
        browser.send("DOM.setFileInputFiles", {"files": [path], "nodeId": node})
        browser.eval("window.__t.until(() => document.getElementById('scene').value === 'file', 10000, 'the file')")
        got = render(browser, scalar=0, width=64, height=48)
    check(got["state"] == "error" and got["error"] == want, f"malformed scene: the page shows `{got['error']}`")
    no_camera = "f 1 1 1 1 0 0 0 0\ns 0 0 0 1\n"
    want = host_error(raypack, "-", no_camera.encode())
    got = render(browser, scene="paste", text=no_camera)
    check(got["state"] == "error" and got["error"] == want, f"pasted scene without a camera: the page shows "
                                                           f"`{got['error']}` (CLI: `{want}`)")
    big = "v\nfrom 0 -60 0\nat 0 0 0\nup 0 0 1\nangle 40\nhither 1\nresolution 32 32\nl 0 -60 60\nf 1 1 1 1 0 0 0 0\n"
    big += "".join(f"s {i % 128 - 64} {i // 128 % 128 - 64} 0 0.4\n" for i in range(16385))
    got = render(browser, scene="paste", text=big)
    check(got["state"] == "error" and "primitive capacity 16384 exceeded (needs 16385)" in got["error"],
          f"over the capacity: the page shows `{got['error'][:160]}`")
    got = render(browser, scene="demo", width=160, height=128, packet=4, scalar=0, output=0, aov=0)
    check(got.get("rgb888") == hx(demo["f32"]["rgb888"]), "a render after the errors gives the demo's checksum")

    # Responsive: a longer render (balls-2, 800x600, fixed point: seconds
    # here). Rendered on the main thread, the timer would stop for all of it.
    got = render(browser, scene="balls-2", width=800, height=600, packet=1, scalar=1, output=0, aov=0)
    if got.get("state") == "done":
        check(got["bands"] == got["totalBands"] > 1 and got["firstBandBeforeDone"],
              f"progress by band: {got['bands']} bands posted one by one over {got['ms']:.0f} ms")
        limit = max(100, min(1000, got["ms"] / 2))
        check(got["maxGap"] < limit, f"the page kept running during the render: longest main-thread gap "
                                     f"{got['maxGap']:.0f} ms (limit {limit:.0f}; the render took {got['ms']:.0f} ms)")
    else:
        check(False, f"balls-2 800x600 rendered (page says: {got.get('error')})")


def run_bench(browser, rounds, width, height, scene):
    """Packet 4 vs 1 (f32) and fixed32, interleaved; the page's own timing."""
    times = {"f32 packet 4": [], "f32 packet 1": [], "fixed32": []}
    configs = [("f32 packet 4", 4, 0), ("f32 packet 1", 1, 0), ("fixed32", 1, 1)]
    rays = {}
    for r in range(rounds + 1):
        for name, packet, scalar in configs:
            got = render(browser, scene=scene, width=width, height=height, packet=packet, scalar=scalar, output=0,
                         aov=0)
            if got.get("state") != "done":
                raise RuntimeError(f"{name}: {got.get('error')}")
            if r > 0:  # round 0 warms up
                times[name].append(got["ms"])
            rays[name] = got["rays"][4]
    log(f"bench scene={scene} size={width}x{height} rounds={rounds} (the page's render time: band calls in the worker)")
    for name, t in times.items():
        best, med = min(t), statistics.median(t)
        log(f"  {name:13} best {best:8.1f} ms  median {med:8.1f} ms  {rays[name] / best / 1e3:6.2f} M rays/s (best)")
    r_best = min(times["f32 packet 1"]) / min(times["f32 packet 4"])
    r_med = statistics.median(times["f32 packet 1"]) / statistics.median(times["f32 packet 4"])
    log(f"  packet 4 / packet 1 speed-up: {r_best:.2f}x (best), {r_med:.2f}x (median)")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dist", default=os.path.join(ROOT, "web", "dist"))
    ap.add_argument("--raypack", help="the host raypack CLI (for the test)")
    ap.add_argument("--chromium", default=shutil.which("chromium") or "/usr/bin/chromium")
    ap.add_argument("--bench", action="store_true")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--size", default="512x512")
    ap.add_argument("--scene", default="balls-2")
    a = ap.parse_args()
    if not os.path.exists(os.path.join(a.dist, "raypack_web.wasm")):
        sys.exit(f"browser_test: {a.dist} has no raypack_web.wasm (run scripts/web.sh)")
    if not a.bench and not a.raypack:
        sys.exit("browser_test: --raypack (the host CLI) is needed for the test")
    if a.raypack:
        a.raypack = os.path.abspath(a.raypack)
        if not os.access(a.raypack, os.X_OK):
            sys.exit(f"browser_test: no raypack CLI at {a.raypack}")
    if not os.access(a.chromium, os.X_OK):
        sys.exit(f"browser_test: no chromium at {a.chromium} (apt-get install chromium)")
    server = serve(a.dist)
    url = f"http://127.0.0.1:{server.server_address[1]}/index.html"
    profile = tempfile.mkdtemp(prefix="raypack-chromium-")
    browser = Chromium(a.chromium, profile)
    t0 = time.monotonic()
    try:
        log(f"chromium: {subprocess.run([a.chromium, '--version'], capture_output=True, text=True).stdout.strip()}")
        browser.open(url)
        first = wait_ready(browser)
        browser.eval(PAGE_JS, timeout=10)
        if a.bench:
            w, h = (int(v) for v in a.size.split("x"))
            run_bench(browser, a.rounds, w, h, a.scene)
        else:
            check(first == "done", f"the page loaded and rendered the demo on its own (state {first})")
            run_tests(browser, a.raypack)
    except Exception as e:  # a clear failure, with what the page said
        FAILURES.append(f"{type(e).__name__}: {e}")
        log(f"FAIL  {type(e).__name__}: {e}")
        for line in browser.console()[-20:]:
            log(f"  page: {line}")
    finally:
        browser.close()
        server.shutdown()
        if not FAILURES:
            shutil.rmtree(profile, ignore_errors=True)
        else:
            log(f"chromium's log: {os.path.join(profile, 'chromium.log')}")
    if a.bench:
        return 1 if FAILURES else 0
    log(f"browser test: {time.monotonic() - t0:.0f} s")
    if FAILURES:
        log(f"browser test FAILED: {len(FAILURES)} check(s)")
        return 1
    log("browser test passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
