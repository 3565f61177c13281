#!/usr/bin/python3
"""Treelet prefetching beside the split node cache: Table 1's sizes,
direct-mapped and set-associative, single and split, with no prefetch,
Dinero IV's tagged prefetch (single only) and the treelet prefetcher, per
scene, structure, integrator and treelet size; miss ratios, prefetch
accuracy and coverage, and the bytes each configuration fetches per ray."""

import os

import common

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)
tracetool = params["tracetool"]


def rays_of(run, row):
    """Rays the trace's render cast (its totals), for bytes per ray."""
    info = common.trace_info(tracetool, common.run_trace(run, row))
    return sum(int(v) for v in info["totals"]["rays"].values())


out = []
scenes, kinds, integrators, treelet_sizes, sizes, assocs = [], [], [], [], [], []
for row in rows:
    rays = rays_of(row["treelet"], row)
    runs = [(entry, entry["prefetch"]) for entry in common.read_cachesim(row["treelet"])[0]]
    runs += [(entry, "tagged") for entry in common.read_cachesim(row["tagged"])[0]]
    for entry, prefetcher in runs:
        block = int(entry["block"])
        misses = int(entry["misses"])
        # Blocks fetched: demand misses (with a retained high cache's loads)
        # and prefetches; cachesim's --fetch tagged does not count its
        # prefetches, so its figure is the demand part only.
        loads = int(entry["high_loads"]) if entry.get("high_loads") else 0
        prefetches = int(entry["prefetches"]) if entry.get("prefetches") else 0
        fetched = misses + loads + prefetches
        out.append({"scene": row["scene"], "accel": row["accel"], "integrator": row["integrator"],
                    "treelet_bytes": int(row["treelet_bytes"]), "scheme": entry["scheme"],
                    "size": int(entry["size"]), "block": block, "assoc": entry["assoc"], "prefetch": prefetcher,
                    "split_level": entry["split_level"], "rays": rays, "fetches": entry["fetches"],
                    "misses": misses, "miss_percent": f"{common.percent(entry):.4f}",
                    "prefetches": entry.get("prefetches", ""),
                    "useful_prefetches": entry.get("useful_prefetches", ""),
                    "prefetch_accuracy": entry.get("prefetch_accuracy", ""),
                    "prefetch_coverage": entry.get("prefetch_coverage", ""),
                    "bytes_per_ray": f"{fetched * block / max(rays, 1):.2f}",
                    "bytes_per_ray_counts_prefetches": "no" if prefetcher == "tagged" else "yes"})
        for known, value in ((scenes, row["scene"]), (kinds, row["accel"]), (integrators, row["integrator"]),
                             (treelet_sizes, int(row["treelet_bytes"])), (sizes, int(entry["size"])),
                             (assocs, entry["assoc"])):
            if value not in known:
                known.append(value)
sizes.sort()
treelet_sizes.sort()
common.write_csv(os.path.join(args.out_dir, "prefetch.csv"), list(out[0]), out)

index = {(r["scene"], r["accel"], r["integrator"], r["treelet_bytes"], r["scheme"], r["size"], r["assoc"],
          r["prefetch"]): r for r in out}


def get(scene, kind, integrator, treelet, scheme, size, assoc, prefetcher):
    return index.get((scene, kind, integrator, treelet, scheme, size, assoc, prefetcher))


def assoc_label(a):
    return "direct-mapped" if a == "1" else f"{a}-way"


def integrator_label(i):
    return "Whitted" if i == "whitted" else f"path, {params['prefetch_spp']} spp"


# The answer, from every cell: does the split still miss less than the
# single cache once both have the treelet prefetcher, and what each
# prefetcher costs in bytes per ray against none.
cells = [(s, k, i, t, z, a) for s in scenes for k in kinds for i in integrators for t in treelet_sizes
         for z in sizes for a in assocs]
