#!/usr/bin/python3
"""Rays in flight: split minus single miss ratio (percentage points) of each
unit's private node cache, and the miss ratio of the second level the units
share, against rays in flight per unit and the number of units; table and
plot."""

import os

import common

args = common.arguments(__doc__)
params, rows = common.read_manifest(args.manifest)


def l2_percent(entry):
    fetches = int(entry["l2_fetches"])
    return 100.0 * int(entry["l2_misses"]) / fetches if fetches else None


table = {}  # (scene, units, rays, size) -> values
scenes, units_list, rays_list, sizes = [], [], [], []
for row in rows:
    report, _ = common.read_cachesim(row["file"])
    scene, units, rays = row["scene"], int(row["units"]), int(row["rays"])
    for single in (e for e in report if e["scheme"] == "single"):
        size = int(single["size"])
        split = common.pick(report, scheme="split", size=single["size"])
        table[(scene, units, rays, size)] = {
            "single": common.percent(single), "split": common.percent(split),
            "l2_single": l2_percent(single), "l2_split": l2_percent(split),
            "fetches": int(single["fetches"]), "split_level": split["split_level"]}
        for known, value in ((scenes, scene), (units_list, units), (rays_list, rays), (sizes, size)):
            if value not in known:
                known.append(value)
units_list.sort()
rays_list.sort()
sizes.sort()

out = []
for scene in scenes:
    for units in units_list:
        for size in sizes:
            for rays in rays_list:
                v = table[(scene, units, rays, size)]
                out.append({"scene": scene, "units": units, "rays_in_flight": rays, "size_per_unit": size,
                            "fetches": v["fetches"], "split_level": v["split_level"],
                            "single_percent": f"{v['single']:.4f}", "split_percent": f"{v['split']:.4f}",
                            "split_minus_single": f"{v['split'] - v['single']:+.4f}",
                            "l2_single_percent": common.fmt(v["l2_single"], 4),
                            "l2_split_percent": common.fmt(v["l2_split"], 4)})
common.write_csv(os.path.join(args.out_dir, "inflight.csv"), list(out[0]), out)

text = ["# Rays in flight\n\n",
        "Each traversal unit keeps R rays in flight (`tracer render --rays-in-flight R --units U`: every step "
        "each busy ray slot issues its ray's next node fetch; a finished ray's secondary rays go first, "
        "depth first); pixels are dealt to the units in 8x8 tiles round robin. Every unit has its own node "
        "caches (`cachesim run --units private`) of the size given per unit, and the units share a "
        f"{params['l2_size']} second level ({params['l2_block']}-byte blocks, {params['l2_assoc']}-way LRU) "
        "that sees the first levels' fetches in trace order.\n\n"
        "Cells: split minus single miss ratio in percentage points (negative: the split has fewer misses), "
        "in brackets the single cache's miss ratio (%), then the shared L2's miss ratio (%) behind the split "
        f"caches. Direct-mapped first levels with {params['block']}-byte blocks, "
        f"{params['inflight_width']}x{params['inflight_height']}, frame {params['frame']}, ray depth "
        f"{params['max_ray_depth']}, hybrid layout sized for the largest high cache, K = auto per size.\n"]
for scene in scenes:
    text.append(f"\n## {common.paper_name(scene)}\n")
    for units in units_list:
        body = []
        for size in sizes:
            cells = [common.size_label(size)]
            for rays in rays_list:
                v = table[(scene, units, rays, size)]
                cells.append(f"{v['split'] - v['single']:+.2f} ({v['single']:.2f}); L2 {common.fmt(v['l2_split'])}")
            body.append(cells)
        text.append(f"\n{units} unit{'s' if units > 1 else ''}:\n\n")
        text.append(common.markdown_table(["Size per unit"] + [f"{r} in flight" for r in rays_list], body))
common.write_atomic(os.path.join(args.out_dir, "inflight.md"), "".join(text))

figure, axes = common.plt.subplots(2, len(scenes), figsize=(4.6 * len(scenes), 6.4), squeeze=False)
for column, scene in enumerate(scenes):
    gain_axis, l2_axis = axes[0][column], axes[1][column]
    for units in units_list:
        for size in sizes:
            label = f"{units} unit{'s' if units > 1 else ''}, {common.size_label(size)}"
            values = [table[(scene, units, r, size)] for r in rays_list]
            gain_axis.plot(range(len(rays_list)), [v["split"] - v["single"] for v in values], marker="o", label=label)
            l2_axis.plot(range(len(rays_list)), [v["l2_split"] if v["l2_split"] is not None else float("nan")
                                                 for v in values], marker="o", label=label)
    gain_axis.axhline(0, color="black", linewidth=0.6)
    for axis in (gain_axis, l2_axis):
        axis.set_xticks(range(len(rays_list)), [str(r) for r in rays_list])
        axis.set_xlabel("rays in flight per unit")
    gain_axis.set_ylabel("split − single (points)")
    l2_axis.set_ylabel("shared L2 miss ratio (%)")
    gain_axis.set_title(common.paper_name(scene))
    gain_axis.legend(fontsize=6)
figure.suptitle("Private node caches per unit: split minus single (top) and the shared L2 behind the split (bottom)",
                fontsize=9)
figure.tight_layout()
common.save_figure(figure, os.path.join(args.out_dir, "inflight.png"))
