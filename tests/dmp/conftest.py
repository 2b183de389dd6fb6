"""Fixtures of the DMP tests (helpers: tests/helpers/dmp.py)."""

import pytest
from helpers.dmp import reach

from vslsp.dmp import DMP


@pytest.fixture(scope="module")
def demo():
    return reach()


@pytest.fixture(scope="module")
def dmp(demo):
    return DMP(3).fit([demo])
