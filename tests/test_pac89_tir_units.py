"""PAC89 .tir [UNITS] TIME scales VERTICAL_DAMPING (issue 25's surviving mutation: 'millisecond'
ignored reads the damping 1000x off)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tyrefit.io.tir import read_tyre

REF = Path(__file__).resolve().parent / "data" / "ref_adams_pac89_example.tir"


def _with(tmp_path, time_unit: str, length: str = "'mm'") -> Path:
    text = REF.read_text(encoding="latin-1")
    text = text.replace("TIME          = 'sec'", f"TIME          = '{time_unit}'")
    text = text.replace("LENGTH        = 'mm'", f"LENGTH        = {length}")
    p = tmp_path / f"d_{time_unit}_{length.strip(chr(39))}.tir"
    p.write_text(text + "[VERTICAL]\nVERTICAL_STIFFNESS = 300\nVERTICAL_DAMPING = 0.5\n", encoding="latin-1")
    return p


def test_time_unit_scales_vertical_damping(tmp_path):
    s = read_tyre(_with(tmp_path, "sec")).vertical_damping
    ms = read_tyre(_with(tmp_path, "millisecond")).vertical_damping
    assert s == pytest.approx(0.5 / 1e-3)          # 0.5 N*s/mm = 500 N*s/m
    assert ms == pytest.approx(0.5 * 1e-3 / 1e-3)  # 0.5 N*ms/mm = 0.5 N*s/m
    assert s == pytest.approx(1000 * ms)


def test_length_unit_scales_vertical_damping(tmp_path):
    mm = read_tyre(_with(tmp_path, "sec", "'mm'")).vertical_damping
    m = read_tyre(_with(tmp_path, "sec", "'meter'")).vertical_damping
    assert mm == pytest.approx(1000 * m)
