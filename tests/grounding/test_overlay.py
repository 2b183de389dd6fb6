"""The overlay of a grounding: pre and post side by side, the line, the object at both places."""

import numpy as np

from vslsp.grounding.operation import ground
from vslsp.grounding.overlay import draw_grounding
from vslsp.grounding.synthetic import Square, tabletop_image

LINE_RGB = np.array([0, 200, 255])


def test_the_overlay_draws_the_line_the_object_before_and_after_and_the_labels():
    pre = tabletop_image([Square("red", (200, 400))])
    post = tabletop_image([Square("red", (210, 150))])
    grounding = ground(pre, post)
    overlay = draw_grounding(pre, post, grounding)
    assert overlay.shape == (480, 1280, 3)
    left, right = overlay[:, :640], overlay[:, 640:]
    for panel, line in ((left, grounding.landmark), (right, grounding.post_landmark)):
        x = 320
        y = int(round(line.p1[1] + (x - line.p1[0]) * (line.p2[1] - line.p1[1]) / (line.p2[0] - line.p1[0])))
        assert np.abs(panel[y - 1 : y + 2, x].astype(int) - LINE_RGB).max(axis=1).min() < 30
    # The pre panel marks the object in white, the post panel in magenta, and both carry text.
    assert (left[400, 195:206] == 255).all(axis=1).any()
    assert (np.abs(right[150, 205:216].astype(int) - [255, 0, 255]).max(axis=1) == 0).any()
    assert not np.array_equal(left[:40, :300], pre[:40, :300])
    assert not np.array_equal(right[:70, :300], post[:70, :300])
