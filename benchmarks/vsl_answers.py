"""What the VSL-from-files benchmarks share (bench_vsl_files.py, bench_vsl_photos.py): a
``vslsp ... --json`` command run in this process, and the placement tolerance they judge by."""

from __future__ import annotations

import contextlib
import io
import json

from vslsp.cli import main as vslsp_main

POSITION = 0.01  # m: an operation is placed right within 1 cm ...
ANGLE = 5.0  # deg: ... and 5 degrees of its goal (issue 39)


def vslsp(*args: object) -> dict:
    """``vslsp ARGS --json`` in this process: its JSON answer."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.suppress(SystemExit):
        vslsp_main([*map(str, args), "--json"])
    return json.loads(out.getvalue())
