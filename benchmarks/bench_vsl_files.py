"""VSL from picture files (docs/recordings.md): a Panda tabletop task's demonstration rendered
and written as a user's recording folder (PNG pictures, calibration.json, names.json,
heights.json), learned with ``vslsp vsl learn``, then reproduced in the new scene of each
seed's reproduction world by the closed loop of ``vslsp vsl reproduce --step`` (photograph,
ask, execute the answer with the Panda's pick-and-place skill, photograph again, until done).

Success per operation: its object within 1 cm and 5 deg of its demonstrated relation to its
anchor just after it was executed (ground truth; issue 39 asks >= 99 % on renders).

    python benchmarks/bench_vsl_files.py [--task alphabet-ordering] [--trials 20] [--seed 0] [--json]

Seeds ``seed`` .. ``seed + trials - 1`` (default 0-19). A trial costs about 15-20 s of one core.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

from vsl_answers import ANGLE, POSITION, vslsp

from vslsp.experiments.picture_folders import closed_loop, write_recording

TARGET = 0.99


def trial(task: str, seed: int, root: Path) -> dict:
    """One seed: record, learn, reproduce in the closed loop; per operation its errors."""
    start = time.perf_counter()
    goal = write_recording(task, seed, root / "recording")
    learned = vslsp("vsl", "learn", root / "recording", "--out", root / "demo")
    if "error" in learned:
        return {"seed": seed, "error": learned["error"], "operations": [], "s": time.perf_counter() - start}
    (root / "scenes").mkdir()

    def ask(scene: Path) -> dict:
        return vslsp("vsl", "reproduce", root / "demo", scene, "--step", root / "session.json")

    try:
        *operations, final = closed_loop(task, seed, goal, root / "scenes", ask)
    except Exception as error:  # a failed question ends the trial; the benchmark goes on
        return {"seed": seed, "error": str(error), "operations": [], "s": time.perf_counter() - start}
    for op in operations:
        op["ok"] = op["position_error_m"] <= POSITION and op["angle_error_deg"] <= ANGLE
    missing = len(goal.items) - len(operations)  # operations never answered count as failed
    operations += [{"operation": None, "ok": False, "position_error_m": 0.0, "angle_error_deg": 0.0}] * missing
    return {"seed": seed, "operations": operations, "final": final["final"], "s": round(time.perf_counter() - start, 1)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--task", default="alphabet-ordering")
    parser.add_argument("--trials", type=int, default=20)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    results = []
    for seed in range(args.seed, args.seed + args.trials):
        with tempfile.TemporaryDirectory() as folder:
            result = trial(args.task, seed, Path(folder))
        results.append(result)
        ok = sum(op["ok"] for op in result["operations"])
        print(
            f"seed {seed}: {ok}/{len(result['operations'])} ok {result.get('error', '')}", file=sys.stderr, flush=True
        )
    operations = [op for r in results for op in r["operations"]]
    expected = sum(max(len(r["operations"]), 1) for r in results)
    ok = sum(op["ok"] for op in operations)
    summary = {
        "task": args.task,
        "seeds": [args.seed, args.seed + args.trials - 1],
        "trials": len(results),
        "operations_ok": ok,
        "operations": expected,
        "operation_success_rate": round(ok / expected, 4) if expected else 0.0,
        "trials_all_ok": sum(bool(r["operations"]) and all(op["ok"] for op in r["operations"]) for r in results),
        "worst_position_mm": round(1000 * max((op["position_error_m"] for op in operations), default=0.0), 1),
        "worst_angle_deg": max((op["angle_error_deg"] for op in operations), default=0.0),
        "s_per_trial": round(sum(r["s"] for r in results) / len(results), 1),
        "target": TARGET,
        "failures": [r for r in results if "error" in r or not all(op["ok"] for op in r["operations"])],
    }
    if args.json:
        print(json.dumps(summary))
        return
    print(
        f"{args.task}, seeds {args.seed}-{args.seed + args.trials - 1}: {ok}/{expected} operations within "
        f"{1000 * POSITION:.0f} mm / {ANGLE:.0f} deg ({100 * summary['operation_success_rate']:.1f} %, target "
        f">= {100 * TARGET:.0f} %); {summary['trials_all_ok']}/{len(results)} trials all ok; worst "
        f"{summary['worst_position_mm']} mm, {summary['worst_angle_deg']} deg; {summary['s_per_trial']} s a trial"
    )


if __name__ == "__main__":
    main()
