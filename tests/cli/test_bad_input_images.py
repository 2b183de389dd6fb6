"""Images: a decompression bomb is refused from its header whatever its format or extension, OpenCV's
own pixel limit is set, and a usable pair the grounding finds no answer in is a failed task
(issue 27, items 4 and 5)."""

from __future__ import annotations

import struct
import subprocess
import sys

import cv2
import numpy as np
import pytest
from helpers.cli import REPO, vslsp

from vslsp.grounding.synthetic import Square, tabletop_image
from vslsp.vision.image import header_size, write_image


def _tiff(width: int, height: int) -> bytes:
    """A little-endian TIFF declaring ``width`` x ``height`` 1-bit pixels, CCITT group 4, one tiny strip."""
    entries = [(256, 4, width), (257, 4, height), (258, 3, 1), (259, 3, 4), (262, 3, 0), (273, 4, 0), (277, 3, 1)]
    entries += [(278, 4, height), (279, 4, 16)]
    offset_ifd = 8
    data_at = offset_ifd + 2 + 12 * len(entries) + 4
    ifd = struct.pack("<H", len(entries))
    for tag, kind, value in entries:
        value = data_at if tag == 273 else value
        packed = struct.pack("<HH", value, 0) if kind == 3 else struct.pack("<I", value)
        ifd += struct.pack("<HHI", tag, kind, 1) + packed
    return b"II*\x00" + struct.pack("<I", offset_ifd) + ifd + b"\x00\x00\x00\x00" + b"\x00" * 16


def _jpeg_with_fill_byte(width: int, height: int) -> bytes:
    """A small JPEG whose frame header declares ``width`` x ``height``, with a (legal) 0xFF fill byte
    before its SOF marker: a header walker that does not skip fill bytes never finds the size."""
    encoded = cv2.imencode(".jpg", np.full((64, 64, 3), 200, np.uint8))[1].tobytes()
    sof = encoded.index(b"\xff\xc0")
    frame = bytearray(encoded[sof:])
    frame[5:7], frame[7:9] = height.to_bytes(2, "big"), width.to_bytes(2, "big")
    return encoded[:sof] + b"\xff" + bytes(frame)


@pytest.fixture
def images(tmp_path):
    still = Square("blue", (500, 420))
    write_image(tmp_path / "pre.png", tabletop_image([Square("purple", (200, 150)), still]))
    write_image(tmp_path / "post.png", tabletop_image([Square("purple", (220, 410)), still]))
    write_image(tmp_path / "lineless_pre.png", tabletop_image([Square("purple", (200, 150)), still], line=None))
    write_image(tmp_path / "lineless_post.png", tabletop_image([Square("purple", (220, 410)), still], line=None))
    (tmp_path / "tiff.png").write_bytes(_tiff(32000, 32000))  # 26 kB as group 4 in the wild, 6 GB decoded
    (tmp_path / "fill.jpg").write_bytes(_jpeg_with_fill_byte(32000, 32000))  # under OpenCV's default 2^30 pixels
    return tmp_path


@pytest.mark.parametrize(
    "bomb, message", [("tiff.png", "not PNG or JPEG by its content"), ("fill.jpg", "32000x32000 pixels")]
)
@pytest.mark.parametrize("side", ["pre", "post"])
def test_a_decompression_bomb_is_refused_from_its_header(capsys, images, bomb, message, side):
    pair = (images / bomb, images / "post.png") if side == "pre" else (images / "pre.png", images / bomb)
    code, _, err = vslsp(capsys, "ground", *pair)
    assert code == 2 and message in err, err


def test_the_jpeg_header_walker_skips_fill_bytes(images):
    assert header_size(images / "fill.jpg") == (32000, 32000)


def test_opencv_own_pixel_limit_is_set_before_cv2_loads():
    # Any format OpenCV decodes is checked on its header against the limit (here TIFF).
    code = (
        "import vslsp, cv2, numpy as np, sys\n"
        f"data = np.frombuffer({_tiff(32000, 32000)!r}, np.uint8)\n"
        "try:\n    cv2.imdecode(data, cv2.IMREAD_UNCHANGED)\nexcept cv2.error as e:\n"
        "    sys.exit(0 if 'CV_IO_MAX_IMAGE_PIXELS' in str(e) else 1)\nsys.exit(1)\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=120)
    assert result.returncode == 0, result.stderr


@pytest.mark.parametrize(
    "pre, post, message",
    [("pre.png", "pre.png", "nothing moved"), ("lineless_pre.png", "lineless_post.png", "no landmark line found")],
)
def test_a_usable_pair_without_an_answer_is_a_failed_task(capsys, images, pre, post, message):
    code, _, err = vslsp(capsys, "ground", images / pre, images / post)
    assert code == 1 and message in err, err
