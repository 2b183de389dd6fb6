"""The iCub model from ``icub-models``, reduced so that pybullet handles it.

As shipped, ``iCubGazeboV2_5`` has ~170 sensor and skin frames with no inertial, visual or
collision element; pybullet gives each of them 1 kg and several state queries fail on the
resulting 212-link body. We keep the links that carry a body (plus the two hand frames used as
end effectors), drop the rest with their fixed joints, and resolve ``package://iCub`` to the
installed mesh folder. The result has 32 revolute joints and weighs about 28 kg.

The copy that the world simulates is lighter still (:func:`simulated_urdf_text`): only the
joints the robot moves stay revolute (every other joint is frozen at its posture, baked into
the joint's origin), only the links that touch the cubes keep a collision shape, and headless
worlds drop the meshes the cameras never see (all but the right arm's, the chest's and the
right leg's). Physics steps, renders and loads are cheaper; the kinematics is unchanged.
"""

from __future__ import annotations

import functools
import hashlib
import os
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from vslsp.errors import VslspError
from vslsp.files import cache_folder

MODEL_NAME = "iCubGazeboV2_5"
HAND_FRAMES = ("r_hand_dh_frame", "l_hand_dh_frame")
FRAME_MASS = 1e-4  # kg: a frame link in the simulated model (see simulated_urdf_text)


def _source_urdf() -> Path:
    try:
        import icub_models
    except ImportError as error:  # pragma: no cover - a broken install
        raise VslspError("the iCub model is missing: install the package 'icub-models' (make install)") from error
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
            kept.add(str(link.get("name")))
        else:
            root.remove(link)
    if kinematic:
        for link in root.findall("link"):
            for element in link.findall("visual") + link.findall("collision"):
                link.remove(element)
    for joint in list(root.findall("joint")):
        child, parent = joint.find("child"), joint.find("parent")
        if child is None or parent is None or child.get("link") not in kept or parent.get("link") not in kept:
            root.remove(joint)
    for axis in root.iter("axis"):  # pybullet warns about (and renormalises) non-unit axes
        values = [float(v) for v in axis.get("xyz", "1 0 0").split()]
        norm = sum(v * v for v in values) ** 0.5 or 1.0
        axis.set("xyz", " ".join(repr(v / norm) for v in values))
    for mesh in root.iter("mesh"):
        filename = mesh.get("filename", "")
        if filename.startswith("package://iCub/"):
            mesh.set("filename", str(package_root / filename[len("package://iCub/") :]))
    for element in list(root):
        if element.tag == "gazebo":
            root.remove(element)
    return ET.tostring(root, encoding="unicode")


def _rpy_matrix(rpy: np.ndarray) -> np.ndarray:
    """URDF's fixed-axis roll-pitch-yaw (3,) as a rotation (3, 3): Rz(yaw) Ry(pitch) Rx(roll)."""
    (cr, cp, cy), (sr, sp, sy) = np.cos(rpy), np.sin(rpy)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def _matrix_rpy(rotation: np.ndarray) -> np.ndarray:
    """The inverse of :func:`_rpy_matrix` (3, 3) -> (3,)."""
    pitch = np.arcsin(np.clip(-rotation[2, 0], -1.0, 1.0))
    return np.array([np.arctan2(rotation[2, 1], rotation[2, 2]), pitch, np.arctan2(rotation[1, 0], rotation[0, 0])])


def _axis_rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation (3, 3) by ``angle`` rad about the unit ``axis`` (3,) (Rodrigues)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * k @ k


