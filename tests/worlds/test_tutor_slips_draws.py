"""The tutor's slips (vslsp.worlds.slips): seeded, in the stated ranges, at the stated rate, and
drawn the same way whether or not an operation slips."""

from __future__ import annotations

import math

import pytest

from vslsp.worlds.slips import MAX_TURN_DEG, NUDGE_M, TutorSlips

OTHERS = ["duck", "mug", "teddy"]


def slips(probability: float, seed: int, operations: int = 400) -> list:
    tutor = TutorSlips(probability, seed)
    return [tutor.draw(k, OTHERS) for k in range(operations)]


def test_the_same_seed_gives_the_same_slips_and_another_seed_others():
    assert slips(0.5, 7) == slips(0.5, 7)
    assert slips(0.5, 7) != slips(0.5, 8)


def test_slips_come_at_the_rate_asked_within_the_ranges():
    drawn = [s for s in slips(0.5, 3) if s is not None]
    assert 160 <= len(drawn) <= 240  # 400 operations at 0.5: 200 +- 4 sigma
    assert {s.name for s in drawn} == set(OTHERS)
    low, high = NUDGE_M
    assert all(low - 1e-9 <= s.distance_m <= high + 1e-9 for s in drawn)
    assert all(abs(s.dyaw_deg) <= MAX_TURN_DEG for s in drawn)
    assert max(abs(s.dyaw_deg) for s in drawn) > 0.8 * MAX_TURN_DEG
    assert {math.copysign(1, s.dx_m) for s in drawn} == {-1.0, 1.0}


def test_a_slip_does_not_shift_the_draws_of_later_operations():
    # the same seed at probability 0 and 1: the same draws, so where both slip they agree
    never, always = slips(0.0, 11, 20), slips(1.0, 11, 20)
    assert never == [None] * 20 and all(s is not None for s in always)
    sometimes = slips(0.5, 11, 20)
    assert all(s is None or s == a for s, a in zip(sometimes, always, strict=True))


def test_nothing_slips_onto_no_other_object_and_a_bad_probability_is_refused():
    assert TutorSlips(1.0, 0).draw(0, []) is None
    with pytest.raises(ValueError, match="from 0 to 1"):
        TutorSlips(1.5, 0)
