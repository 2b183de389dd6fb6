"""Helpers shared by the tests (importable as ``helpers``: ``pythonpath = tests`` in pyproject.toml)."""
