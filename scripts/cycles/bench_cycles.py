#!/usr/bin/python3
"""The path tracer's goals on the Cornell box (issue 49), measured and
printed (run by scripts/bench-cycles.sh):
1. Sobol against independent sampling at 16 spp: RMSE ratio (goal <= 0.6);
2. at equal single-thread CPU time, our RMSE against Cycles' (goal <= 1.2);
In both, each RMSE is the root of the mean squared error over --realizations
independent renders (ours --path-seed 1.., Cycles seeds 1..): one render's
error is mostly a dozen pixels on the lamp's edges, too few for one to decide;
3. writing the trace against --discard-records: CPU ratio (goal <= 2.0).
RMSE over every pixel and channel against a reference of Cycles (4 seeds
of 4096 spp, seeds 1000-1003: no run shares its random numbers), less the
reference's own mean squared error (estimated from the spread of its seeds),
so the figure is the run's alone. CPU: user + sys of the whole `tracer
render --threads 1` command; Cycles' the Blender process's during the render
on one thread (scene synchronisation and BVH build included, Blender's
start-up left out). Times are medians of --runs runs, or of the
realizations."""

import argparse
import glob
import math
import os
import resource
import statistics
import subprocess
import sys
import time

import numpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "reports"))
import common  # noqa: E402
import scenes  # noqa: E402

BOUNCES = 5  # the tracer's default; Cycles' that match it on the Cornell box are the same (scenes.py)


def arguments():
    parser = argparse.ArgumentParser(prog="bench_cycles.py", description=__doc__)
    parser.add_argument("--build-dir", default="build")
    parser.add_argument("--out", default="out/bench-cycles")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--realizations", type=int, default=6, help="independent renders per point of item 2")
    parser.add_argument("--blender", default="blender")
    parser.add_argument("--width", type=int, default=64)
    parser.add_argument("--height", type=int, default=48)
    parser.add_argument("--reference-spp", type=int, default=4096, help="per seed, of 4 seeds")
    parser.add_argument("--trace-width", type=int, default=200)
    parser.add_argument("--trace-height", type=int, default=150)
    return parser.parse_args()


