"""python/examples/kitchen_miss_ratio.py runs and plots (a small render)."""
import os
import subprocess
import sys

from conftest import SOURCE_DIR


def test_kitchen_example_writes_its_plot(kitchen, tmp_path):
    plot = tmp_path / "curve.png"
    done = subprocess.run([sys.executable, str(SOURCE_DIR / "python" / "examples" / "kitchen_miss_ratio.py"),
                           "--scene", kitchen, "--width", "32", "--height", "24", "--sizes", "4k,16k", "--out",
                           str(plot)], capture_output=True, text=True, env=dict(os.environ))
    assert done.returncode == 0, done.stderr
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "split    4 KB  miss ratio" in done.stdout
