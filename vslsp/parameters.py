"""What the parameter objects share: the check of their fields' ranges.

The tuned rules of each algorithm are frozen dataclasses beside it (after Open3D's
``RANSACConvergenceCriteria``): :mod:`vslsp.vision.parameters` (frame search, object finding)
and :mod:`vslsp.vsl3d.parameters` (cloud matching, grasping). Each field says what it controls
and its valid range, checked here on construction, so that a sweep with a value out of range
stops with one clear :class:`~vslsp.errors.InputError`.
"""

from __future__ import annotations

from dataclasses import fields

from vslsp.errors import InputError


def check_ranges(parameters: object, ranges: dict[str, tuple[float, float]]) -> None:
    """Raise InputError unless each field of the dataclass ``parameters`` lies in its closed
    [low, high] of ``ranges`` (every element, for a tuple); a field whose default is an int
    takes ints only."""
    name = type(parameters).__name__
    for field in fields(parameters):  # type: ignore[arg-type]
        low, high = ranges[field.name]
        values = getattr(parameters, field.name)
        whole = isinstance(field.default, int)
        for value in values if isinstance(values, tuple) else (values,):
            number = isinstance(value, int) if whole else isinstance(value, int | float)
            if isinstance(value, bool) or not number or not low <= value <= high:
                raise InputError(f"{name}.{field.name} is {values!r}; it must lie in [{low}, {high}]")
