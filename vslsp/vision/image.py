"""Image input for perception: validation, reading files, the working scale, the table colour.

Paper, "Methodology": observations are plain RGB images of the world. Every perception
function takes ``uint8`` arrays of shape (H, W, 3) in RGB order; this module checks that once
and turns a wrong input into an :class:`~vslsp.errors.InputError` that says what to pass.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Callable, Sequence
from pathlib import Path

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.files import check_name, read_bytes, shown
from vslsp.outputs import write_bytes

# Perception runs on images whose longer side is at most this many pixels: enough for
# tabletop objects tens of pixels wide, and it keeps a grounding within milliseconds.
WORKING_SIZE = 320
# Input images: at least MIN_SIDE and at most MAX_SIDE pixels a side, at most MAX_PIXELS in all,
# and at most MAX_ASPECT times wider than high (or the reverse): a camera's picture.
MIN_SIDE, MAX_SIDE, MAX_PIXELS, MAX_ASPECT = 32, 8192, 40_000_000, 8.0
IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg")
SIZE_LIMITS = (
    f"at least {MIN_SIDE} and at most {MAX_SIDE} pixels a side, at most {MAX_PIXELS // 1_000_000} "
    f"megapixels and at most {MAX_ASPECT:.0f}:1 between the sides"
)


def check_size(width: int, height: int, what: str = "image") -> None:
    """An InputError when a ``width`` x ``height`` image is outside the limits perception takes."""
    if (
        min(width, height) < MIN_SIDE
        or max(width, height) > MAX_SIDE
        or width * height > MAX_PIXELS
        or max(width, height) > MAX_ASPECT * min(width, height)
    ):
        raise InputError(
            f"{what} is {width}x{height} pixels; perception takes images of {SIZE_LIMITS} (resize it, e.g. to 640x480)"
        )


def as_rgb(image: np.ndarray, what: str = "image") -> np.ndarray:
    """Check that ``image`` is an RGB picture: uint8 (H, W, 3), at least 32x32 pixels."""
    if not isinstance(image, np.ndarray):
        raise InputError(f"{what} must be a numpy array (H, W, 3) uint8 RGB, got {type(image).__name__}")
    if image.ndim != 3 or image.shape[2] != 3:
        raise InputError(f"{what} must have shape (H, W, 3) RGB, got shape {image.shape}")
    if image.dtype != np.uint8:
        raise InputError(
            f"{what} must be uint8 (0-255), got {image.dtype}; convert it with "
            "(image * 255).astype(np.uint8) if it holds floats in 0..1"
        )
    check_size(image.shape[1], image.shape[0], what)
    return np.ascontiguousarray(image)


#: The largest image file read (a 40-megapixel PNG of noise is about 120 MB).
MAX_IMAGE_BYTES = 200_000_000


def image_format(head: bytes) -> str | None:
    """ "png" or "jpeg" from a file's first bytes; None for anything else."""
    if head[:8] == b"\x89PNG\r\n\x1a\n":
        return "png"
    return "jpeg" if head[:3] == b"\xff\xd8\xff" else None


