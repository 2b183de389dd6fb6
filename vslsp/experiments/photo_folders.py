"""Demonstrations as a user's camera sees them, made of photographs vslsp did not render
(docs/recordings.md, "Pictures vslsp did not render"): flat cards printed with photographs
that scikit-image ships (``skimage.data``: the astronaut, the coffee cup, the cat, the rocket,
the coins ...) lying on a table whose top is a photographed texture (brick, grass, gravel),
composed top-down in table metres with known poses and photographed through
:class:`~vslsp.experiments.photo_camera.UserCamera`: a tilted pinhole with lens distortion,
defocus and motion blur, sensor noise and JPEG.

The task: a chain of cards. Card 1 is put beside the anchor card, card 2 beside card 1 and so
on, each at an offset and a turn of its own relative to the card before it. The reproduction
starts from a new arrangement (the anchor elsewhere and turned, the loose cards shuffled). The
"robot" of :func:`closed_loop` is this module itself: it lifts the card at the answered pick,
lays it at the answered place turned by the answered turn, and photographs the table again.
The judge reads the ground truth: each card relative to its anchor against the demonstration's.

scikit-image is the ``photos`` extra; only this module imports it.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from vslsp.experiments.photo_camera import Look, TablePicture, UserCamera
from vslsp.geometry.poses import compose, relative, wrap
from vslsp.outputs import write_text
from vslsp.vision.image import write_image

X_RANGE, Y_RANGE = (-0.3, 1.0), (-0.8, 0.8)  # the table top (m), wider than the camera's view
TABLE_PX_PER_M = 1500.0  # the top-down composition's resolution (the camera's: about 1000 px/m)
WORKSPACE = {"x": [0.03, 0.67], "y": [-0.43, 0.43], "px_per_m": 1200.0, "z": 0.0}
SIZE = (1024, 768)
PHOTOGRAPHS = (
    "astronaut",
    "coffee",
    "chelsea",
    "rocket",
    "coins",
    "immunohistochemistry",
    "hubble_deep_field",
    "retina",
    "camera",
    "moon",
    "page",
    "cat",
    "colorwheel",
)  # skimage.data's clock is left out: most of it is a plain wall, and VSL asks objects with texture
TABLE_TEXTURES = ("brick", "grass", "gravel")
SPACING = 0.12  # m between the cards of the chain
BORDER = 0.004  # m of white paper around a card's photograph

Pose = tuple[float, float, float]  # x, y (m), yaw (rad) on the table
Ask = Callable[[Path], dict]


@dataclass(frozen=True, eq=False)
class Card:
    """A printed photograph (h, w, 3) uint8 lying flat; ``size`` (along, across) m."""

    name: str
    picture: np.ndarray
    size: tuple[float, float]


@dataclass(frozen=True, eq=False)
class PhotoTask:
    """One seed's world: the table's texture, the cards (the anchor first), the camera and its
    look, the demonstration's and the reproduction's first arrangements, and per operation the
    place of card k + 1 relative to card k (the anchor: card 0)."""

    table: np.ndarray
    cards: tuple[Card, ...]
    camera: UserCamera
    look: Look
    demonstration: dict[str, Pose]
    reproduction: dict[str, Pose]
    offsets: tuple[Pose, ...]

    @property
    def operations(self) -> int:
        return len(self.offsets)


def photo_task(seed: int, operations: int = 5) -> PhotoTask:
    """The world of ``seed``: a chain of ``operations`` cards beside an anchor card."""
    rng = np.random.default_rng(seed)
    photographs = _photographs()
    names = rng.choice(len(PHOTOGRAPHS), operations + 1, replace=False)
    cards = tuple(
        _card(PHOTOGRAPHS[i], photographs[PHOTOGRAPHS[i]], rng, label)
        for i, label in zip(names, ["anchor", *(f"card {k}" for k in range(1, operations + 1))])
    )
    texture = photographs[TABLE_TEXTURES[int(rng.integers(len(TABLE_TEXTURES)))]]
    camera = UserCamera.looking_at(
        (0.35, float(rng.uniform(-0.03, 0.03))),
        float(rng.uniform(0.95, 1.05)),
        float(rng.uniform(10.0, 20.0)),
        float(rng.uniform(0.0, 360.0)),
        float(rng.uniform(940.0, 1000.0)),
        SIZE,
        (float(rng.uniform(-0.18, -0.05)), float(rng.uniform(0.0, 0.05)), 0.0, 0.0, 0.0),
        (float(rng.uniform(-10, 10)), float(rng.uniform(-10, 10))),
    )
    look = Look(
        float(rng.uniform(0.5, 1.1)),
        float(rng.uniform(0.0, 2.5)),
        float(rng.uniform(0.0, 180.0)),
        float(rng.uniform(1.5, 3.5)),
        int(rng.integers(80, 93)),
    )
    # each card's yaw within 12 deg of the anchor's, so that the chain stays on the table
    yaws = np.radians(np.concatenate([[0.0], rng.uniform(-12.0, 12.0, operations)]))
    offsets = tuple(
        (float(rng.uniform(-0.015, 0.015)), SPACING, float(yaws[k + 1] - yaws[k])) for k in range(operations)
    )
    return PhotoTask(
        _table(texture, rng),
        cards,
        camera,
        look,
        _arrangement(cards, rng, (0.45, -0.34), 0.0),
        _arrangement(cards, rng, (float(rng.uniform(0.42, 0.5)), float(rng.uniform(-0.37, -0.3))), 8.0),
        offsets,
    )


def _photographs() -> dict[str, np.ndarray]:
    import skimage.data  # the photos extra

    found = {}
    for name in PHOTOGRAPHS + TABLE_TEXTURES:
        image = np.asarray(getattr(skimage.data, name)())
        if image.ndim == 2:
            image = np.repeat(image[..., None], 3, axis=2)
        found[name] = np.ascontiguousarray(image[..., :3]).astype(np.uint8)
    return found


def _card(name: str, photograph: np.ndarray, rng: np.random.Generator, label: str) -> Card:
    """A card printed with a crop of ``photograph`` (between 8 and 10 cm by 6.5 and 8 cm)."""
    along, across = float(rng.uniform(0.08, 0.10)), float(rng.uniform(0.065, 0.08))
    height, width = photograph.shape[:2]
    share = rng.uniform(0.6, 0.9)
    crop_w = int(width * share)
    crop_h = min(height, int(crop_w * across / along))
    left, top = int(rng.integers(0, width - crop_w + 1)), int(rng.integers(0, height - crop_h + 1))
    side = (int(round(along * TABLE_PX_PER_M)), int(round(across * TABLE_PX_PER_M)))
    edge = int(round(BORDER * TABLE_PX_PER_M))
    paper = np.full((side[1], side[0], 3), 245, np.uint8)
    paper[edge:-edge, edge:-edge] = cv2.resize(
        photograph[top : top + crop_h, left : left + crop_w],
        (side[0] - 2 * edge, side[1] - 2 * edge),
        interpolation=cv2.INTER_AREA,
    )
    return Card(f"{label} ({name})", paper, (along, across))


def _table(texture: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """The table top (h, w, 3): a photographed texture at low contrast on a wood colour. A real
    table top does not repeat itself: three copies of the texture, each mirrored out to the
    table's size at its own scale and turn, are averaged (a single tiling would repeat it,
    and SIFT would find a place's surroundings again one tile away)."""
    width = int(round((X_RANGE[1] - X_RANGE[0]) * TABLE_PX_PER_M))  # columns run along x, rows along y
    height = int(round((Y_RANGE[1] - Y_RANGE[0]) * TABLE_PX_PER_M))
    grey = cv2.cvtColor(texture, cv2.COLOR_RGB2GRAY).astype(np.float32)
    layers = []
    for scale in (1.7, 2.3, 3.1):
        turn = cv2.getRotationMatrix2D((width / 2.0, height / 2.0), float(rng.uniform(0.0, 360.0)), scale)
        turn[:, 2] += [width / 2.0 - grey.shape[1] / 2.0, height / 2.0 - grey.shape[0] / 2.0]
        layer = cv2.warpAffine(grey, turn, (width, height), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT)
        layers.append(layer - layer.mean())
    grain = np.mean(layers, axis=0)
    grain *= 40.0 / max(float(grain.std()), 1e-6)  # the grain's contrast: grey levels (one sigma)
    colour = np.array([rng.uniform(140, 175), rng.uniform(105, 130), rng.uniform(70, 90)], np.float32)
    return np.clip(colour + 0.35 * grain[..., None], 0, 255).astype(np.uint8)


