"""The tuned rules of the Panda's pick-and-place reproduction (:mod:`vslsp.vsl.reproduction`) as a
parameter object (see :mod:`vslsp.parameters`): each field says what it controls and its valid
range, checked on construction; :data:`DEFAULT_REPRODUCTION` is what the experiments run. The
match finding it calls has its own (:mod:`vslsp.vision.parameters`)."""

from __future__ import annotations

from dataclasses import dataclass

from vslsp.parameters import check_ranges


@dataclass(frozen=True)
class Reproduction:
    """How a recorded pick-and-place is planned in a new world and put right after a last look."""

    # The pre-place frame grows (x1.5 a step) while the match is ambiguous up to this multiple of
    # its first side: beyond, a frame sees mostly the rest of the scene, which the new world does
    # not share (its static landmarks would match in place and outvote the place's surroundings)
    # (1..20).
    place_growth: float = 3.0
    # A footprint whose sides differ by less than this share of the longer is square: the fingers
    # may close across either (0..1).
    square: float = 0.15
    # m: an object found further than this from its planned place after the release is put right
    # (0..0.2).
    correction: float = 0.006
    # The last look's square side, in object sizes about the planned place: the object is in it
    # while it lies less than one size off (1..20).
    look_around: float = 3.0

    def __post_init__(self) -> None:
        check_ranges(
            self,
            {"place_growth": (1.0, 20.0), "square": (0.0, 1.0), "correction": (0.0, 0.2), "look_around": (1.0, 20.0)},
        )


#: The rules the experiments run.
DEFAULT_REPRODUCTION = Reproduction()
