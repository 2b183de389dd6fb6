"""What a perturbation is (:class:`Perturbation`, the levels a user asks for) and what it draws for
one trial (:class:`Drawn`: the camera's move, the light, the seeds of the noise, which object is
hidden and from which side).

The levels are magnitudes; the draw picks the directions (which way the camera moves and turns,
whether the light is brighter or darker, where the shadow falls) from a stream of its own, seeded
by the trial's seed and :data:`STREAM`, so that the scene, the demonstration and the tutor's slips
draw exactly what they drew without it. A perturbation with every level at its neutral value
draws nothing at all (:attr:`Perturbation.none`).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, fields
from typing import Any

import numpy as np

from vslsp.errors import InputError

#: The random stream of perturbations (the second word of the seed sequence, beside the trial's seed).
STREAM = 0x5EE_0038

#: The perturbation kinds, as the issue and the report name them, and the levels of each.
KINDS: dict[str, tuple[str, ...]] = {
    "camera": ("camera",),
    "scale": ("scale",),
    "light": ("brightness", "contrast", "temperature", "shadow"),
    "noise": ("noise", "salt", "jpeg", "depth_noise", "holes"),
    "occlusion": ("occlusion",),
    "clutter": ("clutter",),
}


def _level(low: float, high: float, unit: str, what: str, neutral: float = 0.0) -> Any:
    return field(default=neutral, metadata={"range": (low, high), "unit": unit, "what": what})


@dataclass(frozen=True)
class Perturbation:
    """How the reproduction's world differs from the demonstration's. Each level's neutral value
    (the default) leaves that part as it was; its range and unit are in the field's metadata
    (:meth:`describe`)."""

    camera: float = _level(
        0.0,
        15.0,
        "cm and deg",
        "the camera moved this many cm and turned this many deg (the iCub: its head turned this many deg)",
    )
    scale: float = _level(
        0.5, 2.0, "x", "objects this many times their size in the image (the camera nearer, > 1, or farther, < 1)", 1.0
    )
    brightness: float = _level(0.0, 80.0, "%", "the light this many per cent brighter or darker (which: drawn)")
    contrast: float = _level(0.0, 80.0, "%", "the contrast this many per cent higher or lower (which: drawn)")
    temperature: float = _level(
        2000.0, 12000.0, "K", "the light's colour temperature (the demonstration's: 6500 K daylight)", 6500.0
    )
    shadow: float = _level(0.0, 0.9, "", "a soft band across the view darkened by this share of its light")
    noise: float = _level(0.0, 64.0, "grey levels", "Gaussian sensor noise of this standard deviation")
    salt: float = _level(0.0, 0.2, "", "this share of pixels set black or white")
    jpeg: float = _level(0.0, 100.0, "quality", "each image JPEG-compressed at this quality (0: not compressed)")
    depth_noise: float = _level(0.0, 20.0, "mm", "Gaussian depth noise of this standard deviation (RGB-D)")
    holes: float = _level(0.0, 0.5, "", "this share of depth pixels lost (RGB-D)")
    occlusion: float = _level(0.0, 75.0, "%", "this share of one object hidden in every reproduction observation")
    clutter: float = _level(0.0, 6.0, "objects", "this many distractor objects that were not in the demonstration")

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            low, high = f.metadata["range"]
            if not (isinstance(value, (int, float)) and np.isfinite(value) and low <= value <= high):
                raise InputError(
                    f"perturbation {f.name}={value!r} is out of range: give {f.name}={low:g} to {high:g}"
                    f" ({f.metadata['unit'] or 'a share'}: {f.metadata['what']})"
                )
        if self.jpeg and self.jpeg < 1:
            raise InputError(f"perturbation jpeg={self.jpeg:g}: give a JPEG quality of 1 to 100, or 0 for none")
        if self.clutter != int(self.clutter):
            raise InputError(f"perturbation clutter={self.clutter:g}: give a whole number of distractors, 0 to 6")

    @classmethod
    def parse(cls, items: list[str] | tuple[str, ...]) -> Perturbation:
        """The perturbation of ``items`` such as ``["camera=10", "noise=8"]`` (the ``--perturb``
        option's values; ``NAME=LEVEL`` each, the names of :meth:`describe`)."""
        known = {f.name for f in fields(cls)}
        levels: dict[str, float] = {}
        for item in items:
            name, sep, text = item.partition("=")
            name = name.strip().replace("-", "_")
            if not sep or name not in known:
                raise InputError(
                    f"--perturb {item!r}: give NAME=LEVEL with NAME one of {', '.join(sorted(known))} (e.g. camera=10)"
                )
            try:
                levels[name] = float(text)
            except ValueError:
                raise InputError(f"--perturb {item!r}: the level must be a number (e.g. {name}=10)") from None
        return cls(**levels)

    @classmethod
    def describe(cls) -> dict[str, dict[str, Any]]:
        """Each level's neutral value, range, unit and meaning (for the CLI's help and docs/cli.md)."""
        return {
            f.name: {
                "neutral": f.default,
                "range": f.metadata["range"],
                "unit": f.metadata["unit"],
                "what": f.metadata["what"],
            }
            for f in fields(cls)
        }

    @property
    def none(self) -> bool:
        """Whether every level is at its neutral value (nothing is perturbed, nothing drawn)."""
        return all(getattr(self, f.name) == f.default for f in fields(self))

    def kinds(self) -> tuple[str, ...]:
        """The kinds (:data:`KINDS`) this perturbation changes."""
        return tuple(kind for kind, names in KINDS.items() if any(self._set(n) for n in names))

    def _set(self, name: str) -> bool:
        default = next(f.default for f in fields(self) if f.name == name)
        return bool(getattr(self, name) != default)

    def to_dict(self) -> dict[str, float]:
        """The levels that differ from neutral (the report's ``perturbation.levels``)."""
        return {name: value for name, value in asdict(self).items() if self._set(name)}

    def draw(self, seed: int) -> Drawn:
        """What this perturbation is in the trial of ``seed``: directions and seeds drawn from the
        perturbations' own stream (nothing is drawn when :attr:`none`)."""
        if self.none:
            return Drawn(self)
        rng = np.random.default_rng([seed, STREAM])
        heading = rng.uniform(0.0, 2.0 * np.pi)  # the camera's shift, in the table's plane
        axis = rng.normal(size=3)
        brighter, higher = rng.choice((-1.0, 1.0), size=2)
        shadow_angle, shadow_offset = rng.uniform(0.0, np.pi), rng.uniform(-0.3, 0.3)
        occluded, occluded_from = rng.uniform(), rng.uniform(0.0, 2.0 * np.pi)
        return Drawn(
            self,
            shift=(self.camera / 100.0 * float(np.cos(heading)), self.camera / 100.0 * float(np.sin(heading)), 0.0),
            turn_axis=_unit(axis),
            brightness=1.0 + float(brighter) * self.brightness / 100.0,
            contrast=1.0 + float(higher) * self.contrast / 100.0,
            shadow=(float(shadow_angle), float(shadow_offset)),
            occluded=float(occluded),
            occluded_from=float(occluded_from),
            noise_seed=int(rng.integers(2**63)),
            layout_seed=int(rng.integers(2**63)),
        )


def _unit(vector: np.ndarray) -> tuple[float, float, float]:
    unit = vector / np.linalg.norm(vector)
    return (float(unit[0]), float(unit[1]), float(unit[2]))


@dataclass(frozen=True)
class Drawn:
    """One trial's perturbation: the levels (:attr:`levels`) and what was drawn for them: the
    camera's ``shift`` (m, in the table's plane) and the axis it turns about (by ``levels.camera``
    deg), the light's ``brightness`` and ``contrast`` factors, the shadow's band (its angle in rad
    and its offset from the centre, in shares of the view's diagonal), which object is hidden (a
    share of the world's objects in their order, ``occluded``) and from which side
    (``occluded_from``, rad), and the seeds of the images' noise and of the distractors' layout."""

    levels: Perturbation
    shift: tuple[float, float, float] = (0.0, 0.0, 0.0)
    turn_axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    brightness: float = 1.0
    contrast: float = 1.0
    shadow: tuple[float, float] = (0.0, 0.0)
    occluded: float = 0.0
    occluded_from: float = 0.0
    noise_seed: int = 0
    layout_seed: int = 0

    @property
    def none(self) -> bool:
        return self.levels.none

    @property
    def photometric(self) -> bool:
        """Whether the images themselves change (light or noise)."""
        return any(kind in self.levels.kinds() for kind in ("light", "noise"))

    def noise_rng(self, index: int) -> np.random.Generator:
        """The noise of the reproduction's ``index``-th image (each image its own)."""
        return np.random.default_rng([self.noise_seed, index])

    def to_dict(self) -> dict[str, Any]:
        """The report's ``perturbation``: the levels and the draw that matters to a reader."""
        if self.none:
            return {}
        drawn: dict[str, Any] = {"kinds": list(self.levels.kinds()), "levels": self.levels.to_dict()}
        if self.levels.camera:
            drawn["camera"] = {
                "shift_m": [round(float(v), 4) for v in self.shift],
                "turn_axis": [round(float(v), 3) for v in self.turn_axis],
            }
        if self.levels.brightness:
            drawn["brightness_factor"] = round(self.brightness, 3)
        if self.levels.contrast:
            drawn["contrast_factor"] = round(self.contrast, 3)
        return drawn
