"""Point clouds and depth images from a user's files (docs/recordings.md, "VSL-3D"): PLY
(ASCII or binary, read by ``plyfile``), PCD (ASCII, binary or binary-compressed, read by
``pypcd4``), ``.npz`` (an array ``points`` (N, 3), no pickle) and 16-bit depth PNGs.

A cloud from a file holds points (N, 3) in metres in the *camera* frame (x right, y down, z
along the optical axis), as a depth sensor's driver writes them. VSL-3D's world cloud
(:class:`~vslsp.vsl3d.vsl.WorldCloud`) also needs what the sensor saw through (free space), so
a cloud is seen through the calibrated camera again (:func:`depth_from_cloud`): per pixel the
nearest point's depth, the depth image that cloud came from. The libraries are the ``clouds``
extra; without them vslsp still imports, and reading a PLY or PCD file says what to install.
"""

from __future__ import annotations

import io
from pathlib import Path

import cv2
import numpy as np

from vslsp.errors import InputError
from vslsp.files import load_npz, read_bytes, regular_file, shown

CLOUD_EXTENSIONS = (".ply", ".pcd", ".npz")
#: The largest cloud file read by default, and the most bytes of points its header may declare
#: (16 million points of float32 x, y, z take 200 MB; ``--max-size MB`` changes it).
MAX_CLOUD_BYTES = 200_000_000
#: The option that changes it, named in the message of a cloud over it.
MAX_SIZE_OPTION = "--max-size"
MAX_DEPTH_BYTES = 64_000_000
_INSTALL = "pip install 'vslsp[clouds]'"


def read_cloud(path: str | Path, max_bytes: int = MAX_CLOUD_BYTES) -> np.ndarray:
    """The points (N, 3) float64 of the cloud file ``path`` (.ply, .pcd or .npz), the points
    that are not finite dropped. Raises InputError naming the file when it is missing,
    unreadable, has no x, y, z or no point, or when the file or the points its header declares
    are over ``max_bytes`` (checked before the file, or its points, are read)."""
    path = Path(path)
    size = regular_file(path, "cloud").st_size
    if size > max_bytes:
        raise _over(path, f"the cloud file has {_megabytes(size)} MB", max_bytes)
    data = read_bytes(path, "cloud", max_bytes)
    suffix = path.suffix.lower()
    declared = _declared_bytes(data, suffix)
    if declared > max_bytes:
        raise _over(path, f"its header declares {_megabytes(declared)} MB of points", max_bytes)
    try:
        if suffix == ".ply":
            points = _ply_points(data)
        elif suffix == ".pcd":
            points = _pcd_points(data)
        elif suffix == ".npz":
            points = np.asarray(load_npz(path, "cloud", max_bytes)["points"], dtype=float)
        else:
            raise ValueError(f"not one of {', '.join(CLOUD_EXTENSIONS)}")
    except InputError:
        raise
    except ImportError as error:
        raise InputError(f"cannot read {shown(path)}: {error.name} is not installed; {_INSTALL}") from None
    except Exception as error:  # the parsers raise many types on bad bytes; each is the file's fault
        raise InputError(f"cannot read cloud {shown(path)}: {_reason(error)}") from None
    if points.ndim != 2 or points.shape[1] != 3:
        raise InputError(f"cloud {shown(path)}: its points are {points.shape}, not (N, 3) x, y, z")
    points = points[np.all(np.isfinite(points), axis=1)]
    if len(points) == 0:
        raise InputError(f"cloud {shown(path)} holds no point; capture the scene again")
    return points


def _over(path: Path, what: str, limit: int) -> InputError:
    return InputError(
        f"{shown(path)}: {what}, over the limit of {_megabytes(limit)} MB; thin the cloud out (e.g. a 5 mm "
        f"voxel grid) or raise the limit with {MAX_SIZE_OPTION} MB"
    )


def _megabytes(size: int) -> str:
    shown_size = f"{size / 1e6:.1f}"
    return shown_size if shown_size != "0.0" else f"{size / 1e6:.3g}"


_PLY_SIZES = {
    **dict.fromkeys(("char", "uchar", "int8", "uint8"), 1),
    **dict.fromkeys(("short", "ushort", "int16", "uint16"), 2),
    **dict.fromkeys(("int", "uint", "int32", "uint32", "float", "float32"), 4),
    **dict.fromkeys(("double", "float64"), 8),
}
_HEADER_BYTES = 65_536  # a PLY or PCD header ends within this many bytes


