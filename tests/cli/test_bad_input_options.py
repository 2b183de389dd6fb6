"""Options whose limits are the documented ones (docs/bad-input.md), and ``--gui`` without a display:
exit 2 with the reason before any work (issue 27, items 3 and 5)."""

from __future__ import annotations

import pytest
from helpers.cli import vslsp


@pytest.mark.parametrize(
    "command, option, limit",
    [
        (("experiment", "house-roof"), "--trials", 10_000),
        (("experiment", "house-roof"), "--workers", 64),
        (("vsl3d", "table-cleaning"), "--trials", 10_000),
        (("vsl3d", "table-cleaning"), "--workers", 64),
        (("teach", "push"), "--demos", 100),
    ],
    ids=lambda v: v if isinstance(v, str) else None,
)
def test_counts_stop_at_the_documented_limit(capsys, monkeypatch, tmp_path, command, option, limit):
    monkeypatch.chdir(tmp_path)
    code, _, err = vslsp(capsys, *command, option, limit + 1, "--out", tmp_path / "out")
    assert code == 2 and f"is not in the range 1<=x<={limit}" in err, err


@pytest.mark.parametrize("command", [("scene",), ("demo",)], ids=lambda c: c[0])
def test_gui_without_a_display_is_refused_with_the_reason(capsys, monkeypatch, tmp_path, command):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    code, _, err = vslsp(capsys, *command, "--gui", "--out", tmp_path / "out")
    assert code == 2 and "no display" in err and "DISPLAY is not set" in err, err
    monkeypatch.setenv("DISPLAY", ":4077")  # a local display nobody serves
    code, _, err = vslsp(capsys, *command, "--gui", "--out", tmp_path / "out")
    assert code == 2 and "no X server listens on DISPLAY=:4077" in err, err


@pytest.mark.parametrize("value", ["1.5", "-0.1", "nan", "often"])
def test_a_slip_probability_outside_0_to_1_is_refused(capsys, monkeypatch, tmp_path, value):
    monkeypatch.chdir(tmp_path)
    code, _, err = vslsp(capsys, "experiment", "house-roof", "--tutor-slips", value, "--out", tmp_path / "out")
    assert code == 2 and "a probability from 0 to 1" in err and "--tutor-slips" in err, err
    assert not (tmp_path / "out").exists()  # refused before any work


def test_views_are_one_or_two(capsys, monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)
    code, _, err = vslsp(capsys, "experiment", "table-cleaning", "--views", "3", "--out", tmp_path / "out")
    assert code == 2 and "is not in the range 1<=x<=2" in err, err
