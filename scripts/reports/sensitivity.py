#!/usr/bin/python3
"""What the split's effect depends on: split minus single against K, against
the kd-tree depth limit and against the resolution, one at a time."""

import os

import common

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)
tracetool = params["tracetool"]

STUDIES = {"K": "K (levels in the high-level cache; hybrid layout built for it)",
           "tree_depth": "kd-tree depth limit", "resolution": "resolution"}

out = []
for row in rows:
    single, split, s, p = common.single_and_split(row["file"])
    header = common.trace_header(tracetool, common.run_trace(row["file"], single))
    out.append({"scene": row["scene"], "study": row["study"], "value": row["value"],
                "width": header["render"]["width"], "height": header["render"]["height"],
                "tree_depth_limit": common.tree_depth_limit(header), "split_level": split["split_level"],
                "size": single["size"], "single_percent": f"{s:.4f}", "split_percent": f"{p:.4f}",
                "split_minus_single": f"{p - s:+.4f}", "split_better": common.better_of(s, p)})
common.write_csv(os.path.join(args.out_dir, "sensitivity.csv"), list(out[0]), out)

text = ["# Sensitivity of the split's effect\n\n",
        "Split minus single miss ratio in percentage points (negative: the split has fewer misses), "
        "in brackets single / split (%), varying one parameter at a time around: "
        f"{params['sens_width']}x{params['sens_height']}, frame {params['frame']}, "
        f"{common.size_label(out[0]['size'])} in total, {params['block']}-byte blocks, direct-mapped, "
        f"K = auto, SAH costs {params['traversal_cost']} / {params['intersection_cost']}, empty bonus "
        f"{params['empty_bonus']}, depth limit {params['tree_depth']}. The resolution study renders at "
        "each resolution listed.\n"]
for study, title in STUDIES.items():
    mine = [r for r in out if r["study"] == study]
    if not mine:
        continue
    body = [[common.paper_name(r["scene"]), r["value"], r["split_level"], r["tree_depth_limit"],
             f"{float(r['split_minus_single']):+.2f} ({float(r['single_percent']):.2f} / "
             f"{float(r['split_percent']):.2f})"] for r in mine]
    text.append(f"\n## Against the {title}\n\n")
    text.append(common.markdown_table(["Scene", study, "K used", "depth limit", "split − single"], body))
common.write_atomic(os.path.join(args.out_dir, "sensitivity.md"), "".join(text))

studies = [s for s in STUDIES if any(r["study"] == s for r in out)]
figure, axes = common.plt.subplots(1, len(studies), figsize=(4.2 * len(studies), 3.6), squeeze=False)
for axis, study in zip(axes[0], studies):
    for scene in dict.fromkeys(r["scene"] for r in out):
        mine = [r for r in out if r["study"] == study and r["scene"] == scene]
        axis.plot(range(len(mine)), [float(r["split_minus_single"]) for r in mine], "o-",
                  label=common.paper_name(scene))
        axis.set_xticks(range(len(mine)), [r["value"] for r in mine], fontsize=7)
    axis.axhline(0, color="black", linewidth=0.6)
    axis.set_xlabel(STUDIES[study], fontsize=8)
    axis.set_ylabel("split − single (points)")
    axis.legend(fontsize=7)
figure.suptitle("Split minus single miss ratio (below 0: the split helps)", fontsize=9)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "sensitivity.png"))
