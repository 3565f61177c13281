#!/usr/bin/python3
"""Workloads: Table 1's grid for the Whitted tracer against the path tracer
(1 and more samples per pixel), for several acceleration structures and rays
in flight: single and split miss ratios, fetches per ray and bytes missed per
ray; table, CSV and plot. Does the split help a path tracer's node cache?"""

import os

import common

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)



def rays_of(row):
    """Rays of every kind the render of the row's trace cast (the trailer's
    totals: of the trace, or of the run's .trace.json when it was not kept)."""
    totals = common.trace_info(params["tracetool"], common.run_trace(row["file"], row))["totals"]
    return sum(int(count) for count in totals["rays"].values())


def order(values, first):
    return sorted(values, key=lambda v: (v != first, v))


table = {}  # (scene, integrator, accel, rays_in_flight, size, assoc) -> values
keys = {"scene": [], "integrator": [], "accel": [], "rays": [], "size": [], "assoc": []}
for row in rows:
    report, _ = common.read_cachesim(row["file"])
    rays = rays_of(row)
    block = int(params["block"])
    for single in (e for e in report if e["scheme"] == "single"):
        split = common.pick(report, scheme="split", size=single["size"], assoc=single["assoc"])
        key = (row["scene"], row["integrator"], row["accel"], int(row["rays"]), int(single["size"]), single["assoc"])
        table[key] = {"single": common.percent(single), "split": common.percent(split),
                      "nodes_per_ray": int(single["refs"]) / rays,
                      "fetches_per_ray": int(single["fetches"]) / rays,
                      "single_bytes_per_ray": int(single["misses"]) * block / rays,
                      "split_bytes_per_ray": int(split["misses"]) * block / rays,
                      "split_level": split["split_level"], "rays": rays}
        for name, value in zip(keys, key):
            if value not in keys[name]:
                keys[name].append(value)
scenes = keys["scene"]
integrators = order(keys["integrator"], "whitted")
accels = order(keys["accel"], "kdtree")
rays_list, sizes = sorted(keys["rays"]), sorted(keys["size"])
assocs = sorted(keys["assoc"], key=lambda a: (a == "full", int(a) if a.isdigit() else 0))

out = []
for key, v in table.items():
    scene, integrator, accel, rays, size, assoc = key
    out.append({"scene": scene, "integrator": integrator, "accel": accel, "rays_in_flight": rays, "size": size,
                "assoc": assoc, "rays": v["rays"], "split_level": v["split_level"],
                "single_percent": f"{v['single']:.4f}", "split_percent": f"{v['split']:.4f}",
                "split_minus_single": f"{v['split'] - v['single']:+.4f}",
                "nodes_per_ray": f"{v['nodes_per_ray']:.3f}",
                "fetches_per_ray": f"{v['fetches_per_ray']:.3f}",
                "single_bytes_missed_per_ray": f"{v['single_bytes_per_ray']:.3f}",
                "split_bytes_missed_per_ray": f"{v['split_bytes_per_ray']:.3f}"})
out.sort(key=lambda r: (scenes.index(r["scene"]), integrators.index(r["integrator"]), accels.index(r["accel"]),
                        r["rays_in_flight"], r["size"], assocs.index(r["assoc"])))
common.write_csv(os.path.join(args.out_dir, "workloads.csv"), list(out[0]), out)


def describe(integrator):
    return "Whitted" if integrator == "whitted" else f"path, {integrator.split('-')[1]} spp"


text = ["# Workloads: Whitted against path tracing\n\n",
        "The same node caches under the Whitted tracer's rays and a path tracer's (`tracer render --integrator "
        "path --spp N`: cosine-weighted diffuse, Phong, mirror and glass bounces, one shadow ray per light at "
        "each diffuse or glossy hit, up to 5 bounces, Russian roulette from the third). Cells: split minus "
        "single miss ratio in percentage points (negative: the split has fewer misses) and, in brackets, the "
        "single cache's miss ratio (%). Nodes per ray: node fetches (records) over the rays of every kind; "
        "fetches per ray: the cache blocks those fetches read (a node larger than a block reads several); bytes "
        "missed per ray: the single cache's misses times the block over the rays. "
        f"{params['workloads_width']}x{params['workloads_height']}, frame {params['frame']}, "
        f"{params['block']}-byte blocks, K = auto, each size's trace in the hybrid layout sized for its high "
        "cache (half the size).\n"]
for scene in scenes:
    text.append(f"\n## {common.paper_name(scene)}\n\n")
    header = ["Structure", "Rays", "In flight", "Nodes/ray", "Fetches/ray"]
    for size in sizes:
        for assoc in assocs:
            header.append(f"{common.size_label(size)} {'DM' if assoc == '1' else assoc + '-way'}")
    header.append(f"Bytes missed/ray ({common.size_label(sizes[0])} DM)")
    body = []
    for accel in accels:
        for integrator in integrators:
            for rays in rays_list:
                first = table.get((scene, integrator, accel, rays, sizes[0], assocs[0]))
                if first is None:
                    continue
                cells = [accel, describe(integrator), str(rays), f"{first['nodes_per_ray']:.1f}",
                         f"{first['fetches_per_ray']:.1f}"]
                for size in sizes:
                    for assoc in assocs:
                        v = table[(scene, integrator, accel, rays, size, assoc)]
                        cells.append(f"{v['split'] - v['single']:+.2f} ({v['single']:.2f})")
                cells.append(f"{first['single_bytes_per_ray']:.1f}")
                body.append(cells)
    text.append(common.markdown_table(header, body))
common.write_atomic(os.path.join(args.out_dir, "workloads.md"), "".join(text))

# The split's gain against size, direct-mapped, one ray in flight: one panel
# per scene and structure, one line per integrator.
figure, axes = common.plt.subplots(len(scenes), len(accels), figsize=(3.6 * len(accels), 3.0 * len(scenes)),
                                   squeeze=False)
for r, scene in enumerate(scenes):
    for c, accel in enumerate(accels):
        axis = axes[r][c]
        for integrator in integrators:
            for rays in rays_list:
                values = [table.get((scene, integrator, accel, rays, size, assocs[0])) for size in sizes]
                if any(v is None for v in values):
                    continue
                axis.plot(range(len(sizes)), [v["split"] - v["single"] for v in values], marker="o",
                          linestyle="-" if rays == rays_list[0] else "--",
                          label=f"{describe(integrator)}, {rays} in flight")
        axis.axhline(0, color="black", linewidth=0.6)
        axis.set_xticks(range(len(sizes)), [common.size_label(s) for s in sizes])
        axis.set_title(f"{common.paper_name(scene)}, {accel}", fontsize=9)
        axis.set_ylabel("split − single (points)")
        axis.legend(fontsize=6)
figure.suptitle("Direct-mapped node caches: split minus single miss ratio, Whitted against path tracing", fontsize=9)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "workloads.png"))
