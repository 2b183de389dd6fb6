"""A video of a simulated trial: a scene camera watches the world while it runs (the tutor's
demonstration and the robot's execution), each frame under the caption of the step in
progress, encoded as an H.264 MP4 by the ffmpeg binary that imageio-ffmpeg ships.

Frames are taken on the simulation's clock (every ``1 / fps`` simulated seconds, from
:meth:`LineWorld.step <vslsp.sim.world.LineWorld.step>`), so a seed gives the same frames on any
machine. The table and the objects on it are pybullet's render; the robot's arm is drawn
over it as its kinematic chain (shoulder to hand, projected through the same camera) with the
hand's recent path: rasterising the arm's meshes costs three times the rest of the scene, and
the render is needed only when a cube moved (a picture of cubes that did not move is the last
one). Watching changes nothing in the simulation: the arm is hidden from the scene camera only
while it renders, and no physics runs. Frames stream to ffmpeg as raw RGB through a pipe:
nothing is held in memory, and the encoder works beside the simulation.
"""

from __future__ import annotations

import subprocess
import textwrap
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.sim.camera import Camera
from vslsp.sim.client import pb
from vslsp.sim.scene import TABLE_Z

FPS = 4  # frames per simulated second (and the video's playback rate: real time)
RENDER_SIZE = (256, 192)  # the scene camera's image (the render's cost grows with its pixels)
SCALE = 1.25  # shown this much larger under the caption
RENDER_EVERY = 2  # while cubes move, the render is renewed at most every this many frames
ARM = (200, 30, 30)  # RGB: the arm's chain
HAND = (255, 255, 255)
TRAIL = 18  # frames of the hand's path drawn behind it
JUMP = 60  # px: a hand that moved further in one frame was reset, not moved
CAPTION_LINES = 3
CAPTION_CHARACTERS = 50  # a caption line's width at the caption's font (wrapped beyond)
HOLD_S = 1.0  # a step's outcome stays on screen this long (simulated seconds)
STEPS_PER_SECOND = 240  # the world's physics rate (vslsp.sim.robot.TIME_STEP)


def scene_camera(eye: tuple[float, float, float] = (0.74, -0.26, TABLE_Z + 0.78)) -> Camera:
    """A camera across the table from the robot, looking at the workspace and the robot's arm."""
    return Camera(
        "scene",
        eye=eye,
        target=(0.24, -0.1, TABLE_Z),
        up=(0.0, 0.0, 1.0),
        width=RENDER_SIZE[0],
        height=RENDER_SIZE[1],
        fov=40.0,
    )


def tabletop_scene_camera() -> Camera:
    """A camera beside the Panda's table, looking over the workspace at the robot."""
    return Camera(
        "scene",
        eye=(0.98, -0.58, 0.62),
        target=(0.42, 0.0, 0.02),
        up=(0.0, 0.0, 1.0),
        width=RENDER_SIZE[0],
        height=RENDER_SIZE[1],
        fov=42.0,
    )