def _arrangement(
    cards: tuple[Card, ...], rng: np.random.Generator, anchor_at: tuple[float, float], turn_deg: float
) -> dict[str, Pose]:
    """The anchor at ``anchor_at`` turned up to ``turn_deg`` either way; the loose cards shuffled
    along the near side of the table."""
    poses = {cards[0].name: (anchor_at[0], anchor_at[1], float(np.radians(rng.uniform(-turn_deg, turn_deg))))}
    slots = rng.permutation(len(cards) - 1)
    for card, slot in zip(cards[1:], slots):
        y = -0.36 + slot * (0.72 / max(len(cards) - 2, 1)) + rng.uniform(-0.01, 0.01)
        poses[card.name] = (float(rng.uniform(0.12, 0.16)), float(y), float(rng.uniform(-np.pi, np.pi)))
    return poses


def compose_table(task: PhotoTask, poses: dict[str, Pose]) -> TablePicture:
    """The table top seen straight from above with the cards at ``poses`` (the others away)."""
    plate = task.table.copy()
    s = TABLE_PX_PER_M
    for card in task.cards:
        if card.name not in poses:
            continue
        x, y, yaw = poses[card.name]
        h, w = card.picture.shape[:2]
        # the card's pixel q -> the plate's (col = (x - x0) s, row = (y - y0) s): turned by its
        # yaw about its centre, its long side (the picture's rows) along the yaw
        turn = np.array([[np.cos(yaw), -np.sin(yaw)], [np.sin(yaw), np.cos(yaw)]])
        centre = np.array([(x - X_RANGE[0]) * s, (y - Y_RANGE[0]) * s])
        reach = int(np.ceil(np.hypot(w, h) / 2.0)) + 2  # the plate's part the card may cover
        left, top = int(centre[0]) - reach, int(centre[1]) - reach
        affine = np.hstack([turn, (centre - [left, top] - turn @ np.array([(w - 1) / 2.0, (h - 1) / 2.0]))[:, None]])
        size = (2 * reach, 2 * reach)
        layer = cv2.warpAffine(card.picture, affine, size, flags=cv2.INTER_LINEAR).astype(np.float32)
        mask = cv2.warpAffine(np.ones((h, w), np.float32), affine, size, flags=cv2.INTER_LINEAR)[..., None]
        under = plate[top : top + size[1], left : left + size[0]].astype(np.float32)
        plate[top : top + size[1], left : left + size[0]] = np.rint(under * (1.0 - mask) + layer * mask).astype(
            np.uint8
        )
    return TablePicture(plate, (X_RANGE[0], Y_RANGE[0]), s)