split_wins = {"none": 0, "treelet": 0}
gap = {"none": [], "treelet": []}
bytes_of = {"none": [], "treelet": []}
accuracy = []
compared = 0
cost = {"tagged": [], "treelet": []}
miss_change = {"tagged": [], "treelet": []}
for s, k, i, t, z, a in cells:
    pair = {p: (get(s, k, i, t, "single", z, a, p), get(s, k, i, t, "split", z, a, p)) for p in ("none", "treelet")}
    if all(single and split for single, split in pair.values()):
        compared += 1
        for p, (single, split) in pair.items():
            split_wins[p] += float(split["miss_percent"]) < float(single["miss_percent"])
            gap[p].append(float(split["miss_percent"]) - float(single["miss_percent"]))
    base = get(s, k, i, t, "single", z, a, "none")
    treelet_run = get(s, k, i, t, "single", z, a, "treelet")
    if base and treelet_run:
        bytes_of["none"].append(float(base["bytes_per_ray"]))
        bytes_of["treelet"].append(float(treelet_run["bytes_per_ray"]))
        if treelet_run["prefetch_accuracy"] != "":
            accuracy.append(float(treelet_run["prefetch_accuracy"]))
    for p in ("tagged", "treelet"):
        other = get(s, k, i, t, "single", z, a, p)
        if base and other and float(base["bytes_per_ray"]) > 0:
            cost[p].append(float(other["bytes_per_ray"]) / float(base["bytes_per_ray"]))
            miss_change[p].append(float(other["miss_percent"]) / max(float(base["miss_percent"]), 1e-9))


def mean(values):
    return sum(values) / len(values) if values else float("nan")


text = ["# Treelet prefetching beside the split node cache\n\n",
        f"{params['prefetch_width']}x{params['prefetch_height']}, frame {params['frame']}; Whitted ray depth "
        f"{params['max_ray_depth']}, path tracing {params['prefetch_spp']} spp (the tracer's default bounces). "
        "Each structure in the treelet layout (the only layout whose trace carries treelet maps) with treelets of "
        f"{', '.join(str(t) for t in treelet_sizes)} bytes; {params['prefetch_block']}-byte blocks; single: one "
        "node cache of the size; split: high and low caches half the size each, high cache retained (its loads "
        "counted in the bytes, not as misses), K auto. Prefetchers: none; tagged, Dinero IV's (`--fetch tagged`, "
        "the next block on a miss and on the first use of a prefetched block; single cache only); treelet, "
        "`--prefetch treelet` (on a demand miss the rest of the missed block's treelet, into the cache that "
        "missed). Timing is not modelled: every prefetch arrives in time, an upper bound. Bytes per ray: blocks "
        "fetched (demand misses, high-cache loads, prefetches) x block / rays; cachesim does not count tagged "
        "prefetch's prefetches, so its figure is its demand misses alone, a lower bound.\n\n",
        "## The answer\n\n",
        f"The split runs here over the treelet layout, the only one whose trace carries treelet maps: its top "
        f"levels are not the one contiguous block the paper's hybrid layout gives them. Without prefetching the "
        f"split misses less than the single cache in {split_wins['none']} of {compared} configurations (scene, "
        f"structure, integrator, treelet size, cache size and associativity; split minus single over all of them: "
        f"{mean(gap['none']):+.2f} points on average); with the treelet prefetcher in both, in "
        f"{split_wins['treelet']} of {compared} ({mean(gap['treelet']):+.2f} points). "
        + f"So the split {'pays' if 2 * split_wins['none'] > compared else 'does not pay'} over treelets in most "
        f"configurations without prefetching, and with the treelet prefetcher it pays in "
        f"{'fewer' if split_wins['treelet'] < split_wins['none'] else 'as many' if split_wins['treelet'] == split_wins['none'] else 'more'}"
        f" of them; the mean gap {'narrows' if abs(mean(gap['treelet'])) < abs(mean(gap['none'])) else 'widens'} "
        f"from {mean(gap['none']):+.2f} to {mean(gap['treelet']):+.2f} points. "
        + f"What each prefetcher costs, on the single cache (means over the cells, against no prefetch): the "
        f"treelet prefetcher leaves {mean(miss_change['treelet']):.2f}x the misses for "
        f"{mean(cost['treelet']):.2f}x the bytes per ray, from {mean(bytes_of['none']):.0f} to "
        f"{mean(bytes_of['treelet']):.0f} bytes a ray (its accuracy {mean(accuracy):.2f}: most of what it fetches "
        f"beyond the missed block is never used); tagged prefetch leaves {mean(miss_change['tagged']):.2f}x the "
        f"misses, and its demand misses alone cost {mean(cost['tagged']):.2f}x the bytes, before the prefetches "
        "cachesim does not count (up to one on each miss and on each first use of a prefetched block).\n"]

