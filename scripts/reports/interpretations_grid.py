#!/usr/bin/python3
"""Interpretations, first phase: every reading of the grid at reduced
resolution, ranked by its mean absolute difference to the paper over the BART
cells; what each axis does around the best and around the default reading;
best.txt lists the closest readings for the final phase."""

import os

import common
import interpretation

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)
records = interpretation.cells(rows, common.read_paper(args.paper))
summary = interpretation.score(records)
default = params["interpretation"]
common.write_csv(os.path.join(args.out_dir, "interpretations-grid.csv"),
                 list(interpretation.public(summary[0])), [interpretation.public(s) for s in summary])
# The best distinct readings: one that repeats a better one's numbers adds nothing.
best = [s["interp"] for s, same in interpretation.distinct(summary) if same is None][: int(params["interp_best"])]
common.write_atomic(os.path.join(args.out_dir, "best.txt"), " ".join(best) + "\n")

shown = 20
axes = "\n".join(f"- `{a}`: {t}" for a, t in interpretation.AXIS_TEXT.items())
text = (f"# Interpretations of the paper: grid ({params['interp_width']}x{params['interp_height']})\n\n"
        f"{len(summary)} readings of what the paper leaves open, each rendered and simulated at "
        f"{params['interp_width']}x{params['interp_height']} and ranked by the mean absolute difference "
        "between our miss ratios and the paper's over the BART cells (Robot and Kitchen, without and "
        "with, 4/8/16 KB); then the largest difference and the cells where the split helps or hurts as "
        f"in the paper. The best {params['interp_best']} whose numbers differ go to the final phase (best.txt); "
        "readings with the same numbers as a better one (the same in every cell) say so; all of them "
        "are in interpretations-grid.csv. The axes:\n\n" + axes + "\n\n"
        f"## The closest {min(shown, len(summary))}\n\n"
        + interpretation.ranking_table(summary, default, shown, same=dict(
            (s["interp"], same) for s, same in interpretation.distinct(summary)))
        + "\n## Each axis around the closest reading\n\n"
        "The closest reading with one axis changed (only the readings in the grid).\n\n"
        + interpretation.axis_effects(summary, summary[0]["interp"]))
if default in {s["interp"] for s in summary}:
    text += ("\n## Each axis around the default reading\n\n"
             f"Default: {interpretation.describe(default)}.\n\n" + interpretation.axis_effects(summary, default))
common.write_atomic(os.path.join(args.out_dir, "interpretations-grid.md"), text)
