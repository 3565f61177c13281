#!/usr/bin/python3
"""Sampled renders and simulations against the full run: for each scene,
size, method (rows: tracer --sample-rows; windows: cachesim --sample-windows
on the full trace; sets: cachesim --sample-sets), rate and seed, the
estimates of the single and split miss ratios and of the gain (single minus
split) with their 95% intervals, the absolute error against the full run, the
wall time of render + simulation and the speed-up; which setting met the goal
(mean absolute error <= 0.1 points, no cell > 0.25, <= 10% of the full run's
wall time) and how often the interval held the true value."""

import json
import os

import common

MEAN_GOAL = 0.1    # percentage points
CELL_GOAL = 0.25
TIME_GOAL = 0.10   # of the full run's wall time
COVERAGE_GOAL = 0.90

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)


def timings(path):
    with open(path + ".time", encoding="utf-8") as stream:
        return json.load(stream)


def quantities(path):
    """{'single'|'split'|'gain': (estimate, low, high) in percent} of one run."""
    report, _ = common.read_cachesim(path)
    found = {}
    for scheme in ("single", "split", "gain"):
        row = common.pick(report, scheme=scheme)
        if int(row["fetches"]) == 0:
            value = None  # nothing simulated (a trace shorter than one window in K)
        elif scheme == "gain":  # from the counts, as cachesim computes it
            value = found["single"][0] - found["split"][0]
        else:
            value = common.percent(row)
        low = row.get("miss_ratio_low95") or None
        high = row.get("miss_ratio_high95") or None
        found[scheme] = (value, None if low is None else 100.0 * float(low),
                         None if high is None else 100.0 * float(high),
                         float(row["sampled_fraction"]) if row.get("sampled_fraction") else 1.0)
    return found


def full_truth(path):
    single, split, s, p = common.single_and_split(path)
    return {"single": s, "split": p, "gain": s - p}


full = {}
for row in rows:
    if row["method"] == "full":
        time = timings(row["file"])
        full[(row["scene"], row["size"])] = (full_truth(row["file"]), time)

out = []
for row in rows:
    if row["method"] == "full":
        continue
    truth, full_time = full[(row["scene"], row["size"])]
    time = timings(row["file"])
    if row["method"] == "rows":
        wall = time["render_wall"] + time["sim_wall"]
        cpu = time["render_cpu"] + time["sim_cpu"]
    else:  # the full render, then a sampled simulation of its trace
        wall = full_time["render_wall"] + time["sim_wall"]
        cpu = full_time["render_cpu"] + time["sim_cpu"]
    full_wall = full_time["render_wall"] + full_time["sim_wall"]
    for quantity, (value, low, high, fraction) in quantities(row["file"]).items():
        if value is None:
            continue
        error = abs(value - truth[quantity])
        # The interval as printed: six decimals of a fraction (5e-5 points of rounding).
        covered = low is not None and low - 5e-5 <= truth[quantity] <= high + 5e-5
        out.append({"scene": row["scene"], "size": common.size_bytes(row["size"]),
                    "method": row["method"], "rate": f"1/{row['rate']}", "seed": int(row["seed"]),
                    "quantity": quantity, "estimate_percent": f"{value:.4f}",
                    "low95_percent": "" if low is None else f"{low:.4f}",
                    "high95_percent": "" if high is None else f"{high:.4f}",
                    "true_percent": f"{truth[quantity]:.4f}", "abs_error_points": f"{error:.4f}",
                    "covered": int(covered), "sampled_fraction": f"{fraction:.6f}",
                    "wall_s": f"{wall:.2f}", "cpu_s": f"{cpu:.2f}", "full_wall_s": f"{full_wall:.2f}",
                    "full_cpu_s": f"{full_time['render_cpu'] + full_time['sim_cpu']:.2f}",
                    "time_fraction": f"{wall / full_wall:.4f}", "speedup": f"{full_wall / wall:.2f}"})
common.write_csv(os.path.join(args.out_dir, "sampling.csv"), list(out[0]), out)

# One setting = (scene, method, rate): its cells over sizes, seeds, quantities.
settings = {}
for r in out:
    settings.setdefault((r["scene"], r["method"], r["rate"]), []).append(r)


def ratio(part, whole):
    # Times are in hundredths: a run of a few milliseconds (a tiny test
    # render) is 0.00, and its fraction is unknown, not a division by zero.
    return part / whole if whole > 0 else float("nan")


def summary(cells):
    errors = [float(c["abs_error_points"]) for c in cells]
    # Time: each run counted once (three quantities share it).
    runs = {(c["size"], c["seed"]): c for c in cells}.values()
    time_fraction = ratio(sum(float(c["wall_s"]) for c in runs), sum(float(c["full_wall_s"]) for c in runs))
    cpu_fraction = ratio(sum(float(c["cpu_s"]) for c in runs), sum(float(c["full_cpu_s"]) for c in runs))
    return {"mean": sum(errors) / len(errors), "max": max(errors), "time": time_fraction,
            "cpu": cpu_fraction, "covered": sum(c["covered"] for c in cells), "cells": len(cells)}


def rate_number(rate):
    return int(rate.split("/")[1])