@dataclass(frozen=True)
class Goal:
    """The ground truth of a demonstration: per operation the card moved, its anchor (the card
    before it in the chain) and its pose relative to the anchor afterwards (x, y, yaw)."""

    items: tuple[str, ...]
    anchors: tuple[str, ...]
    relative: tuple[Pose, ...]


def photograph(task: PhotoTask, poses: dict[str, Pose], rng: np.random.Generator) -> np.ndarray:
    """The camera's picture (H, W, 3) of the table with the cards at ``poses``."""
    return task.camera.photograph(compose_table(task, poses), task.look, rng)


def write_recording(task: PhotoTask, seed: int, folder: str | Path) -> Goal:
    """The tutor's demonstration photographed into ``folder`` (created) the documented way:
    ``NN-pre.jpg`` (operation 1), ``NN-mid.jpg``, ``NN-post.jpg``, ``calibration.json``,
    ``names.json``; the goal, on the ground truth."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng([seed, 1])
    poses = dict(task.demonstration)
    calibration = {**task.camera.calibration(), "workspace": WORKSPACE}
    write_text(folder / "calibration.json", json.dumps(calibration, indent=2) + "\n")
    write_image(folder / "01-pre.jpg", photograph(task, poses, rng))
    items, anchors = [], []
    for k, offset in enumerate(task.offsets, start=1):
        card, anchor = task.cards[k].name, task.cards[k - 1].name
        del poses[card]  # in the tutor's hand, out of view
        write_image(folder / f"{k:02d}-mid.jpg", photograph(task, poses, rng))
        poses[card] = compose(poses[anchor], offset)
        write_image(folder / f"{k:02d}-post.jpg", photograph(task, poses, rng))
        items.append(card)
        anchors.append(anchor)
    write_text(folder / "names.json", json.dumps(items) + "\n")
    return Goal(tuple(items), tuple(anchors), task.offsets)


def closed_loop(task: PhotoTask, seed: int, goal: Goal, folder: str | Path, ask: Ask, limit: int = 20) -> list[dict]:
    """The reproduction from the task's new arrangement driven by the answers of ``ask``: the
    table photographed into ``folder`` (``scene-NN.jpg``); each answer executed by lifting the
    card nearest the answered pick and laying it at the answered place, turned by the answered
    turn; until the answer is done (at most ``limit`` questions). Returns per answered operation
    its errors against the goal just after it (ground truth): position (m), angle (deg); a
    question that got an error ends the loop with ``{"error": ...}`` as the last entry."""
    folder = Path(folder)
    rng = np.random.default_rng([seed, 2])
    poses = dict(task.reproduction)
    done: list[dict] = []
    for n in range(1, limit + 1):
        scene = folder / f"scene-{n:02d}.jpg"
        write_image(scene, photograph(task, poses, rng))
        answer = ask(scene)
        if "error" in answer:
            done.append({"error": f"{scene}: {answer['error']}"})
            break
        if answer.get("done"):
            break
        pick, place = answer["pick"]["table_m"], answer["place"]["table_m"]
        card = min(poses, key=lambda name: np.hypot(poses[name][0] - pick[0], poses[name][1] - pick[1]))
        x, y, yaw = poses.pop(card)
        poses[card] = (place[0], place[1], float(wrap(yaw + answer["turn_rad"])))
        k = answer["operation"] - 1
        done.append({"operation": k + 1, "moved": card, **placement_errors(poses, goal, k)})
    return done


def placement_errors(poses: dict[str, Pose], goal: Goal, k: int) -> dict:
    """Operation ``k``'s card against its demonstrated pose relative to its anchor (ground truth)."""
    item, anchor = goal.items[k], goal.anchors[k]
    if item not in poses or anchor not in poses:
        return {"item": item, "position_error_m": float("inf"), "angle_error_deg": 180.0}
    now, wanted = relative(poses[anchor], poses[item]), goal.relative[k]
    return {
        "item": item,
        "position_error_m": round(float(np.hypot(now[0] - wanted[0], now[1] - wanted[1])), 4),
        "angle_error_deg": round(float(np.degrees(abs(wrap(now[2] - wanted[2])))), 2),
    }
