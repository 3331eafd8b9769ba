#!/usr/bin/env python3
"""Benchmark charts for the docs: runs `raypack bench`, saves the results as
JSON and draws two SVG charts by hand (Python standard library only).

    python3 scripts/charts.py --raypack target/release/raypack --out docs/charts
    python3 scripts/charts.py --data docs/charts/data.json --out docs/charts   # re-plot only

Charts (into --out):
- packet-width.svg: rays per second against packet width (1, 4, 8, 16), one
  line per instruction set (baseline, avx2, avx512: those this CPU runs), for
  primary rays and for the full Whitted render of tests/scenes/balls-2.nff.
- accel.svg: brute force (`--accel none`) against the BVH as the number of
  spheres grows, on the sphere grids of scripts/grid-scenes.py (1 to 4096
  spheres), log-log, with the crossover marked.

Measurements run on one thread (`-j 1`: the numbers are per core, and the
benchmark leaves the other core to whatever else the machine runs). The
machine may be shared and noisy, so measurements are interleaved at two
levels: `raypack bench` itself runs all configurations of one invocation
round after round (and reports each one's best and median time), and this
script repeats each invocation --repeats times, rotating the order of the
instruction sets, scenes and accelerators between repeats. A point of a
chart is rays / (median over the repeats of the per-invocation median
time); the whisker spans the per-invocation medians (fastest to slowest).

The data file (data.json) holds every bench line as parsed key/value
records, the commands that produced them, the date and the machine (CPU model
name from /proc/cpuinfo, `nproc`), so the charts can be re-plotted, and
checked, without running anything.
"""

import argparse
import datetime
import json
import math
import os
import platform
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from xml.sax.saxutils import escape

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
BENCH_FORMAT = "1"
ISAS = ["baseline", "avx2", "avx512"]
PACKETS = [1, 4, 8, 16]
GRID_SIZES = [1, 4, 16, 64, 256, 1024, 4096]

# ---------------------------------------------------------------------------
# Running and parsing `raypack bench`


def parse_fields(text):
    """`key=value` fields of a bench line (values may be "quoted"); numbers
    become int or float; fields without `=` are returned in order apart."""
    fields, words = {}, []
    for token in shlex.split(text):
        if "=" in token:
            k, v = token.split("=", 1)
            fields[k] = number(v)
        else:
            words.append(token)
    return fields, words


def number(v):
    try:
        return int(v)
    except ValueError:
        try:
            return float(v)
        except ValueError:
            return v


def parse_bench(text):
    """The header, scene line and measurement records of one bench output."""
    header, scene, records = None, None, []
    for line in text.splitlines():
        if line.startswith("# raypack-bench "):
            header, words = parse_fields(line[2:])
            if words[1:2] != [BENCH_FORMAT]:
                raise SystemExit(f"charts.py: bench output format {words[1:2]}, this script reads format {BENCH_FORMAT}")
        elif line.startswith("# scene="):
            scene, _ = parse_fields(line[2:])
        elif line.startswith("bench "):
            records.append(parse_fields(line[len("bench "):])[0])
        elif line.strip() and not line.startswith("#"):
            raise SystemExit(f"charts.py: unexpected bench output line: {line!r}")
    if header is None or not records:
        raise SystemExit("charts.py: no bench header or no measurements in the output:\n" + text)
    return header, scene, records


def run_bench(raypack, args):
    """Runs `raypack bench ARGS`; returns (command line, header, scene, records)."""
    cmd = [raypack, "bench"] + args
    shown = " ".join(shlex.quote(c) for c in ["raypack", "bench"] + [os.path.relpath(a, ROOT) if os.path.isabs(a) and a.startswith(ROOT) else a for a in args])
    print("  " + shown, file=sys.stderr, flush=True)
    try:
        p = subprocess.run(cmd, capture_output=True, text=True)
    except OSError as e:
        raise SystemExit(f"charts.py: cannot run {raypack}: {e} (build it with `cargo build --release`, or pass --raypack)")
    if p.returncode != 0:
        raise SystemExit(f"charts.py: `{shown}` failed (exit {p.returncode}):\n{p.stderr}")
    for line in p.stderr.splitlines():
        print("  " + line, file=sys.stderr)
    header, scene, records = parse_bench(p.stdout)
    return shown, header, scene, records


