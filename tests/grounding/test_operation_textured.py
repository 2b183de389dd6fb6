"""Grounding on textured cubes (the iCub's cubes carry seeded confetti in shades of their colour,
vslsp.sim.textures): `far`, the colour symbol and the change between two observations must be
found as on plain cubes, on synthetic images (the truth known exactly) and on rendered scenes."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from vslsp.grounding.operation import ground, ground_scene
from vslsp.grounding.synthetic import PAINTS, Square, tabletop_image
from vslsp.sim import COLOURS, LineWorld
from vslsp.sim.textures import cube_face
from vslsp.vision.colour import colour_name

LINE = ((0, 300), (640, 260))  # far is above it in the image (the robot is at the bottom)


def textured_image(squares: list[Square], seed: int, line=LINE) -> np.ndarray:
    """:func:`tabletop_image` with every square's face covered by its cube texture (the same
    shading: the texture's shades times the square's shaded paint over its plain paint)."""
    plain = tabletop_image(squares, line=line, noise=0, seed=seed).astype(np.float32)
    image = plain.copy()
    for k, square in enumerate(squares):
        paint = np.array(PAINTS[square.colour], np.float32)
        face = cube_face(tuple(paint / 255.0), f"{square.colour}/{k}").astype(np.float32)
        corners = cv2.boxPoints((square.centre, (square.side, square.side), square.angle)).astype(np.float32)
        size = face.shape[0]
        source = np.float32([[0, size], [0, 0], [size, 0]])
        warp = cv2.getAffineTransform(source, corners[:3])
        drawn = cv2.warpAffine(
            face / np.maximum(paint, 1.0),
            warp,
            (image.shape[1], image.shape[0]),
            flags=cv2.INTER_LINEAR,
            borderValue=(1.0, 1.0, 1.0),
        )
        mask = np.zeros(image.shape[:2], np.uint8)
        cv2.fillConvexPoly(mask, np.round(corners).astype(np.int32), 1)
        inside = mask.astype(bool)
        image[inside] = plain[inside] * drawn[inside]
    rng = np.random.default_rng(seed)
    return np.clip(np.round(image + rng.normal(0.0, 4.0, image.shape)), 0, 255).astype(np.uint8)


STILL = Square("blue", (500, 420), angle=20)


@pytest.mark.parametrize(
    "before, after, far, action",
    [
        ((200, 400), (210, 150), (False, True), "push"),
        ((200, 150), (230, 400), (True, False), "pull"),
        ((200, 150), (400, 120), (True, True), None),
        ((120, 420), (320, 400), (False, False), None),
    ],
)
@pytest.mark.parametrize("colour", ["red", "orange", "yellow", "green", "purple"])
def test_textured_push_pull_and_null_are_grounded(before, after, far, action, colour):
    pre = textured_image([Square(colour, before), STILL], seed=1)
    post = textured_image([Square(colour, after, angle=12), STILL], seed=2)
    grounding = ground(pre, post)
    assert grounding.name == colour
    assert (grounding.far_pre, grounding.far_post) == far
    assert grounding.action == action
    # the pale confetti leave small holes in the object mask: the centroid moves by up to ~3 px
    # (1.5 px on plain squares, tests/vsl/test_grounding.py), far from deciding which side it is on
    assert np.hypot(*np.subtract(grounding.pre, before)) < 3.5
    assert np.hypot(*np.subtract(grounding.post, after)) < 3.5


def test_every_textured_object_of_one_observation_is_grounded():
    squares = [
        Square("red", (100, 150)),
        Square("orange", (300, 420), angle=30),
        Square("green", (520, 120)),
        Square("purple", (420, 400), angle=-15),
        Square("yellow", (250, 140), angle=40),
    ]
    scene = ground_scene(textured_image(squares, seed=3), robot_side="bottom")
    assert scene.far_by_name() == {"red": True, "orange": False, "green": True, "purple": False, "yellow": True}


@pytest.mark.parametrize("colour", sorted(COLOURS))
def test_every_shade_of_a_texture_keeps_the_colour_name(colour):
    face = cube_face(COLOURS[colour], f"{colour}/face0")
    assert colour_name(face.reshape(-1, 3)) == colour
    # lit and shaded faces of a rendered cube: brightness scaled, the name unchanged
    for light in (0.6, 0.85):
        assert colour_name(np.round(face * light).astype(np.uint8).reshape(-1, 3)) == colour


@pytest.mark.slow
def test_rendered_textured_and_plain_cubes_ground_alike():
    """The same scenes and tutor moves, rendered with plain and with textured cubes: the
    groundings agree with the simulator's truth (and so with each other)."""
    rng = np.random.default_rng(7)
    checked = 0
    for seed in range(4):
        moves = [int(rng.integers(3)) for _ in range(3)]
        for textured in (False, True):
            with LineWorld(seed=seed, robot=False, textured=textured) as world:
                pre = world.observe("head").rgb
                for index in moves:  # the tutor takes the cube across the line
                    cube = world.spec.cubes[index]
                    landmark = world.spec.landmark
                    x, y, _ = world.cube_pose(cube.name)
                    side = landmark.signed_distance((x, y))
                    far_before = world.is_far(cube.name)
                    target = np.array([x, y]) + ((-0.06 if far_before else 0.06) - side) * landmark.normal
                    world.tutor.relocate(cube.name, float(target[0]), float(target[1]))
                    post = world.observe("head").rgb
                    g = ground(pre, post, robot_side="bottom")
                    far_after = world.is_far(cube.name)
                    action = None if far_before == far_after else ("push" if far_after else "pull")
                    assert (g.name, g.far_pre, g.far_post, g.action) == (cube.colour, far_before, far_after, action)
                    scene = ground_scene(post, robot_side="bottom")
                    assert scene.far_by_name() == {c.colour: world.is_far(c.name) for c in world.spec.cubes}
                    pre = post
                    checked += 1
    assert checked == 24


def test_a_texture_mark_beside_the_line_is_no_object_of_its_own():
    """The purple cube of keep-all-near's exploration at seed 1084 (with faults): a pink mark of
    its texture touches the landmark line and once made a second, unnamed object, which the
    robot then tried to push (the trial failed: "exploring push on object ... observed nothing")."""
    from vslsp.experiments.seeds import exploration_seed
    from vslsp.worlds.icub import line_layout

    with LineWorld(
        line_layout(exploration_seed(1084, 0), ("purple",), (False,))
    ) as world:  # the head camera on the robot
        grounding = ground_scene(world.observe("head").rgb, robot_side="bottom")
    assert grounding.far_by_name() == {"purple": False}
