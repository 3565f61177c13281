#!/usr/bin/python3
"""Plot `cachesim run --curve` CSV as miss ratio against cache size (PNG).

Usage: scripts/plot-curve.py CURVE.csv OUT.png   (CURVE.csv may be - for stdin)
One line per trace, scheme, block and associativity; sizes on a log2 axis.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) != 3 or argv[1] in ("-h", "--help"):
        print(__doc__.strip(), file=sys.stderr if len(argv) != 2 else sys.stdout)
        return 0 if len(argv) == 2 else 2
    source = sys.stdin if argv[1] == "-" else open(argv[1], newline="")
    lines = {}
    with source:
        reader = csv.DictReader(source)
        expected = {"trace", "scheme", "block", "assoc", "size", "miss_ratio"}
        if reader.fieldnames is None or not expected <= set(reader.fieldnames):
            print(f"plot-curve.py: {argv[1]}: line 1: expected the header of cachesim run --curve",
                  file=sys.stderr)
            return 1
        for number, row in enumerate(reader, start=2):
            if row.get("miss_ratio") == "":
                continue  # no fetches: no ratio to plot
            try:
                key = (row["trace"], row["scheme"], int(row["block"]), row["assoc"])
                lines.setdefault(key, []).append((int(row["size"]), float(row["miss_ratio"])))
            except (KeyError, ValueError, TypeError) as error:
                print(f"plot-curve.py: {argv[1]}: line {number}: {error}", file=sys.stderr)
                return 1
    if not lines:
        print(f"plot-curve.py: {argv[1]}: no points", file=sys.stderr)
        return 1
    figure, axes = plt.subplots(figsize=(8, 5))
    for (trace, scheme, block, assoc), points in sorted(lines.items()):
        points.sort()
        ways = "fully associative" if assoc == "full" else f"{assoc}-way"
        axes.plot([p[0] for p in points], [p[1] for p in points], marker=".",
                  label=f"{trace} {scheme} {block} B blocks {ways}")
    axes.set_xscale("log", base=2)
    axes.set_xlabel("cache size (bytes; split-low: the low-level cache)")
    axes.set_ylabel("miss ratio")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize="small")
    figure.tight_layout()
    # Fixed metadata: the same CSV gives the same bytes.
    figure.savefig(argv[2], dpi=120, metadata={"Software": None})
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
