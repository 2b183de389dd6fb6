"""Tabletop world benchmark (issue 6, "World"): load time, render time at 1280x960, and the
Panda's pick-and-place over randomised trials: success rate, placement error, wall time.

Each trial builds a world of five random items (6 cm tiles, 5 cm cubes, 9x5 cm Hanoi disks)
in the workspace, picks one at its centre and puts it at a random free spot, or on top of
another item (one trial in five), with a random turn in (-pi, pi]. An operation succeeds when
the world reports ok and the item lands within 1 cm and 5 degrees of the target at the right
height (3 mm). The reference is a bare ``pb.getCameraImage`` of an empty scene at the same
size with the same renderer, measured in this run, so the render ratio reads on any machine.

    python benchmarks/bench_tabletop.py [--trials N] [--seed S] [--json]

Measured on the 2-core development machine (heavily loaded by other jobs, load average 12):
100 % of 100 trials from seed 0 and of 100 from seed 1000 (200/200 more from seeds 2000 and
0 in tuning runs), placement error mean 0.5 mm (max 1.9 mm), turn error mean 0.04 deg; load
0.5 s, render 0.6-0.7 s = 6-7 bare renders; 0.75-0.9 s wall per pick-and-place for 5.9 s
simulated (0.3-0.5 s when the machine was idle).
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from vslsp.sim.quiet import quiet
from vslsp.sim.tabletop import WORKSPACE_X, WORKSPACE_Y, Item, Placement, TabletopWorld

with quiet():
    import pybullet as pb

SHAPES = {"tile": (0.06, 0.06, 0.012), "cube": (0.05, 0.05, 0.05), "disk": (0.09, 0.05, 0.02)}
SPACING = 0.12  # m between item centres
POSITION_TOLERANCE, ANGLE_TOLERANCE, HEIGHT_TOLERANCE = 0.01, np.radians(5.0), 0.003
TARGET = 0.99


def texture(rng: np.random.Generator) -> np.ndarray:
    """A blocky random texture (64, 64, 3) uint8."""
    return np.kron(rng.integers(0, 256, (8, 8, 3)), np.ones((8, 8, 1))).astype(np.uint8)


def free_spot(rng: np.random.Generator, taken: list[np.ndarray]) -> np.ndarray:
    for _ in range(1000):
        spot = rng.uniform([WORKSPACE_X[0], WORKSPACE_Y[0]], [WORKSPACE_X[1], WORKSPACE_Y[1]])
        if all(np.linalg.norm(spot - t) >= SPACING for t in taken):
            return spot
    raise RuntimeError("no free spot in the workspace")


def random_layout(rng: np.random.Generator, n: int = 5) -> list[tuple[Item, Placement]]:
    layout, taken = [], []
    for k in range(n):
        shape = str(rng.choice(list(SHAPES)))
        spot = free_spot(rng, taken)
        taken.append(spot)
        item = Item(f"{shape}-{k}", SHAPES[shape], texture(rng))
        layout.append((item, Placement(float(spot[0]), float(spot[1]), float(rng.uniform(-np.pi, np.pi)))))
    return layout


def trial(seed: int) -> dict:
    """One randomised pick-and-place; figures from the simulator's ground truth."""
    rng = np.random.default_rng(seed)
    layout = random_layout(rng)
    with TabletopWorld(layout, seed=seed) as world:
        item, placement = layout[int(rng.integers(len(layout)))]
        x, y, _, yaw = world.pose(item.name)
        # Close across the item's shorter side: the gripper's closing axis along its y when y is shorter.
        theta_pick = yaw + (np.pi / 2.0 if item.size[1] < item.size[0] else 0.0)
        others = [(i, p) for i, p in layout if i.name != item.name]
        if rng.random() < 0.2:
            below, spot = others[int(rng.integers(len(others)))]
            target_xy = np.array(world.pose(below.name)[:2])
            height = world.pose(below.name)[2] + below.size[2]
        else:
            target_xy = free_spot(rng, [np.array([p.x, p.y]) for _, p in others])
            height = 0.0
        turn = float(rng.uniform(-np.pi, np.pi))
        start = time.perf_counter()
        result = world.pick_and_place((x, y, theta_pick), (*target_xy, theta_pick + turn))
        wall = time.perf_counter() - start
        fx, fy, fz, fyaw = world.pose(item.name)
    position_error = float(np.hypot(fx - target_xy[0], fy - target_xy[1]))
    angle_error = float(abs(np.angle(np.exp(1j * (fyaw - yaw - turn)))))
    landed = (
        position_error < POSITION_TOLERANCE and angle_error < ANGLE_TOLERANCE and abs(fz - height) < HEIGHT_TOLERANCE
    )
    return {
        "seed": seed,
        "item": item.name,
        "stacked": height > 0.0,
        "ok": result.ok,
        "diagnosis": result.diagnosis,
        "success": bool(result.ok and landed),
        "position_error_m": position_error,
        "angle_error_deg": float(np.degrees(angle_error)),
        "height_error_m": float(abs(fz - height)),
        "wall_s": wall,
        "sim_s": result.duration_s,
    }


