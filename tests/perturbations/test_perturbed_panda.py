"""The Panda tasks with ``--perturb`` (issue 38): the demonstration as recorded, the reproduction's
world perturbed; level 0 is exactly the run without the option; a perturbed trial names its
perturbation in its record; the moved camera is the world's, so the table view the robot matches
in still lines up with the table."""

from __future__ import annotations

import json

import cv2
import numpy as np
import pytest
from helpers.cli import vslsp

from vslsp.experiments.seeds import reproduction_seed
from vslsp.perturbations import Perturbation
from vslsp.tasks import get_task
from vslsp.vsl.pick_place import TableView
from vslsp.worlds.panda_table import PandaTable

SEED = 5


def _record(capsys, tmp_path, *perturb: str) -> dict:
    code, out, _ = vslsp(
        capsys, "experiment", "alphabet-ordering", "--seed", SEED, "--out", tmp_path / "r", "--json", *perturb
    )
    assert code in (0, 1), out
    return json.loads((tmp_path / "r" / "report.json").read_text())["results"][0]


def _without_times(record: dict) -> dict:
    return {k: v for k, v in record.items() if k not in ("time_s", "cpu_s", "stages_s")}


def test_level_zero_is_the_run_without_the_option(capsys, tmp_path):
    plain = _record(capsys, tmp_path)
    neutral = _record(capsys, tmp_path, "--perturb", "noise=0", "--perturb", "temperature=6500")
    assert _without_times(neutral) == _without_times(plain) and "perturbation" not in plain


def test_a_perturbed_trial_names_its_perturbation(capsys, tmp_path):
    record = _record(
        capsys, tmp_path, *("--perturb", "camera=10", "--perturb", "noise=8", "--perturb", "occlusion=25"),
        *("--perturb", "clutter=2"),
    )  # fmt: skip
    drawn = record["perturbation"]
    assert drawn["kinds"] == ["camera", "noise", "occlusion", "clutter"]
    assert drawn["levels"] == {"camera": 10.0, "noise": 8.0, "occlusion": 25.0, "clutter": 2.0}
    assert np.hypot(*drawn["camera"]["shift_m"][:2]) == pytest.approx(0.1, abs=1e-3)
    assert drawn["occluded"]["item"] in "ABCD" and len(drawn["distractors"]) == 2
    x0, y0, x1, y1 = drawn["occluded"]["box_px"]
    assert 0 <= x0 < x1 <= 1280 and 0 <= y0 < y1 <= 960
    assert {op["item"] for op in record["operations"]} == set("ABCD")  # the distractors are not items


def _world() -> PandaTable:
    task = get_task("alphabet-ordering")
    return PandaTable.from_layout(task.layout(np.random.default_rng(reproduction_seed(SEED)), "reproduction"), SEED)


def test_the_moved_cameras_table_view_lines_up_with_the_table():
    drawn = Perturbation(camera=10.0, scale=1.25, clutter=2).draw(SEED)
    with _world() as plain, _world() as moved:
        items = moved.items()
        moved.perturb(drawn)
        assert moved.camera != plain.camera and moved.items() == items  # moved; the distractors are no items
        plain_view, moved_view = TableView(plain), TableView(moved)
        plain_image, moved_image = plain_view.rectify(plain.observe()), moved_view.rectify(moved.observe())
        assert np.abs(plain_image.astype(int) - moved_image).mean() > 1.0  # the camera sees otherwise
        checked = 0
        for name in items:
            x, y, z, _ = moved.truth(name)
            top = z + moved.specs[name].size[2]
            cu, cv = moved.camera.table_to_pixel(x, y, top)
            if not (60 <= cu <= moved.WIDTH - 60 and 60 <= cv <= moved.HEIGHT - 60):
                continue  # the nearer, moved camera no longer sees it
            checked += 1
            u, v = moved_view.table_to_pixel(x, y, top)
            assert moved_view.pixel_to_table(u, v, top) == pytest.approx((x, y), abs=1e-6)
            pu, pv = (int(round(c)) for c in plain_view.table_to_pixel(x, y, top))
            patch = plain_image[pv - 16 : pv + 16, pu - 16 : pu + 16]
            search = moved_image[int(v) - 32 : int(v) + 32, int(u) - 32 : int(u) + 32]
            scores = cv2.matchTemplate(search, patch, cv2.TM_CCOEFF_NORMED)
            dv, du = np.unravel_index(int(np.argmax(scores)), scores.shape)
            # the item's top lies where the table view says, within a few px (1 px: 0.67 mm)
            assert np.hypot(du - 16 - (u - int(u)), dv - 16 - (v - int(v))) < 2.0, name
        assert checked >= 4