def rotate(seq, k):
    k %= len(seq)
    return seq[k:] + seq[:k]


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def nproc():
    try:
        return int(subprocess.run(["nproc"], capture_output=True, text=True, check=True).stdout)
    except (OSError, ValueError, subprocess.CalledProcessError):
        return os.cpu_count()


def measure(opts):
    """Runs every benchmark; returns the data dictionary."""
    raypack = os.path.abspath(opts.raypack)
    t0 = time.monotonic()
    scene = os.path.join(ROOT, opts.scene)
    # Which instruction sets this CPU runs (the header says).
    _, header, _, _ = run_bench(raypack, [scene, "--width", "8", "--height", "8", "--packet", "1", "-j", "1", "--rounds", "1"])
    isas = [i for i in ISAS if i in str(header.get("isas", "")).split(",")]
    data = {
        "date": opts.date,
        "machine": {"cpu": cpu_model(), "nproc": nproc(), "isas": isas, "kernel": platform.system() + " " + platform.release()},
        "raypack": {"version": header.get("version"), "bench_format": int(BENCH_FORMAT)},
        "settings": {"repeats": opts.repeats, "rounds": opts.rounds, "threads": 1},
    }

    print(f"packet widths: {opts.scene}, isas {','.join(isas)}, {opts.repeats} repeats x {opts.rounds} rounds", file=sys.stderr)
    runs = []
    for r in range(opts.repeats):
        args = [scene, "--packet", ",".join(map(str, PACKETS)), "--isa", ",".join(rotate(isas, r)), "-j", "1", "--rounds", str(opts.rounds)]
        cmd, _, scene_line, records = run_bench(raypack, args)
        runs.append({"command": cmd, "scene": scene_line, "records": records})
    data["packet_width"] = {"scene": os.path.splitext(os.path.basename(opts.scene))[0], "scene_file": opts.scene, "runs": runs}

    print(f"brute force vs BVH: sphere grids {GRID_SIZES}, {opts.accel_size}x{opts.accel_size}, {opts.repeats} repeats x {opts.rounds} rounds", file=sys.stderr)
    runs = []
    with tempfile.TemporaryDirectory(prefix="raypack-grids-") as tmp:
        subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "grid-scenes.py"), tmp] + [str(n) for n in GRID_SIZES], check=True, stdout=subprocess.DEVNULL)
        for r in range(opts.repeats):
            accel = "bvh,none" if r % 2 == 0 else "none,bvh"
            for n in rotate(GRID_SIZES, r):
                path = os.path.join(tmp, f"grid-{n}.nff")
                args = [path, "--width", str(opts.accel_size), "--height", str(opts.accel_size), "--accel", accel, "--packet", "8", "-j", "1", "--rounds", str(opts.rounds)]
                cmd, _, scene_line, records = run_bench(raypack, args)
                cmd = cmd.replace(path, f"grid-{n}.nff")
                runs.append({"command": cmd, "spheres": n, "scene": scene_line, "records": records})
    data["accel"] = {
        "scenes": "python3 scripts/grid-scenes.py DIR " + " ".join(map(str, GRID_SIZES)),
        "size": f"{opts.accel_size}x{opts.accel_size}",
        "packet": 8,
        "runs": runs,
    }
    data["settings"]["seconds"] = round(time.monotonic() - t0, 1)
    return data


# ---------------------------------------------------------------------------
# Aggregation


def aggregate(runs, key):
    """{key(record): (rays, median of per-run medians, [per-run medians], best)}."""
    groups = {}
    for run in runs:
        for rec in run["records"]:
            groups.setdefault(key(run, rec), []).append(rec)
    out = {}
    for k, recs in groups.items():
        medians = [r["median_s"] for r in recs]
        out[k] = {
            "rays": recs[0]["rays"],
            "median_s": statistics.median(medians),
            "run_medians": medians,
            "best_s": min(r["best_s"] for r in recs),
        }
    return out


def mrays(point, t=None):
    return point["rays"] / (point["median_s"] if t is None else t) / 1e6


