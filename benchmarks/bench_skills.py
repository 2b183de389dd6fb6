"""Skill benchmark: push and pull success over random object positions in the reachable area.

Target (issue "Imitation learning"): >= 98 % success over at least 50 random object positions
per skill. Each trial is a fresh seeded scene with one cube on the side the skill starts from
(near for push, far for pull) and a random line pose; the robot perceives the cube and the line
with its head camera, executes the learned skill (DMP rollout, IK, physics) and perceives
again. Success: the cube crossed the line in the simulator's ground truth, and the robot sees it
on the new side. Reference measured in the same run: the tutor's scripted relocation of the
same cube (no learning, no IK), so that a skill's time reads as "so many tutor moves".

    python benchmarks/bench_skills.py [--positions N] [--seed S] [--json]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np
from rich.progress import Progress

from vslsp.loop.monitor import execute_step
from vslsp.loop.perception import perceive
from vslsp.sim import LineWorld, SceneSpec
from vslsp.skills import SkillLibrary, default_library_path
from vslsp.worlds.icub import tutor_operation

TARGET = 0.98
STARTS_FAR = {"push": False, "pull": True}


def trial(library: SkillLibrary, skill: str, seed: int) -> dict:
    """One execution of ``skill`` on a fresh scene; success judged on ground truth."""
    spec = SceneSpec.random(seed, n_cubes=1, far=(STARTS_FAR[skill],))
    cube = spec.cubes[0]
    with LineWorld(spec) as world:
        state = perceive(world)
        start = time.perf_counter()
        result, after = execute_step(world, library, skill, cube.colour, state, not STARTS_FAR[skill])
        seconds = time.perf_counter() - start
        crossed = world.is_far(cube.name) != STARTS_FAR[skill]
        x, y, _ = world.cube_pose(cube.name)
        distance = float(np.dot(np.array([x, y]) - spec.landmark.point, spec.landmark.normal))
    return {
        "seed": seed,
        "xy": [round(cube.x, 3), round(cube.y, 3)],
        "success": bool(crossed and result.ok),
        "crossed": bool(crossed),
        "seen": result.ok,
        "final_line_distance": round(distance, 4),
        "error": result.error,
        "s": seconds,
    }


def tutor_time(seed: int) -> float:
    """Seconds of the tutor's relocation of a cube across the line (the reference)."""
    spec = SceneSpec.random(seed, n_cubes=1, far=(True,))
    with LineWorld(spec) as world:
        start = time.perf_counter()
        tutor_operation(world, spec.cubes[0].colour, "pull")
        return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--positions", type=int, default=50, help="random object positions per skill")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()

    library = SkillLibrary.load(default_library_path())
    reference = float(np.median([tutor_time(args.seed + k) for k in range(3)]))
    rows = {}
    with Progress(transient=True) as progress:
        for skill in ("push", "pull"):
            task = progress.add_task(skill, total=args.positions)
            results = []
            for k in range(args.positions):
                results.append(trial(library, skill, args.seed + 10_000 * (skill == "pull") + k))
                progress.advance(task)
            rows[skill] = results
    summary = {}
    for skill, results in rows.items():
        rate = sum(r["success"] for r in results) / len(results)
        distances = np.array([abs(r["final_line_distance"]) for r in results if r["crossed"]])
        seconds = float(np.median([r["s"] for r in results]))
        summary[skill] = {
            "positions": len(results),
            "success_rate": rate,
            "target": TARGET,
            "met": rate >= TARGET,
            "median_past_line_m": float(np.median(distances)) if len(distances) else None,
            "median_s": seconds,
            "in_tutor_moves": seconds / reference,
            "failures": [{k: r[k] for k in ("seed", "xy", "error")} for r in results if not r["success"]],
        }
        print(
            f"{skill}: {rate * 100:.1f} % of {len(results)} positions (target {TARGET * 100:.0f} %: "
            f"{'met' if rate >= TARGET else 'MISSED'}); cube ends a median "
            f"{np.median(distances) * 100 if len(distances) else float('nan'):.1f} cm past the line; "
            f"{seconds:.2f} s per execution = {seconds / reference:.1f} tutor moves"
        )
        for failure in summary[skill]["failures"][:5]:
            print(f"    seed {failure['seed']} at {failure['xy']}: {failure['error']}")
    print(f"reference: the tutor's relocation of a cube {reference:.2f} s")
    if args.json:
        print(json.dumps({"reference_tutor_s": reference, "skills": summary}))


if __name__ == "__main__":
    main()
