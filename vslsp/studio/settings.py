"""What ``vslsp studio``'s options set beyond who may reach it (:mod:`vslsp.studio.guard`)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Settings:
    """``max_jobs``: runs and picture jobs that run at once (``--max-runs``, 1-64); the others wait in a
    queue. ``edit_code``: whether the predicates editor may save ``.py`` files under the root
    (``--edit-code``; off: the studio writes no file that Python would run)."""

    max_jobs: int = 2
    edit_code: bool = False
