#!/usr/bin/python3
"""Table 1's grid for each acceleration structure and layout: the miss ratio
of one node cache (single) over each layout, the split scheme against the
single cache over the hybrid layout, and the bytes each ray fetches."""

import os

import common

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)
tracetool = params["tracetool"]


def trace_figures(trace):
    """Rays traced and node size of a trace, from its header and totals."""
    info = common.trace_info(tracetool, trace)
    rays = sum(int(v) for v in info["totals"]["rays"].values())
    return rays, int(info["header"]["layout"]["node_size"])


out = []
scenes, kinds, layouts, sizes, blocks, assocs = [], [], [], [], [], []
for row in rows:
    report, _ = common.read_cachesim(row["file"])
    rays, node_size = trace_figures(common.run_trace(row["file"], row))
    for entry in report:
        if row["layout"] != "hybrid" and entry["scheme"] != "single":
            continue
        size, block, assoc = int(entry["size"]), int(entry["block"]), entry["assoc"]
        refs, misses = int(entry["refs"]), int(entry["misses"])
        out.append({"scene": row["scene"], "accel": row["accel"], "layout": row["layout"], "node_size": node_size,
                    "scheme": entry["scheme"], "size": size, "block": block, "assoc": assoc,
                    "split_level": entry["split_level"], "rays": rays, "refs": refs,
                    "fetches": entry["fetches"], "misses": misses,
                    "miss_percent": f"{common.percent(entry):.4f}",
                    "bytes_fetched_per_ray": f"{refs * node_size / max(rays, 1):.2f}",
                    "miss_bytes_per_ray": f"{misses * block / max(rays, 1):.2f}"})
        for known, value in ((scenes, row["scene"]), (kinds, row["accel"]), (layouts, row["layout"]),
                             (sizes, size), (blocks, block), (assocs, assoc)):
            if value not in known:
                known.append(value)
sizes.sort()
blocks.sort()
common.write_csv(os.path.join(args.out_dir, "accel.csv"), list(out[0]), out)


def find(**match):
    found = [r for r in out if all(r[k] == v for k, v in match.items())]
    return found[0] if len(found) == 1 else None


def assoc_label(a):
    return "direct-mapped" if a == "1" else f"{a}-way"


text = ["# Acceleration structures and the split node cache\n\n",
        f"{params['width']}x{params['height']}, frame {params['frame']}, ray depth {params['max_ray_depth']}; "
        "kd-tree as in table1 (8-byte nodes); bvh2: binned-SAH binary BVH, 64-byte nodes; bvh4 / bvh8: collapsed "
        "from it (greedy, largest surface area first), 128- / 256-byte nodes; cwbvh8: 8-wide, 80-byte nodes of "
        "quantized boxes. One record per node fetched (extended din with the node's size for BVHs). Split: "
        "high and low caches half the size each, high cache retained (its loads not counted), K auto, over the "
        f"hybrid layout sized for the high cache; treelets of {params['treelet_bytes']} bytes.\n"]
for scene in scenes:
    text.append(f"\n## {common.paper_name(scene)}\n\n")
    text.append("Bytes of nodes fetched per ray and node fetches per ray (the same in every layout), and bytes "
                "missed per ray (misses x block / rays) of the single cache over the hybrid layout, "
                f"direct-mapped, {blocks[-1]}-byte blocks:\n\n")
    body = []
    for kind in kinds:
        r = find(scene=scene, accel=kind, layout="hybrid", scheme="single", size=sizes[0], block=blocks[0],
                 assoc=assocs[0])
        if r:
            line = [kind, str(r["node_size"]), r["bytes_fetched_per_ray"], f"{r['refs'] / max(r['rays'], 1):.2f}"]
            for z in sizes:
                m = find(scene=scene, accel=kind, layout="hybrid", scheme="single", size=z, block=blocks[-1],
                         assoc=assocs[0])
                line.append(m["miss_bytes_per_ray"] if m else "")
            body.append(line)
    text.append(common.markdown_table(["Structure", "Node bytes", "Bytes fetched per ray", "Node fetches per ray"]
                                      + [f"Bytes missed per ray, {common.size_label(z)}" for z in sizes], body))
    for assoc in assocs:
        text.append(f"\n### Split minus single, hybrid layout, {assoc_label(assoc)} (miss ratio %, "
                    "negative: the split misses less)\n\n")
        columns = [f"{common.size_label(z)} / {b} B" for z in sizes for b in blocks]
        body = []
        for kind in kinds:
            line = [kind]
            for z in sizes:
                for b in blocks:
                    single = find(scene=scene, accel=kind, layout="hybrid", scheme="single", size=z, block=b,
                                  assoc=assoc)
                    split = find(scene=scene, accel=kind, layout="hybrid", scheme="split", size=z, block=b,
                                 assoc=assoc)
                    if single and split:
                        s, p = float(single["miss_percent"]), float(split["miss_percent"])
                        line.append(f"{s:.2f} → {p:.2f} ({p - s:+.2f})")
                    else:
                        line.append("")
            body.append(line)
        text.append(common.markdown_table(["Structure"] + columns, body))
        text.append(f"\n### Single cache over each layout, {assoc_label(assoc)} (miss ratio %)\n\n")
        body = []
        for kind in kinds:
            for layout in layouts:
                line = [kind, layout]
                for z in sizes:
                    for b in blocks:
                        # The hybrid layout's single run is per size (its K is sized for it).
                        r = find(scene=scene, accel=kind, layout=layout, scheme="single", size=z, block=b, assoc=assoc)
                        line.append(f"{float(r['miss_percent']):.2f}" if r else "")
                body.append(line)
        text.append(common.markdown_table(["Structure", "Layout"] + columns, body))
common.write_atomic(os.path.join(args.out_dir, "accel.md"), "".join(text))

# The figure: split minus single (points) per structure, for each size, at
# the largest block, one panel per scene and associativity.
figure, axes = common.plt.subplots(len(assocs), len(scenes), figsize=(4.6 * len(scenes), 3.4 * len(assocs)),
                                   squeeze=False)
block = blocks[-1]
width = 0.8 / max(len(sizes), 1)
for row_index, assoc in enumerate(assocs):
    for column, scene in enumerate(scenes):
        axis = axes[row_index][column]
        for j, z in enumerate(sizes):
            values = []
            for kind in kinds:
                single = find(scene=scene, accel=kind, layout="hybrid", scheme="single", size=z, block=block,
                              assoc=assoc)
                split = find(scene=scene, accel=kind, layout="hybrid", scheme="split", size=z, block=block,
                             assoc=assoc)
                values.append(float(split["miss_percent"]) - float(single["miss_percent"]) if single and split else 0)
            axis.bar([i + (j - len(sizes) / 2 + 0.5) * width for i in range(len(kinds))], values, width,
                     color=f"C{j}", label=common.size_label(z))
        axis.axhline(0, color="black", linewidth=0.6)
        axis.set_xticks(range(len(kinds)), kinds)
        axis.set_title(f"{common.paper_name(scene)}, {assoc_label(assoc)}, {block}-byte blocks", fontsize=9)
        axis.set_ylabel("split − single (points)")
        axis.legend(fontsize=7)
figure.suptitle("Does the split help? Miss ratio of the split minus the single cache (hybrid layout)", fontsize=9)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "accel.png"))
