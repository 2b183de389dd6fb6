"""Perturbations of the world a demonstration is reproduced in: what a researcher's camera meets
that the demonstration did not (the paper's claims of scale, colour and view invariance, and the
failure factors it names: noise and occlusion).

A :class:`~vslsp.perturbations.spec.Perturbation` says how far the reproduction's world differs
from the demonstration's: the camera moved and turned, nearer or farther, other light (brightness,
contrast, colour temperature, a shadow across the table), sensor noise (Gaussian, salt and pepper,
JPEG, depth noise and holes), part of an object hidden, distractor objects. Its draw for a trial
(:meth:`~vslsp.perturbations.spec.Perturbation.draw`) comes from a random stream of its own, so a
perturbation at level 0 draws nothing and leaves a run exactly as it was. The image operations
(:mod:`~vslsp.perturbations.images`) and the camera's move (:mod:`~vslsp.perturbations.viewpoint`)
are pure numpy and OpenCV: the worlds apply them to what their sensors see.
"""

from vslsp.perturbations.spec import KINDS, Drawn, Perturbation

__all__ = ["KINDS", "Drawn", "Perturbation"]
