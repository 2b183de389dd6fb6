"""Build script: the package list, with the shipped data folders mapped into the package.

Everything else is declared in ``pyproject.toml``; the top-level ``skills/`` and ``pddl/``
folders become the packages ``vslsp.data.skills`` and ``vslsp.data.pddl`` (``package-dir``
there), which a declarative ``packages.find`` cannot list next to the discovered ones.
"""

from setuptools import find_packages, setup

setup(packages=find_packages(include=["vslsp", "vslsp.*"]) + ["vslsp.data.skills", "vslsp.data.pddl"])
