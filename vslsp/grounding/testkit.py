"""The grounding test kit: image pairs whose truth is known, and :func:`assert_grounds`.

Paper, VSL-SP "Implementation": the robot grounds symbols from pre- and post-action images of
a tabletop with coloured cubes and a black borderline. To unit-test a user's predicates, the kit
builds such pairs with the truth of every object known exactly:

- :func:`synthetic_pair`: tabletops drawn with OpenCV (:mod:`vslsp.grounding.synthetic`),
  squares at given pixel places, one of them moved;
- :func:`rendered_pair`: the pybullet scene of a :class:`~vslsp.sim.SceneSpec` seen by a
  camera, one cube moved by the tutor, the truth from the simulator projected into the image.

Each is a :class:`Pair`: the images and the true :class:`~vslsp.grounding.Scene` before and
after, on which predicates give the true atoms (:meth:`Pair.atoms`). :func:`assert_grounds`
grounds a pair as ``vslsp ground --predicates`` does and compares it with expected atoms; on a
difference it writes an overlay picture and names the missing and unexpected atoms.
"""

from __future__ import annotations

import re
import tempfile
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from vslsp.errors import InputError
from vslsp.grounding.loader import with_builtins
from vslsp.grounding.operation import Grounding, ground
from vslsp.grounding.overlay import draw_atoms
from vslsp.grounding.predicates import (
    Box,
    Landmark,
    Predicate,
    Scene,
    SceneObject,
    ground_atoms,
    registered,
    true_atoms,
)
from vslsp.grounding.synthetic import Square, tabletop_image
from vslsp.vision.colour import COLOUR_NAMES, GENERIC
from vslsp.vision.image import read_image, write_image
from vslsp.vision.landmark import Line

if TYPE_CHECKING:
    from vslsp.sim import SceneSpec

__all__ = ["Pair", "Square", "assert_grounds", "rendered_pair", "synthetic_pair", "tabletop_image"]

LINE = ((0.0, 300.0), (640.0, 260.0))  # the synthetic tabletop's default landmark (two points, px)


@dataclass(frozen=True, eq=False)
class Pair:
    """A pre-/post-action image pair (H, W, 3) uint8 RGB with the true scene before and after."""

    pre: np.ndarray
    post: np.ndarray
    truth_pre: Scene
    truth_post: Scene

    def atoms(self, predicates: Sequence[Predicate] | None = None) -> tuple[list[str], list[str]]:
        """The true atoms (PDDL syntax, sorted) before and after, decided on the truth, of the
        built-in ``far`` and ``predicates`` (by default ``far`` alone: the answer never depends on
        what other tests registered)."""
        chosen = with_builtins(predicates or ())
        return (true_atoms(ground_atoms(self.truth_pre, chosen)), true_atoms(ground_atoms(self.truth_post, chosen)))

    def save(self, folder: str | Path) -> tuple[Path, Path]:
        """Write ``pre.png`` and ``post.png`` into ``folder`` (for ``vslsp ground``); their paths."""
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        write_image(folder / "pre.png", self.pre)
        write_image(folder / "post.png", self.post)
        return folder / "pre.png", folder / "post.png"


def _predicates(predicates: Sequence[Predicate] | None, expected: Iterable[str]) -> tuple[Predicate, ...]:
    """``far`` and ``predicates``; without them, ``far`` and the registered predicates that the expected
    atoms name, so that a result depends only on the test itself, never on what other tests registered."""
    if predicates is not None:
        return with_builtins(predicates)
    named = {atom[1:-1].split()[0] for atom in expected}
    return with_builtins([p for p in registered() if p.name in named])


def _square_symbol(square: Square) -> str:
    return square.colour if isinstance(square.colour, str) and square.colour in COLOUR_NAMES else GENERIC


def _square_box(square: Square) -> Box:
    half = square.side / 2.0
    c, s = abs(np.cos(np.radians(square.angle))), abs(np.sin(np.radians(square.angle)))
    reach_x, reach_y = half * (c + s), half * (s + c)
    return Box(
        square.centre[0] - reach_x, square.centre[1] - reach_y, square.centre[0] + reach_x, square.centre[1] + reach_y
    )


