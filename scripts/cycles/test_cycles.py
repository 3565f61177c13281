#!/usr/bin/python3
"""Blender Cycles as the image oracle of our path tracer (run by
scripts/test-cycles.sh). Each scene of scenes.py is rendered by
`tracer render --integrator path` (mean and --variance-pfm) and by Cycles with
several seeds (render_cycles.py); every 8x8-pixel block's mean, in each
channel, must agree within 3 standard errors (ours from the variance image,
Cycles' from the spread of each pixel over the seeds). With 144 tests a scene
a few land beyond 3 by chance (0.27% each), so a scene with such blocks is
rendered again with other random numbers (ours with --sampler sobol, Cycles
with other seeds), and a block disagrees when it is beyond 3 in both. Then the
controls, which must disagree: the Cornell box with one bounce more in Cycles,
the environment scene with Cycles' map turned half a turn about +Z, and the
glossy scene with Cycles' GGX alpha our roughness instead of its square. A
control changes only Cycles' side, so it reuses ours' images of its scene.
Exit 1 on disagreement (or a control that agrees)."""

import argparse
import math
import os
import subprocess
import sys
import time

import numpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "reports"))
import common  # noqa: E402
import scenes  # noqa: E402

BLOCK = 8
LIMIT = 3.0
# A block without spread in either image (the sky seen directly) still
# differs by the float rounding of the sums: agree within this share of it.
ROUNDING = 1e-5


def arguments():
    parser = argparse.ArgumentParser(prog="test_cycles.py", description=__doc__)
    parser.add_argument("--build-dir", default="build")
    parser.add_argument("--out", default="out/test-cycles", help="folder for the scenes, images and Blender's logs")
    parser.add_argument("--threads", type=int, default=2, help="threads of each renderer")
    parser.add_argument("--scenes", default=",".join(scenes.SCENES), help="comma-separated names of scenes.py")
    parser.add_argument("--blender", default="blender")
    return parser.parse_args()


def run(command, log):
    with open(log, "w", encoding="utf-8") as out:
        result = subprocess.run(command, stdout=out, stderr=subprocess.STDOUT, check=False)
    if result.returncode != 0:
        with open(log, encoding="utf-8", errors="replace") as text:
            tail = text.read()[-3000:]
        raise SystemExit(f"test_cycles.py: {' '.join(command[:3])} ... failed (exit {result.returncode}); "
                         f"the end of {log}:\n{tail}")


# Ours' renders of this run by (AFF text, sampler): a control, which changes
# only Cycles' side, reuses them.
OURS_RENDERED = {}


def render_ours(args, scene, aff, prefix, bounces, sampler):
    """The prefix of ours' images and the seconds they took."""
    with open(aff, encoding="ascii") as text:
        key = (text.read(), scene.environment.pfm_bytes() if scene.environment is not None else b"", bounces, sampler)
    if key in OURS_RENDERED:
        return OURS_RENDERED[key]
    environment = []
    if scene.environment is not None:
        environment = ["--environment", os.path.splitext(aff)[0] + ".pfm"]
        with open(environment[1], "wb") as out:
            out.write(scene.environment.pfm_bytes())
    started = time.monotonic()
    run([os.path.join(args.build_dir, "bin", "tracer"), "render", aff, "--integrator", "path", "--spp", str(scene.spp),
         "--max-bounces", str(bounces), "--sampler", sampler, "--width", str(scene.width), "--height",
         str(scene.height), "--threads", str(args.threads), "--pfm", prefix + ".pfm", "--variance-pfm",
         prefix + ".var.pfm", "-q", *environment], prefix + ".log")
    OURS_RENDERED[key] = (prefix, time.monotonic() - started)
    return OURS_RENDERED[key]


def render_cycles(args, scene, prefix, bounces, first_seed):
    seeds = list(range(first_seed, first_seed + scene.seeds))
    started = time.monotonic()
    run([args.blender, "-b", "--factory-startup", "--python", os.path.join(HERE, "render_cycles.py"), "--",
         scene.name, prefix, "--spp", str(scene.spp // scene.seeds), "--seeds", ",".join(map(str, seeds)),
         "--bounces", str(bounces), "--threads", str(args.threads),
         *(["--turn", repr(scene.environment.turn)] if scene.environment is not None else []),
         "--roughness-exponent", repr(scene.cycles_roughness_exponent)],
        prefix + ".blender.log")
    return time.monotonic() - started, [f"{prefix}-seed{s}.pfm" for s in seeds]


def block_sums(image):
    """Sums over BLOCK x BLOCK pixel blocks (rows x columns x channels)."""
    h, w, c = image.shape
    return image.reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK, c).sum(axis=(1, 3))


def compare(scene, ours_prefix, cycles_files):
    """Each block's and channel's z score: the difference of the means over
    its combined standard error."""
    n = BLOCK * BLOCK
    ours = common.read_pfm(ours_prefix + ".pfm")
    ours_variance = common.read_pfm(ours_prefix + ".var.pfm") / scene.spp  # of each pixel's mean
    seeds = numpy.stack([common.read_pfm(f) for f in cycles_files])
    cycles = seeds.mean(axis=0)
    # Each pixel's mean over the seeds has the seeds' variance over their number.
    cycles_variance = seeds.var(axis=0, ddof=1) / len(cycles_files)
    difference = (block_sums(ours) - block_sums(cycles)) / n
    rounding = ROUNDING * numpy.maximum(numpy.abs(block_sums(ours)), numpy.abs(block_sums(cycles))) / n
    error = numpy.sqrt((block_sums(ours_variance) + block_sums(cycles_variance)) / (n * n) + rounding ** 2)
    with numpy.errstate(divide="ignore", invalid="ignore"):
        z = numpy.where(error > 0, difference / numpy.where(error > 0, error, 1), 0.0)
    return z, float(ours.mean()), float(cycles.mean())