def simulated_urdf_text(
    source: Path,
    moving: Iterable[str],
    posture: Mapping[str, float],
    contact_links: Iterable[str],
    visual_links: Iterable[str] | None,
) -> str:
    """The reduced URDF of ``source`` as the world simulates it.

    Joints not in ``moving`` become fixed at their ``posture`` value (0 when not given): the
    child frame ``T(xyz) R(rpy) R(axis, q)`` becomes the origin of a fixed joint. Only links in
    ``contact_links`` keep their collision elements, and only those in ``visual_links`` (all
    when None) their visual elements.
    Link frames, masses and inertias are those of :func:`reduced_urdf_text`; a link with no
    inertial element (a frame such as ``r_hand_dh_frame``) gets :data:`FRAME_MASS` and a
    negligible inertia, where pybullet's importer would give it 1 kg and 1 kg m^2 (a phantom
    weight four times the hand's, fixed to it).
    """
    root = ET.fromstring(reduced_urdf_text(source))
    moving, contact_links = set(moving), set(contact_links)
    seen = None if visual_links is None else set(visual_links)
    for joint in root.findall("joint"):
        if joint.get("type") == "fixed" or joint.get("name") in moving:
            continue
        origin = joint.find("origin")
        if origin is None:
            origin = ET.SubElement(joint, "origin")
        rpy = np.array([float(v) for v in origin.get("rpy", "0 0 0").split()])
        axis_element = joint.find("axis")
        axis_text = axis_element.get("xyz", "1 0 0") if axis_element is not None else "1 0 0"
        axis = np.array([float(v) for v in axis_text.split()])
        rotation = _rpy_matrix(rpy) @ _axis_rotation(axis, float(posture.get(joint.get("name", ""), 0.0)))
        origin.set("rpy", " ".join(repr(float(v)) for v in _matrix_rpy(rotation)))
        joint.set("type", "fixed")
        for tag in ("axis", "limit", "dynamics", "safety_controller"):
            for element in joint.findall(tag):
                joint.remove(element)
    for link in root.findall("link"):
        drop = ([] if link.get("name") in contact_links else link.findall("collision")) + (
            [] if seen is None or link.get("name") in seen else link.findall("visual")
        )
        for element in drop:
            link.remove(element)
        if link.find("inertial") is None:  # a frame (e.g. r_hand_dh_frame): pybullet would make it 1 kg, 1 kg m^2
            inertial = ET.SubElement(link, "inertial")
            ET.SubElement(inertial, "mass", value=repr(FRAME_MASS))
            ET.SubElement(inertial, "inertia", ixx="1e-9", ixy="0", ixz="0", iyy="1e-9", iyz="0", izz="1e-9")
    return ET.tostring(root, encoding="unicode")


def _cached(text: str) -> Path:
    """``text`` written once into a cache folder, keyed by its content."""
    digest = hashlib.sha256(text.encode()).hexdigest()[:16]
    cache = cache_folder()
    path = cache / f"icub-reduced-{digest}.urdf"
    if not path.exists():
        partial = path.with_suffix(f".{os.getpid()}.tmp")
        try:
            partial.write_text(text)
            os.replace(partial, path)
        finally:
            partial.unlink(missing_ok=True)
    return path


def reduced_urdf_path(kinematic: bool = False) -> Path:
    """Path of the reduced URDF (see :func:`reduced_urdf_text`)."""
    return _cached(_reduced_text(kinematic))


def simulated_urdf_path(
    moving: tuple[str, ...],
    posture: tuple[tuple[str, float], ...],
    contact_links: tuple[str, ...],
    visual_links: tuple[str, ...] | None,
) -> Path:
    """Path of the simulated URDF (see :func:`simulated_urdf_text`; ``posture`` as (name, value) pairs)."""
    return _cached(_simulated_text(moving, posture, contact_links, visual_links))


@functools.lru_cache(maxsize=2)
def _reduced_text(kinematic: bool) -> str:
    return reduced_urdf_text(_source_urdf(), kinematic)


@functools.lru_cache(maxsize=4)
def _simulated_text(
    moving: tuple[str, ...],
    posture: tuple[tuple[str, float], ...],
    contact_links: tuple[str, ...],
    visual_links: tuple[str, ...] | None,
) -> str:
    return simulated_urdf_text(_source_urdf(), moving, dict(posture), contact_links, visual_links)
