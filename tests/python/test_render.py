"""nodetrace.render(): the image and trace `tracer render` makes with the same options."""
import os
import signal
import threading
import time

import numpy as np
import pytest

import nodetrace
from conftest import SCENE, run


def read_pfm(path):
    """A colour PFM as height x width x 3, top row first (the file is bottom row first)."""
    data = path.read_bytes()
    kind, size, scale, pixels = data.split(b"\n", 3)
    assert kind == b"PF"
    width, height = map(int, size.split())
    order = "<" if float(scale) < 0 else ">"
    return np.frombuffer(pixels, dtype=order + "f4").reshape(height, width, 3)[::-1]


@pytest.mark.parametrize("options", [
    [],
    ["--pixel-order", "morton", "--rays", "primary+shadow"],
    ["--integrator", "path", "--spp", 2, "--max-bounces", 2],
])
def test_image_and_trace_equal_tracer_render(tmp_path, options):
    program_pfm, program_trace = tmp_path / "program.pfm", tmp_path / "program.din.zst"
    run("tracer", "render", SCENE, "--width", 20, "--height", 12, *options, "--pfm", program_pfm, "-o",
        program_trace, "-q")
    keywords = {options[i][2:].replace("-", "_"): options[i + 1] for i in range(0, len(options), 2)}
    module_trace = tmp_path / "module.din.zst"
    image = nodetrace.render(SCENE, width=20, height=12, output=module_trace, **keywords)
    assert image.dtype == np.float32 and image.shape == (12, 20, 3)
    assert np.array_equal(image, read_pfm(program_pfm))
    assert module_trace.read_bytes() == program_trace.read_bytes()


def test_without_output_no_trace_is_written(tmp_path):
    os.chdir(tmp_path)
    image = nodetrace.render(SCENE, width=4, height=3)
    assert image.shape == (3, 4, 3) and list(tmp_path.iterdir()) == []


def program_usage_error(*options):
    """What `tracer render` says of bad options (exit 2), without its program name."""
    program = run("tracer", "render", SCENE, *options, check=False)
    assert program.returncode == 2
    return program.stderr.splitlines()[0].removeprefix("tracer render: ")


@pytest.mark.parametrize("keywords, options", [
    ({"width": 0}, ["--width", "0"]),
    ({"rays": "all"}, ["--rays", "all"]),
    ({"eye": [0, 0, 0]}, ["--eye", "0", "0", "0"]),
    ({"spp": 4}, ["--spp", "4"]),
    ({"records": "dinn"}, ["--records", "dinn"]),
])
def test_bad_option_raises_value_error_with_the_programs_message(keywords, options):
    with pytest.raises(ValueError) as error:
        nodetrace.render(SCENE, **keywords)
    assert str(error.value) == program_usage_error(*options)


def test_unknown_option_raises_value_error_naming_it():
    with pytest.raises(ValueError, match="--widht"):
        nodetrace.render(SCENE, widht=3)


def test_missing_scene_raises_scene_error(tmp_path):
    with pytest.raises(nodetrace.SceneError, match="missing.obj: cannot open scene file"):
        nodetrace.render(str(tmp_path / "missing.obj"))


def test_ctrl_c_stops_a_long_render():
    """SIGINT (Ctrl-C) during a render that takes seconds raises KeyboardInterrupt within a fraction of it."""
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    started = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        nodetrace.render(SCENE, width=1600, height=1200, threads=1)
    assert time.monotonic() - started < 3
