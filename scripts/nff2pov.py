#!/usr/bin/env python3
"""Convert an NFF scene (with raypack's extensions) into a POV-Ray 3.7 scene.

    python3 scripts/nff2pov.py tests/scenes/balls-2.nff -o balls-2.pov

The output is meant for timing POV-Ray on the same workload as raypack: the
same geometry, lights, shadows, reflection and refraction, traced to the same
depth (5 ray segments, primary included). It is not a pixel-exact match; the
differences are listed in docs/povray.md.

Mapping (NFF as in shared/NFF.md):
- `v`: `camera { perspective }`. NFF's angle is the full *vertical* field of
  view; POV's `angle` is horizontal, so it becomes 2·atan(tan(v/2)·W/H).
  Coordinates are copied unchanged; `right -x*W/H` makes POV's camera
  right-handed (POV's default is left-handed), so the image is not mirrored.
  `hither` has no POV counterpart (raypack does not clip by it either).
- `b`: `background`.
- `l x y z [r g b]`: a point `light_source`; without a colour, intensity
  1/sqrt(number of lights) per channel.
- `f r g b Kd Ks Shine T ior` (and `fx`): a texture `ambient Ka diffuse Kd
  phong Ks phong_size Shine reflection Kr`, pigment `rgbt <r, g, b, T>`
  (transmitted light is not tinted, as in raypack), and `interior { ior }`
  where T > 0. The objects that share one material line become one `union`
  carrying that texture and interior, so that all faces of a closed polygon
  solid share one interior and POV tells entering from leaving.
- `s`: `sphere`; `c`: open `cone` (open `cylinder` when both radii are equal);
  `p`: `triangle` for three vertices, else `polygon` (even-odd, so the
  non-convex gear faces work), closed by repeating the first vertex;
  zero-area polygons (never hit by raypack) are left out; `pp`: a fan of
  `smooth_triangle`s around the first vertex, except that a triangle whose
  vertex normals are not all strictly on one side of its plane becomes a flat
  `triangle` (POV flags such a smooth triangle degenerate and never hits it).
- Extensions: `pl` → `plane`, `box` → `box`, `obox` → `box` with a `matrix`,
  `q` → `quadric` (with `clipped_by { box }` for the optional bounds).
- `global_settings { max_trace_level 5 assumed_gamma 1.0 }`, no radiosity;
  anti-aliasing is a command-line matter (`-A`), as is `File_Gamma=1.0`.

Python 3 standard library only.
"""

import argparse
import math
import sys


class NffError(Exception):
    pass


def tokens(text):
    """(token, line number) pairs, comments and a leading BOM removed."""
    if text.startswith("\ufeff"):
        text = text[1:]
    out = []
    for n, line in enumerate(text.splitlines(), 1):
        line = line.split("#", 1)[0]
        out.extend((t, n) for t in line.split())
    return out


def is_number(t):
    try:
        float(t)
        return True
    except ValueError:
        return False


def fmt(x):
    """A float as POV text: short, exact enough (repr keeps every digit)."""
    if x == 0:
        return "0"
    r = repr(float(x))
    if r.endswith(".0"):
        r = r[:-2]
    return r


def vec(v):
    return "<" + ", ".join(fmt(c) for c in v) + ">"


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    n = math.sqrt(dot(a, a))
    if n == 0:
        raise NffError("zero-length vector")
    return (a[0] / n, a[1] / n, a[2] / n)


def newell_area2(pts):
    """Twice the polygon's vector area (Newell's method); its length is 0 for
    a zero-area polygon."""
    nx = ny = nz = 0.0
    for i, a in enumerate(pts):
        b = pts[(i + 1) % len(pts)]
        nx += (a[1] - b[1]) * (a[2] + b[2])
        ny += (a[2] - b[2]) * (a[0] + b[0])
        nz += (a[0] - b[0]) * (a[1] + b[1])
    return (nx, ny, nz)


def degenerate_triangle(a, b, c):
    n = cross(sub(b, a), sub(c, a))
    scale = max(abs(x) for x in a + b + c) or 1.0
    return math.sqrt(dot(n, n)) <= 1e-12 * scale * scale


