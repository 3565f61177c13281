"""What every experiment report shares: its manifest, cachesim's CSV, the
trace headers, the paper's numbers, and deterministic files and figures."""

import argparse
import csv
import io
import json
import math
import os
import subprocess
import sys

import matplotlib
import numpy

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The paper's scene names for ours (the forest stands in for Fairy Forest).
PAPER_SCENES = {"robot": "Robot", "kitchen": "Kitchen", "forest": "Fairy Forest (forest stands in)"}


def arguments(description):
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("manifest", help="the target's manifest.txt, written by scripts/experiments.mk")
    parser.add_argument("out_dir", help="folder for the CSV, Markdown and figures")
    parser.add_argument("--paper", required=True, help="scripts/paper-table1.csv")
    return parser.parse_args()


def read_manifest(path):
    """params (name -> text) and rows (dicts with 'file') of a manifest."""
    params, rows = {}, []
    with open(path, encoding="utf-8") as stream:
        for number, line in enumerate(stream, 1):
            line = line.strip()
            if not line:
                continue
            kind, *fields = line.split(";")
            values = {}
            for field in fields:
                key, sep, value = field.partition("=")
                if not sep:
                    sys.exit(f"{path}:{number}: expected key=value, got '{field}'")
                values[key] = value
            if kind == "param":
                params.update(values)
            elif kind == "row":
                rows.append(values)
            else:
                sys.exit(f"{path}:{number}: expected a param or row line, got '{kind}'")
    return params, rows


def read_cachesim(path):
    """cachesim run --format csv: the main table, and the per-level table
    (--per-level FILE, written beside it as PATH.levels.csv) if any. Each
    file is one table."""
    def table(name):
        with open(name, encoding="utf-8", newline="") as stream:
            return list(csv.DictReader(stream))
    rows = table(path)
    if not rows:
        sys.exit(f"{path}: no cachesim rows")
    levels = path + ".levels.csv"
    return rows, (table(levels) if os.path.exists(levels) else [])


def percent(row):
    """A report row's miss ratio in percent, from the integer counts."""
    return 100.0 * int(row["misses"]) / int(row["fetches"])


def single_and_split(path):
    """The one single and one split row of a run, and their miss ratios (%)."""
    report, _ = read_cachesim(path)
    single, split = pick(report, scheme="single"), pick(report, scheme="split")
    return single, split, percent(single), percent(split)


def pick(rows, **match):
    found = [r for r in rows if all(r[k] == str(v) for k, v in match.items())]
    if len(found) != 1:
        sys.exit(f"expected one cachesim row with {match}, found {len(found)}")
    return found[0]


_headers = {}


def run_trace(run_path, row):
    """Where to read of the trace a run simulated: the run's RUN.trace.json
    when the trace was not kept (tracer render --simulate --trace-info), else
    the trace file its row names."""
    info = run_path + ".trace.json"
    return info if os.path.exists(info) else row["trace"]


def trace_info(tracetool, trace):
    """{"header": ..., "totals": ...} of a trace container (tracetool info),
    or of a run's .trace.json (the same keys)."""
    if trace not in _headers:
        if trace.endswith(".trace.json"):
            with open(trace, encoding="utf-8") as stream:
                _headers[trace] = json.load(stream)
        else:
            done = subprocess.run([tracetool, "info", "--format", "json", trace],
                                  check=True, capture_output=True, text=True)
            _headers[trace] = json.loads(done.stdout)
    return _headers[trace]


def trace_header(tracetool, trace):
    """The JSON header of a trace (trace_info)."""
    return trace_info(tracetool, trace)["header"]


def tree_depth_limit(header):
    """The kd-tree depth limit a trace was built with (the tracer's default
    is 8 + 1.3 log2 N, rounded half away from zero)."""
    limit = header["kdtree"]["max_depth"]
    if limit:
        return limit
    triangles = header["scene"]["triangles"]
    return 8 if triangles < 2 else 8 + math.floor(1.3 * math.log2(triangles) + 0.5)


def read_paper(path):
    """(scene, size) -> {'without': float|None, 'with': float|None, 'better': str|None}."""
    with open(path, encoding="utf-8") as stream:
        lines = [line for line in stream if not line.startswith("#")]
    table = {}
    for row in csv.DictReader(lines):
        def number(text):
            return float(text) if text else None
        table[(row["scene"], row["size"])] = {
            "paper_scene": row["paper_scene"],
            "without": number(row["without_percent"]),
            "with": number(row["with_percent"]),
            "better": row["better"] or None,
        }
    return table


def better_of(single, split):
    """Which scheme has the lower miss ratio ('tie' when equal)."""
    if split < single:
        return "split"
    if split > single:
        return "single"
    return "tie"


def fmt(value, digits=2, signed=False):
    if value is None:
        return ""
    return f"{value:+.{digits}f}" if signed else f"{value:.{digits}f}"


def write_atomic(path, text):
    """Written to a temporary name and renamed, so no half file is left."""
    temporary = path + ".tmp"
    with open(temporary, "w", encoding="utf-8", newline="\n") as stream:
        stream.write(text)
    os.replace(temporary, path)


def write_csv(path, columns, rows):
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for row in rows:
        writer.writerow(["" if row.get(c) is None else row[c] for c in columns])
    write_atomic(path, buffer.getvalue())


def markdown_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def save_figure(figure, path):
    """PNG with no software or time stamp, so a re-run gives the same bytes."""
    temporary = path + ".tmp.png"
    figure.savefig(temporary, dpi=100, metadata={"Software": None})
    plt.close(figure)
    os.replace(temporary, path)


def parameter_text(params, header):
    """The parameters the paper leaves open, as this run chose them."""
    kd = header["kdtree"]
    return (f"{params['width']}x{params['height']}, frame {params['frame']}, ray depth "
            f"{params['max_ray_depth']}, scanline pixel order; kd-tree SAH traversal cost "
            f"{kd['traversal_cost']:g}, intersection cost {kd['intersection_cost']:g}, empty bonus "
            f"{kd['empty_bonus']:g}, depth limit "
            + ("tracer default 8 + 1.3 log2 N" if not kd["max_depth"] else str(kd["max_depth"])))


def size_label(size_bytes):
    """4096 -> '4KB' (sizes as the paper writes them)."""
    size_bytes = int(size_bytes)
    if size_bytes % 1024 == 0:
        return f"{size_bytes // 1024}KB"
    return f"{size_bytes}B"


def paper_name(scene):
    return PAPER_SCENES.get(scene, scene)


def size_bytes(text):
    """'16k' -> 16384, '1m' -> 1048576, '512' -> 512."""
    text = str(text).lower()
    for suffix, factor in (("k", 1024), ("m", 1 << 20)):
        if text.endswith(suffix):
            return int(text[:-1]) * factor
    return int(text)


def read_pfm(path):
    """A colour PFM's floats as an array (rows x columns x 3), top row first."""
    with open(path, "rb") as stream:
        data = stream.read()
    lines, offset = [], 0
    while len(lines) < 3:
        end = data.index(b"\n", offset)
        lines.append(data[offset:end].decode("ascii"))
        offset = end + 1
    if lines[0] != "PF":
        raise SystemExit(f"{path}: not a colour PFM")
    width, height = (int(v) for v in lines[1].split())
    scale = float(lines[2])
    pixels = numpy.frombuffer(data, dtype="<f4" if scale < 0 else ">f4", offset=offset, count=width * height * 3)
    return pixels.reshape(height, width, 3)[::-1].astype(numpy.float64)
