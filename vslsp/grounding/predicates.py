"""User predicates: Python functions over what perception found, grounded into PDDL atoms.

Paper, VSL-SP "Implementation": "a simple (boolean) spatial reasoning [...] utilizes the detected
pose of the object and the detected borderline and then decides that the object is far or
near"; "Conclusion": "to extract more sophisticated constraints, qualitative spatial reasoning
languages such as Region Connection Calculus can be employed". Here that reasoning is the
user's: a predicate is a function registered with :func:`predicate`::

    @predicate("right-half")                 # unary: (obj, scene) -> bool
    def right_half(obj, scene):
        return obj.x > scene.width / 2

    @predicate("left-of", arity=2)           # binary: (a, b, scene) -> bool
    def left_of(a, b, scene):
        return a.x < b.x

:func:`ground_atoms` evaluates predicates on a :class:`Scene` for every object (every ordered
pair of distinct objects for binary ones) and returns the ground atoms with their values.
"""

from __future__ import annotations

import contextlib
import inspect
import math
import re
import traceback
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from vslsp.errors import InputError
from vslsp.grounding.spatial import ROBOT_SIDES, check_robot_side, towards_robot
from vslsp.grounding.user_code import (
    PREDICATE_TIME_LIMIT_S,
    TimeLimitExceeded,
    describe,
    passes_through,
    quiet_stdout,
    safe_repr,
    time_limit,
)
from vslsp.vision.landmark import Line
from vslsp.vision.objects import DetectedObject

_NAME = re.compile(r"[a-z][a-z0-9_-]*")  # matched whole (fullmatch: "near\n" is no name)
#: Words of PDDL a predicate cannot be named: the reader takes them for the operators.
PDDL_WORDS = frozenset(
    "and or not imply exists forall when either preference define domain problem "
    "always sometime within at-most-once sometime-after sometime-before always-within hold-during "
    "hold-after increase decrease assign scale-up scale-down minimize maximize total-time is-violated".split()
)


@dataclass(frozen=True)
class Box:
    """An axis-aligned footprint in the image: x0 <= x <= x1, y0 <= y <= y1 (px)."""

    x0: float
    y0: float
    x1: float
    y1: float

    @property
    def area(self) -> float:
        return max(0.0, self.x1 - self.x0) * max(0.0, self.y1 - self.y0)

    def overlap(self, other: Box) -> float:
        """Area (px²) the two boxes share."""
        w = min(self.x1, other.x1) - max(self.x0, other.x0)
        h = min(self.y1, other.y1) - max(self.y0, other.y0)
        return max(0.0, w) * max(0.0, h)

    def gap(self, other: Box) -> float:
        """Distance (px) between the boxes; 0 when they touch or overlap."""
        dx = max(0.0, other.x0 - self.x1, self.x0 - other.x1)
        dy = max(0.0, other.y0 - self.y1, self.y0 - other.y1)
        return math.hypot(dx, dy)

    def contains(self, other: Box) -> bool:
        """Whether ``other`` lies wholly within this box (RCC: a tangential or non-tangential part)."""
        return self.x0 <= other.x0 and self.y0 <= other.y0 and other.x1 <= self.x1 and other.y1 <= self.y1


@dataclass(frozen=True)
class SceneObject:
    """An object as a predicate sees it: its symbol ``name``, pixel centre (``x``, ``y``), its
    ``footprint`` (the bounding box of its pixels), ``area`` (px²) and ``orientation`` (deg)."""

    name: str
    x: float
    y: float
    footprint: Box
    area: float = 0.0
    orientation: float = 0.0


@dataclass(frozen=True)
class Landmark:
    """The landmark line as a predicate sees it, oriented by where the robot is."""

    line: Line
    robot_side: str = "bottom"
    _plane: tuple[float, float, float] = field(init=False, repr=False, compare=False, default=(0.0, 0.0, 0.0))

    def __post_init__(self) -> None:
        # signed_distance = a x + b y + c: the line's normal turned to the far side (plain floats: fast).
        sign = -float(np.sign(towards_robot(self.line, self.robot_side)))
        nx, ny = (float(v) * sign for v in self.line.normal)
        object.__setattr__(self, "_plane", (nx, ny, -(nx * self.line.p1[0] + ny * self.line.p1[1])))

    def signed_distance(self, x: float, y: float) -> float:
        """Distance (px) of the image point (x, y) from the line, positive on its far side (away
        from the robot)."""
        a, b, c = self._plane
        return a * x + b * y + c


