"""tower-of-hanoi's ``--intervention`` (vslsp.experiments.real_world.Intervention): by default the
paper's protocol (the user makes the first move on odd seeds), or never, or in every trial; a
bad value, or the option given to another experiment, is refused before any work (exit 2)."""

from __future__ import annotations

import json

import pytest
from helpers.cli import vslsp

from vslsp.errors import InputError
from vslsp.experiments.real_world import Intervention
from vslsp.studio.runs import checked, task_options
from vslsp.tasks import get_task


def _intervened(task, seeds=range(4)) -> list[bool]:
    return [task.for_seed(seed).intervention for seed in seeds]


def test_by_default_the_user_intervenes_on_odd_seeds_as_when_the_option_is_by_seed():
    default, by_seed = get_task("tower-of-hanoi"), get_task("tower-of-hanoi", intervention="by-seed")
    assert _intervened(default) == _intervened(by_seed) == [False, True, False, True]
    assert default.for_seed(3).variant == "intervention" and default.for_seed(3).anchor_map == {
        "base-2": "base-3",
        "base-3": "base-2",
    }
    assert default.for_seed(2) is default  # an even seed's trial is the task as given
    assert "intervention_choice" not in default.summary([])  # a run without the option: its summary unchanged
    assert by_seed.summary([])["intervention_choice"] == "by-seed"


def test_none_and_first_move_hold_for_every_seed():
    assert _intervened(get_task("tower-of-hanoi", intervention="none")) == [False] * 4
    assert _intervened(get_task("tower-of-hanoi", intervention=Intervention.FIRST_MOVE)) == [True] * 4


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["tower-of-hanoi", "--intervention", "sometimes"], "--intervention takes by-seed, none, first-move"),
        (["house-roof", "--intervention", "none"], "--intervention applies to tower-of-hanoi; house-roof takes"),
    ],
)
def test_a_bad_intervention_exits_2_with_one_message(tmp_path, capsys, args, message):
    code, out, err = vslsp(capsys, "experiment", *args, "--out", tmp_path / "report", "--json")
    assert code == 2 and message in err and "Traceback" not in err
    assert not (tmp_path / "report").exists()  # refused before any work
    assert "error" in json.loads(out)  # --json always prints JSON


def test_the_studio_takes_the_intervention_as_a_run_field(tmp_path):
    request = checked({"experiment": "tower-of-hanoi", "intervention": "first-move"})
    assert request["intervention"] == "first-move"
    assert task_options(request, str(tmp_path))["intervention"] == "first-move"
    with pytest.raises(InputError, match="--intervention takes"):
        checked({"experiment": "tower-of-hanoi", "intervention": "always"})
    with pytest.raises(InputError, match="intervention must be by-seed, none or first-move"):
        checked({"experiment": "tower-of-hanoi", "intervention": 1})


@pytest.mark.slow
def test_with_first_move_the_user_makes_the_first_move_on_an_even_seed_too():
    result = get_task("tower-of-hanoi", intervention="first-move").run_trial(2)
    assert result.success and result.details["variant"] == "intervention"
    assert [op["actor"] for op in result.operations or []] == ["tutor"] + ["robot"] * 6
