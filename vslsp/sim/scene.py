"""Scene specifications: the table, the coloured cubes and the landmark line.

A scene is plain data (frozen dataclasses, JSON round trip) so that the same seed gives the
same scene and a scene can be written down, shared and loaded again.

Frame: x forward from the robot over the table, y to the robot's left, z up (metres). The
landmark is a black line through ``(x, LINE_Y)`` whose normal makes the angle ``angle`` with
the x axis; ``far`` is the side the normal points to, away from the robot.
"""

from __future__ import annotations

import functools
import itertools
import json
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np

from vslsp.errors import InputError
from vslsp.files import read_json, shown

TABLE_Z = 0.58  # height of the table top
CUBE_SIZE = 0.05
LINE_Y = -0.10  # the line is placed through the middle of the right hand's workspace
LINE_WIDTH = 0.015
MAX_SCENE_BYTES = 100_000  # a scene file: at most 12 cubes and a landmark
# Where cube centres may lie: the right hand must reach 7 cm behind and 7 cm beyond a cube,
# and a push or pull moves it about 12 cm along the line's normal.
WORKSPACE_X = (0.14, 0.33)
WORKSPACE_Y = (-0.205, 0.035)

# Where the palm can start a push or a pull, palm down, 2 cm above the table (measured with
# the IK over the table; see benchmarks/bench_sim.py).
# Close to the body the hand reaches less far to either side (the reach arcs up to 10 cm high).
HAND_REACH_X = (0.09, 0.395)
HAND_REACH_Y = (-0.235, 0.05)

COLOURS: dict[str, tuple[float, float, float]] = {
    "red": (0.85, 0.10, 0.10),
    "orange": (1.00, 0.50, 0.05),
    "yellow": (0.95, 0.85, 0.10),
    "green": (0.10, 0.70, 0.20),
    "blue": (0.10, 0.25, 0.90),
    "purple": (0.55, 0.15, 0.75),
}


# Along-line offsets (m) of other cubes that the hand disturbs when it pushes / pulls a cube.
PUSH_OVERSHOOT = 0.10  # m past the line a pushed cube may end
SWEEP_BANDS = {"push": (-0.06, 0.11), "pull": (-0.115, 0.08)}


@dataclass(frozen=True)
class CubeSpec:
    """One cube: its symbol name, colour name, and pose on the table (x, y in m, yaw in rad)."""

    name: str
    colour: str
    x: float
    y: float
    yaw: float = 0.0
    size: float = CUBE_SIZE

    def __post_init__(self) -> None:
        if self.colour not in COLOURS:
            raise InputError(f"cube {self.name!r} has unknown colour {self.colour!r}; use one of {', '.join(COLOURS)}")
        if not 0.02 <= self.size <= 0.1:
            raise InputError(f"cube {self.name!r} has size {self.size} m; use 0.02-0.1 m")


@dataclass(frozen=True)
class LandmarkSpec:
    """The black borderline: through ``(x, LINE_Y)``, normal at ``angle`` rad from the x axis."""

    x: float = 0.225
    angle: float = 0.0

    @property
    def point(self) -> np.ndarray:
        return np.array([self.x, LINE_Y])

    @property
    def normal(self) -> np.ndarray:
        """Unit normal (2,) pointing to the far side (away from the robot)."""
        return np.array([np.cos(self.angle), np.sin(self.angle)])

    @property
    def direction(self) -> np.ndarray:
        """Unit vector (2,) along the line."""
        return np.array([-np.sin(self.angle), np.cos(self.angle)])

    def signed_distance(self, xy: np.ndarray) -> float:
        """Distance (m) of a table point from the line, positive on the far side."""
        return float(np.dot(np.asarray(xy, dtype=float)[:2] - self.point, self.normal))


