#!/usr/bin/python3
"""Convergence: the path-traced image's error against CPU time. RMSE and
relative MSE of each render's PFM (ours with each sampler, and Blender
Cycles' where the scene is one of scripts/cycles/scenes.py) against a
high-spp reference of the same scene, beside the CPU time of the render, the
slope of log RMSE against log spp beside the expected -0.5 (Monte Carlo error
falls as 1/sqrt(spp)), and, beside Cycles, each sampler's RMSE at the CPU
time of Cycles' longest run against Cycles'; table, CSV and plot."""

import csv
import math
import os

import numpy

import common

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)
EXPECTED_SLOPE = -0.5
TOLERANCE = 0.1
# Relative MSE's guard against dividing by a black reference pixel
# (Rousselle et al.'s definition: (x - ref)^2 / (ref^2 + 0.01)).
RELATIVE_EPSILON = 0.01
SAMPLER_NAMES = {"independent": "ours, independent", "sobol": "ours, Sobol", "cycles": "Cycles"}


def cpu_seconds(path):
    with open(path, encoding="utf-8", newline="") as stream:
        timing = next(csv.DictReader(stream))
    return float(timing["user"]) + float(timing["sys"])


def fit(entries, key):
    """Least squares of log RMSE against log `key` over the entries whose
    `key` is above 0 (a CPU time below the clock's 0.01 s reads 0):
    (intercept, slope)."""
    entries = [e for e in entries if e[key] > 0]
    x = numpy.log([e[key] for e in entries])
    y = numpy.log([max(e["rmse"], 1e-30) for e in entries])
    if len(entries) < 2:
        return float("nan"), float("nan")
    slope, intercept = numpy.polyfit(x, y, 1)
    return float(intercept), float(slope)


def rmse_at(entries, cpu):
    """RMSE at `cpu` seconds: linear in log-log between the two renders of
    the nearest CPU times around it (beyond them, along the last two). Not a
    fit over every render: at few spp the fixed costs (start-up, Cycles'
    scene synchronisation) dominate the time, and would bend the line."""
    points = sorted((e["cpu"], e["rmse"]) for e in entries if e["cpu"] > 0 and e["rmse"] > 0)
    if len(points) < 2:
        return float("nan")
    i = 1
    while i < len(points) - 1 and points[i][0] < cpu:
        i += 1
    (c0, r0), (c1, r1) = points[i - 1], points[i]
    if c1 == c0:
        return r1
    t = (math.log(cpu) - math.log(c0)) / (math.log(c1) - math.log(c0))
    return math.exp(math.log(r0) + t * (math.log(r1) - math.log(r0)))


references, runs = {}, {}
for row in rows:
    image = common.read_pfm(row["file"][:-len(".csv")] + ".pfm")
    entry = {"spp": int(row["spp"]), "image": image, "cpu": cpu_seconds(row["file"]),
             "sampler": row.get("sampler", "independent")}
    if row["reference"] == "yes":
        references[row["scene"]] = entry
    else:
        runs.setdefault(row["scene"], {}).setdefault(entry["sampler"], []).append(entry)

out, slopes = [], {}
for scene, samplers in runs.items():
    reference = references[scene]
    for sampler, entries in samplers.items():
        entries.sort(key=lambda e: e["spp"])
        for e in entries:
            difference = e["image"] - reference["image"]
            e["rmse"] = math.sqrt(float(numpy.mean(difference ** 2)))
            e["relmse"] = float(numpy.mean(difference ** 2 / (reference["image"] ** 2 + RELATIVE_EPSILON)))
            out.append({"scene": scene, "sampler": sampler, "spp": e["spp"], "cpu_seconds": f"{e['cpu']:.3f}",
                        "rmse": f"{e['rmse']:.6g}", "relative_mse": f"{e['relmse']:.6g}",
                        "reference": reference["sampler"], "reference_spp": reference["spp"],
                        "reference_cpu_seconds": f"{reference['cpu']:.3f}"})
        slopes[(scene, sampler)] = fit(entries, "spp")[1]
common.write_csv(os.path.join(args.out_dir, "convergence.csv"), list(out[0]), out)

