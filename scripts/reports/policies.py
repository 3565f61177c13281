#!/usr/bin/python3
"""Replacement policies beside the split: the single cache under LRU, PLRU,
SRRIP, DRRIP and OPT (Belady's MIN) and the split with each low-cache
policy, the share of the single cache's LRU-to-OPT gap each one closes;
table, CSV and a plot of miss ratio against size with OPT as the floor."""

import os

import common

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)

NAMES = {"lru": "LRU", "fifo": "FIFO", "random": "random", "plru": "PLRU", "srrip": "SRRIP",
         "brrip": "BRRIP", "drrip": "DRRIP", "opt": "OPT"}


def assoc_order(text):
    return (1, 0) if text == "full" else (0, int(text))


# (scene, accel, size, block, assoc, scheme, policy) -> miss ratio (%)
miss = {}
scenes, accels, sizes, blocks, assocs = [], [], [], [], []
columns = []  # (scheme, policy) in the order first met, single first
for row in rows:
    for scheme in ("single", "split"):
        report, _ = common.read_cachesim(row[scheme])
        for entry in report:
            if entry["scheme"] != scheme:
                continue
            key = (row["scene"], row["accel"], int(entry["size"]), int(row["block"]), entry["assoc"], scheme,
                   entry["policy"])
            miss[key] = common.percent(entry)
            if (scheme, entry["policy"]) not in columns:
                columns.append((scheme, entry["policy"]))
            for known, value in ((scenes, row["scene"]), (accels, row["accel"]), (sizes, int(entry["size"])),
                                 (blocks, int(row["block"])), (assocs, entry["assoc"])):
                if value not in known:
                    known.append(value)
columns.sort(key=lambda c: c[0] != "single")
sizes.sort()
blocks.sort()
assocs.sort(key=assoc_order)


def label(column):
    scheme, policy = column
    return NAMES.get(policy, policy) if scheme == "single" else f"split {NAMES.get(policy, policy)}"


def gap_closed(cell, value):
    """Share (%) of the single LRU-to-OPT gap that `value` closes, or None."""
    lru, opt = miss.get(cell + ("single", "lru")), miss.get(cell + ("single", "opt"))
    if lru is None or opt is None or lru == opt:
        return None
    return 100.0 * (lru - value) / (lru - opt)


def share_text(share):
    """A share in whole percent ('' when there is no gap; never '-0')."""
    if share is None:
        return ""
    return f"{round(share) + 0:d}"


cells = [(s, a, z, b, w) for s in scenes for a in accels for z in sizes for b in blocks for w in assocs
         if (s, a, z, b, w, "single", "lru") in miss]
out = []
for cell in cells:
    for column in columns:
        value = miss.get(cell + column)
        if value is None:
            continue
        closed = gap_closed(cell, value)
        out.append({"scene": cell[0], "accel": cell[1], "size": cell[2], "block": cell[3], "assoc": cell[4],
                    "scheme": column[0], "policy": column[1], "miss_percent": f"{value:.4f}",
                    "gap_closed_percent": None if closed is None else f"{closed:.1f}"})
common.write_csv(os.path.join(args.out_dir, "policies.csv"), list(out[0]), out)

# What docs/FINDINGS.md asks of the numbers: does the split beat RRIP, and how far
# are both from OPT (mean shares of the gap closed, over every cell).
summary = []
for column in columns:
    shares = [gap_closed(c, miss[c + column]) for c in cells if c + column in miss]
    shares = [x for x in shares if x is not None]
    above = [miss[c + column] - miss[c + ("single", "opt")] for c in cells
             if c + column in miss and c + ("single", "opt") in miss]
    summary.append([label(column), f"{sum(shares) / len(shares):.1f}" if shares else "",
                    f"{sum(above) / len(above):.2f}" if above else ""])
versus = []
for split_column in [c for c in columns if c[0] == "split"]:
    for single_column in [c for c in columns if c[0] == "single" and c[1] in ("srrip", "drrip")]:
        pairs = [(miss[c + split_column], miss[c + single_column]) for c in cells
                 if c + split_column in miss and c + single_column in miss]
        wins = sum(1 for p, s in pairs if p < s)
        versus.append([label(split_column), label(single_column), f"{wins} of {len(pairs)}"])

text = ["# Replacement policies\n\n",
        "Miss ratio (%) of the single cache under each policy and of the split with each policy in its low-level "
        "cache (high-level cache retained for the frame, K = auto), and the share of the single cache's "
        "LRU-to-OPT gap each closes (100: as good as OPT; above 100: better than the single cache's OPT, "
        "which only the split's other organisation can be). OPT is Belady's MIN with bypass, MIN within "
        f"each set. {params['policy_width']}x{params['policy_height']}, frame {params['frame']}, ray depth "
        f"{params['max_ray_depth']}, hybrid layout sized for each row's high cache.\n",
        "\n## Over every cell\n\n",
        common.markdown_table(["", "mean share of the LRU-to-OPT gap closed (%)", "mean points above OPT"],
                              summary)]
if versus:
    text.append("\nCells where the split has fewer misses than the single cache's RRIP:\n\n")
    text.append(common.markdown_table(["split", "single", "split better in"], versus))
for scene in scenes:
    for accel in accels:
        body = []
        for cell in [c for c in cells if c[0] == scene and c[1] == accel]:
            values = [common.fmt(miss.get(cell + column)) for column in columns]
            closed = [share_text(gap_closed(cell, miss[cell + column])) for column in columns
                      if column != ("single", "lru") and column != ("single", "opt") and cell + column in miss]
            body.append([common.size_label(cell[2]), cell[3], cell[4]] + values + closed)
        if not body:
            continue
        shared = [label(c) + " gap %" for c in columns if c not in (("single", "lru"), ("single", "opt"))]
        text.append(f"\n## {common.paper_name(scene)}, {accel}\n\n")
        text.append(common.markdown_table(["Size", "Block", "Ways"] + [label(c) for c in columns] + shared, body))
common.write_atomic(os.path.join(args.out_dir, "policies.md"), "".join(text))

# Miss ratio against size at one associativity (4 ways when run), OPT the floor.
shown_assoc = "4" if "4" in assocs else assocs[-1]
panels = [(s, a) for s in scenes for a in accels]
figure, axes = common.plt.subplots(len(panels), len(blocks), figsize=(4.2 * len(blocks), 3.2 * len(panels)),
                                   squeeze=False)
for row_axes, (scene, accel) in zip(axes, panels):
    for axis, block in zip(row_axes, blocks):
        for column in columns:
            points = [(z, miss.get((scene, accel, z, block, shown_assoc) + column)) for z in sizes]
            points = [(z, v) for z, v in points if v is not None]
            if not points:
                continue
            xs = [sizes.index(z) for z, _ in points]
            ys = [v for _, v in points]
            if column == ("single", "opt"):
                axis.plot(xs, ys, color="black", linewidth=1.6, label="OPT (floor)")
                axis.fill_between(xs, 0, ys, color="0.85")
            else:
                axis.plot(xs, ys, marker="o", markersize=3, linestyle="-" if column[0] == "single" else "--",
                          label=label(column))
        axis.set_xticks(range(len(sizes)), [common.size_label(z) for z in sizes])
        axis.set_ylim(bottom=0)
        axis.set_xlabel("cache size")
        axis.set_ylabel("miss ratio (%)")
        axis.set_title(f"{common.paper_name(scene)}, {accel}, {block}-byte blocks, {shown_assoc}-way", fontsize=8)
        axis.legend(fontsize=6)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "policies.png"))
