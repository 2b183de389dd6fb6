"""A trial's video: H.264 that ffmpeg reads back, one frame per 1/fps simulated seconds under
the caption, the same frames for the same motion, and a simulation that filming leaves alone."""

from __future__ import annotations

import subprocess

import imageio_ffmpeg
import numpy as np
import pytest

from vslsp.sim import LineWorld, SceneSpec
from vslsp.sim.scene import TABLE_Z
from vslsp.sim.video import FPS, SceneVideo, preview

REACH = np.array([0.3, -0.1, TABLE_Z + 0.05])


def _film(path) -> tuple[SceneVideo, tuple]:
    with LineWorld(SceneSpec.random(3)) as world:
        video = SceneVideo(path)
        video.attach(world)
        video.caption("the robot reaches over the cubes", "second line")
        assert world.robot is not None
        world.robot.move_hand(REACH[None, :])
        video.hold(world, 1.0)
        video.close()
        return video, world.body_poses()


def _frames(path) -> list[np.ndarray]:
    reader = imageio_ffmpeg.read_frames(str(path))
    meta = next(reader)
    width, height = meta["size"]
    return [np.frombuffer(frame, np.uint8).reshape(height, width, 3) for frame in reader]


def test_a_filmed_motion_is_h264_with_a_frame_per_tick_of_the_simulated_clock(tmp_path):
    video, _ = _film(tmp_path / "a.mp4")
    probe = subprocess.run(
        [imageio_ffmpeg.get_ffmpeg_exe(), "-i", str(tmp_path / "a.mp4")], capture_output=True, text=True
    ).stderr
    assert "Video: h264" in probe and "yuv420p" in probe
    frames = _frames(tmp_path / "a.mp4")
    assert len(frames) == video.frames > FPS  # the reach and the held second
    assert 0 < video.rendered < video.frames  # cubes that did not move are not rendered again
    width, height = video.size
    assert frames[0].shape == (height, width, 3)
    band = frames[-1][-40:]
    assert band.max() > 200 and np.median(band) < 60  # white words on the dark caption band
    # The arm moved: the first and last pictures differ above the band.
    assert np.abs(frames[0][:-50].astype(int) - frames[-1][:-50].astype(int)).max() > 50


def test_the_same_motion_gives_the_same_frames_and_filming_changes_no_pose(tmp_path):
    _, poses = _film(tmp_path / "a.mp4")
    _, again = _film(tmp_path / "b.mp4")
    assert poses == again
    assert all(np.array_equal(a, b) for a, b in zip(_frames(tmp_path / "a.mp4"), _frames(tmp_path / "b.mp4")))
    with LineWorld(SceneSpec.random(3)) as world:
        assert world.robot is not None
        world.robot.move_hand(REACH[None, :])
        assert world.body_poses() == poses  # unfilmed, the simulation is the same


def test_the_preview_is_a_small_animated_gif(tmp_path):
    _film(tmp_path / "a.mp4")
    preview(tmp_path / "a.mp4", tmp_path / "a.gif")
    data = (tmp_path / "a.gif").read_bytes()
    assert data[:6] == b"GIF89a" and data.count(b"\x21\xf9\x04") > 1  # more than one frame


@pytest.mark.slow
def test_a_tabletop_trial_is_filmed_without_changing_its_record(tmp_path):
    from vslsp.tasks import get_task, run_one

    plain = run_one(get_task("alphabet-ordering"), 5)
    filmed = run_one(get_task("alphabet-ordering", video=str(tmp_path)), 5)
    assert filmed.video == "videos/trial-5.mp4" and plain.video is None
    times = ("time_s", "cpu_s", "stages_s", "video")
    assert {k: v for k, v in filmed.to_dict().items() if k not in times} == {
        k: v for k, v in plain.to_dict().items() if k not in times
    }
    frames, seconds = imageio_ffmpeg.count_frames_and_secs(str(tmp_path / filmed.video))
    assert frames > 40 and seconds > 10  # the demonstration's settling and four pick-and-place operations