text = ["# Convergence: image error against CPU time\n\n",
        f"Path-traced images (`tracer render --integrator path --spp N --sampler S --threads 1`, no trace "
        f"written) at {params['conv_width']}x{params['conv_height']}, frame {params['frame']}, spp doubling from 1, "
        "with the tracer's default bounces (5). RMSE over every pixel and channel of the mean radiance (PFM); "
        "relative MSE = mean of (x - ref)^2 / (ref^2 + 0.01); CPU = user + sys of the whole command (scene loading "
        "and the tree build included: every render builds its own tree). Reference: for a scene of "
        "scripts/cycles/scenes.py, Blender Cycles at "
        f"{params.get('cycles_reference_spp', '?')} spp (seed 1000), whose random numbers no run shares; "
        "Cycles' runs are single-threaded, seed 1, with the bounces that match ours, their CPU time the Blender "
        "process's during the render (scene synchronisation and BVH build included, Blender's start-up left out). "
        f"Other scenes: ours, independent sampler, at {params['reference_spp']} spp; a render of N spp with the "
        "independent sampler takes the same random numbers as that reference's first N samples, so its expected "
        f"squared error against it is (1/N - 1/{params['reference_spp']}) times one sample's variance, not 1/N, "
        "while the Sobol renders share nothing with it.\n"]
for scene, samplers in runs.items():
    reference = references[scene]
    text.append(f"\n## {common.paper_name(scene)}\n\nReference: {SAMPLER_NAMES[reference['sampler']]}, "
                f"{reference['spp']} spp.\n\n")
    body = [[SAMPLER_NAMES[sampler], str(e["spp"]), f"{e['cpu']:.3f}", f"{e['rmse']:.5f}", f"{e['relmse']:.5f}"]
            for sampler, entries in samplers.items() for e in entries]
    text.append(common.markdown_table(["renderer", "spp", "CPU s", "RMSE", "relative MSE"], body))
    text.append("\n")
    for sampler in samplers:
        slope = slopes[(scene, sampler)]
        within = abs(slope - EXPECTED_SLOPE) <= TOLERANCE
        text.append(f"Slope of log RMSE against log spp, {SAMPLER_NAMES[sampler]}: {slope:.3f} (expected "
                    f"{EXPECTED_SLOPE}; within ±{TOLERANCE}: {'yes' if within else 'no'}).\n")
    if "cycles" in samplers:
        # At the CPU time of Cycles' render of the most spp.
        cycles = samplers["cycles"]
        cpu = cycles[-1]["cpu"]
        ratios = [f"{SAMPLER_NAMES[s]} {rmse_at(entries, cpu) / cycles[-1]['rmse']:.2f}x"
                  for s, entries in samplers.items() if s != "cycles"]
        text.append(f"\nRMSE at equal CPU time ({cpu:.3f} s, Cycles' render of {cycles[-1]['spp']} spp; ours "
                    "read off the line through its two renders nearest that time, log-log), against Cycles': "
                    f"{', '.join(ratios)}.\n")
common.write_atomic(os.path.join(args.out_dir, "convergence.md"), "".join(text))

figure, axes = common.plt.subplots(1, 2, figsize=(9.2, 3.6))
for scene, samplers in runs.items():
    for sampler, entries in samplers.items():
        cpu = [e["cpu"] for e in entries]
        spp = [e["spp"] for e in entries]
        rmse = [e["rmse"] for e in entries]
        label = f"{common.paper_name(scene)}, {SAMPLER_NAMES[sampler]}"
        line = axes[0].loglog(spp, rmse, marker="o", label=f"{label} (slope {slopes[(scene, sampler)]:.2f})")[0]
        axes[0].loglog(spp, [rmse[0] * (s / spp[0]) ** EXPECTED_SLOPE for s in spp], linestyle=":",
                       color=line.get_color())
        measured = [(c, r) for c, r in zip(cpu, rmse) if c > 0]
        axes[1].loglog([c for c, _ in measured], [r for _, r in measured], marker="o", label=label,
                       color=line.get_color())
axes[0].set_xlabel("samples per pixel")
axes[0].set_ylabel("RMSE against the reference")
axes[0].set_title("error against spp (dotted: slope -0.5)", fontsize=9)
axes[1].set_xlabel("CPU seconds (user + sys), one thread")
axes[1].set_ylabel("RMSE against the reference")
axes[1].set_title("error against CPU time", fontsize=9)
for axis in axes:
    axis.legend(fontsize=6)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "convergence.png"))
