"""Studio benchmark (issue 29): ``vslsp studio``'s start-up to serving (target < 3 s), the author
page's check of a keystroke on the shipped domain and problem (target < 100 ms) and its completion
(Ctrl-Space: ``POST /api/complete``, the same engine and the completion context).

Start-up: from spawning ``python -m vslsp studio --no-browser`` to the first answer of ``GET /author``
(the page a browser opens), against the reference ``python -m vslsp --help`` measured in the same run
(a Python start-up and the CLI's import). Check round trip: ``POST /api/check`` with the shipped
domain and problem, a typo put in and taken out at each request (so the diagnostics change), over HTTP
to the running studio: the engine's analysis, the decorations' data and the HTTP round trip (the page
runs the same function on its websocket). Reference: the engine alone in this process
(:func:`vslsp.symbolic.language.analyse`). Each figure is the minimum over the runs (the machine may
be shared; the minimum is the run least disturbed), the median beside it.

    .venv/bin/python benchmarks/bench_studio.py [--starts 3] [--checks 50]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

from vslsp.symbolic.language import analyse

REPO = Path(__file__).resolve().parents[1]
DOMAIN, PROBLEM = REPO / "pddl" / "domain.pddl", REPO / "pddl" / "pull-in-order.pddl"


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def start_studio(root: Path) -> tuple[subprocess.Popen, int, float]:
    """Spawn the studio; (process, port, seconds to the first answer of /author)."""
    port = _free_port()
    began = time.perf_counter()
    process = subprocess.Popen(
        [sys.executable, "-m", "vslsp", "studio", "--root", str(root), "--port", str(port), "--no-browser"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    while True:
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/author", timeout=5) as answer:
                answer.read()
            return process, port, time.perf_counter() - began
        except OSError:
            if process.poll() is not None:
                raise SystemExit("the studio did not start") from None
            time.sleep(0.01)


def reference_start() -> float:
    began = time.perf_counter()
    subprocess.run([sys.executable, "-m", "vslsp", "--help"], stdout=subprocess.DEVNULL, check=True)
    return time.perf_counter() - began


def checks(port: int, count: int) -> list[float]:
    domain, problem = DOMAIN.read_text(), PROBLEM.read_text()
    typo = domain.replace("(not (far ?b))", "(not (fars ?b))", 1)
    times = []
    for number in range(count):
        body = json.dumps({"domain": typo if number % 2 else domain, "problem": problem}).encode()
        request = urllib.request.Request(
            f"http://127.0.0.1:{port}/api/check", body, {"content-type": "application/json"}
        )
        began = time.perf_counter()
        with urllib.request.urlopen(request) as answer:
            answer.read()
        times.append(time.perf_counter() - began)
    return times


def completions(port: int, count: int) -> list[float]:
    """Ctrl-Space after ``(not (f`` in the shipped domain: ``POST /api/complete`` round trips."""
    domain = DOMAIN.read_text().replace("(not (far ?b))", "(not (f ?b))", 1)
    at = domain.index("(not (f") + len("(not (f")
    body = json.dumps({"domain": domain, "problem": PROBLEM.read_text(), "in": "domain", "at": at}).encode()
    times = []
    for _ in range(count):
        request = urllib.request.Request(
            f"http://127.0.0.1:{port}/api/complete", body, {"content-type": "application/json"}
        )
        began = time.perf_counter()
        with urllib.request.urlopen(request) as answer:
            assert "far" in json.loads(answer.read())["items"]
        times.append(time.perf_counter() - began)
    return times


def engine(count: int) -> list[float]:
    domain, problem = DOMAIN.read_text(), PROBLEM.read_text()
    times = []
    for _ in range(count):
        began = time.perf_counter()
        analyse(domain, "domain.pddl", problem, "problem.pddl")
        times.append(time.perf_counter() - began)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--starts", type=int, default=3)
    parser.add_argument("--checks", type=int, default=50)
    options = parser.parse_args()
    root = Path(tempfile.mkdtemp(prefix="bench-studio-"))
    shutil.copytree(REPO / "pddl", root / "pddl")
    try:
        starts, process, port = [], None, 0
        for _ in range(options.starts):
            if process is not None:
                process.terminate()
                process.wait()
            process, port, seconds = start_studio(root)
            starts.append(seconds)
        reference = min(reference_start() for _ in range(options.starts))
        round_trips = checks(port, options.checks)
        completing = completions(port, options.checks)
        alone = engine(options.checks)
        assert process is not None
        process.terminate()
        process.wait()
    finally:
        shutil.rmtree(root, ignore_errors=True)
    print(
        f"start-up to serving /author: min {min(starts):.2f} s, median {statistics.median(starts):.2f} s "
        f"(target < 3 s); python -m vslsp --help: {reference:.2f} s; ratio {min(starts) / reference:.1f}x"
    )
    print(
        f"check round trip (POST /api/check, shipped domain + problem): min {1000 * min(round_trips):.1f} ms, "
        f"median {1000 * statistics.median(round_trips):.1f} ms (target < 100 ms); the engine alone: "
        f"min {1000 * min(alone):.1f} ms; ratio {min(round_trips) / min(alone):.1f}x"
    )
    print(
        f"completion round trip (POST /api/complete, Ctrl-Space): min {1000 * min(completing):.1f} ms, "
        f"median {1000 * statistics.median(completing):.1f} ms; ratio to the engine alone "
        f"{min(completing) / min(alone):.1f}x"
    )
    print(f"cpus: {os.cpu_count()}, load: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
