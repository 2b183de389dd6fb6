"""pytest plugin of the grounding test kit (registered through the ``pytest11`` entry point, so
installing vslsp makes its fixtures available to every test; docs/grounding.md).

Fixtures:

- ``synthetic_pair``: :func:`vslsp.grounding.testkit.synthetic_pair`, drawn tabletop pairs;
- ``rendered_pair``: :func:`vslsp.grounding.testkit.rendered_pair`, pybullet-rendered pairs;
- ``assert_grounds``: :func:`vslsp.grounding.testkit.assert_grounds` writing its overlay
  pictures into the test's ``tmp_path`` (the failure message gives the file).

Paper, VSL-SP "Implementation": grounding symbols from pre- and post-action images.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest


def pytest_configure(config: pytest.Config) -> None:
    """Register the ``slow`` marker the tutorial's rendered-scene tests use (no PytestUnknownMarkWarning)."""
    config.addinivalue_line("markers", "slow: a slow end-to-end test (a rendered scene); deselect with -m 'not slow'")


def pytest_report_header(config: pytest.Config) -> str:
    return "vslsp grounding kit: fixtures synthetic_pair, rendered_pair, assert_grounds"


@pytest.fixture
def synthetic_pair() -> Callable:
    """``synthetic_pair(squares, move=(index, (x, y)), ...)``: a drawn pair with its truth."""
    from vslsp.grounding import testkit

    return testkit.synthetic_pair


@pytest.fixture
def rendered_pair() -> Callable:
    """``rendered_pair(spec, move=(cube, (x, y)), camera="head", ...)``: a rendered pair with its truth."""
    from vslsp.grounding import testkit

    return testkit.rendered_pair


@pytest.fixture
def assert_grounds(tmp_path: Path) -> Callable:
    """``assert_grounds(pre, post, atoms_pre=..., atoms_post=...)``; overlays go to ``tmp_path``."""
    from vslsp.grounding import testkit

    def assert_grounds(*args: Any, **kwargs: Any) -> Any:
        __tracebackhide__ = True  # the failure shows the test's line and the message, not this wrapper
        return testkit.assert_grounds(*args, **{"overlay_dir": tmp_path, **kwargs})

    return assert_grounds
