"""nodetrace.render(simulate=...): the report `tracer render --simulate ... --report FILE` writes, as rows."""
import csv

import numpy as np
import pytest

import nodetrace
from conftest import SCENE, run
from python_simulate_check import typed  # the CSV typed as the module types it (tests/differential)

RENDER = ["--width", 20, "--height", 12, "--high-size", "1k,4k"]  # two hybrid layouts
SIMULATE = "--size 2k,8k --scheme single,split --format csv"


def program_report(tmp_path, simulate):
    """The rows of `tracer render --simulate SIMULATE --report FILE`, typed."""
    report = tmp_path / "r.csv"
    run("tracer", "render", SCENE, *RENDER, "--simulate", simulate, "--report", report, "-q")
    with report.open(newline="") as text:
        return [{key: typed(value) for key, value in row.items()} for row in csv.DictReader(text)]


def module_render(**keywords):
    return nodetrace.render(SCENE, width=20, height=12, high_size="1k,4k", **keywords)


@pytest.mark.parametrize("simulate", [
    "--size 2k,8k --scheme single,split",
    ["--size", "2k,8k", "--scheme", "single,split"],
    {"size": "2k,8k", "scheme": "single,split"},
])
def test_rows_equal_tracer_render_simulate_report_for_two_layouts(tmp_path, simulate):
    expected = program_report(tmp_path, SIMULATE)
    image, rows = module_render(simulate=simulate)
    assert image.shape == (12, 20, 3)
    assert isinstance(rows, nodetrace.SimulationRows)
    assert rows == expected
    # One trace column per layout, each with every cache of the options.
    layouts = sorted({row["trace"] for row in rows})
    assert len(layouts) == 2 and len(rows) == 2 * 4


def test_image_is_the_one_without_simulate():
    image, _ = module_render(simulate="--size 8k")
    assert np.array_equal(image, module_render())


@pytest.mark.parametrize("options", [["--size", "3k"], ["--sizes", "8k"], ["--scheme", "splitt"]])
def test_bad_simulate_option_raises_value_error_as_tracer_render_simulate_says_it(options):
    program = run("tracer", "render", SCENE, *map(str, RENDER), "--simulate", " ".join(options), "--report", "-",
                  check=False)
    assert program.returncode == 2
    with pytest.raises(ValueError) as error:
        module_render(simulate=" ".join(options))
    assert str(error.value) == program.stderr.splitlines()[0].removeprefix("tracer render --simulate: ")
