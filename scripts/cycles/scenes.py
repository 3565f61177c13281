"""The scenes rendered by both our path tracer and Blender Cycles
(scripts/test-cycles.sh, the convergence study, scripts/bench-cycles.sh):
triangles, materials, camera and background, written once here and handed to
each renderer as it is (an AFF file for ours, the same floats to Blender's
Python, no axis conversion).

Materials are what both renderers have in common: a sum of a Lambertian lobe
(diffuse colour), a perfect mirror (reflectance), a smooth dielectric
(transmittance and index of refraction, Fresnel choosing reflection or
refraction), a GGX microfacet lobe (colour and roughness: ours is Cycles'
Glossy BSDF with distribution GGX) and emitted radiance (from both faces).
Our modified-Phong glossy lobe is not among them: Cycles has no such BSDF
(docs/guide/testing.md).

Bounces: the scene gives ours and Cycles' separately. Cycles' max_bounces B
shades B + 1 hits (next-event estimation at each) and lets the last one's
bounce ray collect what it meets; our --max-bounces B shades B + 1 hits too
but casts no ray from the last. Light that next-event estimation reaches
(emitters) therefore gets as many bounces from ours as from Cycles at the
same B, while light that only an escaping ray collects (our constant
background) gets one bounce fewer: there ours is Cycles' B - 1
(docs/guide/testing.md).
"""

import math
import struct
import sys


class Material:
    def __init__(self, diffuse=(0, 0, 0), mirror=0.0, glass=0.0, ior=1.0, emission=(0, 0, 0), ggx=(0, 0, 0),
                 roughness=0.0):
        self.diffuse, self.mirror, self.glass, self.ior, self.emission = diffuse, mirror, glass, ior, emission
        # A GGX lobe of colour `ggx` when roughness > 0 (AFF `fg`).
        self.ggx, self.roughness = ggx, roughness


class Scene:
    """Triangles are (v0, v1, v2, material index), counter-clockwise seen
    from outside (a dielectric's inside is behind its faces)."""

    def __init__(self, name, materials, triangles, eye, look_at, up, fov, background, our_bounces, cycles_bounces,
                 spp, seeds, width=64, height=48):
        self.name, self.materials, self.triangles = name, materials, triangles
        self.eye, self.look_at, self.up, self.fov = eye, look_at, up, fov
        self.background = background
        self.our_bounces, self.cycles_bounces = our_bounces, cycles_bounces
        # Ours renders spp samples; Cycles spp / seeds samples with each of `seeds` seeds.
        self.spp, self.seeds = spp, seeds
        self.width, self.height = width, height
        self.environment = None  # or an Environment, which replaces the background
        # Cycles' Glossy roughness is ours to this power: 1, or 0.5 for the
        # control (Cycles' alpha then our roughness, not its square).
        self.cycles_roughness_exponent = 1.0


def quad(a, b, c, d, material):
    """Two triangles a b c and a c d."""
    return [(a, b, c, material), (a, c, d, material)]


def sphere(center, radius, rings, segments, material):
    """A UV sphere of 2 * segments * (rings - 1) triangles, faces outward."""
    def point(ring, segment):
        theta = math.pi * ring / rings
        phi = 2 * math.pi * segment / segments
        return (center[0] + radius * math.sin(theta) * math.cos(phi), center[1] + radius * math.cos(theta),
                center[2] - radius * math.sin(theta) * math.sin(phi))
    triangles = []
    for ring in range(rings):
        for segment in range(segments):
            a, b = point(ring, segment), point(ring, segment + 1)
            c, d = point(ring + 1, segment + 1), point(ring + 1, segment)
            if ring > 0:
                triangles.append((a, d, b, material))
            if ring < rings - 1:
                triangles.append((b, d, c, material))
    return triangles


def ground(size, material):
    s = size
    return quad((-s, 0, -s), (-s, 0, s), (s, 0, s), (s, 0, -s), material)


def sphere_scene():
    """The issue's scene: a grey Lambertian sphere of 960 triangles above a
    ground quad, a white background, no lights."""
    materials = [Material(diffuse=(0.5, 0.5, 0.5)), Material(diffuse=(0.8, 0.8, 0.8))]
    triangles = sphere((0, 1.2, 0), 1.0, 16, 32, 0) + ground(6, 1)
    return Scene("sphere", materials, triangles, eye=(0, 2.4, 6), look_at=(0, 0.9, 0), up=(0, 1, 0), fov=36,
                 background=(1, 1, 1), our_bounces=4, cycles_bounces=3, spp=2048, seeds=8)


