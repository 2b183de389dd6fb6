"""What the parameter objects share: the check of their fields' ranges, and settings read from
the command line (``--param PREFIX.FIELD=VALUE``).

The tuned rules of each algorithm are frozen dataclasses beside it (after Open3D's
``RANSACConvergenceCriteria``): :mod:`vslsp.vision.parameters` (frame search, object finding)
and :mod:`vslsp.vsl3d.parameters` (cloud matching, grasping). Each field says what it controls
and its valid range, checked here on construction, so that a sweep with a value out of range
stops with one clear :class:`~vslsp.errors.InputError`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import fields, replace
from typing import TypeVar

from vslsp.errors import InputError

T = TypeVar("T")


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


def with_settings(defaults: dict[str, T], settings: Sequence[str]) -> dict[str, T]:
    """The parameter objects ``defaults`` (by prefix, e.g. ``{"cloud": DEFAULT_CLOUD_MATCHING}``)
    with each of ``settings`` applied, ``PREFIX.FIELD=VALUE`` (``cloud.confident_fitness=0.8``;
    a tuple's elements separated by commas): how a benchmark sweeps a rule. Raises InputError
    for an unknown prefix or field, a value that does not parse as the field's type, or one out
    of its range."""
    chosen = dict(defaults)
    for setting in settings:
        name, equals, text = setting.partition("=")
        prefix, dot, field_name = name.strip().partition(".")
        if not equals or not dot or prefix not in chosen:
            raise InputError(
                f"parameter setting {setting!r} is not PREFIX.FIELD=VALUE, PREFIX one of {', '.join(sorted(chosen))}"
            )
        current = chosen[prefix]
        known = {field.name: field for field in fields(current)}  # type: ignore[arg-type]
        if field_name not in known:
            raise InputError(f"{prefix} has no field {field_name!r}; its fields: {', '.join(known)}")
        default = getattr(current, field_name)
        try:
            if isinstance(default, tuple):
                value: object = tuple(float(part) for part in text.split(","))
            else:
                value = int(text) if isinstance(default, int) else float(text)
        except ValueError:
            raise InputError(f"{setting!r}: {text!r} is not a {type(default).__name__}") from None
        chosen[prefix] = replace(current, **{field_name: value})  # type: ignore[type-var]
    return chosen