class Converter:
    def __init__(self, text, width=None, height=None):
        self.toks = tokens(text)
        self.i = 0
        self.width = width
        self.height = height
        self.camera = None
        self.background = (0.0, 0.0, 0.0)
        self.lights = []  # (position, colour or None)
        self.groups = []  # [material, [object text]]
        self.counts = {}
        self.skipped = 0
        self.flat = 0  # patch triangles POV could not interpolate

    # --- token stream -------------------------------------------------------
    def next(self, what):
        if self.i >= len(self.toks):
            raise NffError(f"end of file: expected {what}")
        t = self.toks[self.i]
        self.i += 1
        return t

    def num(self, what="a number"):
        t, n = self.next(what)
        try:
            return float(t)
        except ValueError:
            raise NffError(f"line {n}: expected {what}, found `{t}`") from None

    def nums(self, k, what="a number"):
        return tuple(self.num(what) for _ in range(k))

    def peek_number(self):
        return self.i < len(self.toks) and is_number(self.toks[self.i][0])

    def keyword(self, want):
        t, n = self.next(f"`{want}`")
        if t != want:
            raise NffError(f"line {n}: expected `{want}`, found `{t}`")

    # --- entities -----------------------------------------------------------
    def add(self, kind, text):
        if not self.groups:
            # Objects before any material: NFF leaves it open; use white diffuse.
            self.groups.append([("f", (1.0, 1.0, 1.0), 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0), []])
        self.groups[-1][1].append(text)
        self.counts[kind] = self.counts.get(kind, 0) + 1

    def parse(self):
        while self.i < len(self.toks):
            t, n = self.next("an entity")
            if t == "v":
                self.view()
            elif t == "b":
                self.background = self.nums(3)
            elif t == "l":
                pos = self.nums(3)
                col = self.nums(3) if self.peek_number() else None
                self.lights.append((pos, col))
            elif t == "f":
                r, g, b, kd, ks, shine, kt, ior = self.nums(8)
                # Plain f: Ka = 0, Kr = Ks.
                self.groups.append([("f", (r, g, b), 0.0, kd, ks, shine, ks, kt, ior), []])
            elif t == "fx":
                r, g, b, ka, kd, ks, shine, kr, kt, ior = self.nums(10)
                self.groups.append([("fx", (r, g, b), ka, kd, ks, shine, kr, kt, ior), []])
            elif t == "s":
                cx, cy, cz, r = self.nums(4)
                self.add("sphere", f"sphere {{ {vec((cx, cy, cz))}, {fmt(r)} }}")
            elif t == "c":
                b = self.nums(3)
                br = self.num()
                a = self.nums(3)
                ar = self.num()
                if br == ar:
                    self.add("cylinder", f"cylinder {{ {vec(b)}, {vec(a)}, {fmt(br)} open }}")
                else:
                    self.add("cone", f"cone {{ {vec(b)}, {fmt(br)}, {vec(a)}, {fmt(ar)} open }}")
            elif t == "p":
                self.polygon(int(self.num("a vertex count")), n)
            elif t == "pp":
                self.patch(int(self.num("a vertex count")), n)
            elif t == "pl":
                a, b, c, d = self.nums(4)
                self.add("plane", f"plane {{ {vec((a, b, c))}, {fmt(-d)} }}")
            elif t == "box":
                p0 = self.nums(3)
                p1 = self.nums(3)
                self.add("box", f"box {{ {vec(p0)}, {vec(p1)} }}")
            elif t == "obox":
                c = self.nums(3)
                h = self.nums(3)
                u = norm(self.nums(3))
                v = self.nums(3)
                v = norm(sub(v, tuple(dot(v, u) * x for x in u)))
                w = cross(u, v)
                m = ", ".join(fmt(x) for x in u + v + w + c)
                self.add("box", f"box {{ {vec(tuple(-x for x in h))}, {vec(h)} matrix <{m}> }}")
            elif t == "q":
                k = self.nums(10)
                clip = ""
                if self.peek_number():
                    lo = self.nums(3)
                    hi = self.nums(3)
                    clip = f" clipped_by {{ box {{ {vec(lo)}, {vec(hi)} }} }}"
                A, B, C, D, E, F, G, H, I, J = k
                self.add("quadric", f"quadric {{ {vec((A, B, C))}, {vec((D, E, F))}, {vec((G, H, I))}, {fmt(J)}{clip} }}")
            else:
                raise NffError(f"line {n}: unknown entity `{t}`")

    def view(self):
        cam = {}
        for key in ("from", "at", "up"):
            self.keyword(key)
            cam[key] = self.nums(3)
        self.keyword("angle")
        cam["angle"] = self.num()
        self.keyword("hither")
        cam["hither"] = self.num()
        self.keyword("resolution")
        cam["resolution"] = (int(self.num()), int(self.num()))
        self.camera = cam

    def polygon(self, count, line):
        pts = [self.nums(3) for _ in range(count)]
        if count < 3:
            self.skipped += 1
            return
        a = newell_area2(pts)
        scale = max(abs(x) for p in pts for x in p) or 1.0
        if math.sqrt(dot(a, a)) <= 1e-12 * scale * scale:
            self.skipped += 1  # zero area: legal NFF, never hit
            return
        if count == 3:
            self.add("triangle", "triangle { " + ", ".join(vec(p) for p in pts) + " }")
        else:
            body = ", ".join(vec(p) for p in pts + [pts[0]])
            self.add("polygon", f"polygon {{ {count + 1}, {body} }}")

    def patch(self, count, line):
        vs = [self.nums(6) for _ in range(count)]
        if count < 3:
            self.skipped += 1
            return
        p = [v[:3] for v in vs]
        nn = [v[3:] for v in vs]
        for k in range(1, count - 1):
            if degenerate_triangle(p[0], p[k], p[k + 1]):
                self.skipped += 1
                continue
            tri = (p[0], p[k], p[k + 1])
            ns = (nn[0], nn[k], nn[k + 1])
            face = cross(sub(tri[0], tri[1]), sub(tri[2], tri[1]))
            side = [dot(face, x) for x in ns]
            if not (all(d > 0 for d in side) or all(d < 0 for d in side)):
                # POV flags such a smooth triangle degenerate and never
                # intersects it: keep the geometry as a flat triangle.
                self.flat += 1
                self.add("triangle", "triangle { " + ", ".join(vec(x) for x in tri) + " }")
                continue
            self.add(
                "smooth_triangle",
                "smooth_triangle { "
                + ", ".join(f"{vec(p[j])}, {vec(nn[j])}" for j in (0, k, k + 1))
                + " }",
            )

    # --- output -------------------------------------------------------------
    def texture(self, mat):
        _, col, ka, kd, ks, shine, kr, kt, ior = mat
        finish = [f"ambient {fmt(ka)}", f"diffuse {fmt(kd)}"]
        if ks > 0:
            finish += [f"phong {fmt(ks)}", f"phong_size {fmt(shine)}"]
        if kr > 0:
            finish.append(f"reflection {{ {fmt(kr)} }}")
        tex = f"texture {{ pigment {{ rgbt <{fmt(col[0])}, {fmt(col[1])}, {fmt(col[2])}, {fmt(kt)}> }} finish {{ {' '.join(finish)} }} }}"
        interior = f"interior {{ ior {fmt(ior)} }}" if kt > 0 else ""
        return tex, interior

    def write(self, out, source):
        if self.camera is None:
            raise NffError("no `v` camera block")
        cam = self.camera
        w = self.width or cam["resolution"][0]
        h = self.height or cam["resolution"][1]
        aspect = w / h
        hfov = math.degrees(2 * math.atan(math.tan(math.radians(cam["angle"]) / 2) * aspect))
        o = out.write
        o(f"// Converted from {source} by scripts/nff2pov.py (raypack).\n")
        o(f"// Objects: {', '.join(f'{v} {k}' for k, v in sorted(self.counts.items()))}")
        o(f"; {self.skipped} zero-area polygons or triangles left out")
        o(f"; {self.flat} patch triangles made flat.\n")
        o(f"// Render at +W{w} +H{h} (the aspect the camera was set for).\n")
        o("#version 3.7;\n")
        o("global_settings { max_trace_level 5 assumed_gamma 1.0 }\n\n")
        # NFF's vertical field of view becomes POV's horizontal `angle`;
        # `right -x*aspect` keeps raypack's right-handed image orientation.
        o("camera {\n  perspective\n")
        o(f"  location {vec(cam['from'])}\n")
        o(f"  right -x*{fmt(aspect)}\n  up y\n")
        o(f"  sky {vec(cam['up'])}\n")
        o(f"  angle {fmt(hfov)}  // NFF vertical {fmt(cam['angle'])} deg at aspect {fmt(aspect)}\n")
        o(f"  look_at {vec(cam['at'])}\n}}\n\n")
        o(f"background {{ rgb {vec(self.background)} }}\n\n")
        default = 1 / math.sqrt(len(self.lights)) if self.lights else 0.0
        for pos, col in self.lights:
            c = col if col is not None else (default, default, default)
            o(f"light_source {{ {vec(pos)} color rgb {vec(c)} }}\n")
        o("\n")
        for mat, objs in self.groups:
            if not objs:
                continue
            tex, interior = self.texture(mat)
            if len(objs) == 1:
                # A lone object carries its texture itself (no union needed).
                head = objs[0][:-1].rstrip()
                o(f"{head}\n  {tex}\n")
                if interior:
                    o(f"  {interior}\n")
                o("}\n")
                continue
            o("union {\n")
            for ob in objs:
                o(f"  {ob}\n")
            o(f"  {tex}\n")
            if interior:
                o(f"  {interior}\n")
            o("}\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description="Convert an NFF scene to POV-Ray 3.7 SDL.")
    ap.add_argument("nff", help="input .nff file")
    ap.add_argument("-o", "--output", help="output .pov file (default: standard output)")
    ap.add_argument("--width", type=int, help="image width the camera's aspect is set for (default: the NFF resolution)")
    ap.add_argument("--height", type=int, help="image height (default: the NFF resolution)")
    args = ap.parse_args(argv)
    with open(args.nff, encoding="utf-8") as f:
        text = f.read()
    conv = Converter(text, args.width, args.height)
    try:
        conv.parse()
        if args.output:
            with open(args.output, "w", encoding="utf-8") as out:
                conv.write(out, args.nff)
        else:
            conv.write(sys.stdout, args.nff)
    except NffError as e:
        print(f"nff2pov: {args.nff}: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
