"""A rerun recording of a simulated trial (``--rerun FILE.rrd``): what the robot saw and did on
one timeline, for rerun's own viewer (the rerun SDK, ``pip install 'vslsp[rerun]'``).

Every entry of trial ``seed`` lies under ``trial/<seed>/``:

- ``camera/before``, ``camera/after``: the robot's camera images of each observed operation
  (:class:`rerun.Image`, (H, W, 3) RGB);
- ``cloud/<name>``: VSL-3D's point clouds (:class:`rerun.Points3D`, (N, 3) m, colours (N, 3));
- ``arm``, ``hand_path``: the arm's chain (shoulder to hand, (K, 3) m) as the world steps, and
  the path the hand drew during each step of the trial (:class:`rerun.LineStrips3D`);
- ``narration``: the trial's steps as they begin and end, the planned ones included
  (:class:`rerun.TextLog`); ``plan``: each plan found; ``state``: the symbolic state the robot
  grounded after each observation, one literal a line (:class:`rerun.TextDocument`).

Two timelines: ``step`` (a sequence: one tick per narrated step of the trial) and ``sim_time``
(the simulated seconds the trial's worlds stepped, from :meth:`LineWorld.step
<vslsp.sim.world.LineWorld.step>`: a seed gives the same timeline on any machine). A trial writes
its own file; trials of one run share one recording id, so that their files are one recording
in the viewer and :func:`merge` joins them into one file. Logging changes nothing in the
simulation: the arm is read from the world's pose, no render is taken.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from vslsp.errors import InputError

APPLICATION = "vslsp"
STEPS_PER_SECOND = 240  # the world's physics rate (vslsp.sim.robot.TIME_STEP)
ARM_EVERY = 24  # physics steps between two readings of the arm (10 per simulated second)
INSTALL = "pip install 'vslsp[rerun]'"


def check_rerun() -> None:
    """The rerun SDK is installed (:class:`InputError` saying how to get it otherwise)."""
    try:
        import rerun  # noqa: F401
    except ImportError as missing:
        raise InputError(f"--rerun needs the rerun SDK: {INSTALL} ({missing})") from None


class RerunLog:
    """The recording of one trial, written to ``path`` as it runs (:meth:`close` finishes it).

    :meth:`attach` each world of the trial in turn (its physics steps drive ``sim_time`` and
    the arm's entries); :meth:`caption` starts the trial's next step; :meth:`observation`,
    :meth:`cloud`, :meth:`plan` and :meth:`state` log what the trial found, at the current time."""

    def __init__(self, path: str | Path, seed: int, recording_id: str) -> None:
        import rerun as rr

        self.path = Path(path)
        self.prefix = f"trial/{seed}"
        self.step = 0
        self._ticks = 0
        self._hand: list[np.ndarray] = []  # the hand's positions during the current step
        self._rr = rr
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._stream = rr.RecordingStream(APPLICATION, recording_id=recording_id, send_properties=False)
        self._stream.set_log_time_enabled(False)  # the wall clock: a seed gives the same recording
        self._stream.save(self.path)
        self._stream.set_time("step", sequence=0)
        self._stream.set_time("sim_time", duration=0.0)

    def attach(self, world: Any) -> None:
        """Log ``world`` from now on: after the hook already there (a video's), each physics step
        advances ``sim_time``; its arm is read every :data:`ARM_EVERY` steps, and its narration
        (``world.narrator``, when it has one) starts steps."""
        hook = world.frame_hook
        world.frame_hook = self._on_step if hook is None else _both(hook, self._on_step)
        if hasattr(world, "narrator"):
            narrator = world.narrator
            world.narrator = self._narrate if narrator is None else _both(narrator, self._narrate)
        self._end_path()

    def _on_step(self, world: Any) -> None:
        self._ticks += 1
        if self._ticks % ARM_EVERY:
            return
        chain = world.arm_chain()
        if chain is None:
            return
        self._time()
        self._stream.log(f"{self.prefix}/arm", self._rr.LineStrips3D([np.asarray(chain, np.float32)]))
        self._hand.append(np.asarray(chain[-1], np.float32))

    def _narrate(self, world: Any, lines: tuple[str, ...], hold: float) -> None:
        self.caption(*lines)

    def _time(self) -> None:
        self._stream.set_time("step", sequence=self.step)
        self._stream.set_time("sim_time", duration=self._ticks / STEPS_PER_SECOND)

    def _end_path(self) -> None:
        """The hand's path of the step that ends, as one line strip (none when the hand stood)."""
        if len(self._hand) > 1:
            self._stream.log(f"{self.prefix}/hand_path", self._rr.LineStrips3D([np.stack(self._hand)]))
        self._hand = self._hand[-1:]

    def caption(self, *lines: str) -> None:
        """The trial's next step begins: its words in ``narration``."""
        self._time()
        self._end_path()
        self.step += 1
        self._time()
        text = " / ".join(line for line in lines if line)
        if text:
            self._stream.log(f"{self.prefix}/narration", self._rr.TextLog(text))

    def hold(self, world: Any, seconds: float = 0.0) -> None:
        """A moment to look at the world: nothing to log (the arm and the time are logged as it steps)."""

    def observation(self, title: str, before: np.ndarray, after: np.ndarray) -> None:
        """An observed operation: the camera's images (H, W, 3) before and after it."""
        self._time()
        self._stream.log(f"{self.prefix}/camera/before", self._rr.Image(np.ascontiguousarray(before)))
        self._stream.log(f"{self.prefix}/camera/after", self._rr.Image(np.ascontiguousarray(after)))
        self._stream.log(f"{self.prefix}/narration", self._rr.TextLog(f"observed: {title}"))

    def state(self, literals: Iterable[str]) -> None:
        """The symbolic state the robot grounded, as PDDL literals (``(far orange)``)."""
        self._time()
        self._stream.log(f"{self.prefix}/state", self._rr.TextDocument("\n".join(literals)))

    def plan(self, steps: Sequence[str]) -> None:
        """A plan found: its steps in order (``pull orange``)."""
        self._time()
        text = "\n".join(f"{k}. {step}" for k, step in enumerate(steps, start=1)) or "(the empty plan)"
        self._stream.log(f"{self.prefix}/plan", self._rr.TextDocument(text))

    def cloud(self, name: str, points: np.ndarray, colours: np.ndarray | None = None) -> None:
        """A point cloud (N, 3) m, with its colours (N, 3) (0-255 or 0-1) when it has them."""
        self._time()
        self._stream.log(
            f"{self.prefix}/cloud/{name}",
            self._rr.Points3D(np.asarray(points, np.float32), colors=None if colours is None else colours),
        )

    def close(self) -> None:
        """Finish the file."""
        self._time()
        self._end_path()
        self._stream.flush()
        self._stream.disconnect()


def _both(first: Any, second: Any) -> Any:
    def call(*args: Any) -> None:
        first(*args)
        second(*args)

    return call


PARTS = ".parts"  # FILE.rrd's parts, one per trial, lie in the folder FILE.rrd.parts until merged


def parts_folder(out: str | Path) -> Path:
    """The folder of the trials' parts of the recording ``out`` (beside it)."""
    out = Path(out)
    return out.with_name(out.name + PARTS)


def recording_id(parts: str | Path) -> str:
    """The one recording id of a run's trials, named after its file (the folder ``parts``)."""
    return f"{APPLICATION}:{Path(parts).name.removesuffix(PARTS)}"


def part_path(parts: str | Path, seed: int) -> Path:
    """Where trial ``seed`` writes its part of a run's recording (``parts``: the run's folder of parts)."""
    return Path(parts) / f"trial-{seed}.rrd"


def merge(parts: Sequence[Path], out: str | Path, recording_id: str) -> None:
    """Join the trials' files ``parts`` (one recording id) into the one file ``out``."""
    from rerun.chunk import LazyChunkStream, RrdReader

    streams = [RrdReader(part).stream() for part in parts]
    LazyChunkStream.merge(*streams).write_rrd(str(out), application_id=APPLICATION, recording_id=recording_id)
