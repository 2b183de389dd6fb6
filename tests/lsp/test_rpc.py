"""The LSP base protocol's frames (vslsp/lsp/rpc.py): a malformed frame is reported once and the next
well-formed frame is read as if nothing had happened, however the bytes arrive."""

import json

import pytest

from vslsp.lsp.rpc import Framer, Invalid, Message


def frame(message: object, length: int | None = None, header: bytes | None = None) -> bytes:
    body = json.dumps(message).encode()
    if header is None:
        header = b"Content-Length: %d\r\n" % (len(body) if length is None else length)
    return header + b"\r\n" + body


def request(number: int) -> dict:
    return {"jsonrpc": "2.0", "id": number, "method": "textDocument/hover"}


def read(data: bytes, chunk: int | None = None) -> list[Message | Invalid]:
    framer = Framer()
    if chunk is None:
        return list(framer.feed(data))
    return [found for start in range(0, len(data), chunk) for found in framer.feed(data[start : start + chunk])]


MALFORMED = {
    "a length that is no number": frame(request(90), header=b"Content-Length: abc\r\n"),
    "a header without Content-Length": frame(request(91), header=b"Content-Type: application/json\r\n"),
    "a length shorter than the body": frame(request(92), length=10),
    "a length longer than the body": frame(request(93), length=500),
    "a negative length": frame(request(94), header=b"Content-Length: -5\r\n"),
    "a length over the limit": frame(request(95), header=b"Content-Length: 99999999999\r\n"),
    "bytes that are no header": b"\x00\xffGET / HTTP/1.1 garbage",
    "a line that is no header": b"hello there\r\n",
    "a header without its blank line": b"Content-Length: 12\r\n",
    "a body that is no JSON": b"Content-Length: 7\r\n\r\n{nope!}",
    "a body that is no UTF-8": b"Content-Length: 4\r\n\r\n\xff\xfe\xfd\xfc",
    "JSON nested deeper than Python reads": b"Content-Length: 200000\r\n\r\n" + b"[" * 100_000 + b"]" * 100_000,
}


@pytest.mark.parametrize("malformed", MALFORMED.values(), ids=MALFORMED.keys())
@pytest.mark.parametrize("chunk", [None, 1, 7], ids=["at once", "byte by byte", "in chunks of 7"])
def test_a_malformed_frame_is_reported_once_and_the_next_frame_is_read(malformed: bytes, chunk: int | None):
    found = read(frame(request(1)) + malformed + frame(request(2)) + frame(request(3)), chunk)
    assert [f.value["id"] for f in found if isinstance(f, Message)] == [1, 2, 3]
    problems = [f for f in found if isinstance(f, Invalid)]
    assert len(problems) == 1, problems
    assert found.index(problems[0]) == 1  # reported where it came, before the frames after it


def test_what_each_malformed_frame_is_called():
    reasons = {name: read(data + frame(request(1)))[0] for name, data in MALFORMED.items()}
    assert all(isinstance(reason, Invalid) for reason in reasons.values())
    said = {name: reason.reason for name, reason in reasons.items() if isinstance(reason, Invalid)}
    assert said["a length that is no number"].startswith("Content-Length 'abc' is no number of bytes")
    assert said["a header without Content-Length"].startswith("a header without Content-Length")
    assert said["a length longer than the body"].startswith("a body shorter than its Content-Length 500")
    assert said["a length shorter than the body"].startswith("invalid JSON")
    assert said["a length over the limit"].startswith("Content-Length 99999999999 is over the limit")
    assert said["JSON nested deeper than Python reads"].startswith("JSON nested too deeply")


def test_well_formed_frames_in_any_split_and_with_other_headers():
    data = (
        frame(request(1))
        + b"Content-Type: application/vscode-jsonrpc; charset=utf-8\r\n"
        + frame(request(2))
        + b"content-length:  %d  \r\n\r\n" % len(json.dumps(request(3)))
        + json.dumps(request(3)).encode()
        + b"\r\n"  # a blank line between frames is no frame
        + frame({"jsonrpc": "2.0", "method": "x", "params": {"text": "Content-Length: 12\r\n\r\n{}"}})
    )
    for chunk in (None, 1, 3, 64):
        found = read(data, chunk)
        assert all(isinstance(f, Message) for f in found)
        assert [f.value.get("id") for f in found if isinstance(f, Message)] == [1, 2, 3, None]


def test_a_large_body_is_read_whole():
    text = "(define (domain d) " + "(p) " * 300_000 + ")"
    data = frame({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"text": text}})
    (found,) = read(data, 65_536)
    assert isinstance(found, Message) and found.value["params"]["text"] == text