class SceneVideo:
    """The video of one trial, written to ``path`` as frames arrive (:meth:`close` finishes it).

    :meth:`attach` a world (every world of the trial in turn); :meth:`caption` sets the words
    under the frames from now on; :meth:`hold` shows the current picture for a while (a step's
    outcome)."""

    def __init__(self, path: str | Path, fps: int = FPS, camera: Camera | None = None) -> None:
        self.path = Path(path)
        self.fps = fps
        self.camera = camera or scene_camera()
        self.frames = 0
        self.rendered = 0
        self._text: list[str] = []
        self._band: np.ndarray | None = None  # the caption band as last drawn (None: to draw)
        self._ticks = 0
        self._every = max(1, STEPS_PER_SECOND // fps)
        self._last: tuple[Any, np.ndarray] | None = None
        self._rendered_at = 0  # the frame the last render was taken for
        self._trail: list[np.ndarray] = []
        self._encoder: subprocess.Popen | None = None

    @property
    def size(self) -> tuple[int, int]:
        """The frames' (width, height): the scaled render and the caption band below it."""
        width, height = int(RENDER_SIZE[0] * SCALE), int(RENDER_SIZE[1] * SCALE)
        return width, height + self._band_height

    @property
    def _band_height(self) -> int:
        return 20 * CAPTION_LINES + 8

    def attach(self, world) -> None:
        """Film ``world`` from now on (its steps take the frames) and show it as it is.

        A filmed world has ``frame_hook`` (called after each physics step), ``live_client``,
        ``backdrop``, ``movable_poses()`` (the poses of what may move), ``arm_chain()`` (the
        robot's joints and hand (K, 3), or None) and ``arm_body()`` (the robot's body id)."""
        world.frame_hook = self._on_step
        if hasattr(world, "narrator"):
            world.narrator = self._narrate
        self._last = None
        self._trail = []
        self.frame(world)

    def caption(self, *lines: str) -> None:
        """The words under the frames from now on (at most :data:`CAPTION_LINES` lines)."""
        wrapped = [part for line in lines if line for part in textwrap.wrap(line, CAPTION_CHARACTERS)]
        self._text = wrapped[:CAPTION_LINES]
        self._band = None

    def _narrate(self, world, lines: tuple[str, ...], hold: float) -> None:
        self.caption(*lines)
        if hold > 0:
            self.hold(world, hold)

    def hold(self, world, seconds: float = HOLD_S) -> None:
        """Show the world as it is now for ``seconds`` (under the current caption)."""
        for _ in range(max(1, int(round(seconds * self.fps)))):
            self.frame(world)

    def _on_step(self, world) -> None:
        self._ticks += 1
        if self._ticks % self._every == 0:
            self.frame(world)

    def frame(self, world) -> None:
        """Add one frame: the scene camera's picture of ``world`` and its arm, under the caption."""
        # Poses to 1 mm and about 1 deg: an object settling by less moves less than a pixel.
        cubes = tuple(
            (np.round(pose[0], 3).tobytes(), np.round(pose[1], 2).tobytes()) for pose in world.movable_poses()
        )
        if self._last is None or (self._last[0] != cubes and self.frames - self._rendered_at >= RENDER_EVERY):
            with _arm_hidden(world):
                rgb, _ = self.camera.render(world.live_client, world.backdrop)
            picture = cv2.resize(rgb, None, fx=SCALE, fy=SCALE, interpolation=cv2.INTER_LINEAR)
            self._last = (cubes, picture)
            self._rendered_at = self.frames
            self.rendered += 1
        picture = self._last[1].copy()
        chain = world.arm_chain()
        if chain is not None:
            self._draw_arm(picture, chain)
        self._write(self._captioned(picture))

    def _draw_arm(self, picture: np.ndarray, chain: np.ndarray) -> None:
        """The arm's chain (K, 3) (its joints' positions, then the hand) and the hand's recent path."""
        pixels = np.round(self.camera.project(chain) * SCALE).astype(np.int32)
        if self._trail and np.abs(pixels[-1] - self._trail[-1]).max() > JUMP:
            self._trail = []  # the arm was put back to its parked pose, not moved there
        self._trail = (self._trail + [pixels[-1]])[-TRAIL:]
        if len(self._trail) > 1:
            cv2.polylines(picture, [np.array(self._trail)], False, (250, 220, 60), 1, cv2.LINE_AA)
        cv2.polylines(picture, [pixels], False, ARM, 5, cv2.LINE_AA)
        cv2.circle(picture, tuple(int(v) for v in pixels[-1]), 6, HAND, -1, cv2.LINE_AA)
        cv2.circle(picture, tuple(int(v) for v in pixels[-1]), 6, ARM, 1, cv2.LINE_AA)

    def _captioned(self, picture: np.ndarray) -> np.ndarray:
        if self._band is None or self._band.shape[1] != picture.shape[1]:
            self._band = np.full((self._band_height, picture.shape[1], 3), 24, np.uint8)
            for k, text in enumerate(self._text):
                cv2.putText(
                    self._band, text, (5, 17 + 20 * k), cv2.FONT_HERSHEY_SIMPLEX, 0.38, (255, 255, 255), 1, cv2.LINE_AA
                )
        return np.vstack([picture, self._band])

    def _write(self, frame: np.ndarray) -> None:
        if self._encoder is None:
            self._encoder = _encoder(self.path, frame.shape[1], frame.shape[0], self.fps)
        assert self._encoder.stdin is not None
        self._encoder.stdin.write(np.ascontiguousarray(frame).tobytes())
        self.frames += 1

    def close(self) -> None:
        """Finish the MP4 (a video without frames writes nothing)."""
        if self._encoder is None:
            return
        encoder, self._encoder = self._encoder, None
        assert encoder.stdin is not None
        encoder.stdin.close()
        if encoder.wait() != 0:
            raise RuntimeError(f"ffmpeg could not write {self.path}: exit {encoder.returncode}")


class _arm_hidden:  # noqa: N801 (a context manager named for what it does)
    """The robot's visual shapes transparent while the scene camera renders (pybullet's
    TinyRenderer skips them), their colours back afterwards: no physics is touched."""

    def __init__(self, world) -> None:
        self.world = world
        body = world.arm_body()
        self.shapes = [] if body is None else pb.getVisualShapeData(body, physicsClientId=world.live_client)

    def _colour(self, alpha: bool) -> None:
        for shape in self.shapes:
            colour = list(shape[7]) if alpha else [1.0, 1.0, 1.0, 0.0]
            pb.changeVisualShape(shape[0], shape[1], rgbaColor=colour, physicsClientId=self.world.live_client)

    def __enter__(self) -> None:
        self._colour(False)

    def __exit__(self, *exc: object) -> None:
        self._colour(True)


def check_encoder() -> None:
    """The ffmpeg binary is there (:class:`InputError` saying how to get it otherwise)."""
    try:
        import imageio_ffmpeg

        imageio_ffmpeg.get_ffmpeg_exe()
    except (ImportError, RuntimeError) as missing:
        raise InputError(f"--video needs ffmpeg: pip install imageio-ffmpeg ({missing})") from None


def _encoder(path: Path, width: int, height: int, fps: int) -> subprocess.Popen:
    """ffmpeg reading raw RGB frames on stdin and writing H.264 (yuv420p: any player shows it)."""
    import imageio_ffmpeg

    path.parent.mkdir(parents=True, exist_ok=True)
    command = [
        imageio_ffmpeg.get_ffmpeg_exe(),
        "-y",
        "-loglevel",
        "error",
        "-f",
        "rawvideo",
        "-pix_fmt",
        "rgb24",
        "-s",
        f"{width}x{height}",
        "-r",
        str(fps),
        "-i",
        "-",
        "-c:v",
        "libx264",
        "-preset",
        "ultrafast",
        "-crf",
        "26",
        "-pix_fmt",
        "yuv420p",
        "-threads",
        "1",
        "-movflags",
        "+faststart",
        str(path),
    ]
    return subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def preview(video: str | Path, out: str | Path, width: int = 240, fps: int = 4, speed: int = 8) -> None:
    """A small animated GIF of ``video`` (for report.md), ``speed`` times faster, ``fps`` frames
    a second, ``width`` px wide; made by the same ffmpeg."""
    import imageio_ffmpeg

    subprocess.run(
        [
            imageio_ffmpeg.get_ffmpeg_exe(),
            "-y",
            "-loglevel",
            "error",
            "-i",
            str(video),
            "-vf",
            f"setpts=PTS/{speed},fps={fps},scale={width}:-2:flags=lanczos",
            str(out),
        ],
        check=True,
    )
