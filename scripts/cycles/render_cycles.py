"""Renders a scene of scenes.py with Blender Cycles, once per seed, each
image written as a colour PFM (linear radiance, the mean of the samples):

  blender -b --factory-startup --python scripts/cycles/render_cycles.py -- \\
      NAME OUT_PREFIX --spp N --seeds 1,2,3 [--bounces B | --our-bounces B] [--threads T]
      [--width W --height H] [--turn T] [--roughness-exponent E]

writes OUT_PREFIX-seedS.pfm for each seed S and OUT_PREFIX-times.csv (seed,
wall and CPU seconds of the process during that render: scene
synchronisation, BVH build and the samples; Blender's start-up and this
script's set-up are left out). --our-bounces B: Cycles' bounces that match
our --max-bounces B for this scene's light (scenes.py). --turn T: the
environment map rotated by T of a turn about +Z (the control).
--roughness-exponent E: each GGX lobe's Roughness is ours to the power E
(0.5 for the control: Cycles' alpha, its Roughness squared, is then our
roughness, not its square). A GGX lobe is a Glossy BSDF with distribution
GGX, whose colour is ours (no Fresnel term in either). The same
triangles as ours (no axis conversion: the vertices are set here, not read
by Blender's OBJ importer, which turns Y up into Z up), the camera by eye,
look-at, up and vertical field of view, a box pixel filter of width 1, the
Standard view transform, no denoising, no clamping, no adaptive sampling, no
glossy filter, no light threshold.
"""

import math
import os
import sys
import time

import bpy
import mathutils
import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scenes  # noqa: E402


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) < 2 or argv[0] in ("-h", "--help"):
        print(__doc__)
        sys.exit(0 if argv and argv[0] in ("-h", "--help") else 2)
    options = {"name": argv[0], "prefix": argv[1], "spp": None, "seeds": None, "bounces": None,
               "our-bounces": None, "turn": None, "threads": 0, "width": None, "height": None,
               "roughness-exponent": None}
    i = 2
    while i < len(argv):
        key = argv[i][2:]
        if key not in options or i + 1 >= len(argv):
            print(f"render_cycles.py: unknown option or missing value: {argv[i]}", file=sys.stderr)
            sys.exit(2)
        options[key] = argv[i + 1]
        i += 2
    if options["name"] not in scenes.SCENES:
        print(f"render_cycles.py: unknown scene {options['name']} (expected one of {', '.join(scenes.SCENES)})",
              file=sys.stderr)
        sys.exit(2)
    return options


def shader(nodes, links, material, roughness_exponent):
    """The sum of the material's lobes (Add Shader), as ours adds them."""
    parts = []
    if any(c > 0 for c in material.diffuse):
        node = nodes.new("ShaderNodeBsdfDiffuse")
        node.inputs["Color"].default_value = (*material.diffuse, 1)
        node.inputs["Roughness"].default_value = 0  # Lambert
        parts.append(node)
    if material.mirror > 0:
        node = nodes.new("ShaderNodeBsdfGlossy")
        node.distribution = "SHARP"
        node.inputs["Color"].default_value = (material.mirror, material.mirror, material.mirror, 1)
        parts.append(node)
    if material.roughness > 0:
        node = nodes.new("ShaderNodeBsdfGlossy")
        node.distribution = "GGX"
        node.inputs["Color"].default_value = (*material.ggx, 1)
        node.inputs["Roughness"].default_value = material.roughness ** roughness_exponent
        parts.append(node)
    if material.glass > 0:
        node = nodes.new("ShaderNodeBsdfGlass")
        node.distribution = "SHARP"
        node.inputs["Color"].default_value = (material.glass, material.glass, material.glass, 1)
        node.inputs["IOR"].default_value = material.ior
        parts.append(node)
    if any(c > 0 for c in material.emission):
        # Strength 1: the emitted radiance is the colour (a directly seen
        # emitter's pixel value), whatever the colour's size.
        node = nodes.new("ShaderNodeEmission")
        node.inputs["Color"].default_value = (*material.emission, 1)
        node.inputs["Strength"].default_value = 1
        parts.append(node)
    if not parts:  # black: a diffuse lobe of colour 0
        node = nodes.new("ShaderNodeBsdfDiffuse")
        node.inputs["Color"].default_value = (0, 0, 0, 1)
        parts.append(node)
    total = parts[0]
    for part in parts[1:]:
        add = nodes.new("ShaderNodeAddShader")
        links.new(total.outputs[0], add.inputs[0])
        links.new(part.outputs[0], add.inputs[1])
        total = add
    return total