@dataclass(frozen=True)
class Scene:
    """One observation as predicates see it: the image's ``width`` and ``height`` (px), the
    ``objects`` by symbol, the ``landmark`` (None when none is in view) and the image edge the
    robot is beyond (``robot_side``)."""

    width: int
    height: int
    objects: Mapping[str, SceneObject]
    landmark: Landmark | None = None
    robot_side: str = "bottom"

    def to_dict(self) -> dict:
        """The scene as JSON (every float exact: a predicates file's process sees the very numbers)."""
        landmark = None
        if self.landmark is not None:
            line = self.landmark.line
            landmark = {"p1": list(line.p1), "p2": list(line.p2), "robot_side": self.landmark.robot_side}
        objects = [
            [o.name, o.x, o.y, [o.footprint.x0, o.footprint.y0, o.footprint.x1, o.footprint.y1], o.area, o.orientation]
            for o in self.objects.values()
        ]
        return {
            "width": self.width,
            "height": self.height,
            "robot_side": self.robot_side,
            "landmark": landmark,
            "objects": objects,
        }

    @classmethod
    def from_dict(cls, data: Mapping) -> Scene:
        """The scene of :meth:`to_dict`."""
        objects = {}
        for name, x, y, box, area, orientation in data["objects"]:
            objects[name] = SceneObject(name, x, y, Box(*box), area, orientation)
        landmark = None
        if data["landmark"] is not None:
            (x1, y1), (x2, y2) = data["landmark"]["p1"], data["landmark"]["p2"]
            landmark = Landmark(Line((x1, y1), (x2, y2)), data["landmark"]["robot_side"])
        return cls(data["width"], data["height"], objects, landmark, data["robot_side"])

    @property
    def towards_robot(self) -> tuple[float, float]:
        """Unit direction (x, y) in the image pointing towards the robot."""
        return ROBOT_SIDES[self.robot_side]

    @property
    def robot_left(self) -> tuple[float, float]:
        """Unit direction (x, y) in the image pointing to the robot's left."""
        dx, dy = self.towards_robot  # the robot faces (-dx, -dy); its left is that turned by -90°
        return (-dy, dx)


def symbol_names(objects: Sequence[DetectedObject]) -> list[str]:
    """The objects' symbols, made unique in order with a suffix: red, red_2, ..."""
    names: list[str] = []
    for obj in objects:
        name, k = obj.name, 1
        while name in names:
            k += 1
            name = f"{obj.name}_{k}"
        names.append(name)
    return names


def scene_of(
    objects: Sequence[DetectedObject], size: tuple[int, int], line: Line | None, robot_side: str = "bottom"
) -> Scene:
    """The :class:`Scene` of perceived ``objects`` in an image of ``size`` (W, H) px."""
    check_robot_side(robot_side)
    members = {}
    for name, obj in zip(symbol_names(objects), objects, strict=True):
        x, y, w, h = obj.box
        members[name] = SceneObject(
            name,
            float(obj.centroid[0]),
            float(obj.centroid[1]),
            Box(float(x), float(y), float(x + w), float(y + h)),
            obj.area,
            obj.orientation,
        )
    landmark = Landmark(line, robot_side) if line is not None else None
    return Scene(int(size[0]), int(size[1]), members, landmark, robot_side)


Atom = tuple[str, tuple[str, ...]]  # (predicate, (object, ...))


class AtomSource(Protocol):
    """Decides predicates outside this process: every atom of ``predicates`` over ``scene``."""

    def evaluate(self, scene: Scene, predicates: Sequence[Predicate]) -> dict[Atom, bool]: ...


