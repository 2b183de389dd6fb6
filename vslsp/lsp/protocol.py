"""JSON-RPC 2.0 and the LSP 3.17 lifecycle on top of pygls: every request gets exactly one response.

pygls takes a message only once it is typed; what it cannot type it logs and drops, and a handler's
exception goes back with its traceback. Here each message is checked before pygls sees it, and
refused with the code the specifications give (JSON-RPC 2.0 section 5.1; LSP 3.17 "Response
Message", "initialize", "shutdown", "exit"):

=======  ==========================================================================================
-32700   a frame that is no JSON (answered with id null; :mod:`vslsp.lsp.rpc` finds the next frame)
-32600   no message object, a bad ``jsonrpc``/``id``/``method``/``params``, a second ``initialize``,
         a request after ``shutdown``
-32601   a method the server does not have
-32602   params of the wrong shape or type (``"line": "zero"``), with the place that is wrong
-32002   a request before ``initialize``
-32803   a request the server understood but refuses (a rename to a name PDDL does not allow)
-32603   a bug of the server's: one line, the traceback only in the server's log
=======  ==========================================================================================

Notifications are never answered; before ``initialize`` and after ``shutdown`` they are dropped but
``exit``, which ends the server with code 0 after ``shutdown`` and 1 without. Positions are read
leniently as LSP asks: a negative line or character is 0 (the server clamps a place past the end to
the end of its document), and a range given end first is read start first.
"""

from __future__ import annotations

import json
import logging
import re
from collections.abc import Callable
from typing import Any
from urllib.parse import unquote

import cattrs
from cattrs.v import format_exception
from lsprotocol import types
from pygls.exceptions import JsonRpcException
from pygls.protocol import (
    JsonRPCNotification,
    JsonRPCRequestMessage,
    JsonRPCResponseMessage,
    LanguageServerProtocol,
    default_converter,
    lsp_method,
)

from vslsp.lsp.positions import UTF16, clamped
from vslsp.lsp.rpc import Invalid, Message

logger = logging.getLogger("vslsp.lsp")

PARSE_ERROR = -32700
INVALID_REQUEST = -32600
INVALID_PARAMS = -32602
INTERNAL_ERROR = -32603
SERVER_NOT_INITIALIZED = -32002
REQUEST_CANCELLED = -32800
REQUEST_FAILED = -32803
#: LSP's ``uinteger``: a line or character above it is read as it.
MAX_UINTEGER = 2**31 - 1


class WrongType(TypeError):
    """A value of the wrong JSON type in params; its message says which and what it should be."""


class RequestFailed(JsonRpcException):
    """A request the server understood but cannot carry out; its message says why, in one line."""

    CODE = REQUEST_FAILED
    MESSAGE = "Request failed"


def strict_converter() -> cattrs.Converter:
    """pygls' converter, but a number is no string, a string no number and ``true`` no 1 (cattrs
    would call ``int("5")``), positions are clamped to LSP's ``uinteger`` and ranges put in order."""
    converter = default_converter()

    def exactly(kind: type, name: str) -> Callable[[Any, type], Any]:
        def structure(value: Any, _: type) -> Any:
            if isinstance(value, bool) != (kind is bool) or not isinstance(value, kind):
                raise WrongType(f"expected {name}, got {_json_type(value)}")
            return value

        return structure

    converter.register_structure_hook(int, exactly(int, "an integer"))
    converter.register_structure_hook(str, exactly(str, "a string"))
    converter.register_structure_hook(bool, exactly(bool, "a boolean"))
    converter.register_structure_hook(float, exactly((int, float), "a number"))  # type: ignore[arg-type]

    def position(value: Any, _: type) -> types.Position:
        if not isinstance(value, dict):
            raise WrongType(f"expected a position object, got {_json_type(value)}")
        line, character = (_uinteger(value.get(key), key) for key in ("line", "character"))
        return types.Position(line, character)

    def range_(value: Any, _: type) -> types.Range:
        if not isinstance(value, dict):
            raise WrongType(f"expected a range object, got {_json_type(value)}")
        start, end = position(value.get("start"), types.Position), position(value.get("end"), types.Position)
        if (end.line, end.character) < (start.line, start.character):
            start, end = end, start
        return types.Range(start, end)

    converter.register_structure_hook(types.Position, position)
    converter.register_structure_hook(types.Range, range_)
    return converter


