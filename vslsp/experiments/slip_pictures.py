"""The report's marks of the tutor's slips (issue 30) on an operation's picture: every object
that moved, the operated one and the disturbed ones, as VSL's slip detection found them
(:mod:`vslsp.vsl.slips`), named as the operation's record names them."""

from __future__ import annotations

import cv2
import numpy as np

from vslsp.tasks.drawing import PICK, point

OPERATED, DISTURBED = PICK, (255, 40, 40)  # RGB: the operated object (magenta), a disturbed one (red)


def mark_moves(image: np.ndarray, moves, record: dict) -> None:
    """Draw on ``image`` (H, W, 3, the post observation) each object of ``moves`` (a
    :class:`~vslsp.vsl.slips.detect.Moves`, or None with the detection off): an arrow from where it
    was to where it is and a ring about it, magenta for the operated object, red for a
    disturbed one, with its name from ``record`` (``moves`` of the operation's report record)."""
    if moves is None:
        return
    names = [m["object"] for m in record.get("moves", [])]
    kinds = (["operated"] if moves.operated is not None else []) + ["disturbed"] * len(moves.disturbed)
    for obj, kind, name in zip(moves.moved, kinds, names or [""] * len(kinds)):
        colour = OPERATED if kind == "operated" else DISTURBED
        radius = int(max(20.0, float(np.max(np.hypot(*(obj.keypoints_after - obj.after).T))) + 8.0))
        cv2.arrowedLine(image, point(obj.before), point(obj.after), colour, 3, cv2.LINE_AA, tipLength=0.1)
        cv2.circle(image, point(obj.after), radius, colour, 3, cv2.LINE_AA)
        x, y = point(obj.after)
        text = f"{kind}: {name}"
        width = cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, 0.9, 2)[0][0]
        corner = (min(max(x - radius, 0), image.shape[1] - width), max(y - radius - 8, 60))  # in the picture
        cv2.putText(image, text, corner, cv2.FONT_HERSHEY_SIMPLEX, 0.9, colour, 2)


def moves_caption(record: dict) -> str:
    """The panel's words for an operation's record: what moved, operated and disturbed, and the
    tutor's slip (ground truth)."""
    if not record:
        return ""
    words = []
    if "operated" in record:
        words.append(f"operated {record['operated']}")
        words.append(f"disturbed {', '.join(record['disturbed']) or 'none'}")
    if "slip" in record:
        words.append(f"slip: {record['slip']['object']}")
    return "; ".join(words)
