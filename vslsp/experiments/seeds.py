"""Where every world of a trial takes its seed from: the trial's seed and one offset per world.

A trial of seed s demonstrates in the world of s and reproduces in a new world of
s + :data:`REPRODUCTION` (the objects scattered anew, the landmarks moved where the experiment
says); the iCub's skill explorations use s + :data:`EXPLORATION` + k, and keep-all-near's
demonstrations :func:`demonstration_seed`. The offsets are primes far apart, so that no two
worlds of neighbouring trials share a seed.
"""

from __future__ import annotations

REPRODUCTION = 1_000_003  # the reproduction world of trial s: s + REPRODUCTION
EXPLORATION = 2_000_003  # the iCub's skill explorations of trial s: s + EXPLORATION + k
DEMONSTRATIONS = 7  # keep-all-near's demonstration i of trial s: s * DEMONSTRATIONS + i


def reproduction_seed(seed: int) -> int:
    """The seed of trial ``seed``'s reproduction world."""
    return seed + REPRODUCTION


def exploration_seed(seed: int, k: int) -> int:
    """The seed of trial ``seed``'s ``k``-th skill exploration."""
    return seed + EXPLORATION + k


def demonstration_seed(seed: int, i: int) -> int:
    """The seed of demonstration ``i`` of a trial that demonstrates several times."""
    return seed * DEMONSTRATIONS + i