@dataclass(frozen=True)
class SceneSpec:
    """Cubes and the landmark: everything needed to build a world."""

    cubes: tuple[CubeSpec, ...]
    landmark: LandmarkSpec = field(default_factory=LandmarkSpec)

    def __post_init__(self) -> None:
        names = [cube.name for cube in self.cubes]
        if len(set(names)) != len(names):
            raise InputError(f"cube names must be unique, got {names}")

    def cube(self, name: str) -> CubeSpec:
        for cube in self.cubes:
            if cube.name == name:
                return cube
        raise InputError(f"no cube named {name!r}; the scene has {[c.name for c in self.cubes]}")

    def with_cube(self, cube: CubeSpec) -> SceneSpec:
        return replace(self, cubes=tuple(cube if c.name == cube.name else c for c in self.cubes))

    def to_dict(self) -> dict:
        return {"cubes": [asdict(cube) for cube in self.cubes], "landmark": asdict(self.landmark)}

    @classmethod
    def from_dict(cls, data: dict) -> SceneSpec:
        _check_scene_data(data)
        try:
            cubes = tuple(CubeSpec(**cube) for cube in data["cubes"])
            landmark = LandmarkSpec(**data.get("landmark", {}))
        except (KeyError, TypeError) as error:
            raise InputError(
                f"not a scene description ({error}); expected "
                '{"cubes": [{"name", "colour", "x", "y", "yaw"}, ...], "landmark": {"x", "angle"}}'
            ) from error
        return cls(cubes=cubes, landmark=landmark)

    @classmethod
    def load(cls, path: str | Path) -> SceneSpec:
        data = read_json(path, "scene file", MAX_SCENE_BYTES)
        try:
            return cls.from_dict(data)
        except InputError as error:
            raise InputError(f"scene file {shown(path)}: {error}") from error

    def save(self, path: str | Path) -> None:
        Path(path).write_text(json.dumps(self.to_dict(), indent=2) + "\n")

    @classmethod
    def random(
        cls,
        seed: int,
        n_cubes: int = 3,
        colours: tuple[str, ...] | None = None,
        far: tuple[bool, ...] | None = None,
        landmark: LandmarkSpec | None = None,
    ) -> SceneSpec:
        """Cubes at random, without overlap, on both sides of a randomly placed line.

        Cubes keep 4-8 cm from the line (so a push or pull of ~12 cm crosses it) and out of
        the band the hand and forearm sweep when another cube is pushed or pulled.
        ``far`` fixes the side of each cube; ``colours`` their colours (names = colours).
        """
        rng = np.random.default_rng(seed)
        fixed_landmark = landmark
        if far is not None:  # a layout no seed can give is said at once, with why
            check_layout(tuple(bool(f) for f in far), fixed_landmark)
        elif 2 <= len(colours or ()) <= 8 or (colours is None and 2 <= n_cubes <= 8):
            check_some_layout(len(colours) if colours is not None else n_cubes, fixed_landmark)
        if colours is None:
            if n_cubes > len(COLOURS):
                raise InputError(f"at most {len(COLOURS)} cubes of distinct colours, asked {n_cubes}")
            colours = tuple(str(c) for c in rng.choice(list(COLOURS), size=n_cubes, replace=False))
        n_cubes = len(colours)
        fixed_far = far
        landmark = fixed_landmark or LandmarkSpec(x=0.22, angle=0.0)  # drawn anew below
        sides: tuple[bool, ...] = far if far is not None else (False,) * n_cubes
        sign = np.ones(n_cubes)
        for attempt in range(30000):
            if attempt % 25 == 0:
                landmark = fixed_landmark or LandmarkSpec(
                    x=float(rng.uniform(0.21, 0.24)), angle=float(rng.uniform(-0.3, 0.3))
                )
                if fixed_far is None:  # some sides cannot be laid out with some line poses
                    sides = tuple(bool(v) for v in rng.random(n_cubes) < 0.5)
                sign = np.where(sides, 1.0, -1.0)
            across = rng.uniform(0.04, 0.08, size=n_cubes) * sign
            span = _along_span(landmark, np.asarray(sides), across)
            along = None if span is None else _along_positions(rng, np.asarray(sides), span)
            if along is None:
                continue
            centres = landmark.point + np.outer(along, landmark.direction) + np.outer(across, landmark.normal)
            inside = _placeable(landmark, np.asarray(sides), centres)
            if inside.all():
                yaws = rng.uniform(-0.4, 0.4, size=n_cubes)
                cubes = tuple(
                    CubeSpec(name=colour, colour=colour, x=float(x), y=float(y), yaw=float(yaw))
                    for colour, (x, y), yaw in zip(colours, centres, yaws)
                )
                return cls(cubes=cubes, landmark=landmark)
        raise InputError(
            f"cannot place {n_cubes} cubes without overlap where the robot can push and pull them; "
            "use at most 3 cubes (or another seed)"
        )