def cpu_of(command, log):
    """CPU seconds (user + sys) of the command and its children."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    with open(log, "w", encoding="utf-8") as out:
        subprocess.run(command, stdout=out, stderr=subprocess.STDOUT, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    args = arguments()
    os.makedirs(args.out, exist_ok=True)
    scene = scenes.cornell_box(BOUNCES)
    aff = os.path.join(args.out, "cornell.aff")
    with open(aff, "w", encoding="ascii") as out:
        out.write(scenes.aff_text(scene))
    tracer = os.path.join(args.build_dir, "bin", "tracer")
    size = ["--width", str(args.width), "--height", str(args.height)]

    def cycles(prefix, spp, seeds, threads):
        """Cycles' images (one per seed) and each render's CPU seconds."""
        with open(prefix + ".log", "w", encoding="utf-8") as log:
            subprocess.run([args.blender, "-b", "--factory-startup", "--python", os.path.join(HERE, "render_cycles.py"),
                            "--", "cornell", prefix, "--spp", str(spp), "--seeds", ",".join(map(str, seeds)),
                            "--our-bounces", str(BOUNCES), "--threads", str(threads), "--width", str(args.width),
                            "--height", str(args.height)], stdout=log, stderr=subprocess.STDOUT, check=True)
        with open(prefix + "-times.csv", encoding="ascii") as times:
            cpu = [float(line.split(",")[2]) for line in times.read().split("\n")[1:] if line]
        return [common.read_pfm(f"{prefix}-seed{s}.pfm") for s in seeds], cpu

    reference_seeds = [1000, 1001, 1002, 1003]
    images, _ = cycles(os.path.join(args.out, "reference"), args.reference_spp, reference_seeds, 2)
    reference = numpy.mean(images, axis=0)
    reference_mse = float(numpy.mean(numpy.var(images, axis=0, ddof=1))) / len(images)

    def mse(image):
        """The image's mean squared error, less the reference's own."""
        return max(0.0, float(numpy.mean((image - reference) ** 2)) - reference_mse)

    def ours(spp, sampler, seeds):
        """Median CPU and root mean squared error over one render with each --path-seed."""
        cpus, errors = [], []
        for seed in seeds:
            prefix = os.path.join(args.out, f"ours-{sampler}-{spp}-seed{seed}")
            cpus.append(cpu_of([tracer, "render", aff, "--integrator", "path", "--spp", str(spp), "--sampler",
                                sampler, "--path-seed", str(seed), "--threads", "1", "--pfm", prefix + ".pfm", "-q"] +
                               size, prefix + ".log"))
            errors.append(mse(common.read_pfm(prefix + ".pfm")))
        return {"spp": spp, "cpu": statistics.median(cpus), "rmse": math.sqrt(statistics.mean(errors))}

    print(f"Cornell box {args.width}x{args.height}, {BOUNCES} bounces; reference: Cycles {len(reference_seeds)} x "
          f"{args.reference_spp} spp, its own RMS error {math.sqrt(reference_mse):.5f} (taken out of each RMSE)")

    # 1. Sobol against independent at 16 spp.
    seeds = list(range(1, args.realizations + 1))
    independent16, sobol16 = ours(16, "independent", seeds), ours(16, "sobol", seeds)
    ratio1 = sobol16["rmse"] / independent16["rmse"]
    print(f"\n1. 16 spp: RMSE independent {independent16['rmse']:.5f}, Sobol {sobol16['rmse']:.5f}: "
          f"Sobol/independent {ratio1:.2f}x (goal <= 0.6: {'met' if ratio1 <= 0.6 else 'NOT met'})")

    # 2. Equal single-thread CPU time: Cycles at 256 spp, ours read off the
    # log-log line through the two points whose CPU times are nearest; each
    # point over the same number of independent renders.
    cycles_spp = 256
    cycles_images, cycles_cpus = cycles(os.path.join(args.out, f"cycles-{cycles_spp}"), cycles_spp, seeds, 1)
    cycles_cpu = statistics.median(cycles_cpus)
    cycles_rmse = math.sqrt(statistics.mean(mse(image) for image in cycles_images))
    print(f"\n2. {len(seeds)} independent renders a point. Cycles {cycles_spp} spp: CPU {cycles_cpu:.3f} s (median), "
          f"RMSE {cycles_rmse:.5f}")
    ratios = {}
    for sampler in ("independent", "sobol"):
        points = [ours(spp, sampler, seeds) for spp in (128, 256, 512)]
        for p in points:
            print(f"   ours {sampler:11} {p['spp']:5} spp: CPU {p['cpu']:.3f} s, RMSE {p['rmse']:.5f}")
        below = [p for p in points if p["cpu"] <= cycles_cpu] or points[:1]
        above = [p for p in points if p["cpu"] > cycles_cpu] or points[-1:]
        a, b = below[-1], above[0]
        if a is b:
            a, b = (points[-2], points[-1]) if a is points[-1] else (points[0], points[1])
        t = (math.log(cycles_cpu) - math.log(a["cpu"])) / (math.log(b["cpu"]) - math.log(a["cpu"]))
        at = math.exp(math.log(a["rmse"]) + t * (math.log(b["rmse"]) - math.log(a["rmse"])))
        ratios[sampler] = at / cycles_rmse
        print(f"   ours {sampler} at {cycles_cpu:.3f} s: RMSE {at:.5f}, {ratios[sampler]:.2f}x Cycles'")
    best = min(ratios.values())
    print(f"   equal CPU: ours/Cycles {ratios['independent']:.2f}x independent, {ratios['sobol']:.2f}x Sobol "
          f"(goal <= 1.2: {'met' if best <= 1.2 else 'NOT met'})")

    # 3. Writing the trace against --discard-records.
    trace = os.path.join(args.out, "cornell.din.zst")
    common_args = [tracer, "render", aff, "--integrator", "path", "--spp", "16", "--threads", "1", "-q",
                   "--width", str(args.trace_width), "--height", str(args.trace_height)]
    written, discarded = [], []
    for _ in range(args.runs):  # alternating, so a busy spell of the machine hits both
        written.append(cpu_of(common_args + ["-o", trace], os.path.join(args.out, "write.log")))
        discarded.append(cpu_of(common_args + ["--discard-records"], os.path.join(args.out, "discard.log")))
    ratio3 = statistics.median(written) / statistics.median(discarded)
    print(f"\n3. {args.trace_width}x{args.trace_height}, 16 spp, one thread: CPU writing the trace "
          f"{statistics.median(written):.3f} s, --discard-records {statistics.median(discarded):.3f} s: "
          f"{ratio3:.2f}x (goal <= 2.0: {'met' if ratio3 <= 2.0 else 'NOT met'}); trace "
          f"{os.path.getsize(trace) / 1e6:.1f} MB")
    os.remove(trace)
    for leftover in glob.glob(os.path.join(args.out, "*-seed*.pfm")):
        os.remove(leftover)
    return 0


if __name__ == "__main__":
    started = time.monotonic()
    status = main()
    print(f"bench_cycles.py: {time.monotonic() - started:.0f} s", file=sys.stderr)
    sys.exit(status)
