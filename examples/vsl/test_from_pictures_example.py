"""The VSL-from-pictures example (examples/vsl/from_pictures.py) runs as a user runs it: four
operations learned from picture files and reproduced in a new scene within 1 cm / 5 deg."""

from pathlib import Path

import pytest
from helpers.examples import run_example

EXAMPLE = Path(__file__).with_name("from_pictures.py")


@pytest.mark.slow
def test_the_example_reproduces_the_demonstration_from_pictures(tmp_path, capsys, monkeypatch):
    printed = run_example(EXAMPLE, [str(tmp_path)], capsys, monkeypatch)
    assert "learned 4 operations: A, B, C, D" in printed
    assert sorted(p.name for p in (tmp_path / "recording").glob("*-post.png")) == [
        f"0{k}-post.png" for k in range(1, 5)
    ]
    errors = [line for line in printed.splitlines() if "off the goal" in line]
    assert len(errors) == 4
    for line in errors:
        millimetres, degrees = float(line.split()[1]), float(line.split()[3])
        assert millimetres <= 10.0 and degrees <= 5.0, line
