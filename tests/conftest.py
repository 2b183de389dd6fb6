"""Test-wide settings: headless plotting, single-threaded torch (the suite runs 2 workers)."""

import os

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("OMP_NUM_THREADS", "1")