def _uinteger(value: Any, key: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise WrongType(f"'{key}' must be an integer, got {_json_type(value)}")
    return min(max(value, 0), MAX_UINTEGER)


def _json_type(value: Any) -> str:
    names = {bool: "a boolean", int: "an integer", float: "a number", str: "a string", list: "an array"}
    if value is None:
        return "null"
    return names.get(type(value), "an object")


def one_line(text: str, limit: int = 300) -> str:
    line = " ".join(str(text).split())
    return line if len(line) <= limit else line[: limit - 3] + "..."


class PddlProtocol(LanguageServerProtocol):
    """The server's side of the connection; :meth:`receive` takes what :mod:`vslsp.lsp.rpc` read."""

    def __init__(self, server: Any, converter: cattrs.Converter):
        super().__init__(server, converter)
        self.initialized = False  # an initialize request was taken
        #: Set by ``exit``: 0 after ``shutdown``, else 1; the reading loop ends then.
        self.exit_code: int | None = None

    def receive(self, found: Message | Invalid) -> bool:
        """Handle one frame; False once ``exit`` has come (read no further)."""
        if isinstance(found, Invalid):
            logger.warning("malformed frame: %s", found.reason)
            self.refuse(None, PARSE_ERROR, f"Parse error: {found.reason}")
        elif isinstance(found.value, list):  # a batch (JSON-RPC 2.0; LSP clients send none)
            if not found.value:
                self.refuse(None, INVALID_REQUEST, "Invalid request: an empty batch")
            for item in found.value:
                if self.exit_code is None:
                    self.dispatch(item)
        else:
            self.dispatch(found.value)
        return self.exit_code is None

    def refuse(self, msg_id: Any, code: int, message: str) -> None:
        self._send_response(msg_id, error=types.ResponseError(code, one_line(message)))

    def dispatch(self, data: Any) -> None:
        """Check one message and hand it to pygls, or answer why not."""
        if not isinstance(data, dict):
            self.refuse(None, INVALID_REQUEST, f"Invalid request: a message is a JSON object, not {_json_type(data)}")
            return
        has_id = "id" in data
        msg_id = data.get("id")
        if has_id and (isinstance(msg_id, bool) or not isinstance(msg_id, int | str)):
            self.refuse(None, INVALID_REQUEST, f"Invalid request: 'id' must be an integer or a string, not {msg_id!r}")
            return
        answer = msg_id if has_id else None
        if data.get("jsonrpc") != "2.0":
            self.refuse(answer, INVALID_REQUEST, 'Invalid request: "jsonrpc" must be "2.0"')
            return
        if "method" not in data:
            if has_id and ("result" in data or "error" in data):
                self._take_response(data)
            else:
                self.refuse(
                    answer, INVALID_REQUEST, "Invalid request: neither a request, a notification nor a response"
                )
            return
        method = data["method"]
        problem = self._envelope_problem(method, data)
        if problem:
            if has_id:
                self.refuse(msg_id, INVALID_REQUEST, f"Invalid request: {problem}")
            else:
                logger.warning("notification dropped: %s", problem)
            return
        if method == types.EXIT:
            self.exit_code = 0 if self._shutdown else 1
            return
        if not has_id:
            if self.initialized and not self._shutdown:
                self._take(data, method, None)
            return
        if method == types.INITIALIZE and self.initialized:
            self.refuse(msg_id, INVALID_REQUEST, "Invalid request: the server is already initialized")
        elif not self.initialized and method != types.INITIALIZE:
            self.refuse(msg_id, SERVER_NOT_INITIALIZED, f"Server not initialized: send 'initialize' before {method!r}")
        elif self._shutdown:
            self.refuse(
                msg_id, INVALID_REQUEST, f"Invalid request: the server is shut down ({method!r} after 'shutdown')"
            )
        else:
            self._take(data, method, msg_id)

    @staticmethod
    def _envelope_problem(method: Any, data: dict[str, Any]) -> str:
        if not isinstance(method, str):
            return f"'method' must be a string, not {_json_type(method)}"
        if "params" in data and not isinstance(data["params"], dict | list):
            return f"'params' must be an object or an array, not {_json_type(data['params'])}"
        return ""

    def _take(self, data: dict[str, Any], method: str, msg_id: Any) -> None:
        message_type = self.get_message_type(method)
        try:
            message = self._converter.structure(data, message_type) if message_type else self._generic(data)
        except Exception as error:  # cattrs' errors: the wrong shape or type somewhere in params
            where = "; ".join(_problems(error))
            if msg_id is None:
                logger.warning("notification %r dropped: invalid params: %s", method, where)
            else:
                self.refuse(msg_id, INVALID_PARAMS, f"Invalid params for {method!r}: {where}")
            return
        if method == types.INITIALIZE:
            self.initialized = True
        self.handle_message(message)

    def _generic(self, data: dict[str, Any]) -> Any:
        """A message of a method lsprotocol does not know, as pygls types it (answered -32601)."""
        params = data.get("params")
        if "id" in data:
            return JsonRPCRequestMessage(id=data["id"], method=data["method"], jsonrpc="2.0", params=params)
        return JsonRPCNotification(method=data["method"], jsonrpc="2.0", params=params)

    def _take_response(self, data: dict[str, Any]) -> None:
        """A response of the client's to a request of the server's."""
        try:
            self.handle_message(self.structure_message(data))
        except Exception:
            logger.warning("a response from the client that cannot be read: %s", one_line(json.dumps(data), 200))

    @lsp_method(types.TEXT_DOCUMENT_DID_CHANGE)
    def lsp_text_document__did_change(self, params: types.DidChangeTextDocumentParams) -> Any:
        """pygls' edit, each range clamped to the document first (an edit past the end is made at the
        end); an edit of a document not open is dropped."""
        document = self.workspace.text_documents.get(unquote(params.text_document.uri))  # pygls' keys
        if document is None:
            logger.warning("an edit of %s, which is not open: dropped", params.text_document.uri)
            return
        encoding = str(self.workspace.position_encoding or UTF16)
        for change in params.content_changes:
            if isinstance(change, types.TextDocumentContentChangePartial):
                source = document.source
                start, end = (clamped(source, p, encoding) for p in (change.range.start, change.range.end))
                change.range = types.Range(start, end)
            self.workspace.update_text_document(params.text_document, change)
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_CHANGE)) is not None:
            yield handler, (params,), None

    # pygls' own paths, each sending one response without a traceback:

    def _execute_handler(self, msg_id: Any, handler: Any, callback: Any, args: Any = None, kwargs: Any = None) -> None:
        # pygls keeps the future of every notification (and of a generator's steps) under a fresh id,
        # never removed: memory grew with each keystroke. Each is removed once done.
        def done(future: Any) -> None:
            if self._request_futures.get(msg_id) is future:
                del self._request_futures[msg_id]
            callback(future)

        super()._execute_handler(msg_id, handler, done, args, kwargs)

    def _send_handler_result(self, future: Any, *, msg_id: Any) -> None:
        self._request_futures.pop(msg_id, None)
        if future.cancelled():
            self.refuse(msg_id, REQUEST_CANCELLED, f"Request {msg_id!r} cancelled")
            return
        error = future.exception()
        if error is None:
            self._send_response(msg_id, result=future.result())
        elif isinstance(error, JsonRpcException):
            self.refuse(msg_id, error.code, error.message)
        else:
            logger.error("request %r failed", msg_id, exc_info=error)
            self.refuse(msg_id, INTERNAL_ERROR, f"Internal error: {type(error).__name__}: {error}")

    def _send_response(self, msg_id: Any, result: Any = None, error: types.ResponseError | None = None) -> None:
        if error is not None:  # pygls puts a traceback in `data`: the client is told the one line
            error = types.ResponseError(error.code, one_line(error.message))
        super()._send_response(msg_id, result, error)

    def _send_data(self, data: Any) -> None:
        """Write one message; a result that cannot be written is answered as an internal error."""
        if not data or self.writer is None:
            return
        try:
            body = json.dumps(data, default=self._serialize_message)
        except Exception as failure:
            logger.error("a message cannot be written", exc_info=failure)
            if not isinstance(data, JsonRPCResponseMessage):
                return
            error = types.ResponseError(
                INTERNAL_ERROR, one_line(f"Internal error: the result cannot be written ({failure})")
            )
            body = json.dumps(types.ResponseErrorMessage(id=data.id, error=error), default=self._serialize_message)
        encoded = body.encode("utf-8")
        self.writer.write(b"Content-Length: %d\r\n\r\n" % len(encoded) + encoded)


def _problems(error: BaseException) -> list[str]:
    """cattrs' validation errors as ``what @ $.place`` lines (at most three)."""
    if isinstance(error, cattrs.BaseValidationError):
        found = cattrs.transform_error(error, path="$", format_exception=_described)
    else:
        found = [f"{error}"]
    return [one_line(_json_names(line), 120) for line in found[:3]] or ["invalid"]


def _json_names(line: str) -> str:
    """``... @ $.params.text_document`` as the client wrote it: ``$.params.textDocument``."""
    said, at, place = line.rpartition(" @ ")
    if not at:
        return line
    return f"{said} @ " + re.sub(r"_([a-z])", lambda m: m.group(1).upper(), place)


def _described(error: BaseException, wanted: Any) -> str:
    if isinstance(error, WrongType):
        return str(error)
    return format_exception(error, wanted)
