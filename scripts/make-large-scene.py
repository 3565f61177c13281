#!/usr/bin/python3
"""A large OBJ scene for load and build figures: a terrain (a height field of
two triangles per grid cell) with spheres on it (UV spheres of 16 x 16
segments, 448 triangles each), about half the triangles each, deterministic
for a given count. The issue's 3 M-triangle scene: --triangles 3000000.

  scripts/make-large-scene.py --triangles 1000000 big.obj
  build/bin/tracer info big.obj     # load and build time, peak memory
"""

import argparse
import math
import random

SEGMENTS = 16
SPHERE_TRIANGLES = 2 * SEGMENTS * (SEGMENTS - 3) + 2 * SEGMENTS  # 448: two caps, 13 bands


def height(x, z):
    return 0.08 * math.sin(3.1 * x) * math.cos(2.3 * z) + 0.03 * math.sin(11.0 * x + 7.0 * z)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--triangles", type=int, required=True, help="about this many triangles")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("output")
    args = parser.parse_args()
    rng = random.Random(args.seed)
    cells = max(1, int(math.sqrt(args.triangles / 4)))
    spheres = max(1, (args.triangles - 2 * cells * cells) // SPHERE_TRIANGLES)
    lines = []
    vertex = 0
    # Terrain over [-1, 1]^2 at y = height(x, z).
    for i in range(cells + 1):
        for j in range(cells + 1):
            x, z = -1 + 2 * i / cells, -1 + 2 * j / cells
            lines.append(f"v {x:.6f} {height(x, z):.6f} {z:.6f}")
    for i in range(cells):
        for j in range(cells):
            a = 1 + i * (cells + 1) + j
            b, c, d = a + cells + 1, a + 1, a + cells + 2
            lines.append(f"f {a} {b} {c}")
            lines.append(f"f {c} {b} {d}")
    vertex = (cells + 1) * (cells + 1)
    # Spheres resting on the terrain.
    for _ in range(spheres):
        cx, cz = rng.uniform(-0.95, 0.95), rng.uniform(-0.95, 0.95)
        r = rng.uniform(0.004, 0.02)
        cy = height(cx, cz) + r
        first = vertex + 1
        lines.append(f"v {cx:.6f} {cy + r:.6f} {cz:.6f}")  # north pole
        for ring in range(1, SEGMENTS - 1):
            theta = math.pi * ring / (SEGMENTS - 1)
            for k in range(SEGMENTS):
                phi = 2 * math.pi * k / SEGMENTS
                lines.append(f"v {cx + r * math.sin(theta) * math.cos(phi):.6f} {cy + r * math.cos(theta):.6f} "
                             f"{cz + r * math.sin(theta) * math.sin(phi):.6f}")
        lines.append(f"v {cx:.6f} {cy - r:.6f} {cz:.6f}")  # south pole
        rings = SEGMENTS - 2
        south = first + 1 + rings * SEGMENTS
        ring_vertex = lambda ring, k: first + 1 + ring * SEGMENTS + k % SEGMENTS  # noqa: E731
        for k in range(SEGMENTS):
            lines.append(f"f {first} {ring_vertex(0, k + 1)} {ring_vertex(0, k)}")
            lines.append(f"f {south} {ring_vertex(rings - 1, k)} {ring_vertex(rings - 1, k + 1)}")
        for ring in range(rings - 1):
            for k in range(SEGMENTS):
                a, b = ring_vertex(ring, k), ring_vertex(ring, k + 1)
                c, d = ring_vertex(ring + 1, k), ring_vertex(ring + 1, k + 1)
                lines.append(f"f {a} {b} {c}")
                lines.append(f"f {b} {d} {c}")
        vertex = south
    with open(args.output, "w", encoding="ascii") as out:
        out.write(f"# {2 * cells * cells + spheres * SPHERE_TRIANGLES} triangles: terrain of {cells}x{cells} "
                  f"cells, {spheres} spheres (scripts/make-large-scene.py --triangles {args.triangles} "
                  f"--seed {args.seed})\n")
        out.write("\n".join(lines))
        out.write("\n")


if __name__ == "__main__":
    main()