class LayoutImpossible(InputError):
    """Cubes on these sides of the line cannot be laid out with any seed (:func:`check_layout`)."""


# The upper bound of :func:`check_layout` is taken over the sampler's line poses on this grid (m,
# rad); a layout is refused only when it needs more than the bound plus this margin (the bound
# between grid poses is larger by less than it).
_POSES = [(float(x), float(a)) for x in np.linspace(0.21, 0.24, 4) for a in np.linspace(-0.3, 0.3, 13)]
_ACROSS = np.linspace(0.04, 0.08, 9)
_FIT_MARGIN = 0.005


@functools.lru_cache(maxsize=256)
def check_layout(far: tuple[bool, ...], landmark: LandmarkSpec | None = None) -> None:
    """A :class:`LayoutImpossible` when cubes on the sides ``far`` (True: beyond the line) cannot
    be placed by :meth:`SceneSpec.random` with any seed.

    The rule: the cubes stand in a row along the line, each gap as wide as the sweep bands of the
    hand pushing (near cubes) or pulling (far cubes) its neighbour need; so the row needs at least
    the least sum of gaps over the cubes' orders. The stretch of the line where every cube can
    stand (in view, in reach, out of the forearm's way: :func:`_along_span`, the sampler's own
    test) is at most the intersection of each cube's best stretch over its distances from the
    line, for the best line pose. A row longer than that stretch cannot be laid out."""
    if len(far) < 2:
        return
    sides = np.array(far)
    need = min(_gaps(sides[list(order)]).sum() for order in itertools.permutations(range(len(far))))
    poses = [landmark] if landmark is not None else [LandmarkSpec(x=x, angle=a) for x, a in _POSES]
    room = max(_best_stretch(pose, sides) for pose in poses)
    if need > room + _FIT_MARGIN:
        near, beyond = int((~sides).sum()), int(sides.sum())
        raise LayoutImpossible(
            f"{len(far)} cubes, {near} on the robot's side of the line and {beyond} beyond it, do not fit where the "
            f"robot can push and pull them: in a row along the line, out of the hand's sweep, they need "
            f"{100 * need:.1f} cm, and at most {100 * room:.1f} cm of the line is in reach and in view; "
            "put fewer cubes on one side (or use fewer cubes)"
        )


@functools.lru_cache(maxsize=16)
def check_some_layout(n_cubes: int, landmark: LandmarkSpec | None = None) -> None:
    """A :class:`LayoutImpossible` (the message of the least crowded sides) when ``n_cubes`` cubes
    fit on no choice of sides (:func:`check_layout`)."""
    refusals = []
    for far in itertools.product((False, True), repeat=n_cubes):
        try:
            check_layout(far, landmark)
            return
        except LayoutImpossible as refused:
            refusals.append((abs(sum(far) - n_cubes / 2), str(refused)))
    raise LayoutImpossible(min(refusals)[1])


def _gaps(far: np.ndarray) -> np.ndarray:
    """The least gaps (m) between neighbours in this order along the line (:func:`_along_positions`)."""
    low = np.array([SWEEP_BANDS["pull" if f else "push"][0] for f in far])
    high = np.array([SWEEP_BANDS["pull" if f else "push"][1] for f in far])
    return np.maximum(-low[1:], high[:-1]) + 0.005


