#!/usr/bin/python3
"""The split's effect against associativity: split minus single (percentage
points) for each associativity and size, per scene; table and plot."""

import os

import common

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)


def assoc_order(text):
    return (1, 0) if text == "full" else (0, int(text))


def assoc_label(entry):
    """The ways, or 'full': cachesim run spells a cache of one set so itself."""
    return entry["assoc"]


table = {}  # (scene, size, assoc) -> (single, split)
scenes, sizes, assocs = [], [], []
for row in rows:
    report, _ = common.read_cachesim(row["file"])
    scene = row["scene"]
    singles = {(e["size"], assoc_label(e)): e for e in report if e["scheme"] == "single"}
    splits = {(e["size"], assoc_label(e)): e for e in report if e["scheme"] == "split"}
    for (size_text, assoc), entry in singles.items():
        size = int(size_text)
        table[(scene, size, assoc)] = (common.percent(entry), common.percent(splits[(size_text, assoc)]))
        for known, value in ((scenes, scene), (sizes, size), (assocs, assoc)):
            if value not in known:
                known.append(value)
sizes.sort()
assocs.sort(key=assoc_order)

out = []
for scene in scenes:
    for size in sizes:
        for assoc in assocs:
            s, p = table[(scene, size, assoc)]
            out.append({"scene": scene, "size": size, "assoc": assoc, "single_percent": f"{s:.4f}",
                        "split_percent": f"{p:.4f}", "split_minus_single": f"{p - s:+.4f}",
                        "split_better": common.better_of(s, p)})
common.write_csv(os.path.join(args.out_dir, "assoc.csv"), list(out[0]), out)

text = ["# Associativity\n\n",
        "Split minus single miss ratio in percentage points (negative: the split has fewer misses) "
        "for each associativity of the single cache and of the split's low-level cache (the "
        "high-level cache retains its levels for the frame whatever its associativity); in "
        f"brackets the single cache's miss ratio (%). LRU, {params['block']}-byte blocks, "
        f"{params['width']}x{params['height']}, frame {params['frame']}, hybrid layout sized for "
        "each row's high cache, K = auto.\n"]
for scene in scenes:
    body = [[common.size_label(z)] + [f"{table[(scene, z, a)][1] - table[(scene, z, a)][0]:+.2f} "
                                      f"({table[(scene, z, a)][0]:.2f})" for a in assocs] for z in sizes]
    text.append(f"\n## {common.paper_name(scene)}\n\n")
    text.append(common.markdown_table(["Size"] + [("fully assoc." if a == "full" else f"{a}-way") for a in assocs], body))
common.write_atomic(os.path.join(args.out_dir, "assoc.md"), "".join(text))

figure, axes = common.plt.subplots(1, len(scenes), figsize=(4.2 * len(scenes), 3.6), squeeze=False)
for axis, scene in zip(axes[0], scenes):
    for size in sizes:
        axis.plot(range(len(assocs)), [table[(scene, size, a)][1] - table[(scene, size, a)][0] for a in assocs],
                  marker="o", label=common.size_label(size))
    axis.axhline(0, color="black", linewidth=0.6)
    axis.set_xticks(range(len(assocs)), assocs)
    axis.set_xlabel("associativity (ways)")
    axis.set_ylabel("split − single (points)")
    axis.set_title(common.paper_name(scene))
    axis.legend(fontsize=7)
figure.suptitle("Split minus single miss ratio against associativity (below 0: the split helps)", fontsize=9)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "assoc.png"))
