#!/usr/bin/python3
"""Calibration, first phase: for each kd-tree build setting of the grid, the
distance of our single-cache column to the paper's and in how many cells the
split's direction matches the paper's; best.txt lists the closest settings."""

import os

import common

SETTING_COLUMNS = ["tree_depth", "traversal_cost", "intersection_cost", "empty_bonus"]


def cells(rows, paper, tracetool):
    """One record per (phase, setting, scene, size) with ours and the paper's."""
    out = []
    for row in rows:
        single, split, s, p = common.single_and_split(row["file"])
        header = common.trace_header(tracetool, common.run_trace(row["file"], single))
        known = paper.get((row["scene"], row["size"]), {})
        record = {"phase": row["phase"], "setting": row["setting"]}
        record.update(zip(SETTING_COLUMNS, row["setting"].split(":")))
        better = known.get("better")
        record.update({
            "scene": row["scene"], "size": row["size"], "width": header["render"]["width"],
            "height": header["render"]["height"], "tree_depth_limit": common.tree_depth_limit(header),
            "split_level": split["split_level"], "single_percent": f"{s:.4f}", "split_percent": f"{p:.4f}",
            "paper_without": common.fmt(known.get("without")),
            "without_diff": None if known.get("without") is None else f"{s - known['without']:+.4f}",
            "our_better": common.better_of(s, p), "paper_better": better,
            "direction_agrees": None if better is None else ("yes" if better == common.better_of(s, p) else "no")})
        out.append(record)
    return out


def rank(records):
    """Per setting: mean |ours - paper| over the cells with a paper value
    (points), and the cells where the direction agrees / is known."""
    settings = {}
    for r in records:
        settings.setdefault(r["setting"], []).append(r)
    summary = []
    for setting, mine in settings.items():
        diffs = [abs(float(r["without_diff"])) for r in mine if r["without_diff"] is not None]
        known = [r for r in mine if r["direction_agrees"] is not None]
        summary.append({"setting": setting,
                        "distance": sum(diffs) / len(diffs) if diffs else None, "distance_cells": len(diffs),
                        "agree": sum(r["direction_agrees"] == "yes" for r in known), "known": len(known),
                        "cells": mine})
    # Closest first; then more directions agreeing; then the setting's text.
    summary.sort(key=lambda s: (s["distance"] is None, s["distance"] or 0, -s["agree"], s["setting"]))
    return summary


def setting_text(setting):
    depth, traversal, intersection, empty = setting.split(":")
    return (f"depth {'8+1.3 log2 N' if depth == 'default' else depth}, costs {traversal} / "
            f"{intersection}, empty bonus {empty}")


def ranking_table(summary):
    body = []
    for i, s in enumerate(summary, 1):
        diffs = "; ".join(f"{common.paper_name(c['scene']).split(' (')[0]} {common.size_label(int(common.size_bytes(c['size'])))} "
                          f"{float(c['single_percent']):.2f} vs {c['paper_without']}"
                          for c in s["cells"] if c["paper_without"])
        body.append([i, setting_text(s["setting"]), "" if s["distance"] is None else f"{s['distance']:.2f}",
                     f"{s['agree']} / {s['known']}", diffs])
    return common.markdown_table(["rank", "kd-tree setting", "distance (points)", "direction agrees",
                                  "single: ours vs paper (%)"], body)


def main():
    args = common.arguments(__doc__)
    params, rows = common.read_manifest(args.manifest)
    records = cells(rows, common.read_paper(args.paper), params["tracetool"])
    common.write_csv(os.path.join(args.out_dir, "calibration-grid.csv"), list(records[0]), records)
    summary = rank(records)
    best = [s["setting"] for s in summary[: int(params["cal_best"])]]
    common.write_atomic(os.path.join(args.out_dir, "best.txt"), " ".join(best) + "\n")
    text = ("# Calibration grid\n\n"
            f"Each kd-tree build setting at {params['cal_width']}x{params['cal_height']}: the mean "
            "absolute difference between our single-cache miss ratio and the paper's over the cells "
            "where the paper's value is cited (scripts/paper-table1.csv), and in how many cells the "
            "split's direction (helps / hurts) matches the paper's. The closest "
            f"{params['cal_best']} go to the final phase (best.txt).\n\n" + ranking_table(summary))
    common.write_atomic(os.path.join(args.out_dir, "calibration-grid.md"), text)


if __name__ == "__main__":
    main()
