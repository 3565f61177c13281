#!/usr/bin/python3
"""How much of the split's gain is the baseline's layout: the single cache
over each layout (dfl, bfl, veb, hybrid) against the split over the hybrid
layout, per scene and size."""

import os

import common

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)

single = {}  # (scene, size bytes, layout) -> percent
split = {}   # (scene, size bytes) -> percent
layouts, scenes, sizes = [], [], []
for row in rows:
    report, _ = common.read_cachesim(row["file"])
    scene, layout = row["scene"], row["layout"]
    for entry in report:
        size = int(entry["size"])
        if entry["scheme"] == "single":
            single[(scene, size, layout)] = common.percent(entry)
        else:
            split[(scene, size)] = common.percent(entry)
        for known, value in ((layouts, layout), (scenes, scene), (sizes, size)):
            if value not in known:
                known.append(value)
sizes.sort()

out = []
for scene in scenes:
    for size in sizes:
        for layout in layouts:
            s, p = single[(scene, size, layout)], split[(scene, size)]
            out.append({"scene": scene, "size": size, "baseline_layout": layout,
                        "single_percent": f"{s:.4f}", "split_hybrid_percent": f"{p:.4f}",
                        "split_minus_single": f"{p - s:+.4f}", "split_better": common.better_of(s, p)})
common.write_csv(os.path.join(args.out_dir, "baselines.csv"), list(out[0]), out)

text = ["# Baselines: the 'without' column for each layout\n\n",
        "Miss ratio (%) of one node cache over the tree in each layout, and in brackets the split "
        "scheme's (over the hybrid layout, as in Table 1) minus it: negative means the split has "
        f"fewer misses. {params['width']}x{params['height']}, frame {params['frame']}, ray depth "
        f"{params['max_ray_depth']}, {params['block']}-byte blocks, direct-mapped; kd-tree as in "
        "table1. dfl: depth-first, bfl: breadth-first, veb: van Emde Boas, hybrid: BFL above K "
        "and DFL subtrees below (K sized for each row's high cache).\n"]
for scene in scenes:
    body = []
    for size in sizes:
        line = [common.size_label(size)]
        for layout in layouts:
            s, p = single[(scene, size, layout)], split[(scene, size)]
            line.append(f"{s:.2f} ({p - s:+.2f})")
        line.append(f"{split[(scene, size)]:.2f}")
        body.append(line)
    text.append(f"\n## {common.paper_name(scene)}\n\n")
    text.append(common.markdown_table(["Size"] + [f"single, {l}" for l in layouts] + ["split (hybrid)"], body))
common.write_atomic(os.path.join(args.out_dir, "baselines.md"), "".join(text))

figure, axes = common.plt.subplots(1, len(scenes), figsize=(4.2 * len(scenes), 3.8), squeeze=False)
width = 0.8 / (len(layouts) + 1)
for axis, scene in zip(axes[0], scenes):
    for i, size in enumerate(sizes):
        values = [single[(scene, size, l)] for l in layouts] + [split[(scene, size)]]
        labels = [f"single {l}" for l in layouts] + ["split (hybrid)"]
        for j, (value, label) in enumerate(zip(values, labels)):
            axis.bar(i + (j - len(values) / 2 + 0.5) * width, value, width, color=f"C{j}",
                     label=label if i == 0 else None)
    axis.set_xticks(range(len(sizes)), [common.size_label(z) for z in sizes])
    axis.set_title(common.paper_name(scene))
    axis.set_ylabel("miss ratio (%)")
    axis.legend(fontsize=7)
figure.suptitle("Single cache over each layout vs. the split (hybrid)", fontsize=9)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "baselines.png"))
