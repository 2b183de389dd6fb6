"""Grounding symbols from observations (paper, Algorithm 1 lines 7-9 and VSL-SP
"Implementation": the pre- and post-action observations of a push or pull give its
precondition and effect on (far ?b) relative to the black borderline).

:func:`ground` grounds one demonstrated operation (a pre-/post-action image pair) into a
:class:`Grounding`, whose ``to_dict()`` is the JSON of ``vslsp ground --json`` (docs/grounding.md);
given user predicates it also grounds every atom before and after. :func:`ground_scene`
grounds (far b), and any predicates, for every object of a single observation.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vslsp.grounding.predicates import Atom, Predicate, Scene, ground_atoms, scene_of, symbol_names, true_atoms
from vslsp.grounding.spatial import check_robot_side, far_of, identify_action
from vslsp.stages import in_stage
from vslsp.vision.change import detect_change
from vslsp.vision.landmark import Line, fit_line
from vslsp.vision.objects import DetectedObject, Segmentation, describe, segment


def _point(xy: tuple[float, float]) -> dict:
    return {"x": round(float(xy[0]), 2), "y": round(float(xy[1]), 2)}


@dataclass(frozen=True)
class Grounding:
    """One operation grounded: the moved object's symbol ``name``, its centroid (x, y) px in
    the pre- and post-action images, the landmark (as seen in the pre image), (far b) before
    and after, and the action (``"push"``, ``"pull"`` or None)."""

    name: str
    pre: tuple[float, float]
    post: tuple[float, float]
    landmark: Line
    far_pre: bool
    far_post: bool
    action: str | None
    robot_side: str = "bottom"
    # What perception saw, for overlays and the demonstration recorder (not part of the JSON).
    pre_object: DetectedObject | None = field(default=None, compare=False, repr=False)
    post_object: DetectedObject | None = field(default=None, compare=False, repr=False)
    post_landmark: Line | None = field(default=None, compare=False, repr=False)
    # With predicates: every ground atom's value before and after, and the scenes they were decided on.
    atoms_pre: dict[Atom, bool] | None = field(default=None, compare=False, repr=False)
    atoms_post: dict[Atom, bool] | None = field(default=None, compare=False, repr=False)
    scene_pre: Scene | None = field(default=None, compare=False, repr=False)
    scene_post: Scene | None = field(default=None, compare=False, repr=False)
    # Objects left out as nudged (``min_move``): (symbol, px its centroid moved).
    nudged: tuple[tuple[str, float], ...] = ()

    def to_dict(self) -> dict:
        """The ``vslsp ground --json`` object; ``atoms`` (true atoms, PDDL syntax, sorted) when
        predicates were grounded."""
        data: dict[str, Any] = {
            "object": {"name": self.name, "pre": _point(self.pre), "post": _point(self.post)},
            "landmark": self.landmark.to_dict(),
            "far": {"pre": self.far_pre, "post": self.far_post},
            "action": self.action,
        }
        if self.atoms_pre is not None and self.atoms_post is not None:
            data["atoms"] = {"pre": true_atoms(self.atoms_pre), "post": true_atoms(self.atoms_post)}
        if self.nudged:
            data["nudged"] = [{"name": name, "moved_px": moved} for name, moved in self.nudged]
        return data

    @classmethod
    def from_dict(cls, data: dict, robot_side: str = "bottom") -> Grounding:
        obj = data["object"]
        return cls(
            name=obj["name"],
            pre=(float(obj["pre"]["x"]), float(obj["pre"]["y"])),
            post=(float(obj["post"]["x"]), float(obj["post"]["y"])),
            landmark=Line.from_dict(data["landmark"]),
            far_pre=bool(data["far"]["pre"]),
            far_post=bool(data["far"]["post"]),
            action=data["action"],
            robot_side=robot_side,
        )


@in_stage("perception")
def ground(
    pre: np.ndarray,
    post: np.ndarray,
    robot_side: str = "bottom",
    predicates: Sequence[Predicate] | None = None,
    min_move: float = 0.0,
) -> Grounding:
    """Ground one operation from RGB images ``pre`` and ``post`` (H, W, 3) uint8.

    ``robot_side``: the image edge the robot is beyond (bottom, top, left, right); bottom is
    the robot's own view. With ``predicates`` every ground atom of every object seen is
    decided before and after (``atoms_pre``, ``atoms_post``). ``min_move`` (px): objects that
    moved less are left out as nudged when more than one moved
    (:func:`vslsp.vision.change.detect_change`; 0: none). Raises InputError for unusable
    images (see ``detect_change``), when no landmark line is in view, and for a predicate
    that raises or returns a non-bool.
    """
    check_robot_side(robot_side)
    change = detect_change(pre, post, min_move)
    line_pre = fit_line(change.pre.dark, change.pre.scale, "pre-action image")
    line_post = fit_line(change.post.dark, change.post.scale, "post-action image")
    scenes: tuple[Scene | None, Scene | None] = (None, None)
    atoms: tuple[dict[Atom, bool] | None, dict[Atom, bool] | None] = (None, None)
    if predicates is not None:
        size = (pre.shape[1], pre.shape[0])
        scenes = (_scene(change.pre, size, line_pre, robot_side), _scene(change.post, size, line_post, robot_side))
        atoms = (ground_atoms(scenes[0], predicates), ground_atoms(scenes[1], predicates))
    return grounding_of(
        change.before,
        change.after,
        (line_pre, line_post),
        robot_side,
        atoms_pre=atoms[0],
        atoms_post=atoms[1],
        scene_pre=scenes[0],
        scene_post=scenes[1],
        nudged=change.nudged,
    )


def grounding_of(
    before: DetectedObject, after: DetectedObject, lines: tuple[Line, Line], robot_side: str, **found
) -> Grounding:
    """The grounding of one object seen ``before`` and ``after`` the action, ``far`` from the
    landmark ``lines`` (pre, post), the action it makes; ``found``: the atoms and scenes, when
    predicates were given (:func:`ground`; each moved object of :func:`vslsp.vsl.slips.colour.ground_moves`)."""
    far_pre = far_of(before.centroid, lines[0], robot_side)
    far_post = far_of(after.centroid, lines[1], robot_side)
    return Grounding(
        name=before.name,
        pre=before.centroid,
        post=after.centroid,
        landmark=lines[0],
        far_pre=far_pre,
        far_post=far_post,
        action=identify_action(far_pre, far_post),
        robot_side=robot_side,
        pre_object=before,
        post_object=after,
        post_landmark=lines[1],
        **found,
    )


def _scene(seg: Segmentation, size: tuple[int, int], line: Line, robot_side: str) -> Scene:
    objects = sorted((describe(seg, label) for label in seg.object_labels), key=lambda o: o.centroid)
    return scene_of(objects, size, line, robot_side)


@dataclass(frozen=True)
class SceneGrounding:
    """(far b) for every object of one observation: ``objects`` left to right, ``far`` alike;
    ``size`` (W, H) px of the image and its ``robot_side``."""

    landmark: Line
    objects: tuple[DetectedObject, ...]
    far: tuple[bool, ...]
    size: tuple[int, int] = (0, 0)
    robot_side: str = "bottom"

    def far_by_name(self) -> dict[str, bool]:
        """Object symbol -> (far b); repeated symbols get a suffix: red, red_2, ..."""
        return dict(zip(symbol_names(self.objects), self.far, strict=True))

    def scene(self) -> Scene:
        """The observation as predicates see it."""
        return scene_of(self.objects, self.size, self.landmark, self.robot_side)

    def atoms(self, predicates: Sequence[Predicate]) -> dict[Atom, bool]:
        """Every ground atom of ``predicates`` over the objects seen, with its value."""
        return ground_atoms(self.scene(), predicates)

    def to_dict(self) -> dict:
        return {
            "landmark": self.landmark.to_dict(),
            "objects": [
                {"name": o.name, **_point(o.centroid), "far": f} for o, f in zip(self.objects, self.far, strict=True)
            ],
        }


def ground_scene(image: np.ndarray, robot_side: str = "bottom", features: bool = False) -> SceneGrounding:
    """Detect every object in an RGB image (H, W, 3) uint8 and ground (far b) for each.

    With ``features`` the objects carry their SIFT features φ.
    """
    check_robot_side(robot_side)
    seg = segment(image)
    line = fit_line(seg.dark, seg.scale)
    objects = sorted(
        (describe(seg, label, image if features else None) for label in seg.object_labels), key=lambda o: o.centroid
    )
    return SceneGrounding(
        line,
        tuple(objects),
        tuple(far_of(o.centroid, line, robot_side) for o in objects),
        (image.shape[1], image.shape[0]),
        robot_side,
    )
