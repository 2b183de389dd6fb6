"""The cost of ``--rerun``: a trial's CPU seconds with and without its recording, the same seeds
in the same run, alternated, the minimum of several runs each (issue 39: at most +20 %).

    python benchmarks/bench_rerun.py [--experiment pull-in-order] [--seeds 3] [--repeats 3]
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

from vslsp.sim.rerun_log import parts_folder
from vslsp.tasks import get_task
from vslsp.tasks.base import timed


def trial_cpu(name: str, seed: int, recording: Path | None) -> float:
    """One trial's CPU seconds (its recording's part written and closed inside the trial)."""
    options = {"rerun": str(parts_folder(recording))} if recording is not None else {}
    if recording is not None:
        parts_folder(recording).mkdir(parents=True, exist_ok=True)
    return timed(get_task(name, **options), seed, False).cpu_s


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--experiment", default="pull-in-order")
    parser.add_argument("--seeds", type=int, default=1, help="seeds 0..N-1")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "bench.rrd"
        plain: dict[int, list[float]] = {}
        logged: dict[int, list[float]] = {}
        for _ in range(args.repeats):
            for seed in range(args.seeds):
                plain.setdefault(seed, []).append(trial_cpu(args.experiment, seed, None))
                logged.setdefault(seed, []).append(trial_cpu(args.experiment, seed, out))
        size = sum(p.stat().st_size for p in parts_folder(out).glob("*.rrd")) / args.seeds
    without = sum(min(v) for v in plain.values())
    with_rerun = sum(min(v) for v in logged.values())
    print(
        json.dumps(
            {
                "experiment": args.experiment,
                "seeds": args.seeds,
                "repeats": args.repeats,
                "cpu_s_without": round(without, 3),
                "cpu_s_with_rerun": round(with_rerun, 3),
                "ratio": round(with_rerun / without, 3),
                "recording_mb_per_trial": round(size / 1e6, 2),
            }
        )
    )


if __name__ == "__main__":
    main()
