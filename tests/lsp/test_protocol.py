"""JSON-RPC 2.0 and the LSP 3.17 lifecycle, against the real ``vslsp lsp`` over raw stdio: every request
gets exactly one response with the code the specifications give, a malformed frame costs only itself,
and ``exit`` ends the server with 0 after ``shutdown``, 1 without (vslsp/lsp/protocol.py, rpc.py)."""

from __future__ import annotations

import asyncio
import json
import shutil
from pathlib import Path
from typing import Any

import pytest
from helpers.lsp import DATA
from wire import Wire, frame

from vslsp.lsp import navigation
from vslsp.lsp.protocol import (
    INTERNAL_ERROR,
    INVALID_PARAMS,
    INVALID_REQUEST,
    PARSE_ERROR,
    SERVER_NOT_INITIALIZED,
)
from vslsp.lsp.rpc import Framer
from vslsp.lsp.server import build_server
from vslsp.lsp.workspace import uri_of

HOVER = "textDocument/hover"


@pytest.fixture
def kitchen(tmp_path: Path) -> Path:
    shutil.copytree(DATA / "kitchen", tmp_path / "kitchen")
    return tmp_path / "kitchen"


@pytest.fixture
def wire(tmp_path: Path, kitchen: Path):
    """A server initialized on the kitchen folder, its domain open."""
    started = Wire(tmp_path / "server.log")
    started.initialize(kitchen.parent)
    started.open(kitchen / "domain.pddl", (kitchen / "domain.pddl").read_text())
    yield started
    started.close()
    assert "Traceback" not in started.log.read_text()


def at(path: Path, line: Any, character: Any) -> dict[str, Any]:
    return {"textDocument": {"uri": uri_of(path)}, "position": {"line": line, "character": character}}


def body(message: dict[str, Any]) -> bytes:
    return json.dumps(message).encode()


HOVER_BODY = body({"jsonrpc": "2.0", "id": 990, "method": HOVER, "params": {}})
MALFORMED = {
    "Content-Length: abc": b"Content-Length: abc\r\n\r\n" + HOVER_BODY,
    "a header without Content-Length": b"Content-Type: application/json\r\n\r\n" + HOVER_BODY,
    "a length shorter than the body": b"Content-Length: 20\r\n\r\n" + HOVER_BODY,
    "a length longer than the body": b"Content-Length: 900\r\n\r\n" + HOVER_BODY,
    "garbage": b"\x00\x01 not a frame at all \xff",
    "invalid JSON": b'Content-Length: 16\r\n\r\n{"jsonrpc": 2.0,',
}


@pytest.mark.parametrize("malformed", MALFORMED.values(), ids=MALFORMED.keys())
def test_after_a_malformed_frame_the_next_requests_are_answered(wire: Wire, kitchen: Path, malformed: bytes):
    wire.send(malformed)
    answers = [wire.ask(HOVER, at(kitchen / "domain.pddl", 7, 6)) for _ in range(3)]
    assert all("(on-counter ?d - dish)" in a["result"]["contents"]["value"] for a in answers)
    (error,) = wire.null_id_errors()  # the malformed frame, reported once with id null
    assert error["code"] == PARSE_ERROR and error["message"].startswith("Parse error: ")
    assert not wire.responses(990)  # the request inside a malformed frame is not guessed at


def test_invalid_json_is_a_parse_error_with_id_null(wire: Wire):
    wire.send(b"Content-Length: 9\r\n\r\n{invalid}")
    wire.ask("shutdown")
    (error,) = wire.null_id_errors()
    assert error == {"code": PARSE_ERROR, "message": error["message"]}  # no data: no traceback
    assert "invalid JSON" in error["message"]


