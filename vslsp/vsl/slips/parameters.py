"""The tuned rules of the 2-D slip detection (:func:`vslsp.vsl.slips.detect.find_moved`) as a
parameter object (see :mod:`vslsp.parameters`): each field says what it controls and its valid
range, checked on construction; :data:`DEFAULT_SLIP_RULES` is what the experiments run. A
benchmark sweeps one by passing ``dataclasses.replace(DEFAULT_SLIP_RULES, nudge_well=0.3)``."""

from __future__ import annotations

from dataclasses import dataclass

from vslsp.parameters import check_ranges


@dataclass(frozen=True)
class SlipRules:
    """How :func:`~vslsp.vsl.slips.detect.find_moved` tells every object that moved in an
    operation, and the operated one from those the tutor disturbed."""

    # px: a changed region smaller than this is noise (an object covers thousands) (1..100000).
    min_region: int = 150
    # SIFT matches that must agree on one object's move (3..1000).
    min_inliers: int = 4
    # A move explains its object when it leaves at most this share of the grey difference its
    # object's pixels had left where they were (0..1).
    explains: float = 0.6
    # A fit explaining its object this many times worse than a later, still free fit of the
    # same object waits for that one (1..100).
    rival: float = 2.0
    # A fit that leaves at most this share of its object's difference explains it whole and
    # waits for no rival (two such fits are of identical objects: the nearer stands) (0..1).
    well: float = 0.1
    # A nudge seen between the pre-place and post observations that leaves at most this share of
    # its object's difference is a slip for sure: it overrules pairing the taken object onto its
    # place (0..1).
    nudge_well: float = 0.25
    # px: the rim about an object's keypoints within which two fits are of one object, or put
    # their objects in one place (0..1000).
    same_px: float = 10.0
    # RANSAC placements fitted per changed region at most (1..100).
    fits: int = 6
    # px: RANSAC's reprojection threshold for an object's move (0.1..50).
    reprojection: float = 6.0

    def __post_init__(self) -> None:
        check_ranges(self, RANGES)


RANGES = {
    "min_region": (1, 100000),
    "min_inliers": (3, 1000),
    "explains": (0.0, 1.0),
    "rival": (1.0, 100.0),
    "well": (0.0, 1.0),
    "nudge_well": (0.0, 1.0),
    "same_px": (0.0, 1000.0),
    "fits": (1, 100),
    "reprojection": (0.1, 50.0),
}
#: The rules the experiments run.
DEFAULT_SLIP_RULES = SlipRules()
