"""What ``--video`` costs a trial (issue "Reports a researcher can put in a paper"): each
experiment's trials (the iCub ones and a Panda tabletop task by default) run with and without
filming, through the task framework as ``vslsp experiment`` runs them, interleaved in this process, each seed
``--repeat`` times; the figure per seed is its quickest run, in wall-clock seconds and in CPU
seconds (the process, the planner and the ffmpeg encoder it starts: hardly changed by other
programs loading the machine). Target: the video adds at most 30 % to a trial.

    python benchmarks/bench_video.py [--experiments NAME ...] [--seeds S ...] [--repeat R] [--json]
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

from vslsp.tasks import get_task, run_one
from vslsp.tasks.base import cpu_seconds

TARGET = 1.30


def measure(experiment: str, seed: int, video: Path | None) -> tuple[float, float]:
    """Wall-clock and CPU seconds of one trial (filmed into the folder ``video`` when given)."""
    task = get_task(experiment, video=str(video) if video is not None else None)
    start, cpu = time.perf_counter(), cpu_seconds()
    trial = run_one(task, seed)
    if not trial.success:
        raise SystemExit(f"{experiment} seed {seed} failed: {trial.error}")
    return time.perf_counter() - start, cpu_seconds() - cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--experiments", nargs="+", default=["pull-in-order", "keep-all-near", "alphabet-ordering"])
    parser.add_argument("--seeds", nargs="+", type=int, default=[5, 6])
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    for experiment in args.experiments:  # imports and caches warm
        measure(experiment, args.seeds[0], None)
    figures = {}
    with tempfile.TemporaryDirectory() as folder:
        for experiment in args.experiments:
            plain: dict[int, list] = {}
            filmed: dict[int, list] = {}
            for seed in args.seeds:
                for _ in range(args.repeat):  # interleaved: a load change hits both alike
                    plain.setdefault(seed, []).append(measure(experiment, seed, None))
                    filmed.setdefault(seed, []).append(measure(experiment, seed, Path(folder) / experiment))
            wall = (
                sum(min(w for w, _ in plain[s]) for s in args.seeds),
                sum(min(w for w, _ in filmed[s]) for s in args.seeds),
            )
            cpu = (
                sum(min(c for _, c in plain[s]) for s in args.seeds),
                sum(min(c for _, c in filmed[s]) for s in args.seeds),
            )
            figures[experiment] = {
                "seeds": args.seeds,
                "wall_s": {
                    "without": round(wall[0], 2),
                    "with_video": round(wall[1], 2),
                    "ratio": round(wall[1] / wall[0], 3),
                },
                "cpu_s": {
                    "without": round(cpu[0], 2),
                    "with_video": round(cpu[1], 2),
                    "ratio": round(cpu[1] / cpu[0], 3),
                },
                "within_target": cpu[1] / cpu[0] <= TARGET,
            }
    if args.json:
        print(json.dumps(figures))
        return
    for experiment, f in figures.items():
        print(
            f"{experiment:<16} wall {f['wall_s']['without']:6.2f} s -> {f['wall_s']['with_video']:6.2f} s "
            f"(x{f['wall_s']['ratio']:.3f}); CPU {f['cpu_s']['without']:6.2f} s -> {f['cpu_s']['with_video']:6.2f} s "
            f"(x{f['cpu_s']['ratio']:.3f}, target <= x{TARGET}: {'ok' if f['within_target'] else 'MISSED'})"
        )


if __name__ == "__main__":
    main()
