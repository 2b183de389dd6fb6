"""Picture files for the bound tests: a PNG that is its header only."""

from __future__ import annotations

import zlib


def png_header(width: int, height: int) -> bytes:
    """A PNG file's signature and header chunk claiming ``width`` x ``height`` RGB, and no pixel."""
    body = b"IHDR" + width.to_bytes(4, "big") + height.to_bytes(4, "big") + bytes([8, 2, 0, 0, 0])
    return b"\x89PNG\r\n\x1a\n" + (13).to_bytes(4, "big") + body + zlib.crc32(body).to_bytes(4, "big")
