"""What running a user's predicates in a child process costs (issue 42, vslsp/grounding/contained.py).

On the 10-object 640x480 pair and the predicates file of ``bench_grounding.py`` (5 unary and 3
binary predicates of the file, 50 unary + 270 binary atoms per image), it times

1. one scene's atoms (``ground_atoms``) with the file loaded in this process (``load_predicates``)
   and decided in the child (``UserPredicates``): the overhead per call (the JSON of the scene and
   the atoms, two pipe hops);
2. the child's start-up with the file's load (``UserPredicates.start``) against ``load_predicates``
   (once per command; an experiment's workers each start one).

Minimum and median of ``--runs`` runs, in the same run.

Run: .venv/bin/python benchmarks/bench_user_code.py [--runs N]

Measured (100 runs, a 2-core machine shared with other jobs, load about 3):
  one scene, 320 atoms: in this process 5.53 / 5.64 ms, in the child 6.69 / 6.89 ms: +1.16 / +1.25 ms per call
  start-up with the load: load_predicates 0.3 ms, UserPredicates.start (and close) 175 / 188 ms
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import textwrap
import time
from pathlib import Path

from bench_grounding import COST_FILE

from vslsp.grounding import ground, load_predicates, with_builtins
from vslsp.grounding.contained import UserPredicates
from vslsp.grounding.predicates import collecting, ground_atoms
from vslsp.grounding.testkit import Square, synthetic_pair
from vslsp.vision.colour import COLOUR_NAMES


def _times(run, runs: int) -> tuple[float, float]:
    seconds = []
    for _ in range(runs):
        start = time.perf_counter()
        run()
        seconds.append(time.perf_counter() - start)
    return 1000 * min(seconds), 1000 * statistics.median(seconds)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=50, help="timed runs of each")
    args = parser.parse_args()
    colours = list(COLOUR_NAMES) + list(COLOUR_NAMES[:4])
    places = [(70 + 125 * (i % 5), 90 + 300 * (i // 5) + 30 * (i % 2)) for i in range(10)]
    pair = synthetic_pair([Square(c, p, 50) for c, p in zip(colours, places, strict=True)], move=(2, (330, 300)))
    scene = ground(pair.pre, pair.post, predicates=with_builtins([])).scene_pre
    assert scene is not None and len(scene.objects) == 10, "not all 10 objects seen"
    with tempfile.TemporaryDirectory() as folder:
        file = Path(folder) / "predicates.py"
        file.write_text(textwrap.dedent(COST_FILE))
        with collecting():
            here = load_predicates(file)
        with UserPredicates.start(file) as user:
            assert list(ground_atoms(scene, user.predicates).items()) == list(ground_atoms(scene, here).items())
            here_ms = _times(lambda: ground_atoms(scene, here), args.runs)
            child_ms = _times(lambda: ground_atoms(scene, user.predicates), args.runs)
        load_ms = _times(lambda: load_predicates(file), max(3, args.runs // 10))
        start_ms = _times(lambda: UserPredicates.start(file).close(), max(3, args.runs // 10))
    atoms = sum(len(scene.objects) * (len(scene.objects) - 1) if p.arity == 2 else len(scene.objects) for p in here)
    print(f"one scene, {atoms} atoms (min / median of {args.runs}):")
    print(f"  in this process: {here_ms[0]:.2f} / {here_ms[1]:.2f} ms")
    print(
        f"  in the child:    {child_ms[0]:.2f} / {child_ms[1]:.2f} ms: "
        f"+{child_ms[0] - here_ms[0]:.2f} / +{child_ms[1] - here_ms[1]:.2f} ms per call"
    )
    print(
        f"start-up with the load: load_predicates {load_ms[0]:.1f} / {load_ms[1]:.1f} ms, "
        f"UserPredicates.start (and close) {start_ms[0]:.1f} / {start_ms[1]:.1f} ms"
    )


if __name__ == "__main__":
    main()
