"""An annotated picture of a grounding (paper, Figure "PushPullGrounding"): the landmark line,
the moved object at its pre- and post-action places, and the grounded predicates; with user
predicates, every object's symbol and footprint and the true atoms (or the atoms a test
missed and did not expect)."""

from __future__ import annotations

from collections.abc import Sequence

import cv2
import numpy as np

from vslsp.grounding.operation import Grounding
from vslsp.grounding.predicates import Scene, true_atoms

_LINE = (0, 200, 255)  # colours in RGB
_PRE = (255, 255, 255)
_POST = (255, 0, 255)


def draw_grounding(pre: np.ndarray, post: np.ndarray, grounding: Grounding) -> np.ndarray:
    """Pre and post images (H, W, 3) side by side (H, 2W, 3) uint8 RGB, annotated."""
    return draw_atoms(pre, post, grounding)


def draw_atoms(
    pre: np.ndarray, post: np.ndarray, grounding: Grounding, notes: tuple[Sequence[str], Sequence[str]] | None = None
) -> np.ndarray:
    """As :func:`draw_grounding`; with atoms grounded, each object's footprint and symbol, and
    per panel the lines of ``notes`` (pre, post), by default the true atoms."""
    if notes is None and grounding.atoms_pre is not None and grounding.atoms_post is not None:
        notes = (true_atoms(grounding.atoms_pre), true_atoms(grounding.atoms_post))
    panels = []
    for k, (image, point, obj, far, line, title) in enumerate(
        (
            (pre, grounding.pre, grounding.pre_object, grounding.far_pre, grounding.landmark, "pre"),
            (
                post,
                grounding.post,
                grounding.post_object,
                grounding.far_post,
                grounding.post_landmark or grounding.landmark,
                "post",
            ),
        )
    ):
        panel = image.copy()
        thickness = max(1, image.shape[1] // 320)
        scene = (grounding.scene_pre, grounding.scene_post)[k]
        if scene is not None:
            _draw_scene(panel, scene, thickness)

        cv2.line(panel, _int(line.p1), _int(line.p2), _LINE, thickness, cv2.LINE_AA)
        if obj is not None:
            x, y, w, h = obj.box
            cv2.rectangle(panel, (x, y), (x + w, y + h), _PRE if title == "pre" else _POST, thickness)
        cv2.drawMarker(
            panel, _int(point), _PRE if title == "pre" else _POST, cv2.MARKER_CROSS, 10 * thickness, thickness
        )
        label = f"{title}: {'' if far else 'not '}(far {grounding.name})"
        _text(panel, label, (8, 8 + 16 * thickness), thickness)
        panels.append(panel)
    cv2.arrowedLine(panels[1], _int(grounding.pre), _int(grounding.post), _PRE, thickness, cv2.LINE_AA, tipLength=0.1)
    _text(panels[1], f"action: {grounding.action or 'none'}", (8, 8 + 36 * thickness), thickness)
    if notes is not None:
        rows = max(len(notes[0]), len(notes[1]), 1)
        strips = [_notes(panel.shape[1], lines, thickness, rows) for panel, lines in zip(panels, notes, strict=True)]
        panels = [np.vstack([panel, strip]) for panel, strip in zip(panels, strips, strict=True)]
    return np.hstack(panels)


def _draw_scene(panel: np.ndarray, scene: Scene, thickness: int) -> None:
    for obj in scene.objects.values():
        box = obj.footprint
        cv2.rectangle(panel, _int((box.x0, box.y0)), _int((box.x1, box.y1)), (255, 255, 0), max(1, thickness // 2))
        _text(panel, obj.name, _int((box.x0, max(box.y0 - 4 * thickness, 12 * thickness))), thickness, 0.4)


def _notes(width: int, lines: Sequence[str], thickness: int, rows: int, limit: int = 40) -> np.ndarray:
    """A dark strip (h, width, 3) listing ``lines`` (one atom a line)."""
    rows = min(rows, limit + 1)
    shown = list(lines[:limit]) + ([f"... {len(lines) - limit} more"] if len(lines) > limit else [])
    step = 16 * thickness
    strip = np.full((step * rows + 8 * thickness, width, 3), 40, np.uint8)
    for i, line in enumerate(shown):
        _text(strip, line, (8, step * (i + 1)), thickness, 0.45)
    return strip


def _int(point) -> tuple[int, int]:
    return int(round(point[0])), int(round(point[1]))


def _text(image: np.ndarray, text: str, origin: tuple[int, int], thickness: int, size: float = 0.5) -> None:
    scale = size * thickness
    cv2.putText(image, text, origin, cv2.FONT_HERSHEY_SIMPLEX, scale, (0, 0, 0), thickness + 2, cv2.LINE_AA)
    cv2.putText(image, text, origin, cv2.FONT_HERSHEY_SIMPLEX, scale, (255, 255, 255), thickness, cv2.LINE_AA)
