"""The budget's and the user-code limit's SIGALRM timers never outlive their block, however soon the
alarm fires (CI: a 1 ms budget whose alarm came before its block was entered stayed armed and raised
OverBudget every 50 ms in whatever ran next, pytest's own reporting included)."""

import signal

import pytest

from vslsp.grounding.user_code import TimeLimitExceeded, time_limit
from vslsp.symbolic.budget import OverBudget, time_budget


@pytest.mark.parametrize("limit, stop", [(time_budget, OverBudget), (time_limit, TimeLimitExceeded)])
def test_a_timer_that_fires_at_once_ends_with_its_block(limit, stop):
    before = signal.getsignal(signal.SIGALRM)
    stopped = 0
    for seconds in [1e-6] * 200 + [1e-4] * 100:
        try:
            with limit(seconds):
                sum(range(2000))
        except stop:
            stopped += 1
        assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)  # disarmed, whatever happened
        assert signal.getsignal(signal.SIGALRM) is before  # and the previous handler back
    assert stopped > 0  # the alarm did fire inside (and was raised there)