@dataclass(frozen=True, eq=False)
class Predicate:
    """A named predicate of ``arity`` 1 or 2 and the function that decides it.

    Call it like its function: ``p(obj, scene)`` or ``p(a, b, scene)``.
    """

    name: str
    arity: int
    function: Callable[..., bool] = field(compare=False)
    #: Where the predicate is decided when not in this process (a user's file run in a child:
    #: :class:`vslsp.grounding.contained.UserPredicates`); None: by calling ``function`` here.
    source: AtomSource | None = field(default=None, compare=False, repr=False)

    def __call__(self, *args: object) -> bool:
        return self.function(*args)

    @property
    def signature(self) -> str:
        """Its PDDL declaration: ``(left-of ?a ?b)``."""
        return f"({self.name} {' '.join(('?a', '?b')[: self.arity])})" if self.arity == 2 else f"({self.name} ?b)"

    def evaluate(self, args: Sequence[SceneObject], scene: Scene) -> bool:
        """The value for ``args`` (``arity`` objects); whatever else the function does (raises, exits, runs
        past :data:`PREDICATE_TIME_LIMIT_S`, returns a non-bool) is an InputError naming the predicate."""
        fix = f"fix its function {_where(self.function)}"
        try:
            with time_limit(PREDICATE_TIME_LIMIT_S), quiet_stdout():
                value = self.function(*args, scene)
        except TimeLimitExceeded:
            raise InputError(
                f"predicate {self.name} ran longer than {PREDICATE_TIME_LIMIT_S:g} s while grounding "
                f"{self._atom(args)} and was stopped; {fix} (a predicate decides one atom, in microseconds)"
            ) from None
        except BaseException as error:  # the user's code: whatever it raises is theirs to fix
            if passes_through(error):
                raise
            raise InputError(
                f"predicate {self.name} raised {describe(error)} while grounding {self._atom(args)}; "
                f"{fix}{_raised_at(error, self.function)}"
            ) from None
        if value is True or value is False:
            return value
        if not isinstance(value, np.bool_):
            raise InputError(
                f"predicate {self.name} returned {type(value).__name__} {safe_repr(value)} for {self._atom(args)}, "
                f"not a bool; make its function {_where(self.function)} return True or False"
            )
        return bool(value)

    def _atom(self, args: Sequence[SceneObject]) -> str:
        return f"({self.name} {' '.join(a.name for a in args)})"


def _raised_at(error: BaseException, function: Callable) -> str:
    """``, line N raised it``: the last line of the function's file in the traceback."""
    code = getattr(function, "__code__", None)
    if code is None:
        return ""
    lines = [f.lineno for f in traceback.extract_tb(error.__traceback__) if f.filename == code.co_filename]
    return f", line {lines[-1]} raised it" if lines else ""


def _where(function: Callable) -> str:
    code = getattr(function, "__code__", None)
    name = getattr(function, "__qualname__", repr(function))
    return f"{name} ({code.co_filename}:{code.co_firstlineno})" if code is not None else name


class Registry:
    """Predicates by name, in the order registered."""

    def __init__(self) -> None:
        self._predicates: dict[str, Predicate] = {}

    def add(self, predicate: Predicate) -> Predicate:
        known = self._predicates.get(predicate.name)
        if known is not None and _identity(known.function) != _identity(predicate.function):
            raise InputError(
                f"predicate {predicate.name} is defined twice ({_where(known.function)} and "
                f"{_where(predicate.function)}); give each predicate its own name"
            )
        self._predicates[predicate.name] = predicate
        return predicate

    def predicates(self) -> tuple[Predicate, ...]:
        return tuple(self._predicates.values())

    def clear(self) -> None:
        self._predicates.clear()


def _identity(function: Callable) -> tuple[str, str]:
    return getattr(function, "__module__", ""), getattr(function, "__qualname__", repr(function))


_ACTIVE: list[Registry] = [Registry()]  # a stack: the top one receives new predicates


