#!/usr/bin/python3
"""Why the split works: the miss ratio per kd-tree level of the single cache
and of the split (cachesim run --per-level), one figure per scene."""

import os

import common

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)

out, per_scene = [], {}
for row in rows:
    report, levels = common.read_cachesim(row["file"])
    if not levels:
        raise SystemExit(f"{row['file']}: no per-level table (cachesim run --per-level)")
    split = common.pick(report, scheme="split")
    k = int(split["split_level"])
    for entry in levels:
        refs, misses = int(entry["refs"]), int(entry["misses"])
        record = {"scene": row["scene"], "size": int(entry["size"]), "split_level": k,
                  "scheme": entry["scheme"], "level": int(entry["level"]), "refs": refs,
                  "misses": misses, "miss_ratio_percent": f"{100.0 * misses / refs:.4f}" if refs else ""}
        out.append(record)
        per_scene.setdefault(row["scene"], []).append(record)
common.write_csv(os.path.join(args.out_dir, "levels.csv"), list(out[0]), out)

text = ["# Misses per kd-tree level\n\n",
        "Share of all misses that fall on the levels above K (the high-level cache's levels) and "
        "below, single cache against split: under the split, levels < K never miss (they are loaded "
        "once per frame, counted apart as loads). Per-level miss ratios are in levels.csv and the figures "
        f"levels-SCENE.png. {params['width']}x{params['height']}, frame {params['frame']}, "
        f"{params['block']}-byte blocks, direct-mapped, hybrid layout, K = auto.\n\n"]
body = []
for scene, records in per_scene.items():
    for size in sorted({r["size"] for r in records}):
        group = [r for r in records if r["size"] == size]
        k = group[0]["split_level"]
        line = [common.paper_name(scene), common.size_label(size), str(k)]
        for scheme in ("single", "split"):
            mine = [r for r in group if r["scheme"] == scheme]
            refs = sum(r["refs"] for r in mine)
            high = sum(r["misses"] for r in mine if r["level"] < k)
            low = sum(r["misses"] for r in mine if r["level"] >= k)
            line += [f"{100.0 * high / refs:.2f}", f"{100.0 * low / refs:.2f}"]
        body.append(line)
text.append(common.markdown_table(["Scene", "Size", "K", "single: misses above K (% of refs)",
                                   "single: below K", "split: above K", "split: below K"], body))
common.write_atomic(os.path.join(args.out_dir, "levels.md"), "".join(text))

for scene, records in per_scene.items():
    sizes = sorted({r["size"] for r in records})
    figure, axes = common.plt.subplots(1, len(sizes), figsize=(4.2 * len(sizes), 3.6), squeeze=False)
    for axis, size in zip(axes[0], sizes):
        group = [r for r in records if r["size"] == size]
        for scheme, style in (("single", "o-"), ("split", "s-")):
            mine = sorted((r for r in group if r["scheme"] == scheme and r["refs"]), key=lambda r: r["level"])
            axis.plot([r["level"] for r in mine], [100.0 * r["misses"] / r["refs"] for r in mine], style,
                      markersize=3, label=scheme)
        axis.axvline(group[0]["split_level"] - 0.5, color="gray", linestyle="--", linewidth=0.8, label="K")
        axis.set_title(f"{common.paper_name(scene)}, {common.size_label(size)}")
        axis.set_xlabel("kd-tree level")
        axis.set_ylabel("miss ratio of the level (%)")
        axis.legend(fontsize=7)
    figure.tight_layout()
    common.save_figure(figure, os.path.join(args.out_dir, f"levels-{scene}.png"))