def width_series(data):
    """{measure: {isa: [(packet, M rays/s, lo, hi)]}}: per instruction set
    asked for, what ran (packets 1 and 4 run the baseline whatever is asked)."""
    agg = aggregate(data["packet_width"]["runs"], lambda run, r: (r["measure"], r["isa"], r["packet"]))
    out = {}
    for measure in ("primary", "whitted"):
        for isa in data["machine"]["isas"]:
            pts = []
            for p in PACKETS:
                ran = isa if p >= 8 else "baseline"
                pt = agg.get((measure, ran, p))
                if pt:
                    pts.append((p, mrays(pt), min(mrays(pt, t) for t in pt["run_medians"]), max(mrays(pt, t) for t in pt["run_medians"])))
            out.setdefault(measure, {})[isa] = pts
    return out


def accel_series(data):
    """{measure: {accel: [(spheres, M rays/s, lo, hi, median_s)]}}."""
    agg = aggregate(data["accel"]["runs"], lambda run, r: (r["measure"], r["accel"], run["spheres"]))
    out = {}
    for (measure, accel, n), pt in sorted(agg.items(), key=lambda kv: kv[0][2]):
        rates = [mrays(pt, t) for t in pt["run_medians"]]
        out.setdefault(measure, {}).setdefault(accel, []).append((n, mrays(pt), min(rates), max(rates), pt["median_s"]))
    return out


def crossover(bvh, none):
    """Sphere count above which the BVH stays faster than brute force
    (interpolated on log count and log speed ratio between the last size
    where brute force is at least as fast and the next), or "always" /
    "never"."""
    pairs = [(b[0], math.log(b[1] / n[1])) for b, n in zip(bvh, none) if b[0] == n[0]]
    if all(d > 0 for _, d in pairs):
        return "always"
    if pairs[-1][1] <= 0:
        return "never"
    # The last size where brute force is at least as fast, and the next one
    # (from there on the BVH stays faster).
    last = max(k for k, (_, d) in enumerate(pairs) if d <= 0)
    (x0, d0), (x1, d1) = pairs[last], pairs[last + 1]
    f = -d0 / (d1 - d0)
    return math.exp(math.log(x0) + f * (math.log(x1) - math.log(x0)))


# ---------------------------------------------------------------------------
# SVG by hand

COLORS = {"baseline": "#1b9e77", "avx2": "#d95f02", "avx512": "#7570b3", "bvh": "#1f78b4", "none": "#e31a1c"}
FONT = 'font-family="DejaVu Sans, Helvetica, Arial, sans-serif"'