def header_size(source: bytes | str | os.PathLike[str]) -> tuple[int, int] | None:
    """(width, height) from a PNG or JPEG file's header (its bytes, or its path) without decoding;
    None when it is neither or its header is cut short or malformed."""
    data = source if isinstance(source, bytes) else read_bytes(source, "image", MAX_IMAGE_BYTES)
    kind = image_format(data)
    if kind == "png":
        return (int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")) if len(data) >= 24 else None
    if kind is None:
        return None
    index = 2
    while index < len(data):  # JPEG: walk the segments to the frame header (SOF0-SOF15 but DHT, JPG, DAC)
        if data[index] != 0xFF:
            return None
        while index < len(data) and data[index] == 0xFF:  # any number of fill bytes may precede a marker
            index += 1
        if index + 3 > len(data):
            return None
        kind_byte = data[index]
        if kind_byte == 0x01 or 0xD0 <= kind_byte <= 0xD7:  # markers without a length
            index += 1
            continue
        length = int.from_bytes(data[index + 1 : index + 3], "big")
        if 0xC0 <= kind_byte <= 0xCF and kind_byte not in (0xC4, 0xC8, 0xCC):
            frame = data[index + 3 : index + 8]
            return (int.from_bytes(frame[3:5], "big"), int.from_bytes(frame[1:3], "big")) if len(frame) == 5 else None
        if kind_byte == 0xDA or length < 2:  # image data before any frame header, or a broken segment
            return None
        index += 1 + length
    return None


def read_image(
    path: str | os.PathLike[str], what: str | None = None, fits: Callable[[int, int], None] | None = None
) -> np.ndarray:
    """Read a PNG/JPEG file as RGB (H, W, 3) uint8; ``fits`` (when given) checks its width and
    height, read from its header, before it is decoded (raising an InputError to refuse it).

    The file must be a regular file of at most :data:`MAX_IMAGE_BYTES`; its size in pixels is
    read from its header and checked against :data:`SIZE_LIMITS` before anything is decoded, and
    other formats (TIFF, WebP, ... whatever the extension says) are refused, so no file can make
    the decoder allocate more than the limits allow. The bytes are decoded in memory, so any path
    works (OpenCV's own file functions crash on a path that is not UTF-8).
    """
    what = what or f"image {shown(path)}"
    data = read_bytes(path, what, MAX_IMAGE_BYTES)
    if image_format(data) is None:
        raise InputError(
            f"cannot read {what}: not an image vslsp reads (not PNG or JPEG by its content); save it as PNG or JPEG"
        )
    size = header_size(data)
    if size is None:
        raise InputError(f"cannot read {what}: its header is cut short or malformed; save it again as PNG or JPEG")
    check_size(*size, what)
    if fits is not None:
        fits(*size)
    try:
        image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
    except cv2.error as error:  # OpenCV's own pixel limit (set in vslsp/__init__.py)
        raise InputError(f"cannot read {what}: {str(error).strip().splitlines()[-1]}") from None
    if image is None:
        raise InputError(f"cannot read {what}: not an image file OpenCV can decode (use PNG or JPEG)")
    check_size(image.shape[1], image.shape[0], what)
    return cv2.cvtColor(image, cv2.COLOR_BGR2RGB)


#: The most pixels of the pictures one command reads together (a folder's: they are all held in
#: memory, 3 bytes a pixel, about 0.9 GB; ``--max-pixels MP`` changes it).
MAX_FOLDER_PIXELS = 300_000_000
#: The option that changes it, named in the message of a folder over it.
MAX_PIXELS_OPTION = "--max-pixels"


def read_pictures(paths: Sequence[Path], max_pixels: int = MAX_FOLDER_PIXELS) -> list[np.ndarray]:
    """The pictures ``paths`` (:func:`read_image`) taken by one camera: all of one size, and of
    at most ``max_pixels`` together, both checked from each file's header before it is decoded.
    Raises InputError naming the file that differs or that goes over the limit."""
    first: list[tuple[Path, tuple[int, int]]] = []
    total = 0

    def fits(path: Path, width: int, height: int) -> None:
        nonlocal total
        if not first:
            first.append((path, (width, height)))
        elif (width, height) != first[0][1]:
            (other, size) = first[0]
            raise InputError(
                f"{shown(path)} is {width}x{height} px, {shown(other)} {size[0]}x{size[1]}: "
                "take every picture with the same camera at the same size"
            )
        total += width * height
        if total > max_pixels:
            raise InputError(
                f"{shown(path)}: the pictures read up to it hold {total / 1e6:.1f} megapixels, over the limit of "
                f"{max_pixels / 1e6:g} (all are held in memory, 3 bytes a pixel); use fewer or smaller pictures "
                f"(e.g. 640x480) or raise the limit with {MAX_PIXELS_OPTION} MP"
            )

    return [read_image(path, fits=functools.partial(fits, path)) for path in paths]


def check_image_output(path: str | os.PathLike[str]) -> Path:
    """Check, before any work, that an image can be written at ``path``: a PNG or JPEG name of a
    length the file system takes, in a folder that exists and is writable. Returns the path."""
    path = Path(path)
    name = shown(path)
    if path.suffix.lower() not in IMAGE_EXTENSIONS:
        raise InputError(f"cannot write image {name}: give a file name ending in .png (or .jpg)")
    check_name(path, f"cannot write image {name}")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError(f"cannot write image {name}: the folder {shown(folder)} does not exist; create it first")
    if path.is_dir():
        raise InputError(f"cannot write image {name}: it is a folder; give a file name ending in .png")
    if not os.access(folder, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise InputError(f"cannot write image {name}: no permission to write there; choose another path")
    return path


def encode_image(path: str | os.PathLike[str], image: np.ndarray) -> bytes:
    """The bytes of an RGB (H, W, 3) uint8 image in the format of ``path``'s extension (PNG or JPEG)."""
    extension = ".jpg" if Path(path).suffix.lower() in (".jpg", ".jpeg") else ".png"
    try:
        encoded, buffer = cv2.imencode(extension, cv2.cvtColor(image, cv2.COLOR_RGB2BGR))
    except cv2.error as error:  # OpenCV 5 raises where 4 returned False
        raise InputError(f"cannot write image {shown(path)}: {str(error).strip().splitlines()[-1]}") from None
    if not encoded:
        raise InputError(f"cannot write image {shown(path)}: OpenCV could not encode it as {extension}")
    return buffer.tobytes()


def write_image(path: str | os.PathLike[str], image: np.ndarray) -> None:
    """Write an RGB (H, W, 3) uint8 image (PNG or JPEG by the file's extension), encoded in memory
    (OpenCV never sees the path, which need not be UTF-8) and written by Python: the file is replaced
    whole (vslsp.outputs), never through a link."""
    check_image_output(path)
    write_bytes(path, encode_image(path, image))


def working_scale(shape: tuple[int, ...]) -> int:
    """The integer factor by which an image of ``shape`` is reduced for perception."""
    return max(1, int(np.ceil(max(shape[:2]) / WORKING_SIZE)))


def to_working(image: np.ndarray) -> tuple[np.ndarray, int]:
    """The image (H/s, W/s, 3) at the working scale, smoothed against sensor noise, and s."""
    scale = working_scale(image.shape)
    if scale > 1:
        image = cv2.resize(image, (image.shape[1] // scale, image.shape[0] // scale), interpolation=cv2.INTER_AREA)
    return cv2.GaussianBlur(image, (5, 5), 0), scale


def table_colour(image: np.ndarray) -> np.ndarray:
    """The dominant colour (3,) float32 of an RGB image: the table the objects stand on.

    The mode of a coarse colour histogram over a subsample, refined by the median of the
    pixels in that bin: robust to objects, the line and sensor noise.
    """
    sample = image[::8, ::8].reshape(-1, 3)
    bins = (sample >> 4).astype(np.int32)
    code = (bins[:, 0] << 8) | (bins[:, 1] << 4) | bins[:, 2]
    mode = np.bincount(code, minlength=4096).argmax()
    centre = np.median(sample[code == mode], axis=0)
    near = np.abs(sample - centre).max(axis=1) < 40
    return np.median(sample[near], axis=0).astype(np.float32)


def channel_max(image: np.ndarray) -> np.ndarray:
    """Per-pixel maximum (H, W) over the channels of (H, W, 3) (OpenCV: much faster than numpy)."""
    a, b, c = cv2.split(image)
    return cv2.max(cv2.max(a, b), c)


def channel_min(image: np.ndarray) -> np.ndarray:
    """Per-pixel minimum (H, W) over the channels of (H, W, 3)."""
    a, b, c = cv2.split(image)
    return cv2.min(cv2.min(a, b), c)


def colour_distance(image: np.ndarray, colour: np.ndarray) -> np.ndarray:
    """Largest per-channel difference (H, W) uint8 between an image (H, W, 3) and one colour (3,)."""
    a, b, c = (cv2.absdiff(channel, float(value)) for channel, value in zip(cv2.split(image), colour, strict=True))
    return cv2.max(cv2.max(a, b), c)


GRAIN_SPREAD = 4.0  # the grain's reach: this many times the table pixels' median distance from its colour
NO_GRAIN = 20  # grey levels: a reach below this is a plain table and its sensor noise (sigma up to about 3.5)
GRAIN_SPECK = 0.02  # of the image's shorter side: a patch off the table's colour narrower than this is grain


def table_grain(image: np.ndarray) -> int:
    """How far (grey levels, any channel) the table's own pixels stray from its colour:
    :data:`GRAIN_SPREAD` times the median :func:`colour_distance` of the pixels near it (within
    60); 0 for a plain table (a reach below :data:`NO_GRAIN`)."""
    distance = colour_distance(image[::4, ::4], table_colour(image))
    reach = GRAIN_SPREAD * float(np.median(distance[distance < 60]))
    return 0 if reach < NO_GRAIN else int(round(reach))


def flatten_table(image: np.ndarray, speck: float = GRAIN_SPECK) -> np.ndarray:
    """The image (H, W, 3) with a grained table top painted its one colour (:func:`table_colour`).
    A table's grain (wood, a cloth, a printed pattern) lies still under the objects; a place is
    told by the objects around it, and the grain's features would find the demonstration's
    place on the table again where it was, wherever the objects now lie. The table is every
    pixel within its grain (:func:`table_grain`) of its colour, less what lies inside an
    object's outline (an object may show the table's colour within), plus the patches off its
    colour narrower than ``speck`` of the image's shorter side (the grain's own light and dark
    flecks; an object is many times wider). A plain table is left as it is."""
    grain = table_grain(image)
    if grain == 0:
        return image
    colour = table_colour(image)
    objects = (colour_distance(image, colour) >= grain).astype(np.uint8)
    outlines, _ = cv2.findContours(objects, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    cv2.drawContours(objects, outlines, -1, 1, thickness=cv2.FILLED)
    side = max(3, int(round(speck * min(image.shape[:2]))) | 1)
    objects = cv2.morphologyEx(objects, cv2.MORPH_OPEN, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (side, side)))
    flat = image.copy()
    flat[objects == 0] = np.rint(colour).astype(np.uint8)
    return flat
