"""The one interface of the paper's four worlds (:class:`World`): what an experiment does with a
world, whichever it is.

A world is built (reset) from a seeded layout, the value its module draws from a trial's seed;
its sensor gives one observation type; the tutor moves objects in it; a robot acts in it (none on
the house-roof board, where only the hand's path is planned) and the world settles after it
acted; and it knows the ground truth that judges a trial, which perception never reads. The
VSL-SP loop (:mod:`vslsp.loop`) and the skills' execution (:mod:`vslsp.skills.execute`) act
on any ``World[Observation]``. The worlds, each in :mod:`vslsp.worlds`:

========================  =====================  ====================  =========================  ============
world                     layout (seeded)        observation           tutor moves ``where``      truth
========================  =====================  ====================  =========================  ============
iCub line world (VSL-SP)  ``SceneSpec``          ``Observation``       (x, y) m on the table      (x, y, yaw)
Panda table (VSL)         [(Item, Placement)]    (H, W, 3) RGB         ``Placement``              (x, y, z, yaw)
RGB-D table (VSL-3D)      {name: (x, y, yaw)}    ``RGBDImage``         (4, 4) pose                (4, 4) pose
house-roof board (VSL)    ``HouseWorld``         (H, W, 3) RGB         ``Pose2`` px, or None      ``Pose2``
========================  =====================  ====================  =========================  ============
"""

from __future__ import annotations

from typing import Any, Protocol, Self, TypeVar, runtime_checkable

ObservationT_co = TypeVar("ObservationT_co", covariant=True)


@runtime_checkable
class World(Protocol[ObservationT_co]):
    """A world of the paper: reset from a seeded layout, observed by its sensor, changed by the
    tutor and the robot, judged on its ground truth."""

    @classmethod
    def from_layout(cls, layout: Any, seed: int = 0) -> Self:
        """A fresh world of ``layout`` (reset); ``seed`` seeds whatever the world itself draws."""
        ...

    def observe(self) -> ObservationT_co:
        """What the world's sensor sees now."""
        ...

    def tutor_move(self, name: str, where: Any) -> None:
        """The tutor puts object ``name`` at ``where`` (by hand: no robot involved)."""
        ...

    @property
    def robot(self) -> Any:
        """The robot that acts in this world (None where there is none)."""
        ...

    def settle(self) -> None:
        """Let the world come to rest after the robot acted (its physics, where it has any)."""
        ...

    def truth(self, name: str) -> Any:
        """Ground truth: the pose of object ``name``, for the judge only."""
        ...

    def close(self) -> None:
        """Release the world (its simulator)."""
        ...
