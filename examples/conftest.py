"""The examples run with the vslsp pytest plugin. Installing vslsp registers it (entry point
``pytest11``); this also loads it where vslsp runs from a source checkout that is not installed."""

import pytest


def pytest_configure(config: pytest.Config) -> None:
    if not config.pluginmanager.has_plugin("vslsp.grounding.pytest_plugin"):
        config.pluginmanager.import_plugin("vslsp.grounding.pytest_plugin")
