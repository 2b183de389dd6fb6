"""Pure maths below the simulator: planar poses and the paper's pick-and-place trajectory.

Nothing here imports the simulator, perception or planning.
"""

from vslsp.geometry.poses import Pose2, compose, relative, wrap

__all__ = ["Pose2", "compose", "relative", "wrap"]