def cornell_box(our_bounces=3):
    """The Cornell box as Cornell's measured data gives it (in metres), lit
    by its emissive ceiling quad, lowered 0.1 mm below the ceiling so the two
    never meet; a black background."""
    white = Material(diffuse=(0.725, 0.71, 0.68))
    red = Material(diffuse=(0.63, 0.065, 0.05))
    green = Material(diffuse=(0.14, 0.45, 0.091))
    lamp = Material(diffuse=(0.78, 0.78, 0.78), emission=(17, 12, 4))
    W, R, G, L = 0, 1, 2, 3

    def mm(*corners):
        return [tuple(c / 1000.0 for c in corner) for corner in corners]

    def q(material, *corners):
        return quad(*mm(*corners), material)

    t = []
    t += q(W, (552.8, 0, 0), (0, 0, 0), (0, 0, 559.2), (549.6, 0, 559.2))  # floor
    t += q(W, (556, 548.8, 0), (556, 548.8, 559.2), (0, 548.8, 559.2), (0, 548.8, 0))  # ceiling
    t += q(W, (549.6, 0, 559.2), (0, 0, 559.2), (0, 548.8, 559.2), (556, 548.8, 559.2))  # back wall
    t += q(G, (0, 0, 559.2), (0, 0, 0), (0, 548.8, 0), (0, 548.8, 559.2))  # right wall
    t += q(R, (552.8, 0, 0), (549.6, 0, 559.2), (556, 548.8, 559.2), (556, 548.8, 0))  # left wall
    t += q(L, (343, 548.7, 227), (343, 548.7, 332), (213, 548.7, 332), (213, 548.7, 227))  # lamp
    for block in (
            [(130, 165, 65), (82, 165, 225), (240, 165, 272), (290, 165, 114)],  # short block, top first
            [(423, 330, 247), (265, 330, 296), (314, 330, 456), (472, 330, 406)]):  # tall block
        t += q(W, *block)
        for i in range(4):
            top_a, top_b = block[i], block[(i + 1) % 4]
            t += q(W, (top_a[0], 0, top_a[2]), top_a, top_b, (top_b[0], 0, top_b[2]))
    return Scene("cornell", [white, red, green, lamp], t, eye=(0.278, 0.273, -0.8), look_at=(0.278, 0.273, 0),
                 up=(0, 1, 0), fov=2 * math.degrees(math.atan(12.5 / 35)), background=(0, 0, 0),
                 our_bounces=our_bounces, cycles_bounces=our_bounces, spp=2048, seeds=8)


def mirror_scene():
    """A mirror sphere beside a red Lambertian one on a grey ground, under a
    pale blue sky."""
    materials = [Material(mirror=0.9), Material(diffuse=(0.7, 0.15, 0.1)), Material(diffuse=(0.6, 0.6, 0.6))]
    triangles = (sphere((-0.9, 1.0, 0), 1.0, 12, 24, 0) + sphere((1.2, 0.7, 0.6), 0.7, 12, 24, 1) +
                 ground(6, 2))
    return Scene("mirror", materials, triangles, eye=(0.5, 2.2, 6), look_at=(0, 0.8, 0), up=(0, 1, 0), fov=36,
                 background=(0.8, 0.9, 1.0), our_bounces=4, cycles_bounces=3, spp=2048, seeds=8)


def glass_scene():
    """A glass sphere (index 1.5) on a chequered ground under a white sky."""
    materials = [Material(glass=1.0, ior=1.5), Material(diffuse=(0.8, 0.8, 0.8)), Material(diffuse=(0.1, 0.3, 0.6))]
    triangles = sphere((0, 1.0, 0), 1.0, 16, 32, 0)
    tiles, size = 6, 1.5
    for i in range(tiles):
        for j in range(tiles):
            x0, z0 = (i - tiles / 2) * size, (j - tiles / 2) * size
            triangles += quad((x0, 0, z0), (x0, 0, z0 + size), (x0 + size, 0, z0 + size), (x0 + size, 0, z0),
                              1 + (i + j) % 2)
    return Scene("glass", materials, triangles, eye=(0, 3.0, 5.5), look_at=(0, 0.7, 0), up=(0, 1, 0), fov=36,
                 background=(1, 1, 1), our_bounces=8, cycles_bounces=7, spp=2048, seeds=8)


