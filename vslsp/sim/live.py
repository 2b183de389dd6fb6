"""A running trial's newest picture, for the studio's experiments page (docs/studio.md).

When the environment names a file (:data:`ENV`, set by the studio for the runs it starts), the
simulator's cameras publish each view they render to it, at most one every :data:`INTERVAL_S`
seconds, the PNG replaced whole. Otherwise nothing is done. Publishing only reads the rendered
image, so a trial's course and results are the same with or without it, and a picture that cannot
be written is skipped: it never fails a trial.
"""

from __future__ import annotations

import os
import tempfile
import time
from typing import Any

#: The environment variable naming the picture file.
ENV = "VSLSP_LIVE_PICTURE"
#: The least time between two pictures written (s): a page refreshes about once a second.
INTERVAL_S = 0.5
#: Views smaller than this (pixels a side) are probes (a colour read at one pixel), not pictures.
MIN_SIDE = 64
_last = [-INTERVAL_S]


def publish(rgb: Any) -> None:
    """Write ``rgb`` (H, W, 3) uint8 as the live picture when one is asked for and the last is old enough."""
    path = os.environ.get(ENV)
    if not path or min(rgb.shape[:2]) < MIN_SIDE or time.monotonic() - _last[0] < INTERVAL_S:
        return
    _last[0] = time.monotonic()
    import cv2

    ok, data = cv2.imencode(".png", rgb[:, :, ::-1])  # OpenCV writes BGR
    if not ok:
        return
    try:
        handle, temporary = tempfile.mkstemp(prefix=".live-", suffix=".png", dir=os.path.dirname(path) or ".")
        with os.fdopen(handle, "wb") as stream:
            stream.write(data.tobytes())
        os.replace(temporary, path)
    except OSError:
        return
