"""A raw client of ``vslsp lsp`` for the protocol tests: it writes any bytes (malformed frames too) to
the server's stdin and reads every frame the server writes, on a thread, so that the server never
blocks on a full pipe. Waits go through helpers.events (no clock here)."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
from pathlib import Path
from typing import Any

from helpers.events import wait_until

from vslsp.lsp.workspace import uri_of


def frame(message: Any) -> bytes:
    body = json.dumps(message).encode()
    return b"Content-Length: %d\r\n\r\n" % len(body) + body


class Wire:
    """``vslsp lsp`` as a child process (its log in ``log``), and what it has answered."""

    def __init__(self, log: Path):
        self.log = log
        self._log_file = log.open("wb")
        self.process = subprocess.Popen(
            [sys.executable, "-m", "vslsp", "lsp"], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self._log_file
        )
        self.received: list[dict[str, Any]] = []
        self._answers: dict[Any, list[dict[str, Any]]] = {}  # id -> the responses with it
        self._lock = threading.Lock()
        self._next_id = 0
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    # writing

    def send(self, data: bytes) -> None:
        assert self.process.stdin is not None
        self.process.stdin.write(data)
        self.process.stdin.flush()

    def request(self, method: str, params: Any = None) -> int:
        """Send a request; its id."""
        self._next_id += 1
        message: dict[str, Any] = {"jsonrpc": "2.0", "id": self._next_id, "method": method}
        if params is not None:
            message["params"] = params
        self.send(frame(message))
        return self._next_id

    def notify(self, method: str, params: Any = None) -> None:
        message: dict[str, Any] = {"jsonrpc": "2.0", "method": method}
        if params is not None:
            message["params"] = params
        self.send(frame(message))

    def initialize(self, root: Path) -> dict[str, Any]:
        answer = self.ask("initialize", {"processId": None, "rootUri": uri_of(root), "capabilities": {}})
        self.notify("initialized", {})
        return answer

    def open(self, path: Path, text: str) -> None:
        self.notify(
            "textDocument/didOpen",
            {"textDocument": {"uri": uri_of(path), "languageId": "pddl", "version": 1, "text": text}},
        )

    # reading

    def responses(self, msg_id: Any) -> list[dict[str, Any]]:
        with self._lock:
            return list(self._answers.get(msg_id, []))

    def answer(self, msg_id: Any) -> dict[str, Any]:
        """The one response to the request ``msg_id`` (waits for it)."""
        wait_until(lambda: self.responses(msg_id) or self.process.poll() is not None, f"the answer to {msg_id}")
        found = self.responses(msg_id)
        assert len(found) == 1, f"{len(found)} answers to request {msg_id}: {found} (log: {self.log.read_text()})"
        return found[0]

    def ask(self, method: str, params: Any = None) -> dict[str, Any]:
        return self.answer(self.request(method, params))

    def error_of(self, msg_id: Any) -> dict[str, Any]:
        answer = self.answer(msg_id)
        assert "error" in answer, f"no error but {answer}"
        return answer["error"]

    def null_id_errors(self) -> list[dict[str, Any]]:
        return [m["error"] for m in self.responses(None)]

    def answered(self) -> set[Any]:
        """The ids of every response so far."""
        with self._lock:
            return set(self._answers)

    def published(self, uri: str) -> list[list[dict[str, Any]]]:
        """The diagnostics published for ``uri``, in order."""
        with self._lock:
            return [
                m["params"]["diagnostics"]
                for m in self.received
                if m.get("method") == "textDocument/publishDiagnostics" and m["params"]["uri"] == uri
            ]

    def rss_kib(self) -> int:
        """The server's resident memory."""
        for line in Path(f"/proc/{self.process.pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
        raise AssertionError("no VmRSS")

    # ending

    def exit_code(self, shutdown: bool = True) -> int:
        """Send ``shutdown`` (unless not) and ``exit``; the server's exit code."""
        if shutdown:
            assert self.ask("shutdown").get("result", "missing") is None
        self.notify("exit")
        wait_until(lambda: self.process.poll() is not None, "the server to exit")
        self.close()
        return self.process.returncode

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
        self.process.wait()
        self._reader.join()
        for stream in (self.process.stdin, self.process.stdout):
            if stream is not None and not stream.closed:
                try:
                    stream.close()
                except BrokenPipeError:
                    pass
        self._log_file.close()

    def _read(self) -> None:
        stream = self.process.stdout
        assert stream is not None
        while True:
            length = -1
            while (line := stream.readline()) not in (b"\r\n", b""):
                if line.lower().startswith(b"content-length:"):
                    length = int(line.split(b":")[1])
            if not line:
                return
            message = json.loads(stream.read(length))
            with self._lock:
                self.received.append(message)
                if "method" not in message:
                    self._answers.setdefault(message.get("id"), []).append(message)