class Environment:
    """An equirectangular map of linear RGB radiance: `pixels` holds
    width x height RGB triples, the bottom row first (PFM's order and
    Blender's image.pixels'), read by ours from a PFM file (--environment)
    and given to Cycles' Environment Texture as they are. `turn`: the share
    of a turn about +Z by which Cycles' copy is rotated (the control)."""

    def __init__(self, width, height, pixels, turn=0.0):
        self.width, self.height, self.pixels, self.turn = width, height, pixels, turn

    def turned(self):
        """The pixels rotated by `turn` about +Z: the columns rolled (exact
        for a whole number of columns)."""
        shift = round(self.turn * self.width) % self.width
        rows = [self.pixels[r * self.width:(r + 1) * self.width] for r in range(self.height)]
        return [p for row in rows for p in row[-shift:] + row[:-shift]] if shift else list(self.pixels)

    def pfm_bytes(self):
        """The map (unturned) as a little-endian colour PFM for --environment."""
        values = [c for p in self.pixels for c in p]
        return (f"PF\n{self.width} {self.height}\n-1.0\n".encode("ascii") +
                struct.pack(f"<{len(values)}f", *values))


def sky_map(width=48, height=24):
    """A sky over a dark ground: a gradient from a pale horizon to a deep
    blue zenith, a brown ground below the horizon, and one bright warm pixel
    of sun (radiance 60) at about 41 degrees of elevation, to the camera's
    right and in front of the objects, so their shadows fall behind them."""
    pixels = []
    for row in range(height):  # bottom first: row 0 looks straight down
        elevation = (row + 0.5) / height - 0.5  # in half turns: -0.5 .. 0.5
        for column in range(width):
            if elevation < 0:
                pixels.append((0.3, 0.22, 0.15))
            else:
                t = 2 * elevation  # 0 at the horizon, 1 at the zenith
                pixels.append((0.9 - 0.7 * t, 0.95 - 0.5 * t, 1.0))
    sun_row, sun_column = 17, 30
    pixels[sun_row * width + sun_column] = (60.0, 55.0, 45.0)
    return Environment(width, height, pixels)


def z_up(point):
    """Y up to Z up: a quarter turn about +X, (x, y, z) -> (x, -z, y), which
    keeps the triangles' winding."""
    return (point[0], -point[2], point[1])


def environment_scene(turn=0.0):
    """A mirror sphere beside a grey Lambertian one on a grey ground, lit by
    sky_map() alone (no lights, no emitters), modelled with +Z up so the
    map's zenith is the sky's. Bounces: the map is sampled at every diffuse
    hit (next-event estimation), like an emitter, so ours and Cycles' are the
    same B; they differ only where the last hit is the mirror (Cycles' ray
    from it still meets the sky, ours casts none), which is light of 6
    bounces: too little to show."""
    materials = [Material(mirror=0.9), Material(diffuse=(0.5, 0.5, 0.5)), Material(diffuse=(0.5, 0.5, 0.5))]
    triangles = [(z_up(a), z_up(b), z_up(c), m) for a, b, c, m in
                 sphere((-0.9, 1.0, 0), 1.0, 12, 24, 0) + sphere((1.2, 0.7, 0.6), 0.7, 12, 24, 1) + ground(6, 2)]
    scene = Scene("environment", materials, triangles, eye=z_up((0.5, 2.2, 6)), look_at=z_up((0, 0.8, 0)),
                  up=(0, 0, 1), fov=36, background=(0, 0, 0), our_bounces=5, cycles_bounces=5, spp=2048, seeds=8)
    scene.environment = sky_map()
    scene.environment.turn = turn
    return scene


