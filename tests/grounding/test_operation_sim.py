"""Grounding on rendered scenes, checked against the simulator's ground truth (perception
itself only sees the images): 240 random pre-/post-action pairs over both cameras, random
line poses, cube colours and positions, two image sizes, and worlds with and without the iCub."""

from __future__ import annotations

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.grounding.operation import ground
from vslsp.sim import COLOURS, CubeSpec, LandmarkSpec, LineWorld, SceneSpec
from vslsp.sim.scene import WORKSPACE_X, WORKSPACE_Y

WORLDS, MOVES = 12, 10  # x 2 cameras = 240 pairs
MARGIN = 0.035  # cubes stay this far (m) from the line: a cube 5 cm wide is not "on" it
SPACING = 0.075  # between cube centres (m)
MIN_MOVE = 0.03  # a tutor's operation moves the cube at least this far (m)


def _place(
    rng, landmark: LandmarkSpec, others: list[np.ndarray], far: bool, start: np.ndarray | None = None
) -> np.ndarray:
    """A free cube position on the ``far`` side of the line (the other side if it is full)."""
    for side in (far, not far):
        for _ in range(500):
            along, across = rng.uniform(-0.14, 0.14), rng.uniform(MARGIN, 0.09) * (1.0 if side else -1.0)
            xy = landmark.point + along * landmark.direction + across * landmark.normal
            inside = WORKSPACE_X[0] <= xy[0] <= WORKSPACE_X[1] and WORKSPACE_Y[0] <= xy[1] <= WORKSPACE_Y[1]
            moved = start is None or np.linalg.norm(xy - start) >= MIN_MOVE
            if inside and moved and all(np.linalg.norm(xy - other) >= SPACING for other in others):
                return xy
    raise RuntimeError("no free place; the sampler needs fewer cubes")


def _random_scene(rng) -> SceneSpec:
    landmark = LandmarkSpec(x=float(rng.uniform(0.21, 0.24)), angle=float(rng.uniform(-0.3, 0.3)))
    colours = rng.choice(sorted(COLOURS), size=int(rng.integers(2, 4)), replace=False)
    places: list[np.ndarray] = []
    for _ in colours:
        places.append(_place(rng, landmark, places, bool(rng.random() < 0.5)))
    cubes = tuple(
        CubeSpec(str(c), str(c), float(x), float(y), float(rng.uniform(-0.5, 0.5)))
        for c, (x, y) in zip(colours, places, strict=True)
    )
    return SceneSpec(cubes=cubes, landmark=landmark)


@pytest.mark.slow
def test_rendered_pairs_are_grounded_as_the_simulator_says():
    rng = np.random.default_rng(2024)
    outcomes, failures = 0, []
    for w in range(WORLDS):
        spec = _random_scene(rng)
        size = (640, 480) if w % 2 == 0 else (320, 240)
        with LineWorld(spec, robot=(w % 6 == 0)) as world:
            images = {camera: world.observe(camera, *size).rgb for camera in ("head", "overhead")}
            for _ in range(MOVES):
                cube = spec.cubes[int(rng.integers(len(spec.cubes)))]
                far_before = world.is_far(cube.name)
                others = [np.array(world.cube_pose(c.name)[:2]) for c in spec.cubes if c.name != cube.name]
                start = np.array(world.cube_pose(cube.name)[:2])
                target = _place(rng, spec.landmark, others, bool(rng.random() < 0.5), start)
                world.tutor.relocate(cube.name, float(target[0]), float(target[1]), yaw=float(rng.uniform(-0.6, 0.6)))
                far_after = world.is_far(cube.name)
                truth = (
                    cube.colour,
                    far_before,
                    far_after,
                    None if far_before == far_after else ("push" if far_after else "pull"),
                )
                for camera in ("head", "overhead"):
                    post = world.observe(camera, *size).rgb
                    outcomes += 1
                    try:
                        g = ground(images[camera], post, robot_side="bottom")
                    except InputError as error:
                        failures.append((w, camera, size, truth, str(error)))
                    else:
                        if (g.name, g.far_pre, g.far_post, g.action) != truth:
                            failures.append((w, camera, size, truth, g.to_dict()))
                    images[camera] = post
    assert outcomes >= 200
    assert len(failures) <= 0.01 * outcomes, failures
