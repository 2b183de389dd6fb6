"""VSL-3D: Visuospatial Skill Learning on point clouds (paper, section "VSL-3D: An Extension to
3D Tasks"). Point clouds from depth images, a k-d tree, normals, FPFH, RANSAC/SAC-IA/ICP
registration, and VSL-3D's getObject and findBestMatch over them.
"""

from vslsp.vsl3d.cloud import DepthCamera, Frame, pass_through, voxel_downsample
from vslsp.vsl3d.kdtree import KDTree, Neighbours
from vslsp.vsl3d.matching import CloudMatch, find_best_match
from vslsp.vsl3d.registration import Registration
from vslsp.vsl3d.vsl import CloudObservation, MovedObject, WorldCloud, get_object

__all__ = [
    "CloudObservation",
    "DepthCamera",
    "Frame",
    "KDTree",
    "CloudMatch",
    "MovedObject",
    "Neighbours",
    "Registration",
    "WorldCloud",
    "find_best_match",
    "get_object",
    "pass_through",
    "voxel_downsample",
]
