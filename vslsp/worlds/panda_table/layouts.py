"""The objects, landmarks and randomised layouts of the five real-world VSL tasks (paper,
"Real-world Experiments", Table 1), in the tabletop world's frame (:mod:`vslsp.sim.tabletop`:
x away from the robot, y to its left, metres).

Objects are boxes whose top faces carry the procedural textures of :mod:`vslsp.worlds.panda_table.textures`;
they are narrower across one side than along the other where the task packs them side by side,
so the gripper closes across that side with room for its fingers. Landmarks are static thin
plates. Random layouts scatter objects over :data:`SCATTER_X` × :data:`SCATTER_Y` without
overlap and with room for the fingers around each; items the tutor holds lie on the table's far
strip (:data:`HOLD_X`), outside the camera's image.
"""

from __future__ import annotations

import numpy as np

from vslsp.geometry.poses import compose, relative  # noqa: F401  (poses (x, y, yaw) in the table frame)
from vslsp.sim.tabletop import Item, Placement
from vslsp.worlds.panda_table import textures

SCATTER_X = (0.33, 0.54)  # where objects lie at random: in reach, in view, clear of the goal areas
SCATTER_Y = (-0.28, 0.28)
HOLD_X = 0.95  # the tutor's hand: beyond the image's top edge (the table ends at x = 1.0)
HOLD_Y = tuple(float(y) for y in np.linspace(-0.5, 0.5, 9))
CLEARANCE = 0.045  # free table between scattered objects (fingers and frames)

Pose = tuple[float, float, float]  # x, y (m), yaw (rad)


def _item(name: str, size: tuple[float, float, float], texture: np.ndarray, movable: bool = True) -> Item:
    return Item(name, size, texture, movable)


# -- objects and landmarks ----------------------------------------------------------------------
LETTER = (0.04, 0.055, 0.03)  # letter blocks: closed across x, side by side along y
PIECE = (0.055, 0.04, 0.02)  # puzzle pieces: two halves end to end along x, closed across y
PICTURE = (0.055, 0.045, 0.02)  # animal and machine cards
DOMINO = (0.07, 0.035, 0.015)  # picture-domino pieces: end to end along x
DISKS = {1: (0.06, 0.045, 0.035), 2: (0.075, 0.045, 0.035), 3: (0.09, 0.045, 0.035)}  # thick: fingers hold one
PLATE = 0.004  # the thickness of landmark plates


def letters() -> list[Item]:
    return [_item(letter, LETTER, textures.letter_tile(letter, LETTER[:2])) for letter in "ABCD"]


def baseline_arms() -> list[tuple[Item, Placement]]:
    """The static right-angle baseline: a long ruler along y at the far side and a short one
    along x on the robot's left, meeting at the corner where the letters start."""
    long, short = (0.025, 0.34, PLATE), (0.2, 0.025, PLATE)
    return [
        (_item("baseline-long", long, textures.baseline(long[:2], "long"), False), Placement(0.6775, 0.0)),
        (_item("baseline-short", short, textures.baseline(short[:2], "short"), False), Placement(0.565, 0.1825)),
    ]


LETTER_GOALS = {letter: (0.635, 0.13 - 0.07 * k, 0.0) for k, letter in enumerate("ABCD")}  # row by the baseline


def puzzle_pieces() -> list[Item]:
    return [
        _item(f"{animal}-{part}", PIECE, textures.puzzle_piece(animal, part, PIECE[:2]))
        for animal in ("frog", "giraffe")
        for part in (0, 1)
    ]


LABEL = (0.15, 0.09, PLATE)
LABEL_OF = {"frog": "pond", "giraffe": "tree"}
ON_LABEL = {0: (-0.032, 0.02, 0.0), 1: (0.032, 0.02, 0.0)}  # on its label (label frame), 9 mm apart


def labels() -> list[Item]:
    return [_item(word, LABEL, textures.label(word, LABEL[:2]), False) for word in ("pond", "tree")]


