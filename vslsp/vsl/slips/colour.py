"""One demonstrated operation in which more than the operated object may have moved (issue 30:
the tutor slips and disturbs another object): every moved object grounded, the one the operation
was about told from those disturbed.

:func:`ground_moves` finds every object that moved (:func:`vslsp.vision.change.detect_moves`:
subtraction, thresholding, regions identified by their colour), grounds ``(far b)`` before and
after for each, and names the operated one by a rule: **a push or pull carries its object across
the landmark line, a slip only nudges another one; so the operated object is the one whose
``(far b)`` changed, and when several (or none) changed, the one of them that moved farthest
across the line (along the line's normal), measured in its own size** (the square root of its
pre-action area, so that perspective favours no object nearer the camera). The tutor carries an
object 9.5-13.5 cm across the line (from 4-8 cm on one side to 5.5 cm on the other); a slip moves
one 1-4 cm in any direction, so it changes a side only for a cube within 4 cm of the line, and
then moves less far across it than the operation. (Measured in its own size, an operation moved
its object 0.9-2.1 sizes across the line, a slip up to 0.6: perspective shrinks distances across
the line more than sizes far from the camera, hence the side first.)
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from vslsp.grounding.operation import Grounding, grounding_of
from vslsp.grounding.overlay import draw_grounding
from vslsp.grounding.spatial import check_robot_side
from vslsp.stages import in_stage
from vslsp.vision.change import Change, detect_moves
from vslsp.vision.landmark import Line, fit_line


@dataclass(frozen=True)
class Moves:
    """The objects that moved in one operation (``moved``, left to right as seen before), the
    one it was about (``operated``) and the rest (``disturbed``); ``across`` is how far each moved
    object went across the line, in its own size (the rule's measure), by symbol."""

    moved: tuple[Grounding, ...]
    operated: Grounding
    disturbed: tuple[Grounding, ...]
    across: dict[str, float]

    def to_dict(self) -> dict:
        """The operation's JSON record: ``moved``, ``operated``, ``disturbed`` (symbols) and, per
        moved object, ``(far b)`` before and after and how far it went across the line."""
        return {
            "moved": [g.name for g in self.moved],
            "operated": self.operated.name,
            "disturbed": [g.name for g in self.disturbed],
            "far": {g.name: {"pre": g.far_pre, "post": g.far_post} for g in self.moved},
            "across_sizes": {name: round(value, 2) for name, value in self.across.items()},
        }

    @property
    def crossed(self) -> tuple[Grounding, ...]:
        """The disturbed objects whose ``(far b)`` changed: the slip put them across the line."""
        return tuple(g for g in self.disturbed if g.far_pre != g.far_post)


@in_stage("perception")
def ground_moves(pre: np.ndarray, post: np.ndarray, robot_side: str = "bottom") -> Moves:
    """Ground every object moved between RGB images ``pre`` and ``post`` (H, W, 3) uint8 and
    tell the operated one from the disturbed (the module's rule). Raises as
    :func:`~vslsp.vision.change.detect_moves`, and GroundingFailed when no landmark is in view."""
    check_robot_side(robot_side)
    changes = detect_moves(pre, post)
    line_pre = fit_line(changes[0].pre.dark, changes[0].pre.scale, "pre-action image")
    line_post = fit_line(changes[0].post.dark, changes[0].post.scale, "post-action image")
    moved = tuple(_grounding(change, line_pre, line_post, robot_side) for change in changes)
    across = {g.name: across_sizes(g, line_pre) for g in moved}
    crossed = [g for g in moved if g.far_pre != g.far_post]
    operated = max(crossed or moved, key=lambda g: across[g.name])
    return Moves(moved, operated, tuple(g for g in moved if g is not operated), across)


def across_sizes(grounding: Grounding, line: Line) -> float:
    """How far the object of ``grounding`` went across ``line`` (px along its normal), in its
    own size (the square root of its pre-action area, px)."""
    size = np.sqrt(grounding.pre_object.area) if grounding.pre_object is not None else 1.0
    return abs(line.signed_distance(grounding.post) - line.signed_distance(grounding.pre)) / max(float(size), 1.0)


def _grounding(change: Change, line_pre: Line, line_post: Line, robot_side: str) -> Grounding:
    """One moved object grounded as :func:`vslsp.grounding.operation.ground` grounds the one."""
    return grounding_of(change.before, change.after, (line_pre, line_post), robot_side)


_DISTURBED = (0, 255, 255)  # RGB: cyan boxes and words for the disturbed objects


def draw_moves(pre: np.ndarray, post: np.ndarray, moves: Moves) -> np.ndarray:
    """The operation's picture (H, 2W, 3): the operated object's grounding as
    :func:`~vslsp.grounding.overlay.draw_grounding` draws it, each disturbed object boxed in cyan
    in both panels with its symbol and ``(far b)`` before and after, and the moved, operated and
    disturbed symbols written on the post panel."""
    picture = draw_grounding(pre, post, moves.operated)
    width = pre.shape[1]
    thickness = max(1, width // 320)
    for g in moves.disturbed:
        for offset, obj, far in ((0, g.pre_object, g.far_pre), (width, g.post_object, g.far_post)):
            if obj is None:
                continue
            x, y, w, h = obj.box
            cv2.rectangle(picture, (x + offset, y), (x + offset + w, y + h), _DISTURBED, thickness)
            words = f"disturbed {g.name}: {'far' if far else 'near'}"
            (text_width, _), _ = cv2.getTextSize(words, cv2.FONT_HERSHEY_SIMPLEX, 0.45 * thickness, thickness + 2)
            left = min(x + offset, offset + width - text_width - 4)  # the words stay in their panel
            _text(picture, words, (left, max(12 * thickness, y - 4 * thickness)), thickness)
        cv2.arrowedLine(
            picture,
            (int(round(g.pre[0])) + width, int(round(g.pre[1]))),
            (int(round(g.post[0])) + width, int(round(g.post[1]))),
            _DISTURBED,
            thickness,
            cv2.LINE_AA,
            tipLength=0.3,
        )
    lines = (
        f"moved: {', '.join(g.name for g in moves.moved)}",
        f"operated: {moves.operated.name}",
        f"disturbed: {', '.join(g.name for g in moves.disturbed) or 'none'}",
    )
    for k, line in enumerate(lines):
        _text(picture, line, (width + 8, pre.shape[0] - 8 - 16 * thickness * (len(lines) - 1 - k)), thickness)
    return picture


def _text(image: np.ndarray, text: str, origin: tuple[int, int], thickness: int) -> None:
    scale = 0.45 * thickness
    cv2.putText(image, text, origin, cv2.FONT_HERSHEY_SIMPLEX, scale, (0, 0, 0), thickness + 2, cv2.LINE_AA)
    cv2.putText(image, text, origin, cv2.FONT_HERSHEY_SIMPLEX, scale, _DISTURBED, thickness, cv2.LINE_AA)