def main():
    args = arguments()
    os.makedirs(args.out, exist_ok=True)
    names = [n for n in args.scenes.split(",") if n]
    for name in names:
        if name not in scenes.SCENES:
            print(f"test_cycles.py: unknown scene {name} (expected one of {', '.join(scenes.SCENES)})",
                  file=sys.stderr)
            return 2
    header = ["scene", "size", "spp", "bounces ours/Cycles", "tests", "beyond 3 SE", "worst |z|", "where",
              "again beyond 3 SE", "mean ours", "mean Cycles", "s ours", "s Cycles"]
    rows, failed = [], []

    def check(scene, cycles_bounces, label):
        """The tests still beyond LIMIT after the repeat."""
        aff = os.path.join(args.out, scene.name + ".aff")
        with open(aff, "w", encoding="ascii") as out:
            out.write(scenes.aff_text(scene))

        def render_and_compare(tag, sampler, first_seed):
            ours_prefix, ours_time = render_ours(args, scene, aff, os.path.join(args.out, f"{scene.name}{tag}.ours"),
                                                 scene.our_bounces, sampler)
            cycles_time, files = render_cycles(args, scene, os.path.join(args.out, f"{scene.name}{tag}.cycles"),
                                               cycles_bounces, first_seed)
            return (*compare(scene, ours_prefix, files), ours_time, cycles_time)

        tag = "" if cycles_bounces == scene.cycles_bounces else f"-cycles{cycles_bounces}"
        if scene.environment is not None and scene.environment.turn:
            tag += f"-turn{scene.environment.turn:g}"
        if scene.cycles_roughness_exponent != 1:
            tag += f"-roughness{scene.cycles_roughness_exponent:g}"
        z, ours_mean, cycles_mean, ours_time, cycles_time = render_and_compare(tag, "independent", 1)
        beyond = numpy.abs(z) > LIMIT
        again = "-"
        if beyond.any():
            z_again = render_and_compare(tag + "-again", "sobol", 1 + scene.seeds)[0]
            beyond &= numpy.abs(z_again) > LIMIT
            again = str(int(beyond.sum()))
        worst = numpy.unravel_index(numpy.argmax(numpy.abs(z)), z.shape)
        rows.append([label, f"{scene.width}x{scene.height}", str(scene.spp),
                     f"{scene.our_bounces}/{cycles_bounces}", str(z.size), str(int((numpy.abs(z) > LIMIT).sum())),
                     f"{abs(z[worst]):.2f}", f"block ({worst[1]},{worst[0]}) {'RGB'[worst[2]]}", again,
                     f"{ours_mean:.5f}", f"{cycles_mean:.5f}", f"{ours_time:.1f}", f"{cycles_time:.1f}"])
        return int(beyond.sum())

    for name in names:
        scene = scenes.SCENES[name]
        if check(scene, scene.cycles_bounces, name):
            failed.append(name)
    agreeing_controls = []
    if "cornell" in names:
        # Power: a bounce of light more in Cycles must show.
        control = scenes.cornell_box()
        if check(control, control.cycles_bounces + 1, "control: cornell, Cycles a bounce more") == 0:
            agreeing_controls.append("the test cannot tell a bounce of light missing")
    if "environment" in names:
        # Orientation: the map turned half a turn about +Z in Cycles must show.
        control = scenes.environment_scene(turn=0.5)
        if check(control, control.cycles_bounces, "control: environment, Cycles' map a half turn") == 0:
            agreeing_controls.append("the test cannot tell the environment map turned half a turn")
    if "glossy" in names:
        # The GGX lobe's width: Cycles' alpha our roughness, not its square, must show.
        control = scenes.glossy_scene(cycles_roughness_exponent=0.5)
        if check(control, control.cycles_bounces, "control: glossy, Cycles' alpha = roughness") == 0:
            agreeing_controls.append("the test cannot tell alpha = roughness from alpha = roughness squared")
    print(common.markdown_table(header, rows), end="")
    print(f"Blocks of {BLOCK}x{BLOCK} pixels, each channel a test, agreeing within {LIMIT:g} combined standard errors; "
          "a scene with tests beyond is rendered again with other random numbers (ours --sampler sobol, whose "
          "variance image overstates its error; Cycles other seeds), and a test fails when it is beyond in both. "
          "s: wall seconds of each renderer (Cycles: Blender's start-up included; a control's ours: the reused "
          "render's).")
    if failed:
        print(f"test-cycles: DISAGREE with Cycles: {', '.join(failed)}")
    for what in agreeing_controls:
        print(f"test-cycles: a control agrees: {what}")
    return 1 if failed or agreeing_controls else 0


if __name__ == "__main__":
    sys.exit(main())
