"""Checks of an experiment's report folder (vslsp.tasks.report) shared by the task tests."""

from __future__ import annotations

import re
from pathlib import Path

# Markdown links and images: [text](target) and ![text](target)
_LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def report_links(folder: Path) -> list[str]:
    """The targets of every link and image in ``folder/report.md``, in order."""
    return _LINK.findall((folder / "report.md").read_text())


def assert_links_resolve(folder: Path) -> list[str]:
    """Every link of ``report.md`` names a non-empty file inside the report folder; returns them."""
    links = report_links(folder)
    for target in links:
        path = (folder / target).resolve()
        assert folder.resolve() in path.parents, f"report.md links {target!r} outside its folder"
        assert path.is_file() and path.stat().st_size > 0, f"report.md links {target!r}, which is not there"
    return links
