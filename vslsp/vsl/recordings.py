"""A demonstration recorded as a folder of pictures (docs/recordings.md): the observations of
Algorithm 1 part I (paper, "Methodology" and "Real-world Experiments": pre-pick, pre-place and
post-place) as numbered image files, read and checked before any work, then recorded by the
one :class:`~vslsp.vsl.recorder.Recorder` with the table model
(:class:`~vslsp.vsl.pick_place.TableModel`) that the Panda's tasks record with.

Per operation i (numbered 1, 2, ... without gaps, any number of digits): ``i-pre.png`` (the
world before the tutor takes the object; for i > 1 it may be left out: the world as the last
operation left it), ``i-mid.png`` (while the tutor holds the object out of view) and
``i-post.png`` (after it was put down); PNG or JPEG. Beside them, optional:
``calibration.json`` (:mod:`vslsp.vsl.calibration`), ``names.json`` (a list of the objects'
names, one an operation) and ``heights.json`` (a list, one an operation, of the tutor's
heights h in metres: ``{"height": h, "pick_z": top at the pick, "place_z": top at the place}``;
without it, objects are flat).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from vslsp.errors import GroundingFailed, InputError
from vslsp.files import read_json, shown
from vslsp.folders import MAX_SIDE_FILE_BYTES, Form, operation_files, read_names
from vslsp.vision.image import IMAGE_EXTENSIONS, MAX_FOLDER_PIXELS, read_pictures
from vslsp.vsl.calibration import Calibration, read_calibration, uncalibrated
from vslsp.vsl.pick_place import PickPlaceDemonstration, TableModel
from vslsp.vsl.recorder import Heights, Recorder

ROLES = ("pre", "mid", "post")  # pre-pick, pre-place, post-place


@dataclass(frozen=True, eq=False)
class Recording:
    """A folder of a demonstration, read: per operation its three observations (H, W, 3)
    uint8 as the camera saw them and their files, the objects' names, the tutor's heights and
    the camera's calibration."""

    folder: Path
    observations: tuple[dict[str, np.ndarray], ...]
    files: tuple[dict[str, str], ...]
    names: tuple[str, ...]
    heights: tuple[Heights, ...]
    calibration: Calibration

    @property
    def size(self) -> tuple[int, int]:
        """(W, H) px of every image."""
        height, width = self.observations[0]["mid"].shape[:2]
        return width, height


FORM = Form(
    re.compile(r"^(\d{1,4})-(pre|mid|post)(\.png|\.jpg|\.jpeg)$", re.IGNORECASE),
    IMAGE_EXTENSIONS,
    {"mid": "pre-place picture", "post": "post-place picture", "pre": "pre-pick picture"},
    ("pre",),
    "NN-pre, NN-mid or NN-post (.png or .jpg)",
    "picture",
    "01-pre.png, 01-mid.png, 01-post.png",
    "the demonstration's pictures",
)


def read_recording(folder: str | Path, max_pixels: int = MAX_FOLDER_PIXELS) -> Recording:
    """Read and check the recording in ``folder`` (see the module's docstring). Raises
    InputError naming the file: a missing or unreadable image, images of different sizes or of
    more than ``max_pixels`` together, operations out of order or with gaps, a calibration,
    names or heights file that does not parse or does not fit."""
    folder = Path(folder)
    found = operation_files(folder, FORM)
    paths = [path for number in sorted(found) for path in found[number].values()]
    pictures = iter(read_pictures(paths, max_pixels))
    observations: list[dict[str, np.ndarray]] = []
    files: list[dict[str, str]] = []
    for number in sorted(found):
        roles = found[number]
        images = {role: next(pictures) for role in roles}
        if "pre" not in images:  # nothing moved since the last operation's post-place picture
            images["pre"] = observations[-1]["post"]
        observations.append(images)
        files.append({role: path.name for role, path in roles.items()})
    count = len(observations)
    height, width = observations[0]["mid"].shape[:2]
    names = read_names(folder / "names.json", count)
    heights = _heights(folder / "heights.json", count)
    path = folder / "calibration.json"
    calibration = read_calibration(path, (width, height)) if path.exists() else uncalibrated((width, height))
    return Recording(folder, tuple(observations), tuple(files), names, heights, calibration)


def _heights(path: Path, count: int) -> tuple[Heights, ...]:
    if not path.exists():
        return tuple(Heights(0.0, 0.0, 0.0) for _ in range(count))
    data = read_json(path, "heights", MAX_SIDE_FILE_BYTES)
    if not isinstance(data, list) or len(data) != count:
        raise InputError(f'{shown(path)}: give a list of {count} objects {{"height": m, ...}}, one an operation')
    heights = []
    for k, entry in enumerate(data, start=1):
        try:
            height = float(entry["height"])
            pick_z, place_z = float(entry.get("pick_z", height)), float(entry.get("place_z", height))
        except (TypeError, KeyError, ValueError, AttributeError):
            raise InputError(f'{shown(path)}: operation {k} needs {{"height": m}} (and pick_z, place_z: m)') from None
        if (
            not all(np.isfinite(c) and 0.0 <= c < 2.0 for c in (height, pick_z, place_z))
            or height > min(pick_z, place_z) + _RESTING
        ):
            raise InputError(
                f"{shown(path)}: operation {k}'s heights must be metres in [0, 2), the object's tops "
                "(pick_z, place_z) no lower than its height"
            )
        heights.append(Heights(pick_z, place_z, height))
    return tuple(heights)


_RESTING = 0.002  # m: an object's top may sink this far below its height (it rests in the table a little)


def learn(recording: Recording) -> PickPlaceDemonstration:
    """Algorithm 1 part I on a recording: each operation's observations seen from above and
    recorded with the table model, in order. Raises GroundingFailed (a failed task, exit 1)
    naming the operation when its object is not found."""
    calibration = recording.calibration
    recorder = Recorder(TableModel(calibration.view))
    for k, (images, heights) in enumerate(zip(recording.observations, recording.heights), start=1):
        pre, mid, post = (calibration.observe(images[role]) for role in ROLES)
        try:
            recorder.record(pre, post, mid, heights)
        except InputError as error:
            raise GroundingFailed(f"operation {k} ({recording.names[k - 1]}): {error}") from None
    return recorder.demonstration()
