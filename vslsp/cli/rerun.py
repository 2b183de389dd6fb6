"""``--rerun FILE.rrd`` of ``vslsp experiment`` and ``vslsp demo``: every trial logged for rerun's
viewer (:mod:`vslsp.sim.rerun_log`).

Each trial, in whichever worker runs it, writes its own part into the folder ``FILE.rrd.parts``
beside the file; once the trials are done the parts, one recording id, are merged into
``FILE.rrd`` (written whole or not at all, like every output) and the folder goes. An
interrupted run merges the trials that finished. With ``--backend ray`` on a cluster the folder
must be one the workers share.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import click

from vslsp.errors import InputError
from vslsp.outputs import refuse_link, refuse_special

SUFFIX = ".rrd"


def rerun_option(help: str):  # noqa: A002 (click's name)
    """The ``--rerun FILE.rrd`` option."""
    return click.option("--rerun", "rerun_file", type=click.Path(dir_okay=False), default=None, help=help)


def check_recording(path: str) -> Path:
    """The recording's path, checked before any work: the SDK there, a ``.rrd`` name, no link or
    device at it or at its folder of parts, its folder existing (exit 2 otherwise)."""
    from vslsp.sim.rerun_log import check_rerun, parts_folder

    check_rerun()
    out = Path(path)
    if out.suffix != SUFFIX:
        raise InputError(f"--rerun: {path} is not a rerun recording's name; give a FILE.rrd")
    for place in (out, parts_folder(out)):
        refuse_link(place, "--rerun")
        refuse_special(place, "--rerun")
    if out.is_dir():
        raise InputError(f"--rerun: {path} is a folder; give a FILE.rrd")
    if parts_folder(out).exists() and not parts_folder(out).is_dir():
        raise InputError(f"--rerun: {parts_folder(out)} is in the way of the trials' parts; remove it")
    if not out.resolve().parent.is_dir():
        raise InputError(f"--rerun: the folder of {path} does not exist; create it first")
    return out


def start_recording(out: Path) -> str:
    """An empty folder of parts for the run (the parts of an earlier, unfinished run removed);
    returns it, as the tasks take it (``rerun=``)."""
    from vslsp.sim.rerun_log import parts_folder

    parts = parts_folder(out)
    if parts.is_dir():
        for stale in parts.glob("trial-*.rrd"):
            stale.unlink()
    parts.mkdir(exist_ok=True)
    return str(parts.resolve())


def finish_recording(out: Path, parts: str) -> int:
    """Merge the trials' parts into ``out`` (a temporary file renamed over it when whole) and
    remove the folder of parts; returns the number of trials merged."""
    from vslsp.sim.rerun_log import merge, recording_id

    found = sorted(Path(parts).glob("trial-*.rrd"), key=lambda p: int(p.stem.removeprefix("trial-")))
    if found:
        partial = out.with_name(f".{out.name}.{os.getpid()}.tmp")
        try:
            merge(found, partial, recording_id(parts))
            os.replace(partial, out)
        finally:
            partial.unlink(missing_ok=True)
    shutil.rmtree(parts, ignore_errors=True)
    return len(found)