def predicate(name: str, arity: int = 1, *, register: bool = True) -> Callable[[Callable[..., bool]], Predicate]:
    """Decorator: make ``function`` the predicate ``name`` of ``arity`` 1 (``(obj, scene)``) or 2
    (``(a, b, scene)``) and register it (unless ``register`` is False)."""
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise InputError(
            f"predicate name {safe_repr(name)} is not a PDDL name: use lower-case letters, digits, '-' and '_', "
            "starting with a letter (e.g. 'left-of')"
        )
    if name in PDDL_WORDS:
        raise InputError(
            f"predicate name {name!r} is a word of PDDL ({name} ...); give the predicate another name "
            f"(e.g. '{name}-1' or one that says what it decides)"
        )
    if arity not in (1, 2):
        raise InputError(f"predicate {name}: arity {arity!r} is not supported; use 1 (obj, scene) or 2 (a, b, scene)")

    def wrap(function: Callable[..., bool]) -> Predicate:
        if not callable(function):
            raise InputError(f"predicate {name}: @predicate decorates a function, got {type(function).__name__}")
        try:
            inspect.signature(function).bind(*range(arity + 1))
        except TypeError:
            wanted = "(obj, scene)" if arity == 1 else "(a, b, scene)"
            raise InputError(f"predicate {name}: its function {_where(function)} must take {wanted}") from None
        except ValueError:  # a builtin without a signature: called as it is
            pass
        made = Predicate(name, arity, function)
        return _ACTIVE[-1].add(made) if register else made

    return wrap


def register(*predicates: Predicate) -> None:
    """Register ready predicates (e.g. from :mod:`vslsp.grounding.relations`) to be grounded."""
    for made in predicates:
        _ACTIVE[-1].add(made)


def registered() -> tuple[Predicate, ...]:
    """The predicates registered so far (in the active registry), in order."""
    return _ACTIVE[-1].predicates()


@contextlib.contextmanager
def collecting() -> Iterator[Registry]:
    """A fresh registry receives the predicates registered inside the ``with`` block."""
    _ACTIVE.append(Registry())
    try:
        yield _ACTIVE[-1]
    finally:
        _ACTIVE.pop()


def ground_atoms(scene: Scene, predicates: Sequence[Predicate]) -> dict[Atom, bool]:
    """Every ground atom of ``predicates`` over the scene's objects (ordered pairs of distinct
    objects for binary ones), with its value. Predicates decided elsewhere (``source``) are
    asked once per source for all their atoms; the values keep the predicates' order."""
    objects = list(scene.objects.values())
    decided: dict[Atom, bool] = {}
    sources = {id(p.source): p.source for p in predicates if p.source is not None}
    for source in sources.values():
        decided.update(source.evaluate(scene, [p for p in predicates if p.source is source]))
    values: dict[Atom, bool] = {}
    for made in predicates:
        if made.source is not None:
            values.update((atom, decided[atom]) for atom in atoms_of(made, objects))
        elif made.arity == 1:
            for obj in objects:
                values[(made.name, (obj.name,))] = made.evaluate((obj,), scene)
        else:
            for a in objects:
                for b in objects:
                    if a is not b:
                        values[(made.name, (a.name, b.name))] = made.evaluate((a, b), scene)
    return values


def atoms_of(made: Predicate, objects: Sequence[SceneObject]) -> Iterator[Atom]:
    """The ground atoms of ``made`` over ``objects``, in the order :func:`ground_atoms` decides them."""
    if made.arity == 1:
        yield from ((made.name, (obj.name,)) for obj in objects)
    else:
        yield from ((made.name, (a.name, b.name)) for a in objects for b in objects if a is not b)


def atom_text(atom: Atom) -> str:
    """PDDL syntax of an atom: ``(left-of red green)``."""
    return f"({atom[0]} {' '.join(atom[1])})"


def true_atoms(values: Mapping[Atom, bool]) -> list[str]:
    """The true atoms in PDDL syntax, sorted."""
    return sorted(atom_text(atom) for atom, value in values.items() if value)


def unary_literals(values: Mapping[Atom, bool]) -> dict[str, dict[str, bool]]:
    """The unary atoms as ``{object: {predicate: value}}`` (what action models are learned from)."""
    literals: dict[str, dict[str, bool]] = {}
    for (name, args), value in values.items():
        if len(args) == 1:
            literals.setdefault(args[0], {})[name] = value
    return literals
