"""The table-cleaning experiment of VSL-3D end to end, through its command line: demonstrate
(two objects into the box, one in front), reshuffle, reproduce, check against the truth."""

import json

import pytest
from click.testing import CliRunner

from vslsp.cli.vsl3d import vsl3d
from vslsp.errors import InputError


@pytest.mark.slow
def test_table_cleaning_reproduces_the_demonstration(tmp_path):
    result = CliRunner().invoke(vsl3d, ["table-cleaning", "--seed", "2", "--json", "--out", str(tmp_path)])
    assert result.exit_code == 0, result.output
    summary = json.loads(result.stdout)
    assert summary["experiment"] == "table-cleaning" and summary["success_rate"] == 1.0
    assert summary["operations_succeeded"] == 3 and summary["median_error_mm"] < 5.0
    report = json.loads((tmp_path / "report.json").read_text())
    operations = report["results"][0]["operations"]
    moved = [op["moved"] for op in operations]
    picked = [op["picked"] for op in operations]
    assert moved == picked == ["duck", "teddy", "duckling"]
    for op in operations:
        assert op["demonstration"]["fitness"] > 0.5 and op["final_error_deg"] < 3.0
    assert (tmp_path / report["shown_trial"]["demonstration_3"]).stat().st_size > 10_000
    assert "| 1 (seeds 2-2) | 1 | 100.0 % |" in (tmp_path / "report.md").read_text()


def test_unknown_method_is_refused():
    result = CliRunner().invoke(vsl3d, ["table-cleaning", "--method", "magic"])
    assert isinstance(result.exception, InputError) and "magic" in str(result.exception)
