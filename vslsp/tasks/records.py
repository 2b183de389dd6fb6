"""Trial records compared across runs, processes and backends: everything but the clocks.

A trial is deterministic for its seed, so two runs of it give the same record but for the wall and
CPU times: the report's figure re-run, the Ray backend and the studio's drawing of a trial's pictures
(:mod:`vslsp.studio.trial_figures`) are checked this way."""

from __future__ import annotations

from typing import Any

#: Wall and CPU times, which differ between two runs of the same seeded trial; removed at any depth.
TIMES = frozenset({"time_s", "cpu_s", "reproduction_ms", "stages_s", "planning_s"})


def without_times(record: Any) -> Any:
    """``record`` (a trial's ``to_dict()`` or any JSON value) less every :data:`TIMES` key, at any depth."""
    if isinstance(record, dict):
        return {k: without_times(v) for k, v in record.items() if k not in TIMES}
    if isinstance(record, list):
        return [without_times(v) for v in record]
    return record
