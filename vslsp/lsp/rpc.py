"""The LSP base protocol on a byte stream: frames of ``Content-Length: N`` headers, a blank line and N
bytes of JSON (LSP 3.17, "Base Protocol"), read so that one malformed frame costs only itself.

A malformed frame (a header without ``Content-Length``, a length that is no number, bytes that are no
header, a body that is no JSON) is reported once, as an :class:`Invalid`, and reading goes on at the
next header. The next header is found by its ``Content-Length`` name; a body whose length claims more
bytes than it has is cut where the next frame's ``Content-Length: N`` line begins: that line ends in
a raw line break, which no JSON text holds (JSON strings escape it), so a well-formed body never
contains one.
"""

from __future__ import annotations

import asyncio
import json
import os
import re
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

#: The largest body read (a 1 MB PDDL file is a few MB of JSON); a longer claimed length is malformed.
MAX_BODY_BYTES = 64 * 1024 * 1024
#: The longest header line kept while waiting for its end; longer is junk.
MAX_HEADER_BYTES = 8 * 1024
CHUNK_BYTES = 64 * 1024

_NAME = re.compile(rb"content-length[ \t]*:", re.IGNORECASE)
_NEXT_HEADER = re.compile(rb"content-length[ \t]*:[ \t]*\d+[ \t]*\r?\n", re.IGNORECASE)
_FIELD = re.compile(rb"([!-9;-~]+)[ \t]*:[ \t]*(.*?)[ \t]*\Z")
_LINE_END = re.compile(rb"\r?\n")


@dataclass(frozen=True)
class Invalid:
    """A malformed frame: what was wrong, in one line (answered as a parse error with id null)."""

    reason: str


@dataclass(frozen=True)
class Message:
    """A frame's body, decoded: any JSON value (the protocol checks that it is a message)."""

    value: Any


class Framer:
    """Bytes in (:meth:`feed`), messages and malformed frames out, in the order they came."""

    def __init__(self, max_body: int = MAX_BODY_BYTES):
        self.max_body = max_body
        self._buffer = bytearray()
        self._length: int | None = None  # the header's Content-Length, once read
        self._problem = ""  # what is wrong with the header being read
        self._fields = 0  # header lines read of the present frame
        self._seen_length = False  # whether the present header had a Content-Length line
        self._body: int | None = None  # the body's length once the header is over
        self._scanned = 0  # how far the body was searched for the next header
        self._resync = False  # skipping to the next header
        self._quiet = False  # the bytes skipped belong to a frame already reported

    def feed(self, data: bytes) -> Iterator[Message | Invalid]:
        """Take ``data`` and yield every message or malformed frame it completes."""
        self._buffer += data
        while True:
            if self._resync and not self._skip():
                return
            found: Message | Invalid | bool | None = (
                self._read_body() if self._body is not None else self._read_header_line()
            )
            if found is None:
                return
            if isinstance(found, Message | Invalid):
                yield found

    def _skip(self) -> bool:
        """Drop bytes up to the next ``Content-Length`` name; False while there is none yet."""
        found = _NAME.search(self._buffer)
        if found is None:
            del self._buffer[: max(0, len(self._buffer) - 32)]  # the name may be cut across chunks
            return False
        del self._buffer[: found.start()]
        self._resync = self._quiet = False
        return True

    def _read_header_line(self) -> Invalid | bool | None:
        end = _LINE_END.search(self._buffer)
        if end is None:
            if len(self._buffer) <= MAX_HEADER_BYTES:
                return None
            named = _NAME.search(self._buffer, 1)
            return self._junk(named.start() if named else len(self._buffer) - 32)
        line = bytes(self._buffer[: end.start()])
        if not line:
            del self._buffer[: end.end()]
            if not self._fields:  # blank lines between frames
                return False
            return self._header_over()
        named = _NAME.search(line)
        if named is not None and named.start() > 0:  # junk before a header on the same line
            return self._junk(named.start())
        field = _FIELD.match(line)
        if field is None:
            return self._junk(end.end())
        is_length = field.group(1).lower() == b"content-length"
        if is_length and self._seen_length:  # the next frame's header: this one had no blank line
            self._reset()
            return Invalid("a header without the blank line that ends it: the frame is skipped")
        del self._buffer[: end.end()]
        self._fields += 1
        self._quiet = False
        if is_length:
            self._seen_length = True
            value = field.group(2)
            if not value.isdigit():
                self._problem = f"Content-Length {_shown(value)} is no number of bytes"
            elif int(value) > self.max_body:
                self._problem = f"Content-Length {int(value)} is over the limit of {self.max_body} bytes"
            else:
                self._length = int(value)
        return False

    def _reset(self) -> None:
        self._length, self._problem, self._fields, self._seen_length = None, "", 0, False

    def _header_over(self) -> Invalid | bool:
        problem = self._problem or ("a header without Content-Length" if self._length is None else "")
        length = self._length
        self._reset()
        if problem:
            self._resync, self._quiet = True, True
            return Invalid(f"{problem}: the frame is skipped")
        self._body, self._scanned = length, 0
        return False

    def _junk(self, size: int) -> Invalid | bool:
        """``size`` bytes before the next header, none of a frame: reported once a run."""
        del self._buffer[:size]
        self._reset()
        if self._quiet:
            return False
        self._quiet = True
        return Invalid("bytes that are no LSP header: skipped to the next Content-Length header")

    def _read_body(self) -> Message | Invalid | None:
        length = self._body
        assert length is not None
        # A body is cut where the next frame's header begins (no JSON text holds its line break).
        start = max(0, self._scanned - 64)
        cut = _NEXT_HEADER.search(self._buffer, start, min(len(self._buffer), length + 64))
        if cut is not None and cut.start() < length:
            del self._buffer[: cut.start()]
            self._body = None
            return Invalid(f"a body shorter than its Content-Length {length}: the frame is skipped")
        if len(self._buffer) < length:
            self._scanned = len(self._buffer)
            return None
        body = bytes(self._buffer[:length])
        del self._buffer[:length]
        self._body = None
        try:
            return Message(json.loads(body))
        except (ValueError, RecursionError) as error:  # UnicodeDecodeError is a ValueError
            self._resync, self._quiet = True, True  # what follows a cut body is the rest of it
            reason = "JSON nested too deeply" if isinstance(error, RecursionError) else f"invalid JSON ({error})"
            return Invalid(f"{reason}: the frame is skipped")


def _shown(text: bytes) -> str:
    shown = text[:40].decode("utf-8", "replace")
    return repr(shown + ("..." if len(text) > 40 else ""))


async def read_stream(fd: int, framer: Framer, handle: Callable[[Message | Invalid], bool]) -> None:
    """Read the file descriptor ``fd`` until its end, or until ``handle`` (called on the event loop for
    each message or malformed frame, in order) returns False. The reading thread is a daemon: a server
    that ends while the client still holds stdin open does not wait for it."""
    loop = asyncio.get_running_loop()
    chunks: asyncio.Queue[bytes] = asyncio.Queue()

    def read() -> None:
        while True:
            try:
                chunk = os.read(fd, CHUNK_BYTES)
            except OSError:
                chunk = b""
            try:
                loop.call_soon_threadsafe(chunks.put_nowait, chunk)
            except RuntimeError:  # the loop is closed: the server has ended
                return
            if not chunk:
                return

    threading.Thread(target=read, name="lsp-stdin", daemon=True).start()
    while chunk := await chunks.get():
        for found in framer.feed(chunk):
            if not handle(found):
                return
            await asyncio.sleep(0)  # let a request's task (vslsp.plan) and timers run between messages