for scene in scenes:
    text.append(f"\n## {common.paper_name(scene)}\n\n")
    for assoc in assocs:
        text.append(f"\n### Miss ratio % and bytes per ray, {assoc_label(assoc)}\n\n")
        header = ["Structure", "Integrator", "Treelet B", "Size", "single", "single tagged", "single treelet",
                  "split", "split treelet", "treelet accuracy", "treelet coverage", "B/ray none", "B/ray tagged*",
                  "B/ray treelet"]
        body = []
        for kind in kinds:
            for integrator in integrators:
                for treelet in treelet_sizes:
                    for size in sizes:
                        def cell(scheme, prefetcher, key="miss_percent", digits=2):
                            r = get(scene, kind, integrator, treelet, scheme, size, assoc, prefetcher)
                            return f"{float(r[key]):.{digits}f}" if r and r[key] != "" else ""
                        body.append([kind, integrator_label(integrator), str(treelet), common.size_label(size),
                                     cell("single", "none"), cell("single", "tagged"), cell("single", "treelet"),
                                     cell("split", "none"), cell("split", "treelet"),
                                     cell("single", "treelet", "prefetch_accuracy"),
                                     cell("single", "treelet", "prefetch_coverage"),
                                     cell("single", "none", "bytes_per_ray", 1),
                                     cell("single", "tagged", "bytes_per_ray", 1),
                                     cell("single", "treelet", "bytes_per_ray", 1)])
        text.append(common.markdown_table(header, body))
text.append("\n\\* demand misses only: cachesim does not count tagged prefetch's prefetches.\n")
common.write_atomic(os.path.join(args.out_dir, "prefetch.md"), "".join(text))

# The figure: split minus single (points) without and with the treelet
# prefetcher, per structure and integrator, at the middle size and the
# smallest treelet size; a panel per scene and associativity.
figure, axes = common.plt.subplots(len(assocs), len(scenes), figsize=(4.8 * len(scenes), 3.4 * len(assocs)),
                                   squeeze=False)
size = sizes[len(sizes) // 2]
treelet = treelet_sizes[0]
groups = [(k, i) for k in kinds for i in integrators]
for row_index, assoc in enumerate(assocs):
    for column, scene in enumerate(scenes):
        axis = axes[row_index][column]
        for j, prefetcher in enumerate(("none", "treelet")):
            values = []
            for kind, integrator in groups:
                single = get(scene, kind, integrator, treelet, "single", size, assoc, prefetcher)
                split = get(scene, kind, integrator, treelet, "split", size, assoc, prefetcher)
                values.append(float(split["miss_percent"]) - float(single["miss_percent"]) if single and split else 0)
            axis.bar([g + (j - 0.5) * 0.4 for g in range(len(groups))], values, 0.4, color=f"C{j}",
                     label="no prefetch" if prefetcher == "none" else "treelet prefetch")
        axis.axhline(0, color="black", linewidth=0.6)
        axis.set_xticks(range(len(groups)), [f"{k}\n{'W' if i == 'whitted' else 'P'}" for k, i in groups],
                        fontsize=7)
        axis.set_title(f"{common.paper_name(scene)}, {assoc_label(assoc)}, {common.size_label(size)}, "
                       f"{treelet}-byte treelets", fontsize=9)
        axis.set_ylabel("split − single (points)")
        axis.legend(fontsize=7)
figure.suptitle("Does the split still pay with a treelet prefetcher? (W: Whitted, P: path)", fontsize=9)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "prefetch.png"))