def hanoi_disks() -> list[Item]:
    return [_item(f"disk-{k}", size, textures.hanoi_disk(k, size[:2])) for k, size in DISKS.items()]


BASE = (0.12, 0.12, 0.01)
BASE_POSES = {1: (0.53, 0.24, 0.0), 2: (0.53, 0.0, 0.0), 3: (0.53, -0.24, 0.0)}  # apart: a pre-place frame sees one


def hanoi_bases() -> list[tuple[Item, Placement]]:
    return [
        (_item(f"base-{k}", BASE, textures.hanoi_base(BASE[:2]), False), Placement(*pose))
        for k, pose in BASE_POSES.items()
    ]


def hanoi_moves(disks: int = 3, source: int = 1, target: int = 2, spare: int = 3) -> list[tuple[int, int]]:
    """The shortest solution of the Tower of Hanoi: (disk, base it goes to) per move."""
    if disks == 0:
        return []
    return (
        hanoi_moves(disks - 1, source, spare, target)
        + [(disks, target)]
        + hanoi_moves(disks - 1, spare, target, source)
    )


SUBJECTS = tuple(textures.PICTURES)  # cat, fish (animals), car, gear (machines)
BIN = (0.2, 0.13, 0.006)
BIN_POSES = {"animals": (0.6, 0.15, 0.0), "machines": (0.6, -0.15, 0.0)}
BIN_SLOTS = ((-0.045, 0.0, 0.0), (0.045, 0.0, 0.0))  # where the tutor puts the first and second card


def pictures() -> list[Item]:
    return [_item(subject, PICTURE, textures.picture(subject, PICTURE[:2])) for subject in SUBJECTS]


def bins() -> list[tuple[Item, Placement]]:
    return [
        (_item(f"bin-{word}", BIN, textures.bin_plate(word, BIN[:2]), False), Placement(*pose))
        for word, pose in BIN_POSES.items()
    ]


DOMINOES = 5
DOMINO_NEXT = (DOMINO[0] + 0.002, 0.0, 0.0)  # the next piece, end to end (previous piece's frame)
DOMINO_START = (0.63, 0.16, -np.pi / 2.0)  # the tutor's first piece in the demonstration: chain runs along -y


def domino_pieces() -> list[Item]:
    return [_item(f"domino-{k}", DOMINO, textures.domino_piece(k, DOMINO[:2])) for k in range(1, DOMINOES + 1)]


# -- layouts --------------------------------------------------------------------------------------
def scatter(
    rng: np.random.Generator,
    items: list[Item],
    taken: list[tuple[float, float, float]] | None = None,
    region: tuple[tuple[float, float], tuple[float, float]] = (SCATTER_X, SCATTER_Y),
) -> list[Placement]:
    """Random placements (any yaw) of ``items`` in ``region`` ((x0, x1), (y0, y1)), apart from
    each other and from the ``taken`` discs (x, y, radius) by :data:`CLEARANCE`."""
    discs = list(taken or [])
    placements = []
    for item in items:
        radius = float(np.hypot(item.size[0], item.size[1])) / 2.0
        for _ in range(2000):
            x, y = rng.uniform(*region[0]), rng.uniform(*region[1])
            if all(np.hypot(x - dx, y - dy) >= radius + dr + CLEARANCE for dx, dy, dr in discs):
                break
        else:
            raise RuntimeError(f"no free place for {item.name!r} in the scatter region")  # a layout bug, not input
        discs.append((x, y, radius))
        placements.append(Placement(float(x), float(y), float(rng.uniform(-np.pi, np.pi))))
    return placements


def disc(item: Item, pose: Pose) -> tuple[float, float, float]:
    """The disc (x, y, radius) an item at ``pose`` covers."""
    return pose[0], pose[1], float(np.hypot(item.size[0], item.size[1])) / 2.0


def hold_placement(slot: int) -> Placement:
    """The tutor's hand: the ``slot``-th place on the far strip, outside the image."""
    return Placement(HOLD_X, HOLD_Y[slot % len(HOLD_Y)], 0.0)
