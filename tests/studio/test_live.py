"""The live picture of a running trial (vslsp.sim.live): written only when asked for, only for real views,
at most one per interval, the file replaced whole."""

from __future__ import annotations

import numpy as np

from vslsp.sim import live
from vslsp.vision.image import read_image


def test_a_view_is_published_only_when_asked_for(tmp_path, monkeypatch):
    target = tmp_path / "live.png"
    monkeypatch.delenv(live.ENV, raising=False)
    monkeypatch.setattr(live, "_last", [-live.INTERVAL_S])
    live.publish(np.zeros((120, 160, 3), np.uint8))
    assert not target.exists()
    monkeypatch.setenv(live.ENV, str(target))
    view = np.zeros((120, 160, 3), np.uint8)
    view[:, :, 0] = 200  # red: the file keeps RGB as RGB
    live.publish(view)
    assert np.array_equal(read_image(target, "live picture"), view)
    live.publish(np.zeros((120, 160, 3), np.uint8))  # within the interval: not written
    assert read_image(target, "live picture")[0, 0, 0] == 200
    assert [p.name for p in tmp_path.iterdir()] == ["live.png"]  # no temporary file left


def test_a_probe_is_not_a_picture(tmp_path, monkeypatch):
    monkeypatch.setenv(live.ENV, str(tmp_path / "live.png"))
    monkeypatch.setattr(live, "_last", [-live.INTERVAL_S])
    live.publish(np.zeros((6, 8, 3), np.uint8))
    assert not (tmp_path / "live.png").exists()


def test_a_camera_render_publishes_its_view(tmp_path, monkeypatch):
    from vslsp.sim.world import LineWorld

    monkeypatch.setenv(live.ENV, str(tmp_path / "live.png"))
    monkeypatch.setattr(live, "_last", [-live.INTERVAL_S])
    with LineWorld(seed=0, robot=False) as world:
        seen = world.observe()
    assert read_image(tmp_path / "live.png", "live picture").shape == seen.rgb.shape