def bare_render_s(repeat: int) -> float:
    """s per ``pb.getCameraImage`` of an empty scene at 1280x960 (the reference)."""
    with quiet():
        client = pb.connect(pb.DIRECT)
    view = pb.computeViewMatrix([0, 0, 1], [0, 0, 0], [1, 0, 0])
    projection = pb.computeProjectionMatrixFOV(27.0, 4.0 / 3.0, 0.05, 3.0)
    start = time.perf_counter()
    for _ in range(repeat):
        pb.getCameraImage(
            TabletopWorld.WIDTH,
            TabletopWorld.HEIGHT,
            view,
            projection,
            renderer=pb.ER_TINY_RENDERER,
            physicsClientId=client,
        )
    elapsed = (time.perf_counter() - start) / repeat
    pb.disconnect(client)
    return elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--trials", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", action="store_true", help="print the figures as one JSON object")
    args = parser.parse_args()

    reference = bare_render_s(3)
    layout = random_layout(np.random.default_rng(args.seed))
    start = time.perf_counter()
    world = TabletopWorld(layout)
    load = time.perf_counter() - start
    world.observe()
    start = time.perf_counter()
    for _ in range(3):
        world.observe()
    render = (time.perf_counter() - start) / 3
    world.close()

    trials = [trial(args.seed + k) for k in range(args.trials)]
    ok = [t for t in trials if t["success"]]
    errors = np.array([t["position_error_m"] for t in trials if t["ok"]] or [np.nan])
    angles = np.array([t["angle_error_deg"] for t in trials if t["ok"]] or [np.nan])
    figures = {
        "load_s": round(load, 3),
        "render_s": round(render, 3),
        "bare_render_s": round(reference, 3),
        "render_in_bare_renders": round(render / reference, 2),
        "trials": len(trials),
        "success_rate": len(ok) / len(trials),
        "stacked_trials": sum(t["stacked"] for t in trials),
        "diagnoses": {d: sum(t["diagnosis"] == d for t in trials) for d in {t["diagnosis"] for t in trials} if d},
        "position_error_mm": {
            "mean": round(1000 * float(np.mean(errors)), 2),
            "max": round(1000 * float(np.max(errors)), 2),
        },
        "angle_error_deg": {"mean": round(float(np.mean(angles)), 2), "max": round(float(np.max(angles)), 2)},
        "wall_s_per_pick_and_place": round(float(np.mean([t["wall_s"] for t in trials])), 3),
        "sim_s_per_pick_and_place": round(float(np.mean([t["sim_s"] for t in trials])), 2),
        "failures": [t for t in trials if not t["success"]],
    }
    figures["target_met"] = figures["success_rate"] >= TARGET
    if args.json:
        print(json.dumps(figures))
        return
    print(
        f"tabletop world: load {load:.2f} s (5 items); render 1280x960 {render:.2f} s "
        f"= {render / reference:.2f} x a bare getCameraImage of an empty scene ({reference:.2f} s)"
    )
    print(
        f"pick-and-place, {len(trials)} random trials from seed {args.seed} "
        f"({figures['stacked_trials']} onto another item): success {100 * figures['success_rate']:.0f} % "
        f"{figures['diagnoses']}"
    )
    print(
        f"  placement error mean {figures['position_error_mm']['mean']} mm "
        f"(max {figures['position_error_mm']['max']}), "
        f"turn error mean {figures['angle_error_deg']['mean']} deg (max {figures['angle_error_deg']['max']})"
    )
    print(
        f"  {figures['wall_s_per_pick_and_place']:.2f} s wall per pick-and-place for "
        f"{figures['sim_s_per_pick_and_place']:.1f} s simulated "
        f"({figures['sim_s_per_pick_and_place'] / figures['wall_s_per_pick_and_place']:.0f} x real time)"
    )
    print(f"target >= {100 * TARGET:.0f} % of operations: {'met' if figures['target_met'] else 'NOT met'}")
    for failure in figures["failures"][:10]:
        print("  failed:", {k: (round(v, 4) if isinstance(v, float) else v) for k, v in failure.items()})


if __name__ == "__main__":
    main()