NOT_REQUESTS = {
    "a number": (5, None),
    "an empty batch": ([], None),
    "jsonrpc 1.0": ({"jsonrpc": "1.0", "id": 41, "method": HOVER}, 41),
    "no jsonrpc": ({"id": 42, "method": HOVER}, 42),
    "a fractional id": ({"jsonrpc": "2.0", "id": 4.5, "method": HOVER}, None),
    "a boolean id": ({"jsonrpc": "2.0", "id": True, "method": HOVER}, None),
    "a method that is no string": ({"jsonrpc": "2.0", "id": 43, "method": 7}, 43),
    "params that are a string": ({"jsonrpc": "2.0", "id": 44, "method": HOVER, "params": "x"}, 44),
    "neither request nor response": ({"jsonrpc": "2.0", "id": 45}, 45),
}


@pytest.mark.parametrize(("message", "answered_as"), NOT_REQUESTS.values(), ids=NOT_REQUESTS.keys())
def test_a_message_that_is_no_request_is_an_invalid_request(wire: Wire, message: Any, answered_as: Any):
    wire.send(frame(message))
    wire.ask("shutdown")  # answered after it: the refusal is there by then
    (error,) = [r["error"] for r in wire.responses(answered_as)]
    assert error["code"] == INVALID_REQUEST and set(error) == {"code", "message"}


def test_a_batch_s_requests_are_each_answered(wire: Wire, kitchen: Path):
    hover = {"jsonrpc": "2.0", "method": HOVER, "params": at(kitchen / "domain.pddl", 7, 6)}
    wire.send(frame([{**hover, "id": 61}, {"jsonrpc": "2.0", "method": "$/nothing"}, {**hover, "id": 62}]))
    assert all("result" in wire.answer(i) for i in (61, 62))


WRONG = {
    '"line": "zero"': (at(Path("/k/domain.pddl"), "zero", 0), "$.params.position"),
    '"line": "5"': (at(Path("/k/domain.pddl"), "5", 0), "'line' must be an integer, got a string"),
    '"character": true': (at(Path("/k/domain.pddl"), 0, True), "'character' must be an integer, got a boolean"),
    '"line": 1.5': (at(Path("/k/domain.pddl"), 1.5, 0), "'line' must be an integer, got a number"),
    '"uri": 5': ({**at(Path("/k"), 0, 0), "textDocument": {"uri": 5}}, "got an integer @ $.params.textDocument.uri"),
    "no position": ({"textDocument": {"uri": "file:///k/domain.pddl"}}, "$.params.position"),
    "params an array": ([1, 2], "$.params"),
}


@pytest.mark.parametrize(("params", "said"), WRONG.values(), ids=WRONG.keys())
def test_wrong_typed_params_are_invalid_params(wire: Wire, params: Any, said: str):
    for method in (HOVER, "textDocument/completion", "textDocument/definition"):
        error = wire.error_of(wire.request(method, params))
        assert error["code"] == INVALID_PARAMS and set(error) == {"code", "message"}
        assert error["message"].startswith(f"Invalid params for '{method}': ") and said in error["message"]
        assert "\n" not in error["message"]


def test_positions_before_the_start_or_past_the_end_are_clamped(wire: Wire, kitchen: Path):
    domain = kitchen / "domain.pddl"
    completion = "textDocument/completion"
    assert wire.ask(completion, at(domain, -3, -3))["result"] == wire.ask(completion, at(domain, 0, 0))["result"]
    last = len((domain).read_text().split("\n")) - 1
    assert wire.ask(HOVER, at(domain, 7, 10**6))["result"] == wire.ask(HOVER, at(domain, 7, 27))["result"]
    end = wire.ask(completion, at(domain, last, 0))["result"]
    assert wire.ask(completion, at(domain, 10**9, 10**9))["result"] == end
    assert wire.ask(completion, at(domain, 2**40, 2**40))["result"] == end