def _scene(
    entries: Iterable[tuple[str, float, float, Box]], size: tuple[int, int], line: Line | None, robot_side: str
) -> Scene:
    """A true scene; objects named by symbol left to right (then top down), repeats suffixed
    (red, red_2) as perception names them."""
    objects: dict[str, SceneObject] = {}
    for symbol, x, y, box in sorted(entries, key=lambda e: (e[1], e[2])):
        name, k = symbol, 1
        while name in objects:
            k += 1
            name = f"{symbol}_{k}"
        objects[name] = SceneObject(name, float(x), float(y), box, box.area)
    return Scene(size[0], size[1], objects, Landmark(line, robot_side) if line is not None else None, robot_side)


def synthetic_pair(
    squares: Sequence[Square],
    move: tuple[int, tuple[float, float]],
    *,
    line: tuple[tuple[float, float], tuple[float, float]] | None = LINE,
    size: tuple[int, int] = (640, 480),
    noise: float = 2.0,
    seed: int = 0,
    robot_side: str = "bottom",
) -> Pair:
    """A drawn tabletop of ``size`` (W, H) px with ``squares``, and the same after the square of
    index ``move[0]`` was moved to the centre ``move[1]`` (x, y) px; ``line`` passes through two
    points (px); Gaussian sensor ``noise`` (grey levels, seeded)."""
    index, centre = move
    if not 0 <= index < len(squares):
        raise InputError(f"move names square {index}, but there are {len(squares)} squares")
    after = list(squares)
    after[index] = replace(after[index], centre=(float(centre[0]), float(centre[1])))
    pre = tabletop_image(list(squares), line, size, noise=noise, seed=seed)
    post = tabletop_image(after, line, size, noise=noise, seed=seed + 1)
    truth_line = None
    if line is not None:
        ends = sorted(((float(line[0][0]), float(line[0][1])), (float(line[1][0]), float(line[1][1]))))
        truth_line = Line(ends[0], ends[1])

    def truth(placed: Sequence[Square]) -> Scene:
        return _scene(
            ((_square_symbol(s), s.centre[0], s.centre[1], _square_box(s)) for s in placed),
            size,
            truth_line,
            robot_side,
        )

    return Pair(pre, post, truth(squares), truth(after))


def rendered_pair(
    spec: SceneSpec,
    move: tuple[str, tuple[float, float]],
    *,
    camera: str = "head",
    size: tuple[int, int] = (640, 480),
    robot: bool = False,
) -> Pair:
    """The pybullet scene of ``spec`` (a :class:`~vslsp.sim.SceneSpec`) seen by ``camera`` at
    ``size`` (W, H), before and after the tutor moved cube ``move[0]`` to ``move[1]`` (x, y) m
    on the table. The truth: each cube's centre (half-way up its visible faces) and its eight
    corners projected into the image, and the landmark line projected likewise."""
    from vslsp.sim import TABLE_Z, LineWorld

    name, (x, y) = move
    with LineWorld(spec, robot=robot) as world:
        view = world.camera(camera, *size)

        def observe() -> tuple[np.ndarray, Scene]:
            rgb = world.observe(camera, *size).rgb
            entries = []
            for cube in world.spec.cubes:
                cx, cy, yaw = world.cube_pose(cube.name)
                half, c, s = cube.size / 2.0, np.cos(yaw), np.sin(yaw)
                corners = np.array(
                    [
                        [cx + c * dx - s * dy, cy + s * dx + c * dy, TABLE_Z + dz]
                        for dx in (-half, half)
                        for dy in (-half, half)
                        for dz in (0.0, cube.size)
                    ]
                )
                pixels = view.project(corners)
                u, v = view.table_to_pixel(cx, cy, TABLE_Z + half)
                box = Box(*pixels.min(axis=0), *pixels.max(axis=0))
                entries.append((cube.colour, u, v, box))
            landmark = world.spec.landmark
            ends = sorted(view.table_to_pixel(*(landmark.point + t * landmark.direction)) for t in (-0.3, 0.3))
            line = Line(ends[0], ends[1])
            return rgb, _scene(entries, size, line, "bottom")

        pre, truth_pre = observe()
        world.tutor.relocate(name, float(x), float(y))
        post, truth_post = observe()
    return Pair(pre, post, truth_pre, truth_post)


