"""Visuospatial Skill Learning (paper, Algorithm 1): grounding the ``far`` predicate from
observations, spatial reasoning, and the demonstration recorder (part I) with its observation
dictionaries O^Pre, O^Post, saved to disk and loaded again.
"""

from vslsp.vsl.grounding import Grounding, SceneGrounding, ground, ground_scene
from vslsp.vsl.spatial import ROBOT_SIDES, far_of, identify_action

__all__ = ["ROBOT_SIDES", "Grounding", "SceneGrounding", "far_of", "ground", "ground_scene", "identify_action"]
