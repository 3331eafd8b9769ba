#!/usr/bin/env python3
"""Writes NFF sphere-grid scenes for scaling benchmarks (brute force against BVH).

Each scene is k x k spheres in a square at z = -10, centred on the z axis, seen
from the origin looking down -z with a 60 degree vertical field of view (the
square fills the view), one light above and behind the eye, a background
colour. The spheres sit on a regular grid of spacing 10/k with radius 0.4 of
the spacing, so every scene covers the same part of the image and only the
number of spheres changes.

    python3 scripts/grid-scenes.py DIR [SIZE ...]

writes DIR/grid-SIZE.nff for each SIZE (number of spheres, a perfect square;
default: 1 4 16 64 256 1024 4096). The output is deterministic: the same
bytes on every run and machine (coordinates are printed with fixed decimals).
"""

import math
import os
import sys

DEFAULT_SIZES = [1, 4, 16, 64, 256, 1024, 4096]

# The square's side: the 60 degree view at distance 10 sees 2·10·tan(30°) ≈ 11.5.
SIDE = 10.0
DEPTH = -10.0


def scene(count):
    """The NFF text of a grid of `count` spheres (count = k·k)."""
    k = math.isqrt(count)
    if k * k != count or k < 1:
        raise ValueError(f"{count}: the number of spheres must be a perfect square (k x k)")
    spacing = SIDE / k
    radius = 0.4 * spacing
    out = [
        f"# raypack sphere grid: {k} x {k} = {count} spheres at z = {DEPTH:g}, written by scripts/grid-scenes.py",
        "b 0.1 0.1 0.15",
        "v",
        "from 0 0 0",
        f"at 0 0 {DEPTH:g}",
        "up 0 1 0",
        "angle 60",
        "hither 0.01",
        "resolution 512 512",
        "l 4 6 2",
        # Red, mostly diffuse, a little mirror (Ks is also the reflected weight).
        "f 0.85 0.25 0.2 0.8 0.2 20 0 1",
    ]
    for j in range(k):
        y = SIDE / 2 - (j + 0.5) * spacing
        for i in range(k):
            x = -SIDE / 2 + (i + 0.5) * spacing
            out.append(f"s {x:.6f} {y:.6f} {DEPTH:.6f} {radius:.6f}")
    return "\n".join(out) + "\n"


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) >= 2 else 2
    directory = argv[1]
    try:
        sizes = [int(s) for s in argv[2:]] or DEFAULT_SIZES
        texts = [(n, scene(n)) for n in sizes]
    except ValueError as e:
        print(f"grid-scenes.py: {e}", file=sys.stderr)
        return 2
    os.makedirs(directory, exist_ok=True)
    for n, text in texts:
        path = os.path.join(directory, f"grid-{n}.nff")
        with open(path, "w", encoding="ascii", newline="\n") as f:
            f.write(text)
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
