"""The tuned rules of 2-D perception as parameter objects (frozen dataclasses, one per
algorithm; see :mod:`vslsp.parameters`): each field says what it controls and its valid range,
checked on construction; the default instance is what the experiments run.

- :class:`FrameSearch`: match finding with adaptive frames (``findBestMatch``, Algorithm 1 lines
  13-14): :func:`vslsp.vision.matching.find_best_match` and :mod:`vslsp.vsl.matcher`.
- :class:`ObjectFinding`: finding an object by its SIFT features (``getObject`` and the
  reproduction's object candidates, :func:`vslsp.vsl.pick_place.object_candidates`) and
  telling an object from its texture when segmenting (:mod:`vslsp.vision.objects`).

A benchmark sweeps a field by passing ``dataclasses.replace(DEFAULT_FRAME_SEARCH, margin=0.05)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vslsp.errors import InputError
from vslsp.parameters import check_ranges


@dataclass(frozen=True)
class FrameSearch:
    """How an observation's frame is found in a world (:func:`~vslsp.vision.matching.find_best_match`)
    and how :mod:`vslsp.vsl.matcher` compares and re-fits the candidates."""

    # Normalised cross-correlation a match must reach before a unique frame stops the growth
    # (0..1).
    min_score: float = 0.5
    # The correlation by which a candidate must beat every other one to be unique; a frame rules
    # out for good the candidates it beats by this, and stops growing once its best falls this far
    # below a smaller frame's best (0..1).
    margin: float = 0.1
    # Each adaptive frame's side is the last one's times this (> 1, up to 4).
    frame_growth: float = 1.5
    # px: the smallest adaptive frame side, whatever the object's size (1..1000).
    min_frame: float = 16.0
    # World matches kept per frame keypoint, so that every copy of a repeated object gets its
    # matches (1..32).
    neighbours: int = 4
    # A further neighbour is kept when its descriptor distance is within this factor of the
    # nearest one's (1..4).
    alternative: float = 1.3
    # At most this many RANSAC placements per frame (1..64).
    max_candidates: int = 8
    # px: RANSAC's reprojection threshold for a frame's placements (0.1..50).
    reprojection: float = 3.0
    # The scale a placement may apply, (low, high): the same camera sees the same objects, so a
    # frame or an object is not much scaled (0.01..100, low <= 1 <= high).
    scale_range: tuple[float, float] = (0.67, 1.5)
    # The re-fit's first step: px moved and rad turned (0..100 px, 0..π rad).
    refit_step: float = 4.0
    refit_turn: float = float(np.radians(4.0))
    # px: the re-fit stops when its step has halved to below this (0.01..100).
    refit_stop: float = 0.5
    # The re-fit takes at most this many steps uphill (1..10000).
    refit_moves: int = 60
    # A fit whose scale is below this collapsed its frame to a line or a point: no pose (0..1).
    degenerate: float = 1e-6

    def __post_init__(self) -> None:
        check_ranges(
            self,
            {
                "min_score": (0.0, 1.0),
                "margin": (0.0, 1.0),
                "frame_growth": (1.0 + 1e-9, 4.0),
                "min_frame": (1.0, 1000.0),
                "neighbours": (1, 32),
                "alternative": (1.0, 4.0),
                "max_candidates": (1, 64),
                "reprojection": (0.1, 50.0),
                "scale_range": (0.01, 100.0),
                "refit_step": (0.0, 100.0),
                "refit_turn": (0.0, float(np.pi)),
                "refit_stop": (0.01, 100.0),
                "refit_moves": (1, 10_000),
                "degenerate": (0.0, 1.0),
            },
        )
        if len(self.scale_range) != 2 or not self.scale_range[0] <= 1.0 <= self.scale_range[1]:
            raise InputError(
                f"FrameSearch.scale_range is {self.scale_range!r}; it must be (low, high) with low <= 1 <= high"
            )


@dataclass(frozen=True)
class ObjectFinding:
    """How an object is found by its SIFT features among a world's
    (:func:`~vslsp.vsl.pick_place.object_candidates`, :mod:`vslsp.vsl.reproduction`), the
    tutor's turn of it (:func:`~vslsp.vsl.demonstration.perceived_turn`) and an object told from
    texture when segmenting (:mod:`vslsp.vision.objects`)."""

    # Lowe's ratio test: a match is kept when its nearest neighbour is nearer than this share
    # of the second's (0..1).
    ratio: float = 0.8
    # RANSAC inliers a placement of the object needs at least (3..1000: a similarity needs 2
    # points, a third checks it).
    min_inliers: int = 4
    # px: RANSAC's reprojection threshold for the object's placements (0.1..50).
    reprojection: float = 4.0
    # m: a feature match agrees with the object's seen footprint when it puts the object's centre
    # this near where it was seen put down (0..1).
    agree: float = 0.01
    # A second placement with this share of the best one's inliers makes a match ambiguous
    # (0..1).
    close: float = 0.7
    # RANSAC inliers of the object's features that must agree before the robot acts on a last
    # look: a count, not a share, since an object seen turned half round keeps 10-15 % of its
    # features (3..1000).
    sure: int = 10
    # RANSAC inliers that recognise which object someone else moved (3..1000).
    min_matches: int = 6
    # The first candidate seen at least this share as well as the best one is the moved object
    # (0..1).
    same_object: float = 0.6
    # px: the side of the window about the moved object in which the tutor's turn is searched
    # (larger than the object: a house's roof is 60 px across) (8..4096).
    patch: int = 128
    # Segmenting: a region's patch of no named colour smaller than this share of its named colour
    # is texture, not an object of its own (0..1).
    texture_share: float = 0.35
    # Grey levels an object's colour differs from the table's at least (1..255).
    object_contrast: int = 45

    def __post_init__(self) -> None:
        check_ranges(
            self,
            {
                "ratio": (0.0, 1.0),
                "min_inliers": (3, 1000),
                "reprojection": (0.1, 50.0),
                "agree": (0.0, 1.0),
                "close": (0.0, 1.0),
                "sure": (3, 1000),
                "min_matches": (3, 1000),
                "same_object": (0.0, 1.0),
                "patch": (8, 4096),
                "texture_share": (0.0, 1.0),
                "object_contrast": (1, 255),
            },
        )


DEFAULT_FRAME_SEARCH = FrameSearch()
DEFAULT_OBJECT_FINDING = ObjectFinding()
