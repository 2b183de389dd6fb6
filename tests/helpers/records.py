"""Trial records compared across runs, processes and backends: everything but the clocks
(:mod:`vslsp.tasks.records`, which the studio's re-drawn trials are checked with too)."""

from vslsp.tasks.records import TIMES, without_times

__all__ = ["TIMES", "without_times"]
