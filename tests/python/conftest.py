"""Fixtures of the nodetrace Python module's tests: the programs of the same
build (NODETRACE_BIN_DIR, set by CTest; default build/bin) that every number
is compared with, and small traces they make."""
import os
import pathlib
import subprocess
import sys

import pytest

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]
BIN_DIR = pathlib.Path(os.environ.get("NODETRACE_BIN_DIR", SOURCE_DIR / "build" / "bin"))
SHARED_DIR = pathlib.Path(os.environ.get("NODETRACE_SHARED_DIR", SOURCE_DIR.parent / "shared"))
# The harness's check of simulate() (config_diff --python) shares its CSV typing with these tests.
sys.path.insert(0, str(SOURCE_DIR / "tests" / "differential"))

# A small built-in scene: its tree builds in well under a second.
SCENE = "sphereflake:1"


def program(name):
    return str(BIN_DIR / name)


def run(*args, check=True):
    """Runs one of the programs; returns its CompletedProcess (text)."""
    # Messages quote damaged bytes as they are: shown as backslash escapes, as the module shows them.
    return subprocess.run([program(args[0]), *map(str, args[1:])], capture_output=True, text=True, check=check,
                          errors="backslashreplace")


@pytest.fixture(scope="session")
def traces(tmp_path_factory):
    """One render's trace in every form the reader takes."""
    folder = tmp_path_factory.mktemp("traces")
    made = {"container": folder / "t.din.zst"}
    run("tracer", "render", SCENE, "--width", 24, "--height", 16, "-q", "-o", made["container"])
    made["xdin_container"] = folder / "t.xdin.zst"
    run("tracetool", "convert", made["container"], made["xdin_container"])
    for name, file in [("din", "t.din"), ("xdin", "t.xdin"), ("binary", "t.bin")]:
        made[name] = folder / file
        run("tracetool", "convert", made["container"], made[name])
    made["plain_zstd"] = folder / "plain.din.zst"
    subprocess.run(["zstd", "-q", "-f", str(made["din"]), "-o", str(made["plain_zstd"])], check=True)
    return made


@pytest.fixture(scope="session")
def kitchen():
    """BART Kitchen from ../shared (skipped without it, a failure under CI)."""
    scene = SHARED_DIR / "scenes" / "bart" / "kitchen" / "kitchen.aff"
    if not scene.exists():
        if os.environ.get("NODETRACE_REQUIRE_SHARED") == "1":
            pytest.fail(f"{scene} is missing (NODETRACE_REQUIRE_SHARED=1)")
        pytest.skip(f"{scene} is missing")
    return str(scene)
