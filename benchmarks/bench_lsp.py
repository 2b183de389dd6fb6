"""Language-server benchmark: how long ``vslsp lsp`` takes to re-check an edited document, measured
through the server (issue 25, target <= 20 ms for files of the shipped domain's size).

A real client (pygls) starts ``python -m vslsp lsp`` and opens the shipped domain and problem
(pddl/domain.pddl, pddl/pull-in-order.pddl); each edit is one ``textDocument/didChange`` (a typo put
in or taken out, so that every edit changes the diagnostics), and the time is from sending it to
receiving the ``publishDiagnostics`` of that version: the engine's analysis, the conversion to LSP
and the JSON-RPC round trip over the pipes. Edits of the problem re-check it with its domain; edits of
the domain re-check the domain and the open problem (two publications; the time is to the last).

The reference, measured in the same run: the engine alone on the same texts
(:func:`vslsp.symbolic.language.analyse`, in this process), so that the server's share shows as a
ratio. Each figure is the minimum over the runs (wall time: the client waits on a pipe, so CPU time
would not see the server's work; the machine may be shared, and the minimum is the run least
disturbed by the other programs).

    .venv/bin/python benchmarks/bench_lsp.py [--edits 50] [--json results.json]
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import statistics
import sys
import time
from pathlib import Path

from lsprotocol import types
from pygls.lsp.client import LanguageClient

from vslsp.lsp.workspace import uri_of
from vslsp.symbolic.language import analyse

REPO = Path(__file__).resolve().parents[1]
ROVERS = REPO / "tests" / "data" / "pddl3" / "ipc2006" / "rovers-preferences-qualitative"
#: (name, domain, problem): the shipped pair (the target's size), and a larger IPC-2006 pair for information.
PAIRS = (
    ("shipped", REPO / "pddl" / "domain.pddl", REPO / "pddl" / "pull-in-order.pddl"),
    ("ipc2006 rovers", ROVERS / "domain.pddl", ROVERS / "instance-3.pddl"),
)
TARGET_MS = 20.0


def with_typo(text: str, problem: bool) -> str:
    """``text`` with one more diagnostic: an undeclared predicate in the problem's initial state, an
    unused one among the domain's predicates."""
    section = "(:init" if problem else "(:predicates"
    at = text.lower().index(section) + len(section)
    return text[:at] + " (xtypo)" + text[at:]


class Timed:
    """The client's side: when each document version's diagnostics arrived."""

    def __init__(self) -> None:
        self.client = LanguageClient("bench-lsp", "1")
        self.arrived: dict[tuple[str, int | None], asyncio.Event] = {}

        @self.client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def published(params: types.PublishDiagnosticsParams) -> None:
            self.arrived.setdefault((params.uri, params.version), asyncio.Event()).set()

    async def wait(self, uri: str, version: int) -> None:
        await asyncio.wait_for(self.arrived.setdefault((uri, version), asyncio.Event()).wait(), 60)


async def through_server(domain: Path, problem: Path, edits: int) -> dict[str, list[float]]:
    """Seconds from each didChange to the diagnostics of its version, problem edits then domain edits."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")])}
    timed = Timed()
    client = timed.client
    await client.start_io(sys.executable, "-m", "vslsp", "lsp", env=env)
    capabilities = types.ClientCapabilities()
    await client.initialize_async(types.InitializeParams(capabilities=capabilities, process_id=os.getpid()))
    client.initialized(types.InitializedParams())
    texts = {domain: domain.read_text(), problem: problem.read_text()}
    for path, text in texts.items():
        client.text_document_did_open(
            types.DidOpenTextDocumentParams(types.TextDocumentItem(uri_of(path), "pddl", 1, text))
        )
        await timed.wait(uri_of(path), 1)
    times: dict[str, list[float]] = {"problem": [], "domain": []}
    problem_version = 1
    for name, path in (("problem", problem), ("domain", domain)):
        uri = uri_of(path)
        for version in range(2, edits + 2):
            text = with_typo(texts[path], path == problem) if version % 2 == 0 else texts[path]
            if path == problem:
                problem_version = version
            last = uri_of(problem)  # a domain edit ends with its open problem's publication
            timed.arrived.pop((last, problem_version), None)
            start = time.perf_counter()
            client.text_document_did_change(
                types.DidChangeTextDocumentParams(
                    types.VersionedTextDocumentIdentifier(version, uri),
                    [types.TextDocumentContentChangeWholeDocument(text)],
                )
            )
            await timed.wait(last, problem_version)
            times[name].append(time.perf_counter() - start)
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()
    return times


def engine_alone(domain: Path, problem: Path, runs: int) -> list[float]:
    """The reference: the engine's analysis of the pair (the problem's typo in every other run, as the
    server saw it), in this process."""
    domain_text, problem_text = domain.read_text(), problem.read_text()
    typo = with_typo(problem_text, True)
    times = []
    for run in range(runs):
        start = time.perf_counter()
        analyse(domain_text, str(domain), typo if run % 2 == 0 else problem_text, str(problem))
        times.append(time.perf_counter() - start)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--edits", type=int, default=50, help="edits of each document (default 50)")
    parser.add_argument("--json", type=Path, default=None, help="also write the figures there")
    args = parser.parse_args()
    results: dict[str, object] = {"edits": args.edits, "target_ms": TARGET_MS}
    print(f"re-check after an edit, {args.edits} edits of each document; min (median) in ms")
    for label, domain, problem in PAIRS:
        server = asyncio.run(through_server(domain, problem, args.edits))
        engine = engine_alone(domain, problem, args.edits)
        size = domain.stat().st_size + problem.stat().st_size
        engine_ms = min(engine) * 1000
        print(f"{label} ({domain.name} + {problem.name}, {size} bytes):")
        print(
            f"  engine alone (analyse, in process, reference): {engine_ms:.2f} ({statistics.median(engine) * 1000:.2f})"
        )
        entry: dict[str, object] = {
            "bytes": size,
            "engine_ms": {"min": engine_ms, "median": statistics.median(engine) * 1000},
        }
        for name, times in server.items():
            best = min(times) * 1000
            verdict = "ok" if best <= TARGET_MS else "OVER"
            print(
                f"  through the server, {name} edited -> diagnostics: {best:.2f} "
                f"({statistics.median(times) * 1000:.2f}), {best / engine_ms:.1f}x the engine; "
                f"target <= {TARGET_MS:.0f} ms: {verdict}"
            )
            entry[f"recheck_{name}_ms"] = {"min": best, "median": statistics.median(times) * 1000}
        results[label] = entry
    if args.json:
        args.json.write_text(json.dumps(results, indent=2))


if __name__ == "__main__":
    main()
