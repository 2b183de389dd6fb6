"""vslsp: Visuospatial Skill Learning for robots.

Three systems from Ahmadzadeh et al., "Visuospatial Skill Learning for Robots":
VSL (learn a pick-and-place task from pre-/post-action images of one demonstration),
VSL-3D (the same on point clouds) and VSL-SP (imitation-learned push/pull skills, VSL
grounding of the ``far`` predicate, PDDL 3.0 planning with Fast Downward, execution in a
pybullet iCub simulator).
"""

__version__ = "0.1.0"

import os

# OpenCV's own limit on the pixels of an image it decodes, checked on the header of every format
# it reads: the same 40 megapixels as vslsp.vision.image.MAX_PIXELS (a lower limit a user set is
# kept). OpenCV reads it once, when cv2 is loaded, so it is set before anything imports cv2.
_CV_LIMIT = "OPENCV_IO_MAX_IMAGE_PIXELS"
if not os.environ.get(_CV_LIMIT, "").isdigit() or int(os.environ[_CV_LIMIT]) > 40_000_000:
    os.environ[_CV_LIMIT] = "40000000"

from vslsp.errors import VslspError  # noqa: E402

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (mypy reads it the same)

if TYPE_CHECKING:
    from vslsp.api import *  # noqa: F403

__all__ = ["VslspError", "__version__", "api", "ground"]  # noqa: F405 (resolved by __getattr__)


def __getattr__(name: str):
    # ``vslsp.api`` and its names (``vslsp.ground``, ``vslsp.Recorder``, ...: docs/api.md) are
    # imported on first use, so that ``import vslsp`` stays light (no OpenCV, no simulator).
    import importlib

    api = importlib.import_module("vslsp.api")
    if name == "api":
        return api
    if name in api.__all__:
        return getattr(api, name)
    raise AttributeError(f"module 'vslsp' has no attribute {name!r}")
