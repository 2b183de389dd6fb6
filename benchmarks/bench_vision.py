"""Perception benchmark (issue 3): ms per grounding of a pre-/post-action pair at 640x480 and
1280x960, ms per single-image scene grounding, ms per match finding, and grounding accuracy as
image noise grows (sigma = 0, 5, 10, 20 grey levels). Target: <= 10 ms per grounding at 640x480.

Inputs are rendered in the simulator (vslsp.sim LineWorld.observe, head and overhead cameras); the
truth (colour, far before and after, action) comes from the simulator, perception only sees
the images. References measured in the same run on the same images: a plain OpenCV change
detector (grey absdiff, threshold, opening, largest contour at full size: the least any
grounding does) and SIFT on the whole image (what match finding starts from).

Run: .venv/bin/python benchmarks/bench_vision.py [--worlds N]
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import dataclass

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.grounding.operation import Grounding, ground, ground_scene
from vslsp.sim import LineWorld, SceneSpec
from vslsp.sim.scene import TABLE_Z, WORKSPACE_X, WORKSPACE_Y
from vslsp.vision.features import sift
from vslsp.vision.matching import find_best_match
from vslsp.worlds.house_roof.sprites import BODY_SIZE, houses_world

SIZES = ((640, 480), (1280, 960))
CAMERAS = ("head", "overhead")
NOISE = (0, 5, 10, 20)
TARGET_MS = 10.0
_KERNEL = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (3, 3))


@dataclass(frozen=True)
class Pair:
    """A rendered operation: images (H, W, 3) uint8 and the simulator's truth."""

    camera: str
    pre: np.ndarray
    post: np.ndarray
    truth: tuple[str, bool, bool, str | None]  # colour, far pre, far post, action
    top_pre: tuple[float, float]  # overhead: pixel of the cube's top face centre, before/after
    top_post: tuple[float, float]
    yaw_change: float  # rad


def _scene(seed: int) -> SceneSpec:
    for n_cubes in (3, 2, 1):
        try:
            return SceneSpec.random(seed, n_cubes=n_cubes)
        except InputError:
            continue
    raise RuntimeError("no scene")


def _target(world: LineWorld, name: str, rng: np.random.Generator) -> np.ndarray | None:
    """Where a push / pull (across the line) or a null move (along it) takes the cube."""
    landmark = world.spec.landmark
    xy = np.array(world.cube_pose(name)[:2])
    others = [np.array(world.cube_pose(c)[:2]) for c in world.cubes if c != name]
    for _ in range(50):
        if rng.random() < 0.7:
            target = xy - landmark.signed_distance(xy) * (2.0 + rng.uniform(-0.3, 0.3)) * landmark.normal
        else:
            target = xy + rng.choice([-1.0, 1.0]) * rng.uniform(0.03, 0.06) * landmark.direction
        inside = WORKSPACE_X[0] <= target[0] <= WORKSPACE_X[1] and WORKSPACE_Y[0] - 0.02 <= target[1] <= WORKSPACE_Y[1]
        if inside and all(np.linalg.norm(target - other) > 0.07 for other in others):
            return target
    return None


def rendered_pairs(worlds: int, moves: int, size: tuple[int, int]) -> list[Pair]:
    """Operations rendered at ``size`` (W, H) by both cameras, ``moves`` per world."""
    rng = np.random.default_rng(size[0])
    pairs: list[Pair] = []
    for w in range(worlds):
        with LineWorld(_scene(w), robot=w % 2 == 0) as world:
            before = {camera: world.observe(camera, *size) for camera in CAMERAS}
            for _ in range(moves):
                name = world.spec.cubes[int(rng.integers(len(world.spec.cubes)))].name
                target = _target(world, name, rng)
                if target is None:
                    continue
                x0, y0, yaw0 = world.cube_pose(name)
                far_pre = world.is_far(name)
                world.tutor.relocate(name, float(target[0]), float(target[1]), yaw=yaw0 + float(rng.uniform(-0.5, 0.5)))
                x1, y1, yaw1 = world.cube_pose(name)
                far_post = world.is_far(name)
                action = None if far_pre == far_post else ("push" if far_post else "pull")
                top = TABLE_Z + world.spec.cube(name).size
                for camera in CAMERAS:
                    after = world.observe(camera, *size)
                    pairs.append(
                        Pair(
                            camera,
                            before[camera].rgb,
                            after.rgb,
                            (world.spec.cube(name).colour, far_pre, far_post, action),
                            after.camera.table_to_pixel(x0, y0, top),
                            after.camera.table_to_pixel(x1, y1, top),
                            yaw1 - yaw0,
                        )
                    )
                    before[camera] = after
    return pairs