def _best_stretch(landmark: LandmarkSpec, far: np.ndarray) -> float:
    """An upper bound (m) of the stretch of the line where every cube could stand with this line."""
    stretches = [_side_stretch(landmark, bool(side)) for side in far]
    if any(stretch is None for stretch in stretches):
        return 0.0
    return max(0.0, min(hi for _, hi in stretches) - max(lo for lo, _ in stretches))  # type: ignore[misc]


@functools.lru_cache(maxsize=512)
def _side_stretch(landmark: LandmarkSpec, far: bool) -> tuple[float, float] | None:
    """The widest stretch (m along the line) where a cube on side ``far`` could stand, over its
    distances from the line; None when it can stand nowhere."""
    spans = [_along_span(landmark, np.array([far]), np.array([a if far else -a])) for a in _ACROSS]
    found = [span for span in spans if span is not None]
    return (min(lo for lo, _ in found), max(hi for _, hi in found)) if found else None


# The table top of vslsp.sim.world (TABLE_CENTRE ± TABLE_HALF): scene files must keep cubes on it.
TABLE_X = (0.06, 0.86)
TABLE_Y = (-0.75, 0.65)
MAX_CUBES = 12


def _check_scene_data(data: object) -> None:
    """Check a scene description read from a file: types, finite numbers, cubes whole on the table
    top; an :class:`InputError` names the field (``cubes[1].x``) and what is wrong."""
    if not isinstance(data, dict) or not isinstance(data.get("cubes"), list):
        raise InputError(
            'not a scene description: expected {"cubes": [{"name", "colour", "x", "y", "yaw"}, ...], '
            '"landmark": {"x", "angle"}}'
        )
    if len(data["cubes"]) > MAX_CUBES:
        raise InputError(f"cubes: {len(data['cubes'])} cubes, at most {MAX_CUBES} fit the table")

    def number(value: object, field: str) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise InputError(f"not a scene description: {field} is {value!r}, not a number")
        if not np.isfinite(value):
            raise InputError(f"{field} is {value}: not a finite number")
        return float(value)

    for k, cube in enumerate(data["cubes"]):
        if not isinstance(cube, dict):
            raise InputError(
                f"not a scene description: cubes[{k}] is {cube!r}, not an object with name, colour, x, y, yaw"
            )
        if not isinstance(cube.get("name"), str) or not cube["name"]:
            raise InputError(f"not a scene description: cubes[{k}].name is {cube.get('name')!r}, not a name")
        size = number(cube.get("size", CUBE_SIZE), f"cubes[{k}].size")
        if not 0.02 <= size <= 0.1:
            raise InputError(f"cubes[{k}].size is {size} m; use 0.02-0.1 m")
        for axis, (low, high) in (("x", TABLE_X), ("y", TABLE_Y)):
            value = number(cube.get(axis), f"cubes[{k}].{axis}")
            if not low + size / 2 <= value <= high - size / 2:
                raise InputError(
                    f"cubes[{k}].{axis} is {value} m: the cube {cube['name']!r} would be off the table "
                    f"({axis} from {low + size / 2:.3f} to {high - size / 2:.3f} m)"
                )
        number(cube.get("yaw", 0.0), f"cubes[{k}].yaw")
    landmark = data.get("landmark", {})
    if not isinstance(landmark, dict):
        raise InputError(f"not a scene description: landmark is {landmark!r}, not an object with x and angle")
    x = number(landmark.get("x", LandmarkSpec.x), "landmark.x")
    if not TABLE_X[0] <= x <= TABLE_X[1]:
        raise InputError(
            f"landmark.x is {x} m: the line would be off the table (x from {TABLE_X[0]} to {TABLE_X[1]} m)"
        )
    number(landmark.get("angle", LandmarkSpec.angle), "landmark.angle")


