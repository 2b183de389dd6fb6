"""The server's commands ``vslsp.plan`` and ``vslsp.validate``: exactly the JSON of ``vslsp plan --json``
and ``vslsp validate --json`` (docs/cli.md), because they run that command.

The command line runs as a child process (``python -m vslsp plan ... --json``), off the server's event
loop: the server keeps answering while Fast Downward searches (``timeout`` bounds a search; the
server's end stops one still running), and whatever the command line prints or adds to its JSON (a
conflict's explanation, located violations) comes through as the user would see it in a terminal.
The editor's text is what is planned: a document with unsaved edits is written to a private
temporary folder under its own file name, and that folder's paths are named back as the document's
own in the result. Arguments name the files (URIs or paths; a problem's domain is found as for
diagnostics; none: the problem and plan last opened or edited). The user is also told the outcome
(``window/showMessage``), as an editor bound to a key shows nothing of a command's result.
"""

from __future__ import annotations

import asyncio
import json
import logging
import os
import re
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lsprotocol import types

import vslsp
from vslsp.lsp.workspace import Files, path_of, uri_of
from vslsp.symbolic.language import WARNING, Diagnostic, Span

logger = logging.getLogger(__name__)
_NAME = re.compile(r"[^\s()]+")
#: The options of ``vslsp plan`` a ``vslsp.plan`` object may give (as the command line's ``--NAME VALUE``).
PLAN_OPTIONS = ("planner", "compilation", "timeout", "memory", "conflict_budget")


@dataclass(frozen=True)
class Source:
    """A file's text as the editor holds it; ``name`` is its path (what messages call it)."""

    name: str
    text: str


def plan_arguments(sources: dict[str, Path], options: dict[str, Any]) -> list[str]:
    """``vslsp plan``'s command line for ``sources`` (domain, problem) and the options given."""
    arguments = ["plan", str(sources["domain"]), str(sources["problem"])]
    for option in PLAN_OPTIONS:
        if options.get(option) is not None:
            arguments += [f"--{option.replace('_', '-')}", str(options[option])]
    return arguments


def validate_arguments(sources: dict[str, Path], options: dict[str, Any]) -> list[str]:
    return ["validate", str(sources["domain"]), str(sources["problem"]), str(sources["plan"])]


async def run_cli(
    make_arguments: Callable[[dict[str, Path], dict[str, Any]], list[str]],
    sources: dict[str, Source],
    options: dict[str, Any],
    failure: dict[str, Any],
) -> dict[str, Any]:
    """``python -m vslsp ARGUMENTS --json`` on ``sources`` (unsaved ones as private copies), its JSON with
    the copies' paths named back as the documents' own; ``failure`` + the error should it print none."""
    with tempfile.TemporaryDirectory(prefix="vslsp-lsp-") as folder:
        paths: dict[str, Path] = {}
        renamed: dict[str, str] = {}
        for role, source in sources.items():
            if _saved(source):
                paths[role] = Path(source.name)
                continue
            copy = Path(folder, role, Path(source.name).name)
            copy.parent.mkdir()
            copy.write_text(source.text, encoding="utf-8")
            paths[role] = copy
            renamed[str(copy)] = source.name
        command = [sys.executable, "-m", "vslsp", *make_arguments(paths, options), "--json"]
        package_root = str(Path(vslsp.__file__).resolve().parents[1])  # the same vslsp as this server
        env = {
            **os.environ,
            "PYTHONPATH": os.pathsep.join(p for p in (package_root, os.environ.get("PYTHONPATH")) if p),
        }
        process = await asyncio.create_subprocess_exec(
            *command,
            stdin=asyncio.subprocess.DEVNULL,
            stdout=asyncio.subprocess.PIPE,
            stderr=asyncio.subprocess.PIPE,
            env=env,
        )
        try:
            out, err = await process.communicate()
        except asyncio.CancelledError:  # the server is ending: stop the planner too
            process.kill()
            await process.wait()
            raise
    try:
        result = json.loads(out)
    except ValueError:
        said = err.decode(errors="replace").strip().splitlines()
        logger.error("%s printed no JSON: %s", " ".join(command), "\n".join(said))
        reason = said[-1] if said else f"exit code {process.returncode}"
        result = {
            **failure,
            "error": f"internal error (vslsp printed no JSON: {reason})",
            "exit_code": 3,
            "warnings": [],
        }
    return _named_back(result, renamed)


def _saved(source: Source) -> bool:
    """Whether ``source``'s file on disk holds the editor's text (then the command reads the file itself)."""
    try:
        return Path(source.name).read_bytes().decode("utf-8-sig") == source.text
    except (OSError, UnicodeDecodeError):
        return False


def _named_back(value: Any, renamed: dict[str, str]) -> Any:
    """``value`` with each private copy's path replaced by the document's own, in every string."""
    if not renamed:
        return value
    if isinstance(value, str):
        for copy, original in renamed.items():
            value = value.replace(copy, original)
        return value
    if isinstance(value, list):
        return [_named_back(item, renamed) for item in value]
    if isinstance(value, dict):
        return {key: _named_back(item, renamed) for key, item in value.items()}
    return value


def named(arguments: tuple[Any, ...], names: tuple[str, ...], last: dict[str, str]) -> dict[str, Any]:
    """A command's arguments by name: one object, or the files in order (the domain may be left out);
    with none, the problem and plan last opened or edited (``last``: kind -> URI)."""
    if len(arguments) == 1 and isinstance(arguments[0], dict):
        return dict(arguments[0])
    if not arguments:
        return {name: last[name] for name in names if name in last}
    files = [str(a) for a in arguments]
    return dict(zip(names[len(names) - len(files) :] if len(files) < len(names) else names, files))


