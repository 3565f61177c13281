#!/usr/bin/python3
"""Convergence: the path-traced image's error against CPU time. RMSE and
relative MSE of each render's PFM against a high-spp reference of the same
scene, beside the CPU time of the render, and the slope of log RMSE against
log spp beside the expected -0.5 (Monte Carlo error falls as 1/sqrt(spp));
table, CSV and plot."""

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


def cpu_seconds(path):
    with open(path, encoding="utf-8", newline="") as stream:
        timing = next(csv.DictReader(stream))
    return float(timing["user"]) + float(timing["sys"])


references, runs = {}, {}
for row in rows:
    image = common.read_pfm(row["file"][:-len(".csv")] + ".pfm")
    entry = {"spp": int(row["spp"]), "image": image, "cpu": cpu_seconds(row["file"])}
    if row["reference"] == "yes":
        references[row["scene"]] = entry
    else:
        runs.setdefault(row["scene"], []).append(entry)

out, slopes = [], {}
for scene, entries in runs.items():
    reference = references[scene]["image"]
    entries.sort(key=lambda e: e["spp"])
    for e in entries:
        difference = e["image"] - reference
        e["rmse"] = math.sqrt(float(numpy.mean(difference ** 2)))
        e["relmse"] = float(numpy.mean(difference ** 2 / (reference ** 2 + RELATIVE_EPSILON)))
        out.append({"scene": scene, "spp": e["spp"], "cpu_seconds": f"{e['cpu']:.3f}", "rmse": f"{e['rmse']:.6g}",
                    "relative_mse": f"{e['relmse']:.6g}", "reference_spp": references[scene]["spp"],
                    "reference_cpu_seconds": f"{references[scene]['cpu']:.3f}"})
    # Least squares of log RMSE against log spp.
    x = numpy.log([e["spp"] for e in entries])
    y = numpy.log([max(e["rmse"], 1e-30) for e in entries])
    slopes[scene] = float(numpy.polyfit(x, y, 1)[0]) if len(entries) > 1 else float("nan")
common.write_csv(os.path.join(args.out_dir, "convergence.csv"), list(out[0]), out)

text = ["# Convergence: image error against CPU time\n\n",
        f"Path-traced images (`tracer render --integrator path --spp N`, no trace written) at "
        f"{params['conv_width']}x{params['conv_height']}, frame {params['frame']}, spp doubling from 1, against a "
        f"reference of {params['reference_spp']} spp of the same scene. RMSE over every pixel and channel of the "
        "mean radiance (PFM); relative MSE = mean of (x - ref)^2 / (ref^2 + 0.01); CPU = user + sys of the whole "
        "command (scene loading and the tree build included: every render builds its own tree). A render of N spp "
        "takes the same random numbers as the reference's first N samples, so its expected squared error against "
        f"the reference is (1/N - 1/{params['reference_spp']}) times one sample's variance, not 1/N.\n"]
for scene, entries in runs.items():
    text.append(f"\n## {common.paper_name(scene)}\n\n")
    body = [[str(e["spp"]), f"{e['cpu']:.2f}", f"{e['rmse']:.5f}", f"{e['relmse']:.5f}"] for e in entries]
    text.append(common.markdown_table(["spp", "CPU s", "RMSE", "relative MSE"], body))
    within = abs(slopes[scene] - EXPECTED_SLOPE) <= TOLERANCE
    text.append(f"\nSlope of log RMSE against log spp: {slopes[scene]:.3f} (expected {EXPECTED_SLOPE}; within "
                f"±{TOLERANCE}: {'yes' if within else 'no'}).\n")
common.write_atomic(os.path.join(args.out_dir, "convergence.md"), "".join(text))

figure, axes = common.plt.subplots(1, 2, figsize=(9.2, 3.6))
for scene, entries in runs.items():
    cpu = [e["cpu"] for e in entries]
    spp = [e["spp"] for e in entries]
    rmse = [e["rmse"] for e in entries]
    line = axes[0].loglog(spp, rmse, marker="o", label=f"{common.paper_name(scene)} (slope {slopes[scene]:.2f})")[0]
    axes[0].loglog(spp, [rmse[0] * (s / spp[0]) ** EXPECTED_SLOPE for s in spp], linestyle=":",
                   color=line.get_color())
    axes[1].loglog(cpu, rmse, marker="o", label=common.paper_name(scene))
axes[0].set_xlabel("samples per pixel")
axes[0].set_ylabel("RMSE against the reference")
axes[0].set_title("error against spp (dotted: slope -0.5)", fontsize=9)
axes[1].set_xlabel("CPU seconds (user + sys)")
axes[1].set_ylabel("RMSE against the reference")
axes[1].set_title("error against CPU time", fontsize=9)
for axis in axes:
    axis.legend(fontsize=7)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "convergence.png"))
