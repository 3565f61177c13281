#!/usr/bin/python3
"""config_diff --python: nodetrace.simulate() on a case's trace and list
against the CSV `cachesim run` printed for them (every row, every column,
typed as the module types the CSV: int, float, None for an empty cell).
    python_simulate_check.py CACHESIM_CSV TRACE ARGS...
ARGS are cachesim run's, as the harness gave them; --format (the module
returns rows, not a format) is left out. Exit 0 when the rows are the
same, 1 with the first difference."""
import csv
import sys

import nodetrace


def typed(cell):
    """A CSV cell as the module types it: int, float, None for an empty cell, else the text."""
    if cell == "":
        return None
    for kind in (int, float):
        try:
            return kind(cell)
        except ValueError:
            pass
    return cell


def main():
    csv_file, trace, *args = sys.argv[1:]
    if "--format" in args:
        at = args.index("--format")
        del args[at:at + 2]
    with open(csv_file, newline="") as text:
        expected = [{key: typed(value) for key, value in row.items()} for row in csv.DictReader(text)]
    rows = nodetrace.simulate(trace, args)
    if len(rows) != len(expected):
        sys.exit(f"python simulate: {len(rows)} rows, cachesim run {len(expected)}")
    for number, (got, want) in enumerate(zip(rows, expected), 1):
        if got != want:
            differing = [key for key in want if got.get(key) != want[key]]
            sys.exit(f"python simulate: row {number} differs in {', '.join(differing)}: "
                     f"{[got.get(key) for key in differing]} against cachesim run's {[want[key] for key in differing]}")


if __name__ == "__main__":
    main()
