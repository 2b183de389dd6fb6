"""What ``--video`` costs a trial (issue "Reports a researcher can put in a paper"): each iCub
experiment's trials run with and without filming, interleaved in this process, each seed
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

from vslsp.loop.experiments import run_trial
from vslsp.skills.library import SkillLibrary, default_library_path
from vslsp.tasks.base import cpu_seconds

TARGET = 1.30


def measure(experiment: str, seed: int, library: SkillLibrary, video: Path | None) -> tuple[float, float]:
    """Wall-clock and CPU seconds of one trial (filmed into ``video`` when given)."""
    start, cpu = time.perf_counter(), cpu_seconds()
    trial = run_trial(experiment, seed, library, video=video)
    if not trial.success:
        raise SystemExit(f"{experiment} seed {seed} failed: {trial.error}")
    return time.perf_counter() - start, cpu_seconds() - cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--experiments", nargs="+", default=["pull-in-order", "keep-all-near"])
    parser.add_argument("--seeds", nargs="+", type=int, default=[5, 6])
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    library = SkillLibrary.load(default_library_path())
    run_trial(args.experiments[0], args.seeds[0], library)  # imports and caches warm
    figures = {}
    with tempfile.TemporaryDirectory() as folder:
        for experiment in args.experiments:
            plain: dict[int, list] = {}
            filmed: dict[int, list] = {}
            for seed in args.seeds:
                for _ in range(args.repeat):  # interleaved: a load change hits both alike
                    plain.setdefault(seed, []).append(measure(experiment, seed, library, None))
                    video = Path(folder) / f"{experiment}-{seed}.mp4"
                    filmed.setdefault(seed, []).append(measure(experiment, seed, library, video))
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
