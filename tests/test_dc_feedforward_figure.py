"""scripts/dc_feedforward_figure.py: writes its figure and prints both runs' outcome; refuses a bad factor."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _script():
    spec = importlib.util.spec_from_file_location("dc_feedforward_figure", ROOT / "scripts" / "dc_feedforward_figure.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_figure(tmp_path, capsys):
    out = tmp_path / "f.png"
    assert _script().main(["--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert out.stat().st_size > 10_000
    assert "feed-forward off (trips hf_response" in text and "feed-forward on; angle error after the sag" in text


def test_bad_factor(capsys):
    assert _script().main(["--factor", "0"]) == 1
    assert "--factor must be in (0, 2]" in capsys.readouterr().err