_ATOM = re.compile(r"^\(\s*([^\s()]+)((?:\s+[^\s()]+)*)\s*\)$")


def _normal(atom: str) -> str:
    match = _ATOM.match(atom.strip())
    if match is None:
        raise InputError(f"expected atom {atom!r} is not a PDDL atom like '(left-of red green)'")
    return f"({' '.join([match.group(1).lower(), *match.group(2).lower().split()])})"


def _image(image: np.ndarray | str | Path, what: str) -> np.ndarray:
    return read_image(image, what) if isinstance(image, (str, Path)) else image


def assert_grounds(
    pre: np.ndarray | str | Path,
    post: np.ndarray | str | Path,
    *,
    atoms_pre: Iterable[str] | None = None,
    atoms_post: Iterable[str] | None = None,
    predicates: Sequence[Predicate] | None = None,
    robot_side: str = "bottom",
    overlay_dir: str | Path | None = None,
) -> Grounding:
    """Ground the pair (images (H, W, 3) uint8 RGB or file paths) as ``vslsp ground --predicates``
    does, and check that exactly ``atoms_pre`` / ``atoms_post`` (PDDL syntax) hold before / after
    (None: not checked). ``pre`` and ``post`` may be paths of PNG or JPEG files. ``predicates``: the
    predicates to ground with the built-in ``far``; by default ``far`` and the registered predicates
    the expected atoms name (never others, so that the result does not depend on test order).

    On a difference, raises AssertionError naming the missing and the unexpected atoms, every atom
    grounded, and the overlay picture written to ``overlay_dir`` (a fresh temporary folder by
    default); the kit's own frames are hidden from pytest's report. Returns the grounding.
    """
    __tracebackhide__ = True  # pytest shows the test's line, not the kit's source
    expected_atoms = [_normal(a) for a in [*(atoms_pre or ()), *(atoms_post or ())]]
    chosen = _predicates(predicates, expected_atoms)
    names = {p.name for p in chosen}
    pre_image, post_image = _image(pre, "pre-action image"), _image(post, "post-action image")
    grounding = ground(pre_image, post_image, robot_side=robot_side, predicates=chosen)
    report, notes = [], []
    for side, expected, values in (("pre", atoms_pre, grounding.atoms_pre), ("post", atoms_post, grounding.atoms_post)):
        got = set(true_atoms(values or {}))
        if expected is None:
            notes.append(sorted(got))
            continue
        wanted = {_normal(a) for a in expected}
        unknown = sorted(a for a in wanted if a[1:-1].split()[0] not in names)
        if unknown:
            raise InputError(
                f"expected {side} atoms {', '.join(unknown)} name no grounded predicate "
                f"(grounded: {', '.join(sorted(names))}); register it or pass it in predicates="
            )
        missing, unexpected = sorted(wanted - got), sorted(got - wanted)
        if missing or unexpected:
            report.append(
                f"{side}: missing {' '.join(missing) or 'none'}; unexpected {' '.join(unexpected) or 'none'}\n"
                f"    grounded {side}: {' '.join(sorted(got)) or '(none true)'}"
            )
        notes.append(
            [f"missing {a}" for a in missing]
            + [f"unexpected {a}" for a in unexpected]
            + [a for a in sorted(got) if a not in unexpected]
        )
    if report:
        folder = Path(overlay_dir) if overlay_dir is not None else Path(tempfile.mkdtemp(prefix="vslsp-grounding-"))
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / "grounding.png"
        k = 1
        while path.exists():
            k += 1
            path = folder / f"grounding_{k}.png"
        write_image(path, draw_atoms(pre_image, post_image, grounding, (notes[0], notes[1])))
        seen = ", ".join(
            f"{n} at ({o.x:.0f}, {o.y:.0f})"
            for n, o in (grounding.scene_pre.objects.items() if grounding.scene_pre else ())
        )
        raise AssertionError(
            "grounding differs from the expected atoms\n  "
            + "\n  ".join(report)
            + f"\n  objects seen before: {seen or 'none'}\n  overlay: {path}"
        )
    return grounding
