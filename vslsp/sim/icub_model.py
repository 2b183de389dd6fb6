"""The iCub model from ``icub-models``, reduced so that pybullet handles it.

As shipped, ``iCubGazeboV2_5`` has ~170 sensor and skin frames with no inertial, visual or
collision element; pybullet gives each of them 1 kg and several state queries fail on the
resulting 212-link body. We keep the links that carry a body (plus the two hand frames used as
end effectors), drop the rest with their fixed joints, and resolve ``package://iCub`` to the
installed mesh folder. The result has 32 revolute joints and weighs about 28 kg.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

from vslsp.errors import VslspError

MODEL_NAME = "iCubGazeboV2_5"
HAND_FRAMES = ("r_hand_dh_frame", "l_hand_dh_frame")


def _source_urdf() -> Path:
    try:
        import icub_models
    except ImportError as error:  # pragma: no cover - a broken install
        raise VslspError(
            "the iCub model is missing: install the package 'icub-models' (make install)"
        ) from error
    return Path(icub_models.get_model_file(MODEL_NAME))


def reduced_urdf_text(source: Path, kinematic: bool = False) -> str:
    """The URDF text of ``source`` without body-less links, meshes resolved to absolute paths.

    ``kinematic`` also drops every visual and collision element (the inertials stay, so link
    frames and masses are unchanged): the kinematics-only copy that IK runs on loads in a
    fraction of the time, with no meshes to parse.
    """
    root = ET.parse(source).getroot()
    package_root = source.parents[2]  # .../share/iCub/robots/<model>/model.urdf -> .../share/iCub
    kept: set[str] = set()
    for link in list(root.findall("link")):
        has_body = any(link.find(tag) is not None for tag in ("inertial", "visual", "collision"))
        if has_body or link.get("name") in HAND_FRAMES:
            kept.add(link.get("name"))
        else:
            root.remove(link)
    if kinematic:
        for link in root.findall("link"):
            for element in link.findall("visual") + link.findall("collision"):
                link.remove(element)
    for joint in list(root.findall("joint")):
        if joint.find("child").get("link") not in kept or joint.find("parent").get("link") not in kept:
            root.remove(joint)
    for axis in root.iter("axis"):  # pybullet warns about (and renormalises) non-unit axes
        values = [float(v) for v in axis.get("xyz", "1 0 0").split()]
        norm = sum(v * v for v in values) ** 0.5 or 1.0
        axis.set("xyz", " ".join(repr(v / norm) for v in values))
    for mesh in root.iter("mesh"):
        filename = mesh.get("filename", "")
        if filename.startswith("package://iCub/"):
            mesh.set("filename", str(package_root / filename[len("package://iCub/"):]))
    for element in list(root):
        if element.tag == "gazebo":
            root.remove(element)
    return ET.tostring(root, encoding="unicode")


def reduced_urdf_path(kinematic: bool = False) -> Path:
    """Path of the reduced URDF (see :func:`reduced_urdf_text`), written once into a cache folder
    keyed by its content."""
    source = _source_urdf()
    text = reduced_urdf_text(source, kinematic)
    digest = hashlib.sha256(text.encode()).hexdigest()[:16]
    cache = Path(os.environ.get("VSLSP_CACHE", Path(tempfile.gettempdir()) / "vslsp-cache"))
    cache.mkdir(parents=True, exist_ok=True)
    path = cache / f"icub-reduced-{digest}.urdf"
    if not path.exists():
        partial = path.with_suffix(f".{os.getpid()}.tmp")
        partial.write_text(text)
        os.replace(partial, path)
    return path
