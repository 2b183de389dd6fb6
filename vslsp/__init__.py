"""vslsp: Visuospatial Skill Learning for robots.

Three systems from Ahmadzadeh et al., "Visuospatial Skill Learning for Robots":
VSL (learn a pick-and-place task from pre-/post-action images of one demonstration),
VSL-3D (the same on point clouds) and VSL-SP (imitation-learned push/pull skills, VSL
grounding of the ``far`` predicate, PDDL 3.0 planning with Fast Downward, execution in a
pybullet iCub simulator).
"""

__version__ = "0.1.0"

from vslsp.errors import VslspError  # noqa: E402

__all__ = ["VslspError", "__version__", "ground"]


def __getattr__(name: str):
    # ``vslsp.ground`` is imported on first use, so that ``import vslsp`` stays light (no OpenCV).
    if name == "ground":
        from vslsp.grounding.operation import ground

        return ground
    raise AttributeError(f"module 'vslsp' has no attribute {name!r}")