def _declared_bytes(data: bytes, suffix: str) -> int:
    """The bytes of points (at the least) that a PLY or PCD file's header declares: what its
    parser allocates, whatever the file's own size (0 when the header does not say; the parser
    then refuses the file)."""
    if suffix == ".ply":
        end = data.find(b"end_header", 0, _HEADER_BYTES)
        total, count = 0, 0
        for words in (line.split() for line in data[: max(end, 0)].decode("ascii", "replace").splitlines()):
            if len(words) == 3 and words[0] == "element" and words[2].isdigit():
                count = int(words[2])
            elif len(words) >= 3 and words[0] == "property":
                total += count * _PLY_SIZES.get(words[2 if words[1] == "list" else 1], 1)
        return total
    if suffix == ".pcd":
        end = data.find(b"\nDATA", 0, _HEADER_BYTES)
        fields: dict[str, list[str]] = {}
        for line in data[: max(end, 0)].decode("ascii", "replace").splitlines():
            words = line.split()
            if words and not words[0].startswith("#"):
                fields[words[0].upper()] = words[1:]
        try:
            sizes = [int(c) for c in fields.get("SIZE", [])]
            counts = [int(c) for c in fields.get("COUNT", ["1"] * len(sizes))]
            points = int(fields.get("POINTS", ["0"])[0])
        except ValueError:
            return 0
        total = points * sum(size * count for size, count in zip(sizes, counts))
        line_end = data.find(b"\n", end + 1) if end >= 0 else -1
        if line_end >= 0 and b"binary_compressed" in data[end:line_end]:  # then the sizes, uint32 each
            total = max(total, int.from_bytes(data[line_end + 5 : line_end + 9], "little"))
        return total
    return 0


def _reason(error: Exception) -> str:
    text = str(error).strip() or type(error).__name__
    return text.splitlines()[0][:200]


def _ply_points(data: bytes) -> np.ndarray:
    from plyfile import PlyData

    vertex = PlyData.read(io.BytesIO(data))["vertex"]
    return np.column_stack([np.asarray(vertex[axis], dtype=float) for axis in ("x", "y", "z")])


def _pcd_points(data: bytes) -> np.ndarray:
    from pypcd4 import PointCloud

    cloud = PointCloud.from_fileobj(io.BufferedReader(io.BytesIO(data)))
    return np.asarray(cloud.numpy(("x", "y", "z")), dtype=float)


def write_ply(path: str | Path, points: np.ndarray, binary: bool = True) -> None:
    """Write ``points`` (N, 3) (float32 x, y, z) as a PLY file, binary or ASCII."""
    from plyfile import PlyData, PlyElement

    points = np.asarray(points, dtype=np.float32)
    vertex = np.empty(len(points), dtype=[("x", "f4"), ("y", "f4"), ("z", "f4")])
    vertex["x"], vertex["y"], vertex["z"] = points.T
    PlyData([PlyElement.describe(vertex, "vertex")], text=not binary).write(str(path))


def write_pcd(path: str | Path, points: np.ndarray, binary: bool = True) -> None:
    """Write ``points`` (N, 3) (float32 x, y, z) as a PCD file, binary or ASCII."""
    from pypcd4 import Encoding, PointCloud

    cloud = PointCloud.from_xyz_points(np.asarray(points, dtype=np.float32))
    cloud.save(str(path), encoding=Encoding.BINARY if binary else Encoding.ASCII)


def read_depth_png(path: str | Path, scale: float, size: tuple[int, int]) -> np.ndarray:
    """The depth image (H, W) in metres of the 16-bit PNG ``path`` (``scale`` m a unit: 0.001
    for millimetres; 0: no return), checked to be ``size`` (W, H) px."""
    path = Path(path)
    data = read_bytes(path, "depth image", MAX_DEPTH_BYTES)
    image = (
        cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED) if data[:8] == b"\x89PNG\r\n\x1a\n" else None
    )
    if image is None or image.ndim != 2 or image.dtype != np.uint16:
        raise InputError(f"depth image {shown(path)} is not a one-channel 16-bit PNG (depth in millimetres)")
    if (image.shape[1], image.shape[0]) != size:
        raise InputError(
            f"depth image {shown(path)} is {image.shape[1]}x{image.shape[0]} px, the calibration's camera "
            f"{size[0]}x{size[1]}: give the camera's image_size in calibration.json"
        )
    return image.astype(np.float64) * scale


def write_depth_png(path: str | Path, depth: np.ndarray, scale: float = 0.001) -> None:
    """Write ``depth`` (H, W) m as a 16-bit PNG of ``scale`` m a unit (0 where nothing is seen)."""
    units = np.clip(np.round(np.nan_to_num(np.asarray(depth, float)) / scale), 0, 65535).astype(np.uint16)
    ok, encoded = cv2.imencode(".png", units)
    assert ok
    Path(path).write_bytes(encoded.tobytes())


def depth_from_cloud(points: np.ndarray, intrinsics: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """The depth image (H, W) m that ``points`` (N, 3) of the camera frame are seen as through
    the camera ``intrinsics`` K (3, 3) of ``size`` (W, H) px: per pixel the nearest point's
    depth, 0 where no point projects. A cloud back-projected from a depth image at the pixels'
    centres gives that image back."""
    width, height = size
    points = points[points[:, 2] > 0.0]
    u = intrinsics[0, 0] * points[:, 0] / points[:, 2] + intrinsics[0, 2]
    v = intrinsics[1, 1] * points[:, 1] / points[:, 2] + intrinsics[1, 2]
    cols, rows = np.floor(u).astype(np.int64), np.floor(v).astype(np.int64)
    inside = (cols >= 0) & (cols < width) & (rows >= 0) & (rows < height)
    depth = np.full(width * height, np.inf)
    np.minimum.at(depth, rows[inside] * width + cols[inside], points[inside, 2])
    depth[~np.isfinite(depth)] = 0.0
    return depth.reshape(height, width)
