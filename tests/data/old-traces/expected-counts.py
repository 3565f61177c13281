#!/usr/bin/env python3
"""Writes expected.json: what the programs that wrote these traces, and the
real Dinero IV, counted on them (README.md says how each trace was made).

  expected-counts.py OLD_BUILD_2026_11_22 OLD_BUILD_2026_12_02 DINEROIV > expected.json

OLD_BUILD_*: the bin/ folders of the builds that wrote the traces (their
tracetool and cachesim count); DINEROIV: scripts/build-dinero.sh's program.
"""
import csv
import io
import json
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
RUN_OPTIONS = ["--size", "1k,4k", "--block", "8", "--scheme", "single,split", "--format", "csv"]
RUN_COLUMNS = ["scheme", "size", "refs", "fetches", "misses", "high_loads", "low_misses", "split_level",
               "miss_ratio", "sampled_fraction", "miss_ratio_se"]
DINERO_SIZES = ["1k", "4k"]

TRACES = [
    # file, the build that wrote it, written by, the tracer's command
    ("hybrid-k4.din.zst", 0, "tracer ab98383 (2026-11-22)",
     "tracer render mountain:6 --width 8 --height 6 --split-level 4 --zstd-level 19 -o hybrid-k4.din.zst"),
    ("streams.xdin.zst", 0, "tracer ab98383 (2026-11-22)",
     "tracer render mountain:6 --width 6 --height 4 --streams nodes,lists,triangles --node-size 16 "
     "--zstd-level 19 -o streams.xdin.zst"),
    ("frames.din.zst", 0, "tracer ab98383 (2026-11-22)",
     "tracer render moving.aff --frames 0-1 --width 16 --height 12 --high-size 256 --zstd-level 19 "
     "-o frames.din.zst"),
    ("rows.din.zst", 1, "tracer cfbbf58 (2026-12-02)",
     "tracer render mountain:6 --width 8 --height 8 --sample-rows 1/2 --sample-seed 3 --high-size 1k "
     "--zstd-level 19 -o rows.din.zst"),
    ("archive.din.zst", 1, "tracer and tracetool cfbbf58 (2026-12-02)",
     "tracer render moving.aff --frames 0-1 --width 12 --height 8 --layout veb -o t.din.zst; "
     "tracetool convert t.din.zst archive.din.zst --archive"),
]


def run(args, stdin=None):
    return subprocess.run(args, stdin=stdin, capture_output=True, text=True, check=True, cwd=HERE).stdout


def main():
    builds = sys.argv[1:3]
    dinero = sys.argv[3]
    out = []
    for name, build, written_by, command in TRACES:
        tool = lambda program: os.path.join(builds[build], program)
        info = json.loads(run([tool("tracetool"), "info", name, "--format", "json"]))
        rows = list(csv.DictReader(io.StringIO(run([tool("cachesim"), "run", name] + RUN_OPTIONS))))
        form = info["records_form"]
        dinero_rows = []
        for size in DINERO_SIZES:
            with subprocess.Popen(["zstd", "-dc", os.path.join(HERE, name)], stdout=subprocess.PIPE) as text:
                report = run([dinero, "-informat", "D" if form == "xdin" else "d", "-l1-usize", size,
                              "-l1-ubsize", "8", "-l1-uassoc", "1"], stdin=text.stdout)
            fetches = int(re.search(r"^ Demand Fetches\s+(\d+)", report, re.M).group(1))
            misses = int(re.search(r"^ Demand Misses\s+(\d+)", report, re.M).group(1))
            dinero_rows.append({"size": size, "demand_fetches": fetches, "demand_misses": misses})
        out.append({
            "file": name,
            "written_by": written_by,
            "command": command,
            "records": info["records"],
            "animation_frames": info["animation_frames"],
            "data_frames": info["data_frames"],
            "cachesim_run": {"options": " ".join(RUN_OPTIONS[:-2]),
                             "rows": [{k: row[k] for k in RUN_COLUMNS if k in row} for row in rows]},
            "dinero": {"informat": "D" if form == "xdin" else "d",
                       "options": "-l1-ubsize 8 -l1-uassoc 1 -l1-usize SIZE", "rows": dinero_rows},
        })
    json.dump(out, sys.stdout, indent=1)
    sys.stdout.write("\n")


main()
