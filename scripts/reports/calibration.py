#!/usr/bin/python3
"""Calibration, final phase: the best settings of the grid again at the
final resolution, with the distance to the paper's single-cache column and
the cells where the split's direction matches; the grid ranking beside."""

import os

import calibration_grid as grid
import common

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)
records = grid.cells(rows, common.read_paper(args.paper), params["tracetool"])
common.write_csv(os.path.join(args.out_dir, "calibration.csv"), list(records[0]), records)
grid_summary = grid.rank([r for r in records if r["phase"] == "grid"])
final_summary = grid.rank([r for r in records if r["phase"] == "final"])

default = f"{params['tree_depth']}:{params['traversal_cost']}:{params['intersection_cost']}:{params['empty_bonus']}"
text = ("# Calibration of the kd-tree build against the paper\n\n"
        "The paper does not state its kd-tree's depth limit, SAH costs or empty bonus. The grid "
        f"({params['cal_width']}x{params['cal_height']}) ranks settings by the mean absolute "
        "difference (percentage points) between our single-cache miss ratio and the paper's, over "
        "the cells where the paper's value is cited; the best "
        f"{params['cal_best']} are rendered again at {params['cal_final_width']}x"
        f"{params['cal_final_height']}. 'direction agrees' counts the cells where the split helps "
        "or hurts as in the paper, out of those where the paper's direction is known. The leaf-size "
        "rule (tracer --leaf-size) is an axis of the interpretations study. These are findings, not defaults: table1 "
        f"keeps its setting ({grid.setting_text(default)}).\n\n"
        f"## Final ({params['cal_final_width']}x{params['cal_final_height']})\n\n"
        + grid.ranking_table(final_summary) + "\n## Grid\n\n" + grid.ranking_table(grid_summary))
common.write_atomic(os.path.join(args.out_dir, "calibration.md"), text)

figure, axis = common.plt.subplots(figsize=(8, 3.8))
labels = [s["setting"] for s in grid_summary]
axis.bar(range(len(labels)), [s["distance"] or 0 for s in grid_summary], color="C0",
         label=f"grid, {params['cal_width']}x{params['cal_height']}")
final = {s["setting"]: s["distance"] for s in final_summary}
for i, label in enumerate(labels):
    if final.get(label) is not None:
        axis.plot(i, final[label], "D", color="C3",
                  label=f"final, {params['cal_final_width']}x{params['cal_final_height']}" if i == 0 else None)
axis.set_xticks(range(len(labels)), labels, rotation=90, fontsize=6)
axis.set_ylabel("mean |ours − paper| (points)")
axis.set_title("Single-cache miss ratio: distance to the paper's, per kd-tree setting "
               "(depth:traversal:intersection:empty)", fontsize=8)
handles, names = axis.get_legend_handles_labels()
axis.legend(dict(zip(names, handles)).values(), dict(zip(names, handles)).keys(), fontsize=7)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "calibration.png"))
