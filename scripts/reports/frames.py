#!/usr/bin/python3
"""The split's effect over an animation: split minus single per sampled
frame (each frame its own trace and its own K), its mean and a 95%
confidence interval, plotted against the frame number."""

import math
import os

import common

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)

# Two-sided 95% quantiles of Student's t for 1..30 degrees of freedom.
T95 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160,
       2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056,
       2.052, 2.048, 2.045, 2.042]


def t95(df):
    if df <= len(T95):
        return T95[df - 1]
    z = 1.959964  # Cornish-Fisher expansion around the normal quantile
    return z + (z ** 3 + z) / (4 * df) + (5 * z ** 5 + 16 * z ** 3 + 3 * z) / (96 * df * df)


out = []
for row in rows:
    single, split, s, p = common.single_and_split(row["file"])
    out.append({"scene": row["scene"], "size": int(single["size"]), "frame": int(row["frame"]),
                "split_level": split["split_level"], "single_percent": f"{s:.4f}",
                "split_percent": f"{p:.4f}", "split_minus_single": f"{p - s:+.4f}",
                "split_better": common.better_of(s, p)})
common.write_csv(os.path.join(args.out_dir, "frames.csv"), list(out[0]), out)

groups = {}
for r in out:
    groups.setdefault((r["scene"], r["size"]), []).append(r)
body, summary = [], {}
for (scene, size), mine in groups.items():
    values = [float(r["split_minus_single"]) for r in mine]
    n = len(values)
    mean = sum(values) / n
    half = None
    if n > 1:
        sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1))
        half = t95(n - 1) * sd / math.sqrt(n)
    summary[(scene, size)] = (mean, half)
    ks = sorted({int(r["split_level"]) for r in mine})
    body.append([common.paper_name(scene), common.size_label(size), n,
                 f"{mine[0]['frame']}-{mine[-1]['frame']}", f"{mean:+.3f}",
                 "" if half is None else f"[{mean - half:+.3f}, {mean + half:+.3f}]",
                 f"{min(values):+.2f} .. {max(values):+.2f}", sum(v < 0 for v in values),
                 "-".join(str(k) for k in (ks[0], ks[-1])) if len(ks) > 1 else str(ks[0])])
text = ("# The split over an animation\n\n"
        "Split minus single miss ratio in percentage points per sampled frame (negative: the split "
        "has fewer misses); every sampled frame is its own trace (tracer --frame N), its tree rebuilt "
        "and its hybrid layout and K sized for that frame. Mean with a 95% confidence interval "
        "(Student's t over the sampled frames, which treats them as independent samples of the "
        f"animation). {params['frame_width']}x{params['frame_height']}, every {params['frame_step']}th "
        f"frame, {params['block']}-byte blocks, direct-mapped, kd-tree as in table1.\n\n"
        + common.markdown_table(["Scene", "Size", "frames", "range", "mean", "95% CI", "min .. max",
                                 "split helps in", "K"], body))
common.write_atomic(os.path.join(args.out_dir, "frames.md"), text)

figure, axis = common.plt.subplots(figsize=(7, 3.8))
for i, ((scene, size), mine) in enumerate(groups.items()):
    mean, half = summary[(scene, size)]
    frames = [r["frame"] for r in mine]
    axis.plot(frames, [float(r["split_minus_single"]) for r in mine], "o-", color=f"C{i}", markersize=3,
              label=f"{common.paper_name(scene)} {common.size_label(size)} (mean {mean:+.2f})")
    axis.axhline(mean, color=f"C{i}", linestyle="--", linewidth=0.8)
    if half is not None:
        axis.axhspan(mean - half, mean + half, color=f"C{i}", alpha=0.15)
axis.axhline(0, color="black", linewidth=0.6)
axis.set_xlabel("animation frame")
axis.set_ylabel("split − single (points)")
axis.legend(fontsize=7)
axis.set_title("Split minus single per frame; dashed: mean, band: 95% CI", fontsize=9)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "frames.png"))