body = []
results = {}
for (scene, method, rate), cells in sorted(settings.items(),
                                           key=lambda item: (item[0][0], item[0][1], rate_number(item[0][2]))):
    s = summary(cells)
    results[(scene, method, rate)] = s
    met = s["mean"] <= MEAN_GOAL and s["max"] <= CELL_GOAL and s["time"] <= TIME_GOAL
    body.append([common.paper_name(scene), method, rate, f"{s['mean']:.3f}", f"{s['max']:.3f}",
                 f"{100 * s['time']:.1f}%", f"{ratio(1, s['time']):.1f}x", f"{100 * s['cpu']:.1f}%",
                 f"{s['covered']}/{s['cells']}", "yes" if met else ""])

lines = []
for scene in sorted({key[0] for key in results}):
    mine = {key: s for key, s in results.items() if key[0] == scene}
    met = [(s["time"], key) for key, s in mine.items()
           if s["mean"] <= MEAN_GOAL and s["max"] <= CELL_GOAL and s["time"] <= TIME_GOAL]
    if met:
        time, key = min(met)
        s = mine[key]
        lines.append(f"- {common.paper_name(scene)}: cheapest setting that met the goal: {key[1]} "
                     f"{key[2]} ({100 * time:.1f}% of the full wall time, mean error {s['mean']:.3f}, "
                     f"max {s['max']:.3f} points)")
        continue
    accurate = [(s["time"], key) for key, s in mine.items()
                if s["mean"] <= MEAN_GOAL and s["max"] <= CELL_GOAL]
    fast = [(s["mean"], key) for key, s in mine.items() if s["time"] <= TIME_GOAL]
    text = f"- {common.paper_name(scene)}: no setting met the goal."
    if accurate:
        time, key = min(accurate)
        text += (f" Cheapest within the error goal: {key[1]} {key[2]} at {100 * time:.1f}% of the "
                 f"full wall time.")
    if fast:
        error, key = min(fast)
        text += (f" Most accurate within 10% of the time: {key[1]} {key[2]} (mean error "
                 f"{error:.3f}, max {mine[key]['max']:.3f} points).")
    lines.append(text)

covered = sum(r["covered"] for r in out)
coverage_lines = [f"- all methods: the true value was inside the 95% interval in {covered} of "
                  f"{len(out)} cases ({100 * covered / len(out):.1f}%; goal >= {100 * COVERAGE_GOAL:.0f}%)"]
for method in sorted({r["method"] for r in out}):
    mine = [r for r in out if r["method"] == method]
    inside = sum(r["covered"] for r in mine)
    coverage_lines.append(f"- {method}: {inside} of {len(mine)} ({100 * inside / len(mine):.1f}%)")

text = ("# Error against run time: sampled renders and simulations\n\n"
        "Each setting (scene, method, rate) over the sizes "
        f"{', '.join(common.size_label(z) for z in sorted({r['size'] for r in out}))}, "
        f"seeds {', '.join(str(e) for e in sorted({r['seed'] for r in out}))} and three quantities "
        "(single and split miss ratio, gain = single minus split): mean and largest absolute error "
        "against the full run in percentage points, wall time (render + trace + simulation, tree "
        "build included) as a share of the full run's and the speed-up, CPU user + sys share, and how "
        "many 95% intervals held the true value. Methods: rows = tracer --sample-rows (sampled "
        "render), windows = cachesim --sample-windows and sets = cachesim --sample-sets on the full "
        "trace (they pay the full render). Goal: mean <= 0.1, no cell > 0.25 points, <= 10% of the "
        f"time. {params['width']}x{params['height']}, frame {params['frame']}, block {params['block']}, "
        "direct-mapped, hybrid layout per size as table1. Times from one run each on the machine "
        "that made this report, under whatever load it had.\n\n"
        + common.markdown_table(["Scene", "method", "rate", "mean abs err", "max abs err",
                                 "wall time", "speed-up", "CPU time", "in 95% CI", "goal met"], body)
        + "\n## The goal\n\n" + "\n".join(lines) + "\n\n## Interval coverage\n\n"
        + "\n".join(coverage_lines) + "\n")
common.write_atomic(os.path.join(args.out_dir, "sampling.md"), text)

scenes = sorted({key[0] for key in results})
figure, axes = common.plt.subplots(1, len(scenes), figsize=(5 * len(scenes), 3.8), squeeze=False)
markers = {"rows": "o", "windows": "s", "sets": "^"}
for axis, scene in zip(axes[0], scenes):
    for i, method in enumerate(sorted({key[1] for key in results})):
        keys = sorted((key for key in results if key[0] == scene and key[1] == method),
                      key=lambda key: rate_number(key[2]))
        if not keys:
            continue
        times = [100 * results[key]["time"] for key in keys]
        errors = [results[key]["mean"] for key in keys]
        axis.plot(times, errors, marker=markers.get(method, "o"), color=f"C{i}", label=method)
        for key, x, y in zip(keys, times, errors):
            axis.annotate(key[2], (x, y), fontsize=6, xytext=(2, 2), textcoords="offset points")
    axis.axhline(MEAN_GOAL, color="black", linestyle="--", linewidth=0.7)
    axis.axvline(100 * TIME_GOAL, color="black", linestyle=":", linewidth=0.7)
    axis.set_xscale("log")
    axis.set_xlabel("wall time, % of the full run (log)")
    axis.set_ylabel("mean abs error (points)")
    axis.set_title(common.paper_name(scene), fontsize=9)
    axis.legend(fontsize=7)
figure.suptitle("Error against run time; dashed: 0.1-point goal, dotted: 10% of the time", fontsize=9)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "sampling.png"))