def glossy_scene(cycles_roughness_exponent=1.0):
    """GGX lobes: a gold GGX sphere of roughness 0.3 beside a grey
    Lambertian one, on a ground whose left half is a rough GGX lobe (0.6)
    over a dark diffuse one and whose right half is diffuse, lit by sky_map()
    (its sun gives the sphere a highlight) and a small emissive quad high
    on the left; modelled with +Z up as environment_scene(). Both lights are
    sampled at every hit by next-event estimation, so the bounces are the
    same B in both."""
    materials = [Material(ggx=(0.9, 0.65, 0.3), roughness=0.3), Material(diffuse=(0.5, 0.5, 0.5)),
                 Material(diffuse=(0.15, 0.15, 0.15), ggx=(0.6, 0.6, 0.6), roughness=0.6),
                 Material(diffuse=(0.5, 0.5, 0.5)), Material(emission=(8, 8, 8))]
    s = 6
    ground = (quad((-s, 0, -s), (-s, 0, s), (0, 0, s), (0, 0, -s), 2) +
              quad((0, 0, -s), (0, 0, s), (s, 0, s), (s, 0, -s), 3))
    lamp = quad((-3.5, 4, -1.5), (-2.5, 4, -1.5), (-2.5, 4, -0.5), (-3.5, 4, -0.5), 4)
    triangles = [(z_up(a), z_up(b), z_up(c), m) for a, b, c, m in
                 sphere((-0.9, 1.0, 0), 1.0, 12, 24, 0) + sphere((1.2, 0.7, 0.6), 0.7, 12, 24, 1) + ground + lamp]
    scene = Scene("glossy", materials, triangles, eye=z_up((0.5, 2.2, 6)), look_at=z_up((0, 0.8, 0)),
                  up=(0, 0, 1), fov=36, background=(0, 0, 0), our_bounces=5, cycles_bounces=5, spp=2048, seeds=8)
    scene.environment = sky_map()
    scene.cycles_roughness_exponent = cycles_roughness_exponent
    return scene


# The list test-cycles.sh runs, in order.
SCENES = {s.name: s for s in (sphere_scene(), cornell_box(), mirror_scene(), glass_scene(), environment_scene(),
                              glossy_scene())}


def aff_text(scene):
    """The scene as an AFF file for our tracer: the view, the background, no
    ambient light, one `fm` material (plus `fe` for an emitter, `fg` for a
    GGX lobe) before its triangles."""
    def v(values):
        return " ".join(repr(float(x)) for x in values)
    lines = [f"# {scene.name}: written by scripts/cycles/scenes.py", "v",
             f"from {v(scene.eye)}", f"at {v(scene.look_at)}", f"up {v(scene.up)}", f"angle {float(scene.fov)!r}",
             "hither 0.001", f"resolution {scene.width} {scene.height}",
             f"b {v(scene.background)}", "am 0 0 0"]
    current = None
    for v0, v1, v2, material in scene.triangles:
        if material != current:
            m = scene.materials[material]
            # fm: ambient, diffuse, specular (= the mirror's reflectance; no
            # Phong lobe at shininess 0), shininess, transmittance, index.
            lines.append(f"fm 0 0 0 {v(m.diffuse)} {v([m.mirror] * 3)} 0 {float(m.glass)!r} {float(m.ior)!r}")
            if any(e > 0 for e in m.emission):
                lines.append(f"fe {v(m.emission)}")
            if m.roughness > 0:
                lines.append(f"fg {v(m.ggx)} {float(m.roughness)!r}")
            current = material
        lines.append(f"p 3 {v(v0)} {v(v1)} {v(v2)}")
    return "\n".join(lines) + "\n"


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print("scenes.py: writes a scene of test-cycles.sh as an AFF file for our tracer\n"
              "  /usr/bin/python3 scripts/cycles/scenes.py NAME FILE.aff [MAP.pfm]\n"
              "    NAME: " + ", ".join(SCENES) + "\n"
              "    MAP.pfm: the scene's environment map, for --environment\n"
              "  /usr/bin/python3 scripts/cycles/scenes.py --list          the names, one a line")
        return 0
    if argv[1] == "--list":
        print("\n".join(SCENES))
        return 0
    if len(argv) not in (3, 4) or argv[1] not in SCENES:
        print(f"scenes.py: expected NAME FILE.aff [MAP.pfm] with NAME one of {', '.join(SCENES)}", file=sys.stderr)
        return 2
    scene = SCENES[argv[1]]
    if len(argv) == 4 and scene.environment is None:
        print(f"scenes.py: scene {argv[1]} has no environment map to write to {argv[3]}", file=sys.stderr)
        return 2
    with open(argv[2], "w", encoding="ascii") as out:
        out.write(aff_text(scene))
    if len(argv) == 4:
        with open(argv[3], "wb") as out:
            out.write(scene.environment.pfm_bytes())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
