"""PDDL size benchmark: ``vslsp pddl check``'s CPU time and peak memory on logistics problems from 50 000
objects (1.4 MB) to 20 MB, linear in the size (issue 41, item 5), against two other readers of the same
files measured in the same run: the PyPI ``pddl`` 0.5.1 parser (``parse_domain`` + ``parse_problem``)
and the VS Code PDDL extension's parser (npm ``pddl-workspace`` 11.3.0, ``PddlDomainParser.parseText`` +
``PddlProblemParser.parseText`` under node). Target: vslsp at least 2x faster in CPU than both.

Each figure is a whole process (its start-up and imports included, as a user runs each), its CPU time
(user + system) and peak RSS read from ``wait4``; the minimum over ``--runs`` runs (the machine may be
shared: the minimum is the run least disturbed). Linearity: CPU per MB above the start-up (the CPU on a
7-object problem). Every process runs under an address-space limit of ``--memory`` MB (node: a heap
limit of the same size) and a CPU limit of ``--cpu-limit`` s, so a reader that blows up is stopped,
not the machine; a reader stopped by the CPU limit is shown as ``>`` its CPU (a lower bound; its
ratio too).

The problems are :func:`vslsp.symbolic.io.generated.logistics_problem` (IPC-1998 logistics), written to a
temporary folder. ``pddl-workspace`` is read from ``--node-modules`` (default: ``$PDDL_WORKSPACE``, or
``/tmp/pddlws/node_modules``; install it with ``npm install pddl-workspace@11.3.0`` in that folder's
parent); without node or the package, that yardstick is skipped with one line saying why.

    .venv/bin/python benchmarks/bench_pddl_size.py [--objects 50000 200000 700000] [--runs 3] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

import vslsp
from vslsp.symbolic.io.generated import LOGISTICS_DOMAIN, logistics_problem

TARGET_RATIO = 2.0
_PDDL_PYPI = (
    "import sys\nfrom pddl import parse_domain, parse_problem\n"
    "parse_domain(sys.argv[1]); problem = parse_problem(sys.argv[2])\nassert len(problem.objects) > 0\n"
)
_PDDL_WORKSPACE = """
const fs = require('fs');
const { parser } = require('pddl-workspace');
(async () => {
  const domain = parser.PddlDomainParser.parseText(fs.readFileSync(process.argv[1], 'utf8'));
  const problem = await parser.PddlProblemParser.parseText(fs.readFileSync(process.argv[2], 'utf8'));
  if (!domain || !problem || problem.getInits().length === 0) { process.exit(1); }
})();
"""


def measure(command: list[str], memory_mb: int, env: dict[str, str], cpu_limit_s: int) -> dict[str, float]:
    """One run of ``command`` (stdout discarded): its CPU seconds and peak RSS in MB (``over``: 1 when it
    ran out of ``cpu_limit_s``, its CPU then a lower bound); ValueError when it fails otherwise."""

    def limit() -> None:
        size = memory_mb * 1024 * 1024
        resource.setrlimit(resource.RLIMIT_AS, (size, size))
        resource.setrlimit(resource.RLIMIT_CPU, (cpu_limit_s, cpu_limit_s + 5))

    # from the problem's folder: the repository's own pddl/ folder (the shipped files) is no `pddl` module
    folder = os.path.dirname(command[-1])
    process = subprocess.Popen(
        command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, preexec_fn=limit, env=env, cwd=folder
    )
    assert process.stderr is not None
    error = process.stderr.read()
    _, status, usage = os.wait4(process.pid, 0)
    process.returncode = os.waitstatus_to_exitcode(status)
    cpu = usage.ru_utime + usage.ru_stime
    if process.returncode == -signal.SIGXCPU or (process.returncode == -signal.SIGKILL and cpu >= cpu_limit_s):
        return {"cpu_s": cpu, "rss_mb": usage.ru_maxrss / 1024, "over": 1.0}
    if process.returncode != 0:
        raise ValueError(f"{command[0]} exited {process.returncode}: {error.decode(errors='replace')[-300:]}")
    return {"cpu_s": cpu, "rss_mb": usage.ru_maxrss / 1024, "over": 0.0}


def best(command: list[str], runs: int, memory_mb: int, env: dict[str, str], cpu_limit_s: int) -> dict[str, float]:
    """The minimum CPU and the minimum peak RSS over ``runs`` runs (one, when it ran past the CPU limit)."""
    rows = [measure(command, memory_mb, env, cpu_limit_s)]
    while len(rows) < runs and not rows[0]["over"]:
        rows.append(measure(command, memory_mb, env, cpu_limit_s))
    return {"cpu_s": min(r["cpu_s"] for r in rows), "rss_mb": min(r["rss_mb"] for r in rows), "over": rows[0]["over"]}


def readers(node_modules: Path, memory_mb: int) -> tuple[dict[str, list[str]], list[str]]:
    """The commands (by reader, domain and problem appended) and the lines saying which were skipped."""
    python = sys.executable
    # the vslsp this script imports (a worktree's, under PYTHONPATH), whichever the interpreter installs
    source = str(Path(vslsp.__file__).resolve().parents[1])
    check = ["env", f"PYTHONPATH={source}", python, "-m", "vslsp", "pddl", "check", "--json", "--max-size", "10000"]
    commands = {"vslsp": check}
    skipped: list[str] = []
    try:
        import pddl  # noqa: F401

        commands["pddl 0.5.1"] = [python, "-c", _PDDL_PYPI]
    except ImportError:
        skipped.append("pddl (PyPI) skipped: not installed (pip install 'pddl==0.5.1', or the bench extra)")
    node = shutil.which("node")
    if node is None:
        skipped.append("pddl-workspace skipped: node is not on the PATH")
    elif not (node_modules / "pddl-workspace").is_dir():
        skipped.append(f"pddl-workspace skipped: not in {node_modules} (npm install pddl-workspace@11.3.0)")
    else:
        commands["pddl-workspace 11.3.0"] = [node, f"--max-old-space-size={memory_mb}", "-e", _PDDL_WORKSPACE, "--"]
    return commands, skipped


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--objects", type=int, nargs="+", default=[50_000, 200_000, 700_000])
    parser.add_argument("--runs", type=int, default=3, help="runs of each reader on each file (the minimum counts)")
    parser.add_argument("--memory", type=int, default=8192, help="address-space limit of each process, MB")
    parser.add_argument("--cpu-limit", type=int, default=300, help="CPU limit of each process, s (past it: '>')")
    default_modules = os.environ.get("PDDL_WORKSPACE", "/tmp/pddlws/node_modules")
    parser.add_argument("--node-modules", type=Path, default=Path(default_modules))
    parser.add_argument("--json", type=Path, default=None, help="also write the figures there")
    args = parser.parse_args()
    commands, skipped = readers(args.node_modules, args.memory)
    for line in skipped:
        print(line, flush=True)
    # PYTHONPATH may name the repository, whose pddl/ folder would shadow the PyPI package
    env = {**{k: v for k, v in os.environ.items() if k != "PYTHONPATH"}, "NODE_PATH": str(args.node_modules)}
    results: list[dict[str, object]] = []
    with tempfile.TemporaryDirectory(prefix="bench-pddl-size-") as folder:
        domain = Path(folder) / "domain.pddl"
        domain.write_text(LOGISTICS_DOMAIN)
        start_up: dict[str, float] = {}
        for n_objects in [7, *args.objects]:
            problem = Path(folder) / f"logistics-{n_objects}.pddl"
            problem.write_text(logistics_problem(n_objects))
            size_mb = problem.stat().st_size / 1e6
            row: dict[str, object] = {"objects": n_objects, "mb": size_mb}
            for name, command in commands.items():
                figures = best([*command, str(domain), str(problem)], args.runs, args.memory, env, args.cpu_limit)
                start_up.setdefault(name, figures["cpu_s"])
                row[name] = {**figures, "cpu_s_per_mb": (figures["cpu_s"] - start_up[name]) / size_mb}
            problem.unlink()
            results.append(row)
            if n_objects == 7:
                print("start-up (7 objects): " + ", ".join(f"{n} {row[n]['cpu_s']:.2f} s" for n in commands))  # type: ignore[index]
                print(
                    f"{'objects':>8} {'MB':>6}  " + "  ".join(f"{n:>34}" for n in commands) + "  ratios (CPU x vslsp)"
                )
                continue
            cells = [
                f"{'>' if row[n]['over'] else ' '}{row[n]['cpu_s']:6.1f} s {row[n]['cpu_s_per_mb']:5.2f} s/MB "  # type: ignore[index]
                f"{row[n]['rss_mb']:6.0f} MB"  # type: ignore[index]
                for n in commands
            ]
            ratios = [
                f"{n} {'>' if row[n]['over'] else ''}{row[n]['cpu_s'] / row['vslsp']['cpu_s']:.1f}x"  # type: ignore[index]
                for n in commands
                if n != "vslsp"
            ]
            print(
                f"{n_objects:>8} {size_mb:>6.2f}  " + "  ".join(f"{c:>34}" for c in cells) + "  " + ", ".join(ratios),
                flush=True,
            )
    sized = [r for r in results if r["objects"] != 7]
    per_mb = [r["vslsp"]["cpu_s_per_mb"] for r in sized]  # type: ignore[index]
    base_rss = results[0]["vslsp"]["rss_mb"]  # type: ignore[index]
    rss_per_mb = [(r["vslsp"]["rss_mb"] - base_rss) / r["mb"] for r in sized]  # type: ignore[index, operator]
    print(
        f"vslsp linearity: CPU per MB from {min(per_mb):.2f} to {max(per_mb):.2f} s/MB "
        f"(largest/smallest {max(per_mb) / min(per_mb):.2f}); peak RSS {min(rss_per_mb):.0f}-{max(rss_per_mb):.0f} "
        f"MB per MB of PDDL above the start-up's {base_rss:.0f} MB"
    )
    for name in commands:
        if name != "vslsp":
            worst = min(r[name]["cpu_s"] / r["vslsp"]["cpu_s"] for r in sized)  # type: ignore[index]
            verdict = "met" if worst >= TARGET_RATIO else "NOT met"
            print(
                f"vs {name}: vslsp at least {worst:.1f}x faster in CPU (target {TARGET_RATIO:g}x: {verdict})",
                flush=True,
            )
    if args.json is not None:
        args.json.write_text(json.dumps({"results": results, "skipped": skipped}, indent=2))


if __name__ == "__main__":
    main()
