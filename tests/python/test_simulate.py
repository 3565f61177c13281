"""nodetrace.simulate(): the rows `cachesim run --format csv` prints, typed."""
import csv
import io

import pytest

import nodetrace
from conftest import SCENE, run
from python_simulate_check import typed  # the CSV typed as the module types it (tests/differential)


def cachesim_rows(trace, *options):
    text = run("cachesim", "run", trace, *options, "--format", "csv").stdout
    return [{key: typed(value) for key, value in row.items()} for row in csv.DictReader(io.StringIO(text))]


LIST = ["--size", "2k,8k", "--block", "8,16", "--assoc", "1,2", "--scheme", "single,split"]


def test_rows_equal_cachesim_run_csv(traces):
    trace = str(traces["container"])
    rows = nodetrace.simulate(trace, " ".join(LIST))
    assert rows == cachesim_rows(trace, *LIST)
    assert len(rows) == 16 and isinstance(rows[0]["refs"], int) and isinstance(rows[0]["miss_ratio"], float)
    assert rows[0]["high_refs"] is None  # single: empty in the CSV
    assert rows.columns == list(rows[0].keys())


@pytest.mark.parametrize("options, program", [
    ({"size": "4k,8k", "scheme": ["single", "split"], "policy": "fifo"},
     ["--size", "4k,8k", "--scheme", "single,split", "--policy", "fifo"]),
    ({"size": "8k", "split_level": 6, "scheme": "split", "high_policy": "cache", "count_loads": True},
     ["--size", "8k", "--split-level", "6", "--scheme", "split", "--high-policy", "cache", "--count-loads"]),
    ({"size": "8k", "sample_sets": "1/4"}, ["--size", "8k", "--sample-sets", "1/4"]),
    ({"curve": True, "block": 8}, ["--curve", "--block", "8"]),
])
def test_dict_and_keyword_options_equal_the_command_line(traces, options, program):
    trace = str(traces["container"])
    expected = cachesim_rows(trace, *program)
    assert nodetrace.simulate(trace, options) == expected
    assert nodetrace.simulate(trace, **options) == expected


@pytest.mark.parametrize("form", ["din", "xdin", "binary", "plain_zstd", "xdin_container"])
def test_every_trace_form(traces, form):
    trace = str(traces[form])
    levels = [] if "container" in form or form == "binary" else ["--tags-are-levels"]
    # Binary records carry no level: no split scheme.
    schemes = "single" if form == "binary" else "single,split"
    options = ["--size", "4k", "--scheme", schemes, "--split-level", "5", *levels]
    assert nodetrace.simulate(trace, " ".join(options)) == cachesim_rows(trace, *options)


def test_arrays_simulate_as_their_trace(traces, tmp_path):
    """Records given as an array: the rows of cachesim run on the same records written as xdin."""
    records = nodetrace.open(str(traces["xdin_container"])).records()
    options = "--size 4k,8k --scheme single,split --split-level 7"
    rows = nodetrace.simulate(records, options, name=str(traces["xdin"]))
    assert rows == cachesim_rows(str(traces["xdin"]), *options.split(), "--tags-are-levels")


def test_an_open_trace_is_simulated_from_its_file(traces):
    trace = nodetrace.open(str(traces["container"]))
    assert nodetrace.simulate(trace, size="8k") == cachesim_rows(str(traces["container"]), "--size", "8k")


def program_usage_error(trace, *options):
    program = run("cachesim", "run", trace, *options, check=False)
    assert program.returncode == 2
    return program.stderr.splitlines()[0].removeprefix("cachesim run: ")


@pytest.mark.parametrize("options", [
    ["--size", "3k"],
    ["--assoc", "zero"],
    ["--scheme", "splitt"],
    ["--policy", "lfu"],
    ["--fetch", "never"],
])
def test_bad_option_raises_value_error_with_cachesim_runs_message(traces, options):
    trace = str(traces["container"])
    with pytest.raises(ValueError) as error:
        nodetrace.simulate(trace, " ".join(options))
    assert str(error.value) == program_usage_error(trace, *options)


def test_unknown_option_raises_value_error_as_tracer_render_simulate_says_it():
    """The parser's message for options without trace names, as --simulate's."""
    program = run("tracer", "render", SCENE, "--simulate", "--sizes 8k", "--report", "-", check=False)
    assert program.returncode == 2
    with pytest.raises(ValueError) as error:
        nodetrace.simulate("unused.din.zst", "--sizes 8k")
    assert str(error.value) == program.stderr.splitlines()[0].removeprefix("tracer render --simulate: ")


def test_missing_trace_raises_os_error(tmp_path):
    with pytest.raises(OSError, match="missing.din.zst"):
        nodetrace.simulate(str(tmp_path / "missing.din.zst"), size="8k")


def test_damaged_trace_raises_format_error_and_returns_no_rows(traces, tmp_path):
    data = bytearray(traces["container"].read_bytes())
    index = nodetrace.open(str(traces["container"])).trailer["index"]
    data[index[-1][0] + 100] ^= 0xFF  # the last data frame: the rows before it are not returned
    damaged = tmp_path / "damaged.din.zst"
    damaged.write_bytes(bytes(data))
    program = run("cachesim", "run", damaged, "--size", "8k", check=False)
    assert program.returncode == 1
    with pytest.raises(nodetrace.FormatError) as error:
        nodetrace.simulate(str(damaged), size="8k")
    assert str(error.value) == program.stderr.strip().splitlines()[-1].removeprefix("cachesim run: ")


def test_to_pandas_is_the_rows():
    pandas = pytest.importorskip("pandas")
    rows = nodetrace.SimulationRows([{"a": 1, "b": None}], ["a", "b"], [])
    assert rows.to_pandas().equals(pandas.DataFrame([{"a": 1, "b": None}], columns=["a", "b"]))