class Svg:
    def __init__(self, width, height):
        self.w, self.h, self.items = width, height, []

    def add(self, s):
        self.items.append(s)

    def text(self, x, y, s, size=12, anchor="start", weight="normal", color="#222", rotate=None, italic=False):
        tr = f' transform="rotate({rotate} {x:.1f} {y:.1f})"' if rotate is not None else ""
        style = ' font-style="italic"' if italic else ""
        self.add(f'<text x="{x:.1f}" y="{y:.1f}" font-size="{size}" text-anchor="{anchor}" font-weight="{weight}" fill="{color}"{style}{tr}>{escape(s)}</text>')

    def line(self, x0, y0, x1, y1, color="#222", width=1.0, dash=None):
        d = f' stroke-dasharray="{dash}"' if dash else ""
        self.add(f'<line x1="{x0:.1f}" y1="{y0:.1f}" x2="{x1:.1f}" y2="{y1:.1f}" stroke="{color}" stroke-width="{width}"{d}/>')

    def polyline(self, pts, color, width=2.0, dash=None):
        if len(pts) < 2:
            return
        d = f' stroke-dasharray="{dash}"' if dash else ""
        p = " ".join(f"{x:.1f},{y:.1f}" for x, y in pts)
        self.add(f'<polyline points="{p}" fill="none" stroke="{color}" stroke-width="{width}" stroke-linejoin="round"{d}/>')

    def marker(self, x, y, color, shape="circle"):
        if shape == "square":
            self.add(f'<rect x="{x - 3.5:.1f}" y="{y - 3.5:.1f}" width="7" height="7" fill="{color}"/>')
        elif shape == "diamond":
            self.add(f'<polygon points="{x:.1f},{y - 4.5:.1f} {x + 4.5:.1f},{y:.1f} {x:.1f},{y + 4.5:.1f} {x - 4.5:.1f},{y:.1f}" fill="{color}"/>')
        else:
            self.add(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="3.8" fill="{color}"/>')

    def render(self):
        head = f'<svg xmlns="http://www.w3.org/2000/svg" width="{self.w}" height="{self.h}" viewBox="0 0 {self.w} {self.h}" {FONT}>'
        return "\n".join([head, f'<rect width="{self.w}" height="{self.h}" fill="white"/>'] + self.items + ["</svg>"]) + "\n"


class Axis:
    """A linear or log10 mapping from data to pixels."""

    def __init__(self, lo, hi, p0, p1, log=False):
        self.lo, self.hi, self.p0, self.p1, self.log = lo, hi, p0, p1, log

    def __call__(self, v):
        f = (lambda x: math.log10(x)) if self.log else (lambda x: x)
        return self.p0 + (f(v) - f(self.lo)) / (f(self.hi) - f(self.lo)) * (self.p1 - self.p0)


def nice_linear_ticks(hi, n=6):
    """0, step, 2·step, ... covering hi, with a 1/2/5 step."""
    raw = hi / n
    mag = 10 ** math.floor(math.log10(raw))
    step = next(m * mag for m in (1, 2, 2.5, 5, 10) if m * mag >= raw)
    ticks = [0.0]
    while ticks[-1] < hi:
        ticks.append(ticks[-1] + step)
    return ticks


def log_range(lo, hi):
    return 10 ** math.floor(math.log10(lo)), 10 ** math.ceil(math.log10(hi))


def fmt(v):
    if v >= 100 or v == int(v):
        return f"{v:.0f}"
    if v >= 1:
        return f"{v:.1f}".rstrip("0").rstrip(".")
    return f"{v:g}"


def frame(svg, x0, y0, x1, y1):
    svg.add(f'<rect x="{x0:.1f}" y="{y0:.1f}" width="{x1 - x0:.1f}" height="{y1 - y0:.1f}" fill="none" stroke="#444" stroke-width="1"/>')


def legend(svg, x, y, entries):
    """entries: (label, color, dash, shape); a box with a sample of each."""
    w = 12 + max(len(e[0]) for e in entries) * 6.6 + 40
    h = 8 + 18 * len(entries)
    svg.add(f'<rect x="{x:.1f}" y="{y:.1f}" width="{w:.1f}" height="{h:.1f}" fill="white" fill-opacity="0.9" stroke="#999"/>')
    for k, (label, color, dash, shape) in enumerate(entries):
        yy = y + 13 + 18 * k
        svg.line(x + 8, yy, x + 36, yy, color, 2, dash)
        svg.marker(x + 22, yy, color, shape)
        svg.text(x + 42, yy + 4, label, 11.5)


def header(svg, title, subtitle):
    svg.text(20, 26, title, 16, weight="bold")
    svg.text(20, 45, subtitle, 11.5, color="#555")


SHAPES = {"baseline": "circle", "avx2": "square", "avx512": "diamond", "bvh": "circle", "none": "square"}
MEASURE_TITLE = {"primary": "Primary rays (closest hit, no shading)", "whitted": "Whitted render (shadows, reflection; all rays)"}


def chart_packet_width(data):
    series = width_series(data)
    pw = data["packet_width"]
    run0 = pw["runs"][0]
    size = run0["scene"]["size"]
    svg = Svg(960, 485)
    machine = data["machine"]
    header(svg, f"raypack: rays per second against packet width, one line per instruction set",
           f"{pw['scene']} ({run0['scene']['primitives']} primitives, BVH), {size}, 1 thread; {machine['cpu']}, nproc {machine['nproc']}; "
           f"raypack {data['raypack']['version']}, {data['date']}; median of {len(pw['runs'])} runs x {data['settings']['rounds']} rounds")
    xs = {p: math.log2(p) for p in PACKETS}
    for k, measure in enumerate(("primary", "whitted")):
        x0, y0, x1, y1 = 80 + k * 450, 75, 80 + k * 450 + 370, 400
        top = max(hi for s in series[measure].values() for (_, _, _, hi) in s)
        ticks = nice_linear_ticks(top * 1.08)
        X = Axis(0, 4, x0 + 20, x1 - 20)
        Y = Axis(0, ticks[-1], y1, y0)
        for t in ticks:
            svg.line(x0, Y(t), x1, Y(t), "#e4e4e4")
            svg.text(x0 - 6, Y(t) + 4, fmt(t), 11, "end")
        for p in PACKETS:
            svg.line(X(xs[p]), y1, X(xs[p]), y1 + 5, "#444")
            svg.text(X(xs[p]), y1 + 19, str(p), 11, "middle")
        frame(svg, x0, y0, x1, y1)
        svg.text((x0 + x1) / 2, y0 - 8, MEASURE_TITLE[measure], 12.5, "middle", "bold")
        svg.text((x0 + x1) / 2, y1 + 38, "packet width (rays traced together; --packet)", 12, "middle")
        svg.text(x0 - 48, (y0 + y1) / 2, "million rays per second (1 thread)", 12, "middle", rotate=-90)
        for isa, pts in series[measure].items():
            color = COLORS[isa]
            own = [(X(xs[p]), Y(v)) for (p, v, _, _) in pts if p >= 8 or isa == "baseline"]
            if isa != "baseline":
                # Packets of 1 and 4 run the baseline code whatever --isa asks.
                base = [(X(xs[p]), Y(v)) for (p, v, _, _) in pts if p == 4]
                svg.polyline(base + own[:1], color, 1.5, "4,3")
            svg.polyline(own, color, 2)
            for (p, v, lo, hi) in pts:
                if p >= 8 or isa == "baseline":
                    svg.line(X(xs[p]), Y(lo), X(xs[p]), Y(hi), color, 1)
                    svg.marker(X(xs[p]), Y(v), color, SHAPES[isa])
        if k == 0:
            legend(svg, x0 + 10, y0 + 10, [(f"--isa {isa}", COLORS[isa], None, SHAPES[isa]) for isa in series[measure]])
    svg.text(20, 455, "Packets of 1 and 4 rays run the baseline (SSE2) code whatever --isa says; dashed: where avx2 and avx512 take over, at 8.", 11, color="#555", italic=True)
    svg.text(20, 470, "Points: median over the runs of each run's median time; whiskers: fastest to slowest run.", 11, color="#555", italic=True)
    return svg.render()


def chart_accel(data):
    series = accel_series(data)
    ac = data["accel"]
    svg = Svg(960, 500)
    machine = data["machine"]
    isa = ac["runs"][0]["records"][0]["isa"]
    header(svg, "raypack: brute force (--accel none) against the BVH as the number of spheres grows",
           f"k x k sphere grids (scripts/grid-scenes.py), {ac['size']}, packet {ac['packet']}, isa {isa}, 1 thread; {machine['cpu']}, nproc {machine['nproc']}; "
           f"raypack {data['raypack']['version']}, {data['date']}")
    notes = []
    for k, measure in enumerate(("primary", "whitted")):
        x0, y0, x1, y1 = 80 + k * 450, 75, 80 + k * 450 + 370, 405
        s = series[measure]
        counts = [p[0] for p in s["bvh"]]
        lo = min(p[2] for a in s.values() for p in a)
        hi = max(p[3] for a in s.values() for p in a)
        ylo, yhi = log_range(lo, hi)
        X = Axis(counts[0], counts[-1], x0 + 18, x1 - 18, log=True)
        Y = Axis(ylo, yhi, y1, y0, log=True)
        decade = ylo
        while decade <= yhi * 1.0001:
            for m in (1, 2, 5):
                v = decade * m
                if v > yhi * 1.0001:
                    break
                svg.line(x0, Y(v), x1, Y(v), "#d8d8d8" if m == 1 else "#f0f0f0")
                svg.text(x0 - 6, Y(v) + 4, fmt(v), 11 if m == 1 else 9.5, "end", color="#222" if m == 1 else "#777")
            decade *= 10
        for n in counts:
            svg.line(X(n), y1, X(n), y1 + 5, "#444")
            svg.line(X(n), y0, X(n), y1, "#f0f0f0")
            svg.text(X(n), y1 + 19, str(n), 11, "middle")
        frame(svg, x0, y0, x1, y1)
        svg.text((x0 + x1) / 2, y0 - 8, MEASURE_TITLE[measure], 12.5, "middle", "bold")
        svg.text((x0 + x1) / 2, y1 + 38, "spheres in the scene (log scale)", 12, "middle")
        svg.text(x0 - 50, (y0 + y1) / 2, "million rays per second (log scale)", 12, "middle", rotate=-90)
        for accel in ("bvh", "none"):
            pts = s[accel]
            color = COLORS[accel]
            svg.polyline([(X(n), Y(v)) for (n, v, _, _, _) in pts], color, 2, None if accel == "bvh" else "6,3")
            for (n, v, a, b, _) in pts:
                svg.line(X(n), Y(a), X(n), Y(b), color, 1)
                svg.marker(X(n), Y(v), color, SHAPES[accel])
        c = crossover(s["bvh"], s["none"])
        if isinstance(c, float):
            svg.line(X(c), y0, X(c), y1, "#555", 1, "2,3")
            svg.text(X(c) + 5, y0 + 18, f"crossover ≈ {c:.0f} spheres", 11.5, color="#333")
            notes.append(f"{measure}: BVH faster above ~{c:.0f} spheres")
        else:
            notes.append(f"{measure}: BVH {'faster at every size' if c == 'always' else 'never faster'}")
        if k == 0:
            legend(svg, x0 + 10, y1 - 54, [("BVH (--accel bvh)", COLORS["bvh"], None, "circle"), ("brute force (--accel none)", COLORS["none"], "6,3", "square")])
    svg.text(20, 470, "; ".join(notes) + ". Crossover: interpolated on the log scales between the last size where brute force", 11, color="#555", italic=True)
    svg.text(20, 485, "is at least as fast and the next one. Points: median over the runs; whiskers: fastest to slowest run.", 11, color="#555", italic=True)
    return svg.render()


# ---------------------------------------------------------------------------


def summary(data):
    lines = []
    ws = width_series(data)
    for measure, by_isa in ws.items():
        lines.append(f"packet width, {data['packet_width']['scene']}, {measure}: M rays/s (median)")
        for isa, pts in by_isa.items():
            lines.append(f"  {isa:<9}" + "  ".join(f"w{p}={v:6.2f}" for (p, v, _, _) in pts))
    acs = accel_series(data)
    for measure, by in acs.items():
        lines.append(f"accel, sphere grids {data['accel']['size']}, {measure}: M rays/s (median) bvh / none, frame time ms bvh / none")
        for b, n in zip(by["bvh"], by["none"]):
            lines.append(f"  {b[0]:>5} spheres: {b[1]:7.2f} / {n[1]:7.2f}   {b[4] * 1e3:8.2f} / {n[4] * 1e3:8.2f} ms   bvh {b[1] / n[1]:.2f}x")
        c = crossover(by["bvh"], by["none"])
        lines.append(f"  crossover: {c if isinstance(c, str) else f'{c:.1f} spheres'}")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--raypack", default=os.path.join(ROOT, "target", "release", "raypack"), help="the raypack binary (default: target/release/raypack)")
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "charts"), help="directory of the SVGs and data.json (default: docs/charts)")
    ap.add_argument("--data", help="re-plot from this data file instead of running the benchmarks")
    ap.add_argument("--repeats", type=int, default=7, help="bench invocations per measurement, orders rotated (default 7)")
    ap.add_argument("--rounds", type=int, default=7, help="--rounds of each bench invocation (default 7)")
    ap.add_argument("--scene", default="tests/scenes/balls-2.nff", help="scene of the packet-width chart (default tests/scenes/balls-2.nff)")
    ap.add_argument("--accel-size", type=int, default=256, help="image side of the brute-force/BVH measurements (default 256)")
    ap.add_argument("--date", default=datetime.date.today().isoformat(), help="date recorded in the data file (default today)")
    opts = ap.parse_args()

    os.makedirs(opts.out, exist_ok=True)
    if opts.data:
        with open(opts.data) as f:
            data = json.load(f)
    else:
        data = measure(opts)
        path = os.path.join(opts.out, "data.json")
        with open(path, "w") as f:
            json.dump(data, f, indent=1)
            f.write("\n")
        print(f"wrote {os.path.relpath(path)} ({data['settings']['seconds']} s of benchmarks)", file=sys.stderr)
    for name, chart in (("packet-width.svg", chart_packet_width), ("accel.svg", chart_accel)):
        path = os.path.join(opts.out, name)
        with open(path, "w") as f:
            f.write(chart(data))
        print(f"wrote {os.path.relpath(path)}", file=sys.stderr)
    print(summary(data))


if __name__ == "__main__":
    main()