def reference_change(pre: np.ndarray, post: np.ndarray) -> tuple[float, float] | None:
    """Plain OpenCV change detection: the centroid of the largest changed contour."""
    a = cv2.GaussianBlur(cv2.cvtColor(pre, cv2.COLOR_RGB2GRAY), (5, 5), 0)
    b = cv2.GaussianBlur(cv2.cvtColor(post, cv2.COLOR_RGB2GRAY), (5, 5), 0)
    _, mask = cv2.threshold(cv2.absdiff(a, b), 40, 255, cv2.THRESH_BINARY)
    mask = cv2.morphologyEx(mask, cv2.MORPH_OPEN, _KERNEL)
    contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    if not contours:
        return None
    moments = cv2.moments(max(contours, key=cv2.contourArea))
    return (moments["m10"] / moments["m00"], moments["m01"] / moments["m00"]) if moments["m00"] else None


def median_ms(function, inputs: list, repeat: int = 3) -> float:
    """Median over inputs of the best of ``repeat`` runs, in ms."""
    times = []
    for item in inputs:
        best = np.inf
        for _ in range(repeat):
            start = time.perf_counter()
            function(*item)
            best = min(best, time.perf_counter() - start)
        times.append(best)
    return 1000.0 * float(np.median(times))


def attempt(function, *args):
    """``function(*args)``, or None where perception refuses the input (timed all the same)."""
    try:
        return function(*args)
    except InputError:
        return None


def correct(pair: Pair, g: Grounding | None) -> bool:
    """Whether a grounding has the simulator's colour, far before and after, and action."""
    return g is not None and (g.name, g.far_pre, g.far_post, g.action) == pair.truth


def noisy(image: np.ndarray, sigma: float, rng: np.random.Generator) -> np.ndarray:
    if sigma == 0:
        return image
    return np.clip(image + rng.normal(0.0, sigma, image.shape), 0, 255).astype(np.uint8)


def bench_grounding(pairs_by_size: dict[tuple[int, int], list[Pair]]) -> None:
    measured = {}
    print("| image | pairs | ground ms | ground_scene ms | plain OpenCV change ms | ratio ground/plain | correct |")
    print("|---|---|---|---|---|---|---|")
    for size, pairs in pairs_by_size.items():
        images = [(p.pre, p.post) for p in pairs]
        ours = median_ms(lambda *images: attempt(ground, *images), images)
        scene = median_ms(lambda image: attempt(ground_scene, image), [(p.post,) for p in pairs])
        plain = median_ms(reference_change, images)
        right = sum(correct(p, attempt(ground, p.pre, p.post)) for p in pairs)
        print(
            f"| {size[0]}x{size[1]} | {len(pairs)} | {ours:.2f} | {scene:.2f} | {plain:.2f} | "
            f"{ours / plain:.1f} | {_share(right, len(pairs))} |"
        )
        measured[size] = ours
    verdict = "met" if measured[SIZES[0]] <= TARGET_MS else "MISSED"
    print(
        f"target <= {TARGET_MS:.0f} ms per grounding at 640x480: {verdict} ({measured[SIZES[0]]:.2f} ms; "
        f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)"
    )


