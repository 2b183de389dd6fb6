"""The table-cleaning and stacking experiments of VSL-3D end to end with the robot, through the
command line: demonstrate, reshuffle, reproduce with the Panda, check against the truth."""

import json

import numpy as np
import pytest
from helpers.cli import vslsp

from vslsp.errors import InputError
from vslsp.tasks.registry import get_task


@pytest.mark.slow
def test_table_cleaning_is_executed_by_the_robot(tmp_path, capsys):
    code, out, err = vslsp(capsys, "vsl3d", "table-cleaning", "--seed", "0", "--json", "--out", tmp_path)
    assert code == 0, out + err
    summary = json.loads(out)
    assert summary["experiment"] == "table-cleaning" and summary["success_rate"] == 1.0
    assert summary["operations_succeeded"] == 3 and summary["median_error_mm"] < 15.0
    report = json.loads((tmp_path / "report.json").read_text())
    operations = report["results"][0]["operations"]
    assert [op["moved"] for op in operations] == [op["picked"] for op in operations] == ["duck", "teddy", "duckling"]
    for op in operations:
        assert op["executed_by"] == "robot" and op["grasp_outcome"][-1] == "held"
        assert op["match_fitness"] > 0.5 and op["final_error_deg"] < 15.0 and op["grasp"]["width_m"] < 0.08
    for key in ("demonstration_3", "reproduction_1", "cloud", "final"):
        assert (tmp_path / report["shown_trial"][key]).stat().st_size > 10_000
    clouds = report["shown_trial"]["clouds"]  # for a 3-D view: each demonstration's scenes, each match
    assert clouds == [f"clouds/demonstration_{n}_{when}.npz" for n in (1, 2, 3) for when in ("pre", "post")] + [
        f"clouds/reproduction_{n}.npz" for n in (1, 2, 3)
    ]
    with np.load(tmp_path / clouds[-1], allow_pickle=False) as cloud:
        assert cloud["points"].shape[1] == 3 and 100 < cloud["labels"].sum() < len(cloud["labels"])
    markdown = (tmp_path / "report.md").read_text()
    assert "| 1 (seeds 0-0) | 1 | 100.0 % (" in markdown  # the rate, then its Wilson interval
    assert "| 0 | ok |" in markdown and "None" not in markdown.split("## Trials")[-1]


@pytest.mark.slow
def test_stacking_puts_each_object_on_its_moved_box():
    result = get_task("stacking").run_trial(0)
    assert result.success, result.error
    assert [op["box"] for op in result.operations] == ["box1", "box2"]
    assert all(op["executed_by"] == "robot" and op["landmark_fitness"] > 0.5 for op in result.operations)


@pytest.mark.slow
def test_a_box_missing_from_the_new_scene_is_diagnosed_and_the_other_stack_still_made():
    from vslsp.experiments.stacking import run_stacking

    results, _ = run_stacking(0, absent=("box2",))
    assert results[0].success
    assert not results[1].success and "landmark box2 not found" in results[1].error


def test_unknown_method_is_refused(capsys):
    code, _, err = vslsp(capsys, "vsl3d", "table-cleaning", "--method", "magic")
    assert code == 2 and "magic" in err
    with pytest.raises(InputError, match="magic"):
        get_task("stacking", method="magic")
