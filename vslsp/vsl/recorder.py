"""VSL's demonstration recorder: Algorithm 1, part I, written once for every task (the
house-and-roof simulation, the Panda's tabletop tasks, the iCub's VSL reproduction).

For each operation i the tutor performs, the :class:`Recorder` keeps the pre-action
observation O^Pre_i, the post-action observation O^Post_i and, when the camera saw the world
while the tutor held the object, the pre-place observation (lines 5-6), and asks its
observation model for ``getObject`` (line 7: the moved object found by image subtraction, its
symbol B_i, its poses P^Pre_i, P^Post_i, its SIFT features φ_i and the turn the tutor gave
it), ``getConstraint`` and ``getAction`` (lines 8-9, where the model has a landmark L).

The observation model is what differs between the tasks: images seen straight from above with
a landmark line, poses in image pixels (:class:`vslsp.vsl.demonstration.ImagePlane`), or a
calibrated camera over a table, poses unprojected at the tutor's heights
(:class:`vslsp.vsl.pick_place.TableModel`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic, Protocol, TypeVar

import numpy as np

from vslsp.errors import InputError

_Op = TypeVar("_Op")
_Demo = TypeVar("_Demo", covariant=True)


@dataclass(frozen=True)
class Heights:
    """The tutor's heights (m) for one operation (the paper's h, "provided by the tutor"): of
    the object's top at the pick and at the place, and the object's own height."""

    pick_z: float
    place_z: float
    height: float


class ObservationModel(Protocol[_Op, _Demo]):
    """How a task's observations are read: ``get_object`` (Algorithm 1 lines 7-9) for one
    operation's observations, and the demonstration its operations make."""

    def get_object(
        self, pre: np.ndarray, post: np.ndarray, pre_place: np.ndarray | None, heights: Heights | None
    ) -> _Op: ...

    def demonstration(self, operations: tuple[_Op, ...]) -> _Demo: ...


class Recorder(Generic[_Op, _Demo]):
    """Records a demonstration operation by operation (Algorithm 1, part I).

    ``recorder = Recorder(model)`` (the model detected the landmark L when it has one: line 2);
    ``recorder.record(pre, post, pre_place, heights)`` adds one operation (lines 5-9);
    ``recorder.demonstration()`` gives the recorded demonstration.
    """

    def __init__(self, model: ObservationModel[_Op, _Demo]) -> None:
        self.model = model
        self.operations: list[_Op] = []

    def record(
        self,
        pre: np.ndarray,
        post: np.ndarray,
        pre_place: np.ndarray | None = None,
        heights: Heights | None = None,
    ) -> _Op:
        """Add one operation from its pre- and post-action observations (H, W, 3) uint8, the
        pre-place one (the world while the tutor holds the object; None: not seen) and the
        tutor's ``heights`` (for a calibrated camera). The observations are kept as copies.
        Raises InputError when the model does not find the moved object."""
        operation = self.model.get_object(
            np.array(pre, copy=True),
            np.array(post, copy=True),
            None if pre_place is None else np.array(pre_place, copy=True),
            heights,
        )
        self.operations.append(operation)
        return operation

    def demonstration(self) -> _Demo:
        """The demonstration recorded so far. Raises InputError when it has no operation."""
        if not self.operations:
            raise InputError("the demonstration has no operations; record at least one operation of the tutor")
        return self.model.demonstration(tuple(self.operations))