def environment(world, data):
    """The map as the World's Environment Texture (equirectangular, no
    Mapping node, Closest: ours is constant over each pixel) of an image made
    here from the same numbers as ours, Non-Color so no transform applies;
    rotated by data.turn about +Z (the control)."""
    image = bpy.data.images.new("environment", data.width, data.height, alpha=False, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    image.pixels.foreach_set(numpy.array([(*p, 1.0) for p in data.turned()], dtype=numpy.float32).ravel())
    image.update()
    texture = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    texture.image = image
    texture.projection = "EQUIRECTANGULAR"
    texture.interpolation = "Closest"
    world.node_tree.links.new(texture.outputs["Color"], world.node_tree.nodes["Background"].inputs["Color"])


def build(scene_data, width, height):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    vertices, faces, material_indices = [], [], []
    for v0, v1, v2, material in scene_data.triangles:
        faces.append((len(vertices), len(vertices) + 1, len(vertices) + 2))
        vertices += [v0, v1, v2]
        material_indices.append(material)
    mesh = bpy.data.meshes.new(scene_data.name)
    mesh.from_pydata(vertices, [], faces)
    for index, material in enumerate(scene_data.materials):
        m = bpy.data.materials.new(f"m{index}")
        m.use_nodes = True
        nodes, links = m.node_tree.nodes, m.node_tree.links
        nodes.clear()
        output = nodes.new("ShaderNodeOutputMaterial")
        links.new(shader(nodes, links, material, scene_data.cycles_roughness_exponent).outputs[0],
                  output.inputs["Surface"])
        mesh.materials.append(m)
    mesh.polygons.foreach_set("material_index", material_indices)
    mesh.update()
    scene.collection.objects.link(bpy.data.objects.new(scene_data.name, mesh))

    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*scene_data.background, 1)
    background.inputs["Strength"].default_value = 1
    if scene_data.environment is not None:
        environment(world, scene_data.environment)
    scene.world = world

    camera_data = bpy.data.cameras.new("camera")
    camera_data.sensor_fit = "VERTICAL"
    camera_data.angle_y = math.radians(scene_data.fov)
    camera_data.clip_start, camera_data.clip_end = 1e-4, 1e6
    camera = bpy.data.objects.new("camera", camera_data)
    eye, look_at, up = (mathutils.Vector(v) for v in (scene_data.eye, scene_data.look_at, scene_data.up))
    forward = (look_at - eye).normalized()
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    # A camera looks along its -Z with +Y up and +X to the right, as ours.
    rotation = mathutils.Matrix((right, true_up, -forward)).transposed()
    camera.matrix_world = mathutils.Matrix.Translation(eye) @ rotation.to_4x4()
    scene.collection.objects.link(camera)
    scene.camera = camera

    render = scene.render
    render.engine = "CYCLES"
    render.resolution_x, render.resolution_y, render.resolution_percentage = width, height, 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1
    render.film_transparent = False
    render.use_persistent_data = True  # the BVH is built once for every seed
    render.image_settings.file_format = "OPEN_EXR"
    render.image_settings.color_depth = "32"
    render.image_settings.color_mode = "RGB"
    render.image_settings.exr_codec = "NONE"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0
    scene.view_settings.gamma = 1
    c = scene.cycles
    c.device = "CPU"
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = c.sample_clamp_indirect = 0
    c.blur_glossy = 0
    c.light_sampling_threshold = 0
    c.caustics_reflective = c.caustics_refractive = True
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.use_animated_seed = False
    c.min_light_bounces = c.min_transparent_bounces = 0
    c.film_exposure = 1.0
    for layer in scene.view_layers:
        layer.cycles.use_denoising = False
    return scene


def write_pfm(path, pixels, width, height):
    """pixels: RGBA floats, bottom row first (as Blender gives them and PFM stores them)."""
    rgb = pixels.reshape(height, width, 4)[:, :, :3].astype("<f4")
    with open(path, "wb") as out:
        out.write(f"PF\n{width} {height}\n-1.0\n".encode("ascii"))
        out.write(rgb.tobytes())


def main():
    options = arguments()
    data = scenes.SCENES[options["name"]]
    width = int(options["width"] or data.width)
    height = int(options["height"] or data.height)
    seeds = [int(s) for s in (options["seeds"] or ",".join(str(s) for s in range(data.seeds))).split(",")]
    spp = int(options["spp"] or data.spp // len(seeds))
    if options["turn"] is not None:
        if data.environment is None:
            print(f"render_cycles.py: --turn: scene {data.name} has no environment map", file=sys.stderr)
            sys.exit(2)
        data.environment.turn = float(options["turn"])
    if options["roughness-exponent"] is not None:
        data.cycles_roughness_exponent = float(options["roughness-exponent"])
    bounces = data.cycles_bounces
    if options["bounces"] is not None:
        bounces = int(options["bounces"])
    elif options["our-bounces"] is not None:
        bounces = int(options["our-bounces"]) - (data.our_bounces - data.cycles_bounces)
    scene = build(data, width, height)
    c = scene.cycles
    c.samples = spp
    c.max_bounces = bounces
    # The total alone limits the path: every kind's own limit is the total.
    c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = c.transparent_max_bounces = bounces
    c.volume_bounces = 0
    threads = int(options["threads"])
    scene.render.threads_mode = "FIXED" if threads > 0 else "AUTO"
    if threads > 0:
        scene.render.threads = threads
    prefix = os.path.abspath(options["prefix"])
    times = ["seed,wall_seconds,cpu_seconds"]
    for seed in seeds:
        c.seed = seed
        exr = f"{prefix}-seed{seed}.exr"
        scene.render.filepath = exr
        started, cpu_started = time.monotonic(), time.process_time()
        bpy.ops.render.render(write_still=True)
        times.append(f"{seed},{time.monotonic() - started:.4f},{time.process_time() - cpu_started:.4f}")
        image = bpy.data.images.load(exr)
        image.colorspace_settings.name = "Non-Color"  # the file's numbers as they are
        pixels = numpy.empty(width * height * 4, dtype=numpy.float32)
        image.pixels.foreach_get(pixels)
        bpy.data.images.remove(image)
        os.remove(exr)
        write_pfm(f"{prefix}-seed{seed}.pfm", pixels, width, height)
    with open(f"{prefix}-times.csv", "w", encoding="ascii") as out:
        out.write("\n".join(times) + "\n")


main()
