"""Dynamic movement primitives (Ijspeert et al. 2013), batched in torch.

Paper section "Learning Sensorimotor Skills using Imitation Learning".
"""

from vslsp.dmp.dmp import DMP, Rollout

__all__ = ["DMP", "Rollout"]