def _placeable(landmark: LandmarkSpec, far: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """Which cube centres (n, 2) are in view and leave the hand room to push (near cubes) or
    pull (far cubes) them."""
    # Where the hand starts a push (behind the cube) or a pull (beyond it, to its right).
    contacts = (
        centres
        - np.outer(np.where(far, -0.10, 0.07), landmark.normal)
        - np.outer(np.where(far, 0.04, 0.0), landmark.direction)
    )
    # Where the cube lands after its push or pull (the tutor's: 5.5 cm beyond the line): the
    # head camera must still see it whole. Its view's lower edge cuts the table closer to the
    # robot on its right than on its left (measured: a cube is seen whole from x = 0.16 at
    # y = 0.06, from 0.12 at y = 0, from 0.08 at y = -0.1 and from 0.14 at y = -0.25).
    # A pushed cube often tips over and travels 10 cm past the line or more (measured), so a
    # near cube's landing is checked that far out, against the view's upper edge too.
    across = (centres - landmark.point) @ landmark.normal
    landed = centres - np.outer(across + np.where(far, 0.065, -PUSH_OVERSHOOT), landmark.normal)
    return (
        (landed[:, 0] >= 0.10 + 0.6 * np.maximum(0.0, landed[:, 1] + 0.05) + 0.8 * np.maximum(0.0, -0.2 - landed[:, 1]))
        & (landed[:, 0] <= 0.37)
        & (landed[:, 1] >= WORKSPACE_Y[0] - 0.03)
        & (landed[:, 1] <= WORKSPACE_Y[1])
        & (centres[:, 0] >= WORKSPACE_X[0])
        & (centres[:, 0] <= WORKSPACE_X[1])
        & (centres[:, 1] >= WORKSPACE_Y[0])
        & (centres[:, 1] <= WORKSPACE_Y[1])
        & (contacts[:, 0] >= HAND_REACH_X[0])
        & (contacts[:, 0] <= HAND_REACH_X[1])
        & (contacts[:, 1] >= HAND_REACH_Y[0])
        & (contacts[:, 1] <= HAND_REACH_Y[1])
        & (contacts[:, 1] <= -0.01 + 0.5 * (contacts[:, 0] - HAND_REACH_X[0]))
        & (contacts[:, 1] >= HAND_REACH_Y[0] + 1.5 * np.maximum(0.0, 0.15 - contacts[:, 0]))
    )


def _margins(landmark: LandmarkSpec, far: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """The constraints of :func:`_placeable` as margins (n, 17), each >= 0 where it holds.

    Every margin is affine in the centre (the ``max(0, ...)`` bounds are split into their
    linear pieces), so along a line each is affine in the distance along it."""
    contacts = (
        centres
        - np.outer(np.where(far, -0.10, 0.07), landmark.normal)
        - np.outer(np.where(far, 0.04, 0.0), landmark.direction)
    )
    across = (centres - landmark.point) @ landmark.normal
    landed = centres - np.outer(across + np.where(far, 0.065, -PUSH_OVERSHOOT), landmark.normal)
    lx, ly, cx, cy, kx, ky = landed[:, 0], landed[:, 1], centres[:, 0], centres[:, 1], contacts[:, 0], contacts[:, 1]
    return np.column_stack(
        [
            lx - 0.10,
            lx - 0.10 - 0.6 * (ly + 0.05),
            lx - 0.10 - 0.8 * (-0.2 - ly),
            0.37 - lx,
            ly - (WORKSPACE_Y[0] - 0.03),
            WORKSPACE_Y[1] - ly,
            cx - WORKSPACE_X[0],
            WORKSPACE_X[1] - cx,
            cy - WORKSPACE_Y[0],
            WORKSPACE_Y[1] - cy,
            kx - HAND_REACH_X[0],
            HAND_REACH_X[1] - kx,
            ky - HAND_REACH_Y[0],
            HAND_REACH_Y[1] - ky,
            -0.01 + 0.5 * (kx - HAND_REACH_X[0]) - ky,
            ky - HAND_REACH_Y[0] - 1.5 * (0.15 - kx),
        ]
    )


_GRID = np.linspace(-0.2, 0.2, 81)
_TIE = 1e-9  # m: a margin this close to 0 on a grid point is decided by _placeable itself


@functools.lru_cache(maxsize=64)
def _line_forms(landmark: LandmarkSpec, far: tuple[bool, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The margins (n, 17) of cubes on the line's point, and their change per metre across
    the line and per metre along it (both (n, 17))."""
    n, sides = len(far), np.array(far * 3)
    base = np.repeat(landmark.point[None], n, axis=0)
    ends = _margins(landmark, sides, np.vstack([base, base + landmark.normal, base + landmark.direction]))
    return ends[:n], ends[n : 2 * n] - ends[:n], ends[2 * n :] - ends[:n]


def _along_span(landmark: LandmarkSpec, far: np.ndarray, across: np.ndarray) -> tuple[float, float] | None:
    """The stretch of the line (m along it) where every cube, at its distance ``across`` from
    the line, would be placeable (on a grid of 81 points, 5 mm apart); None when there is none.

    The scene sampler asks this thousands of times per scene, so the constraints are
    evaluated as margins affine along the line for all cubes and grid points at once; the
    rare grid point that lies on a constraint's boundary is decided by :func:`_placeable`."""
    far = np.asarray(far)
    at_line, per_across, slope = _line_forms(landmark, tuple(bool(f) for f in far))
    margins = (at_line + np.asarray(across, dtype=float)[:, None] * per_across)[:, :, None] + slope[
        :, :, None
    ] * _GRID  # (n, 17, 81)
    # A point is placeable where its least margin is >= 0; a least margin within _TIE of 0 is
    # a tie that rounding could decide either way: _placeable, the reference, decides it.
    least = margins.min(axis=1)  # (n, 81)
    ok = least >= 0.0
    for k, i in np.argwhere(np.abs(least) < _TIE):
        centre = landmark.point + _GRID[i] * landmark.direction + across[k] * landmark.normal
        ok[k, i] = _placeable(landmark, far[k : k + 1], centre[None])[0]
    if not ok.any(axis=1).all():
        return None
    low = _GRID[ok.argmax(axis=1)].max()  # the grid ascends: the first and last placeable points
    high = _GRID[len(_GRID) - 1 - ok[:, ::-1].argmax(axis=1)].min()
    return (float(low), float(high)) if low < high else None


def _along_positions(rng: np.random.Generator, far: np.ndarray, span: tuple[float, float]):
    """Random positions (n,) along the line, with no cube in the band the hand sweeps when it
    pushes (near cubes) or pulls (far cubes) another; None when they cannot fit in ``span``.

    Cubes are laid out in a random order, each gap at least what the sweep bands need
    (measured in the simulator: there a neighbour changes side or is carried more than
    2.5 cm), plus a random share of the room left.
    """
    order = rng.permutation(len(far))
    low = np.array([SWEEP_BANDS["pull" if f else "push"][0] for f in far])[order]
    high = np.array([SWEEP_BANDS["pull" if f else "push"][1] for f in far])[order]
    # Neighbours k (right) and k+1 (left): acting on k+1 sweeps down to low, on k up to high.
    gaps = np.maximum(-low[1:], high[:-1]) + 0.005
    room = span[1] - span[0] - gaps.sum()
    if room < 0:
        return None
    slack = rng.dirichlet(np.ones(len(far) + 1)) * room
    sorted_along = span[0] + slack[0] + np.concatenate([[0.0], np.cumsum(gaps + slack[1:-1])])
    along = np.empty(len(far))
    along[order] = sorted_along
    return along


def seen_whole(x: float, y: float) -> bool:
    """Whether the head camera sees a cube at (x, y) m whole, with the bounds the scene
    generator keeps a cube's landing place in (:func:`_placeable`)."""
    return (
        x >= 0.10 + 0.6 * max(0.0, y + 0.05) + 0.8 * max(0.0, -0.2 - y)
        and x <= 0.37
        and WORKSPACE_Y[0] - 0.03 <= y <= WORKSPACE_Y[1]
    )
