"""Simulator benchmark: iCub load time, physics steps/s, render time per frame, IK time per call.

Reference measured in the same run: loading the iCub URDF as shipped by icub-models (all its
212 links) against our reduced model, and pybullet's own IK (calculateInverseKinematics,
which moves the torso freely and cannot be locked) against our DLS IK.
"""

from __future__ import annotations

import time

import numpy as np

from vslsp.sim import TABLE_Z, LineWorld
from vslsp.sim.icub import KinematicICub, palm_down_rotation
from vslsp.sim.icub_model import _source_urdf
from vslsp.sim.quiet import quiet
from vslsp.sim.robot import HAND_YAW, _reach_seed

with quiet():
    import pybullet as pb


def timed(function, repeat: int = 1) -> float:
    start = time.perf_counter()
    for _ in range(repeat):
        function()
    return (time.perf_counter() - start) / repeat


def main() -> None:
    client = pb.connect(pb.DIRECT)
    with quiet():
        shipped = timed(lambda: pb.loadURDF(str(_source_urdf()), useFixedBase=True, physicsClientId=client), 3)
    pb.disconnect(client)
    kinematics = KinematicICub()
    reduced = timed(lambda: KinematicICub().close(), 3)
    print(
        f"iCub load: reduced model {reduced * 1000:.0f} ms (incl. Jacobian calibration), "
        f"as shipped {shipped * 1000:.0f} ms, ratio {shipped / reduced:.2f}x"
    )

    with LineWorld(seed=0) as world:
        steps = timed(lambda: world.step(240))
        print(f"physics with the iCub and 3 cubes: {240 / steps:,.0f} steps/s ({240 / steps / 240:.1f}x real time)")
        for width, height in [(320, 240), (640, 480), (1280, 960)]:
            view = world.camera("head", width, height)  # observe() would reuse the view of an unchanged world
            render = timed(lambda view=view: view.render(world.client, world.backdrop), 3)
            print(f"render head camera {width}x{height}: {render * 1000:.0f} ms/frame")

    rng = np.random.default_rng(0)
    targets = np.column_stack(
        [rng.uniform(0.15, 0.40, 100), rng.uniform(-0.22, 0.0, 100), np.full(100, TABLE_Z + 0.02)]
    )
    rotation = palm_down_rotation(HAND_YAW)
    errors, start = [], time.perf_counter()
    for target in targets:
        errors.append(kinematics.solve(target, rotation, _reach_seed()).position_error)
    ours = (time.perf_counter() - start) / len(targets)
    errors = np.array(errors) * 1000
    # warm-started solves, as along a path of 5 mm steps
    path = np.linspace(targets[0], targets[0] + [0.1, 0.05, 0.0], 21)
    q = kinematics.solve(path[0], rotation, _reach_seed()).q
    start = time.perf_counter()
    for point in path[1:]:
        q = kinematics.solve(point, rotation, q).q
    warm = (time.perf_counter() - start) / (len(path) - 1)
    hand = kinematics.hand_link
    start = time.perf_counter()
    theirs_errors = []
    for target in targets:
        solution = pb.calculateInverseKinematics(
            kinematics.body, hand, target, maxNumIterations=200, physicsClientId=kinematics.client
        )
        theirs_errors.append(np.nan if solution is None else 0.0)
    theirs = (time.perf_counter() - start) / len(targets)
    print(
        f"IK (torso + arm, position + palm-down orientation) from a neutral seed: {ours * 1000:.2f} ms/call, "
        f"error median {np.median(errors):.3f} mm, 95th pct {np.percentile(errors, 95):.3f} mm, "
        f"max {errors.max():.3f} mm "
        f"over {len(targets)} table targets"
    )
    print(f"IK warm-started along a 5 mm path: {warm * 1000:.2f} ms/call")
    print(
        f"pybullet calculateInverseKinematics (all 32 joints, position only): {theirs * 1000:.2f} ms/call; "
        f"ours/theirs time ratio {ours / theirs:.1f}"
    )
    kinematics.close()


if __name__ == "__main__":
    main()
