"""An annotated picture of a grounding (paper, Figure "PushPullGrounding"): the landmark line,
the moved object at its pre- and post-action places, and the grounded predicates."""

from __future__ import annotations

import cv2
import numpy as np

from vslsp.vsl.grounding import Grounding

_LINE = (0, 200, 255)  # colours in RGB
_PRE = (255, 255, 255)
_POST = (255, 0, 255)


def draw_grounding(pre: np.ndarray, post: np.ndarray, grounding: Grounding) -> np.ndarray:
    """Pre and post images (H, W, 3) side by side (H, 2W, 3) uint8 RGB, annotated."""
    panels = []
    for image, point, obj, far, line, title in (
        (pre, grounding.pre, grounding.pre_object, grounding.far_pre, grounding.landmark, "pre"),
        (post, grounding.post, grounding.post_object, grounding.far_post,
         grounding.post_landmark or grounding.landmark, "post"),
    ):
        panel = image.copy()
        thickness = max(1, image.shape[1] // 320)
        cv2.line(panel, _int(line.p1), _int(line.p2), _LINE, thickness, cv2.LINE_AA)
        if obj is not None:
            x, y, w, h = obj.box
            cv2.rectangle(panel, (x, y), (x + w, y + h), _PRE if title == "pre" else _POST, thickness)
        cv2.drawMarker(panel, _int(point), _PRE if title == "pre" else _POST, cv2.MARKER_CROSS,
                       10 * thickness, thickness)
        label = f"{title}: {'' if far else 'not '}(far {grounding.name})"
        _text(panel, label, (8, 8 + 16 * thickness), thickness)
        panels.append(panel)
    cv2.arrowedLine(panels[1], _int(grounding.pre), _int(grounding.post), _PRE, thickness, cv2.LINE_AA,
                    tipLength=0.1)
    _text(panels[1], f"action: {grounding.action or 'none'}", (8, 8 + 36 * thickness), thickness)
    return np.hstack(panels)


def _int(point) -> tuple[int, int]:
    return int(round(point[0])), int(round(point[1]))


def _text(image: np.ndarray, text: str, origin: tuple[int, int], thickness: int) -> None:
    scale = 0.5 * thickness
    cv2.putText(image, text, origin, cv2.FONT_HERSHEY_SIMPLEX, scale, (0, 0, 0), thickness + 2, cv2.LINE_AA)
    cv2.putText(image, text, origin, cv2.FONT_HERSHEY_SIMPLEX, scale, (255, 255, 255), thickness, cv2.LINE_AA)
