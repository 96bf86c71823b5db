"""The scripts of examples/python run and save their plots."""

import os
import subprocess
import sys

import pytest

from conftest import ROOT

SCRIPTS = ROOT / "examples" / "python"


def run(script, out):
    p = subprocess.run(
        [sys.executable, str(SCRIPTS / script), str(out)],
        capture_output=True,
        text=True,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    assert p.returncode == 0, p.stderr
    return p.stdout


def test_five_sheet_guide_script(tmp_path):
    pytest.importorskip("matplotlib", reason="the example plots with matplotlib (pip install matplotlib)")
    out = run("five_sheet_guide.py", tmp_path)
    assert "6 motions" in out  # the x translation and the five internal modes of the folds
    png = tmp_path / "five_sheet_guide_sweep.png"
    assert png.stat().st_size > 1000 and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bode_script(tmp_path):
    pytest.importorskip("matplotlib", reason="the example plots with matplotlib (pip install matplotlib)")
    pytest.importorskip("control", reason="the example needs python-control (pip install control)")
    run("bode.py", tmp_path)
    png = tmp_path / "five_sheet_guide_bode.png"
    assert png.stat().st_size > 1000 and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