def test_a_reversed_range_is_read_start_first(wire: Wire, kitchen: Path):
    text = (kitchen / "domain.pddl").read_text().replace("(clean ?d)", "(clen ?d)")  # a quick fix to find
    wire.notify(
        "textDocument/didChange",
        {
            "textDocument": {"uri": uri_of(kitchen / "domain.pddl"), "version": 2},
            "contentChanges": [{"text": text}],
        },
    )
    forward = {"start": {"line": 0, "character": 0}, "end": {"line": 40, "character": 0}}
    backward = {"start": forward["end"], "end": forward["start"]}
    asked = [
        wire.ask(
            "textDocument/codeAction",
            {"textDocument": {"uri": uri_of(kitchen / "domain.pddl")}, "range": span, "context": {"diagnostics": []}},
        )
        for span in (forward, backward, {"start": {"line": -9, "character": -9}, "end": forward["end"]})
    ]
    assert asked[0]["result"] and all(a["result"] == asked[0]["result"] for a in asked)


def test_a_request_before_initialize_is_refused_and_notifications_dropped(tmp_path: Path, kitchen: Path):
    wire = Wire(tmp_path / "server.log")
    try:
        wire.open(kitchen / "domain.pddl", "(define (domain x) (:predicates (p))")
        error = wire.error_of(wire.request(HOVER, at(kitchen / "domain.pddl", 0, 0)))
        assert error["code"] == SERVER_NOT_INITIALIZED and "initialize" in error["message"]
        assert "result" in wire.initialize(kitchen.parent)
        assert wire.error_of(wire.request("initialize", {"capabilities": {}}))["code"] == INVALID_REQUEST
        wire.ask("textDocument/documentSymbol", {"textDocument": {"uri": uri_of(kitchen / "domain.pddl")}})
        assert wire.published(uri_of(kitchen / "domain.pddl")) == []  # the didOpen before initialize was dropped
        assert wire.exit_code() == 0
    finally:
        wire.close()


def test_a_request_after_shutdown_is_an_invalid_request_and_exit_ends_with_0(wire: Wire, kitchen: Path):
    assert wire.ask("shutdown") == {"jsonrpc": "2.0", "id": wire._next_id, "result": None}
    for method in (HOVER, "shutdown", "vslsp/unknown"):
        error = wire.error_of(wire.request(method, at(kitchen / "domain.pddl", 0, 0)))
        assert error["code"] == INVALID_REQUEST and "after 'shutdown'" in error["message"]
    assert wire.exit_code(shutdown=False) == 0


def test_exit_without_shutdown_ends_with_1(wire: Wire):
    assert wire.exit_code(shutdown=False) == 1


def test_exit_before_initialize_ends_with_1(tmp_path: Path):
    wire = Wire(tmp_path / "server.log")
    assert wire.exit_code(shutdown=False) == 1


def test_a_nested_document_too_deep_to_analyse_gets_one_error(wire: Wire, kitchen: Path):
    deep = kitchen / "deep.pddl"
    depth = 100_000
    text = "(define (domain deep)\n (:predicates (p))\n (:action a :parameters ()\n  :precondition "
    text += "(and " * depth + "(p)" + ")" * depth + "\n  :effect (p)))\n"
    wire.open(deep, text)
    symbols = wire.ask("textDocument/documentSymbol", {"textDocument": {"uri": uri_of(deep)}})
    assert symbols["result"] == []
    assert "result" in wire.ask("textDocument/completion", at(deep, 3, 500))  # answered, from the text alone
    (published,) = wire.published(uri_of(deep))
    (error,) = published
    assert error["message"].startswith("nested too deeply (limit 256)")
    assert error["severity"] == 1 and error["code"] == "nested-too-deeply"
    assert error["range"]["start"] == {"line": 3, "character": 16 + 5 * 254}  # the 257th '('


# In the server's own process: what pygls keeps, and what a bug of the server's answers.


