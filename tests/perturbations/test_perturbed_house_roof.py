"""house-roof with ``--perturb`` (issue 38): the demonstration as recorded, the reproduction's camera
perturbed; level 0 is exactly the run without the option; a perturbed trial names its perturbation in
its record; a bad level or an experiment that takes none is refused before any trial runs."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers.cli import vslsp

from vslsp.perturbations import Perturbation
from vslsp.tasks import get_task
from vslsp.worlds.house_roof.board import HouseWorld
from vslsp.worlds.house_roof.camera import BoardCamera

SEED = 2003


def _record(capsys, tmp_path, *perturb: str) -> dict:
    code, out, _ = vslsp(
        capsys, "experiment", "house-roof", "--seed", SEED, "--out", tmp_path / "r", "--json", *perturb
    )
    assert code in (0, 1), out
    return json.loads((tmp_path / "r" / "report.json").read_text())["results"][0]


def _without_times(record: dict) -> dict:
    return {k: v for k, v in record.items() if k not in ("time_s", "cpu_s", "stages_s", "reproduction_ms")}


def test_level_zero_is_the_run_without_the_option(capsys, tmp_path):
    plain = _record(capsys, tmp_path)
    neutral = _record(capsys, tmp_path, "--perturb", "noise=0", "--perturb", "scale=1")
    assert _without_times(neutral) == _without_times(plain) and "perturbation" not in plain


def test_a_perturbed_trial_names_its_perturbation_and_sees_a_changed_board(capsys, tmp_path):
    record = _record(capsys, tmp_path, "--perturb", "camera=10", "--perturb", "noise=8", "--perturb", "clutter=2")
    drawn = record["perturbation"]
    assert drawn["kinds"] == ["camera", "noise", "clutter"] and drawn["levels"] == {
        "camera": 10.0,
        "noise": 8.0,
        "clutter": 2.0,
    }
    assert len(drawn["distractors"]) == 2 and np.hypot(*drawn["camera"]["shift_m"][:2]) == pytest.approx(0.1, abs=1e-3)
    task = get_task("house-roof", perturb=("camera=10", "noise=8", "clutter=2"))
    world = HouseWorld.random(SEED)
    camera = BoardCamera(task.perturbation().draw(SEED), world)
    seen, plain = camera.see(world), world.render()
    assert seen.shape[0] > plain.shape[0]  # the camera's view reaches past the board
    back = camera.on_board(seen)
    inner = (slice(150, 570), slice(150, 810))
    assert (
        np.abs(back[inner].astype(int) - plain[inner]).mean()
        < np.abs(seen[inner].astype(int) - plain[inner]).mean() / 2
    )


def test_bad_perturbations_are_refused_before_any_trial(capsys, tmp_path):
    code, out, err = vslsp(
        capsys, "experiment", "house-roof", "--perturb", "camera=99", "--out", tmp_path / "x", "--json"
    )
    assert code == 2 and "camera=0 to 15" in json.loads(out)["error"] and not (tmp_path / "x").exists()
    code, out, _ = vslsp(
        capsys, "experiment", "pull-in-order", "--perturb", "noise=8", "--out", tmp_path / "y", "--json"
    )
    assert code == 2 and "--perturb applies to the VSL experiments" in json.loads(out)["error"]


def test_an_occluder_hides_its_share_of_one_object():
    world = HouseWorld.random(SEED)
    camera = BoardCamera(Perturbation(occlusion=25).draw(SEED), world)
    x0, y0, x1, y1 = (int(v) for v in camera.occluded)
    changed = np.any(camera.see(world) != world.render(), axis=2)
    assert changed.sum() > 0.1 * (x1 - x0) * (y1 - y0) and not changed[:, : max(0, x0 - 1)].any()