def bench_noise(pairs: list[Pair]) -> None:
    # The plain detector gives no colour, line or far: both are scored on where the moved cube
    # went (overhead camera), within half a cube's width of its top face.
    print("\n| noise sigma | grounding correct (ours) | moved cube located: ours | plain OpenCV |")
    print("|---|---|---|---|")
    overhead = [p for p in pairs if p.camera == "overhead"]
    for sigma in NOISE:
        rng = np.random.default_rng(sigma)
        right = ours = plain = 0
        for pair in pairs:
            pre, post = noisy(pair.pre, sigma, rng), noisy(pair.post, sigma, rng)
            g = attempt(ground, pre, post)
            right += correct(pair, g)
            if pair.camera == "overhead":
                near = 0.025 * pre.shape[1]  # half a cube's width (px)
                ours += g is not None and np.hypot(*np.subtract(g.post, pair.top_post)) < near
                found = reference_change(pre, post)
                plain += found is not None and np.hypot(*np.subtract(found, pair.top_post)) < near
        print(
            f"| {sigma} | {_share(right, len(pairs))} | {_share(ours, len(overhead))} | "
            f"{_share(plain, len(overhead))} |"
        )


def _share(count: int, total: int) -> str:
    return f"{count}/{total} ({100.0 * count / max(total, 1):.1f}%)"


def bench_matching(pairs: list[Pair]) -> None:
    # Known rotation and translation on the textured house-and-roof world.
    observation = houses_world([(200, 150)], [0], size=(480, 360))
    point = (230.0, 165.0)
    cases, errors, angles = [], [], []
    for angle, shift in ((25.0, (40.0, -30.0)), (-60.0, (-25.0, 15.0)), (90.0, (10.0, 60.0)), (5.0, (-70.0, 0.0))):
        turn = cv2.getRotationMatrix2D(point, angle, 1.0)
        turn[:, 2] += shift
        world = cv2.warpAffine(observation, turn, (480, 360), borderMode=cv2.BORDER_REPLICATE)
        cases.append((observation, world, point, BODY_SIZE))
        match = find_best_match(observation, world, point, BODY_SIZE)
        expected = turn @ np.array([*point, 1.0])
        errors.append(np.hypot(match.x - expected[0], match.y - expected[1]))
        angles.append(abs((np.degrees(match.theta) + angle + 180.0) % 360.0 - 180.0))
    demo = houses_world([(40, 100), (200, 100), (360, 100)], [0, 1], loose_roofs=[(60, 320)])
    world = houses_world([(60, 170), (200, 60), (340, 190)], [0, 2], loose_roofs=[(380, 330)], seed=1)
    ours = median_ms(find_best_match, cases)
    adaptive = median_ms(find_best_match, [(demo, world, (390.0, 175.0), 40)])
    grey = cv2.cvtColor(cases[0][1], cv2.COLOR_RGB2GRAY)
    detect = median_ms(lambda image: sift().detectAndCompute(image, None), [(grey,)] * 4)
    print(
        f"\nmatch finding (480x360, known rotation + translation, 4 cases): {ours:.1f} ms/match, "
        f"position error max {max(errors):.2f} px, angle error max {max(angles):.2f} deg; "
        f"SIFT detect+describe of one image alone {detect:.1f} ms (ratio {ours / detect:.1f})"
    )
    print(f"house-and-roof with the adaptive frame: {adaptive:.1f} ms/match")
    # Rendered cubes seen from above: the moved cube found again in the post-action image.
    found = []
    for pair in (p for p in pairs if p.camera == "overhead"):
        try:
            match = find_best_match(pair.pre, pair.post, pair.top_pre, 40)
        except ValueError:
            found.append(np.inf)
            continue
        found.append(np.hypot(match.x - pair.top_post[0], match.y - pair.top_post[1]))
    found = np.array(found)
    # Plain-coloured cubes have almost no texture: SIFT finds too few keypoints on them, which
    # is why cubes are told apart by their colour symbols, not by match finding.
    print(
        f"plain-coloured rendered cubes (overhead 640x480, {len(found)} moves): found within half a "
        f"cube in {(found < 16).sum()}/{len(found)}, median error {np.median(found):.0f} px"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worlds", type=int, default=6)
    parser.add_argument("--moves", type=int, default=5)
    args = parser.parse_args()
    started = time.perf_counter()
    pairs_by_size = {size: rendered_pairs(args.worlds, args.moves, size) for size in SIZES}
    print(f"rendered {sum(map(len, pairs_by_size.values()))} pairs in {time.perf_counter() - started:.0f} s\n")
    bench_grounding(pairs_by_size)
    bench_noise(pairs_by_size[SIZES[0]])
    bench_matching(pairs_by_size[SIZES[0]])


if __name__ == "__main__":
    main()