async def _session(messages: list[Any]) -> tuple[Any, list[Any]]:
    """A server fed ``messages`` in this process; the server and what it wrote."""
    server = build_server()
    written = Framer()
    out: list[Any] = []

    class Writer:
        def write(self, data: bytes) -> None:
            out.extend(found.value for found in written.feed(data))

        def close(self) -> None:
            pass

    server.protocol.set_writer(Writer())
    for message in messages:
        for found in Framer().feed(frame(message)):
            server.protocol.receive(found)
        await asyncio.sleep(0)
    return server, out


def _message(method: str, params: Any, msg_id: int | None = None) -> dict[str, Any]:
    message = {"jsonrpc": "2.0", "method": method, "params": params}
    return message if msg_id is None else {**message, "id": msg_id}


def _opened(uri: str, text: str) -> dict[str, Any]:
    document = {"uri": uri, "languageId": "pddl", "version": 1, "text": text}
    return _message("textDocument/didOpen", {"textDocument": document})


def _changed(uri: str, version: int, change: dict[str, Any]) -> dict[str, Any]:
    params = {"textDocument": {"uri": uri, "version": version}, "contentChanges": [change]}
    return _message("textDocument/didChange", params)


def test_no_future_is_kept_per_notification_or_request(kitchen: Path):
    domain = uri_of(kitchen / "domain.pddl")
    text = (kitchen / "domain.pddl").read_text()
    messages = [
        _message("initialize", {"capabilities": {}, "rootUri": uri_of(kitchen)}, 1),
        _message("initialized", {}),
        _opened(domain, text),
    ]
    for version in range(2, 302):
        change = {"range": {"start": {"line": 0, "character": 0}, "end": {"line": 0, "character": 0}}, "text": " "}
        messages.append(_changed(domain, version, change))
        messages.append(
            _message(HOVER, {"textDocument": {"uri": domain}, "position": {"line": 7, "character": 6}}, version)
        )
    server, out = asyncio.run(_session(messages))
    assert server.protocol._request_futures == {}
    assert len([m for m in out if "id" in m and "result" in m]) == 301


def test_a_bug_of_the_server_s_is_one_line_without_its_traceback(kitchen: Path, monkeypatch):
    def broken(*_: Any) -> None:
        raise RuntimeError("the outline broke\n  at line 3")

    monkeypatch.setattr(navigation, "outline", broken)
    domain = uri_of(kitchen / "domain.pddl")
    messages = [
        _message("initialize", {"capabilities": {}}, 1),
        _message("textDocument/documentSymbol", {"textDocument": {"uri": domain}}, 2),
    ]
    _, out = asyncio.run(_session(messages))
    (answer,) = [m for m in out if m.get("id") == 2]
    assert answer["error"] == {
        "code": INTERNAL_ERROR,
        "message": "Internal error: RuntimeError: the outline broke at line 3",
    }


def test_an_edit_past_the_end_is_made_at_the_end_and_one_of_a_closed_document_dropped(kitchen: Path):
    uri = uri_of(kitchen / "new.pddl")
    text = "(define (domain d)\n  (:predicates (p)))"

    def edit(version: int, start: tuple[int, int], end: tuple[int, int], inserted: str, to: str = uri) -> Any:
        span = {"start": dict(zip(("line", "character"), start)), "end": dict(zip(("line", "character"), end))}
        return _changed(to, version, {"range": span, "text": inserted})

    messages = [
        _message("initialize", {"capabilities": {}}, 1),
        _opened(uri, text),
        edit(2, (10**6, 0), (10**6, 5), "\n; the end"),  # past the last line: at the end
        edit(3, (0, 10**6), (0, 10**6), " ; one"),  # past the line's end: at its end
        edit(4, (1, 15), (1, 2), ""),  # end first: the text between goes
        edit(5, (0, 0), (0, 0), "x", to=uri_of(kitchen / "closed.pddl")),
    ]
    server, _ = asyncio.run(_session(messages))
    assert server.workspace.get_text_document(uri).source == "(define (domain d) ; one\n  (p)))\n; the end"
