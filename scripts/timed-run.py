#!/usr/bin/python3
"""Render (optionally) and simulate one trace, timing each step: the
`sampling` experiment's unit of work. Writes cachesim's CSV to --out and the
timings (wall and user + sys seconds of the render and of the simulation) as
JSON to --out with '.time' appended."""

import argparse
import json
import os
import resource
import shlex
import subprocess
import sys
import time


def timed(command, stdout=None):
    """Runs command; returns (wall seconds, CPU user + sys seconds) of it."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    done = subprocess.run(command, stdout=stdout)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        sys.exit(f"timed-run: {shlex.join(command)} exited {done.returncode}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def write_atomic(path, data):
    temporary = f"{path}.tmp{os.getpid()}"
    with open(temporary, "wb") as stream:
        stream.write(data)
    os.replace(temporary, path)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--out", required=True, help="cachesim's CSV goes here")
    parser.add_argument("--trace", required=True, help="the trace to render (with --render) or read")
    parser.add_argument("--render", help="the tracer command line, without -o (the trace is added)")
    parser.add_argument("--keep-trace", action="store_true", help="keep a rendered trace")
    parser.add_argument("--simulate", required=True, help="the cachesim run command line, without the trace")
    args = parser.parse_args()
    timings = {"render_wall": 0.0, "render_cpu": 0.0}
    if args.render:
        temporary = f"{args.trace}.tmp{os.getpid()}.din.zst"
        timings["render_wall"], timings["render_cpu"] = timed(
            shlex.split(args.render) + ["-o", temporary])
        os.replace(temporary, args.trace)
    csv_path = f"{args.out}.tmp{os.getpid()}"
    with open(csv_path, "wb") as stream:
        simulate = shlex.split(args.simulate)
        timings["sim_wall"], timings["sim_cpu"] = timed(
            simulate[:2] + [args.trace] + simulate[2:] + ["--format", "csv"], stdout=stream)
    if args.render and not args.keep_trace:
        os.remove(args.trace)
    write_atomic(f"{args.out}.time", (json.dumps(timings, sort_keys=True) + "\n").encode())
    os.replace(csv_path, args.out)


main()