def sources(
    files: Files, given: dict[str, Any], names: tuple[str, ...], failure: dict[str, Any]
) -> tuple[dict[str, Source], dict[str, Any]]:
    """The editor's text of each named file (the problem's domain found when not given), or else the
    CLI's failure object (exit code 2) saying what is missing."""

    def fail(message: str) -> tuple[dict[str, Source], dict[str, Any]]:
        return {}, {**failure, "error": message, "exit_code": 2, "warnings": []}

    uris = {name: as_uri(str(given[name])) for name in names if given.get(name)}
    if "problem" not in uris:
        return fail(f"give the problem: arguments {list(names)} as URIs or paths, or one object with those keys")
    if "plan" in names and "plan" not in uris:
        return fail("give the plan to validate (a .plan file, one (action arg ...) per line)")
    if "domain" not in uris:
        domain = files.domain_for(uris["problem"])
        if domain is None:
            header = files.header(uris["problem"])
            return fail(
                f"{path_of(uris['problem'])}: no domain '{header.domain}' among the open documents and the "
                ".pddl files of its folder; give the domain too"
            )
        uris["domain"] = domain
    sources: dict[str, Source] = {}
    for name in names:
        text = files.text(uris[name])
        if text is None:
            return fail(f"{path_of(uris[name])}: cannot read the file (not open in the editor, not on disk)")
        sources[name] = Source(path_of(uris[name]), text)
    return sources, {}


def as_uri(given: str) -> str:
    return given if "://" in given or given.startswith("file:") else uri_of(os.path.abspath(given))


def told(command: str, result: dict[str, Any]) -> types.ShowMessageParams:
    """What the user is shown of a command's result: the plan or the verdict, or the error; why there is
    no plan (the conflicting goal conjuncts and constraints) and every violation of an invalid plan,
    each with its line."""
    if "error" in result:
        kind = types.MessageType.Error if result.get("exit_code") != 1 else types.MessageType.Warning
        conflict = result.get("conflict") or []
        why = "; ".join(f"{c['text']} (line {c['line']})" for c in conflict)
        because = "".join(f"; because: {reason}" for reason in result.get("reasons") or [])
        return types.ShowMessageParams(
            kind, f"{command}: {result['error']}" + (f"; these cannot all hold: {why}" if why else "") + because
        )
    if command.endswith("plan"):
        steps = result["plan"]
        listed = "; ".join(f"{n}. {step}" for n, step in enumerate(steps, 1))
        count = f"{len(steps)} step{'' if len(steps) == 1 else 's'}"
        said = f"{count} ({result['planner']}, {result['time_s']:.2f} s): {listed}"
        return types.ShowMessageParams(types.MessageType.Info, f"{command}: {said}")
    kind = types.MessageType.Info if result["valid"] else types.MessageType.Warning
    broken = result.get("violations") or []
    said = "; ".join(v["message"] + (f" (line {v['line']})" if v.get("line") else "") for v in broken)
    return types.ShowMessageParams(
        kind, f"{command}: {'valid' if result['valid'] else 'invalid'}: {said or result['reason']}"
    )


def findings(result: dict[str, Any], texts: Callable[[str], str | None]) -> dict[str, list[Diagnostic]]:
    """A command's findings as diagnostics, by document URI: each goal conjunct and constraint of a
    proved conflict, and each violation of an invalid plan, at the formula or step it names (``texts``
    gives a URI's text, to find the formula's extent)."""
    found: dict[str, list[Diagnostic]] = {}
    conflict = result.get("conflict") or []
    for item in conflict:
        others = [c["text"] for c in conflict if c is not item]
        message = f"no plan: this {item['kind']} cannot hold together with {', '.join(others) or 'the rest'}"
        message += "".join(f"; {reason}" for reason in result.get("reasons") or [] if reason.startswith(item["text"]))
        _found_at(found, item, message, "conflict", texts)
    for item in result.get("violations") or []:
        _found_at(found, item, item["message"], "violation", texts)
    return found


def _found_at(
    found: dict[str, list[Diagnostic]],
    item: dict[str, Any],
    message: str,
    code: str,
    texts: Callable[[str], str | None],
) -> None:
    if not item.get("file") or not item.get("line") or not item.get("column"):
        return
    uri = as_uri(item["file"])
    line, column = int(item["line"]), int(item["column"])
    end = _extent(texts(uri) or "", line, column)
    span = Span(path_of(uri), line, column, *end)
    found.setdefault(uri, []).append(Diagnostic(span, WARNING, message, code))


def _extent(text: str, line: int, column: int) -> tuple[int, int]:
    """Where the formula or name starting at (``line``, ``column``) ends (its line and the column after it)."""
    lines = text.split("\n")
    if not 0 < line <= len(lines) or column > len(lines[line - 1]):
        return line, column + 1
    if lines[line - 1][column - 1] != "(":
        word = _NAME.match(lines[line - 1], column - 1)
        return line, column + (len(word.group()) if word else 1)
    depth = 0
    for number in range(line, len(lines) + 1):
        code = lines[number - 1].split(";", 1)[0]
        start = column - 1 if number == line else 0
        for index in range(start, len(code)):
            depth += {"(": 1, ")": -1}.get(code[index], 0)
            if depth == 0:
                return number, index + 2
    return line, column + 1
