#!/usr/bin/python3
"""Renders BART Kitchen, simulates single and split node caches of several
sizes on its node fetches, and plots the miss-ratio curves to a PNG.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/kitchen_miss_ratio.py

The trace's layout is the paper's hybrid, sized for an 8 KB high-level cache
(half of the 16 KB split cache); the split scheme's K is sized per cache from
the trace's kd-tree (--split-level auto), as cachesim run does.
"""
import argparse
import pathlib
import tempfile

import matplotlib

matplotlib.use("Agg")  # a file, no display
import matplotlib.pyplot as plt

import nodetrace

SHARED = pathlib.Path(__file__).resolve().parents[2].parent / "shared"

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--scene", default=str(SHARED / "scenes" / "bart" / "kitchen" / "kitchen.aff"))
parser.add_argument("--width", type=int, default=400)
parser.add_argument("--height", type=int, default=300)
parser.add_argument("--sizes", default="2k,4k,8k,16k,32k,64k")
parser.add_argument("--out", default="kitchen_miss_ratio.png")
arguments = parser.parse_args()

with tempfile.TemporaryDirectory() as folder:
    trace = pathlib.Path(folder) / "kitchen.din.zst"
    image = nodetrace.render(arguments.scene, width=arguments.width, height=arguments.height,
                             high_size="8k", output=trace)
    print(f"rendered {image.shape[1]}x{image.shape[0]}: {nodetrace.open(trace).trailer['totals']['records']} "
          "node fetches")
    rows = nodetrace.simulate(trace, size=arguments.sizes, block=8, assoc=1, scheme="single,split")

figure, axes = plt.subplots(figsize=(6, 4))
for scheme in ("single", "split"):
    mine = [row for row in rows if row["scheme"] == scheme]
    axes.plot([row["size"] / 1024 for row in mine], [100 * row["miss_ratio"] for row in mine], marker="o",
              label=scheme)
    for row in mine:
        print(f"{scheme:6} {row['size'] // 1024:3} KB  miss ratio {100 * row['miss_ratio']:.2f}%")
axes.set_xscale("log", base=2)
axes.set_xlabel("node cache size (KB; split: high + low)")
axes.set_ylabel("miss ratio (%)")
axes.set_title(f"BART Kitchen {arguments.width}x{arguments.height}, direct-mapped, 8-byte blocks")
axes.legend()
figure.tight_layout()
figure.savefig(arguments.out, dpi=120)
print(f"wrote {arguments.out}")
