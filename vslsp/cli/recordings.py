"""What the commands on a user's recording folders share (docs/recordings.md): ``vslsp vsl
learn/reproduce``, ``vslsp vsl3d learn/reproduce`` and ``vslsp learn-domain`` take their folder,
``--out``, ``--json``, ``--step`` and ``--operation`` and their input limits (``--max-pixels``,
``--max-size``) from here, and a reproduction answers its next operation, with or without a
session file, by :func:`answer`."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import click

from vslsp.cli.params import millions_option, prepare_output_file, prepare_output_folder
from vslsp.errors import InputError

JSON_HELP = 'Print one JSON object on stdout ({"error": ...} on failure).'
#: The largest --max-pixels (MP) and --max-size (MB): past them a folder outgrows a machine's memory.
MAX_PIXELS_MP, MAX_SIZE_MB = 10_000.0, 10_000.0


def learn_options(what: str) -> Callable[[Any], Any]:
    """FOLDER, ``--out`` (the folder to write ``what`` into) and ``--json`` of a learning command."""

    def decorate(function: Any) -> Any:
        function = click.option("--json", "as_json", is_flag=True, help=JSON_HELP)(function)
        function = click.option(
            "--out", "out", required=True, type=click.Path(file_okay=False), help=f"The folder to write {what} into."
        )(function)
        return click.argument("folder", type=click.Path(file_okay=False))(function)

    return decorate


def max_pixels_option(function: Any) -> Any:
    """``--max-pixels MP``: the most pixels of the pictures read together, given as ``max_pixels``."""
    from vslsp.vision.image import MAX_FOLDER_PIXELS, MAX_PIXELS_OPTION

    help = (
        "The most megapixels of all the pictures read together (they are held in memory, 3 bytes a pixel; "
        "more is exit 2, naming the picture that goes over)."
    )
    return millions_option(MAX_PIXELS_OPTION, "max_pixels", MAX_FOLDER_PIXELS, "MP", MAX_PIXELS_MP, help)(function)


def max_size_option(function: Any) -> Any:
    """``--max-size MB``: the largest cloud file read (and the most its header may declare), given as ``max_bytes``."""
    from vslsp.vsl3d.files import MAX_CLOUD_BYTES, MAX_SIZE_OPTION

    help = (
        "The largest cloud file read, in MB, and the most bytes of points its header may declare "
        "(a larger one is exit 2, naming it and its size)."
    )
    return millions_option(MAX_SIZE_OPTION, "max_bytes", MAX_CLOUD_BYTES, "MB", MAX_SIZE_MB, help)(function)


def prepare_learned(folder: str, out: str, places: tuple[str, ...], what: str = "the demonstration") -> None:
    """Check that ``out``, where a learning command writes ``places`` (``what``), is not the
    recording's ``folder`` and can be written, and lock it for this run."""
    from vslsp.outputs import refuse_places

    if Path(out).resolve() == Path(folder).resolve():
        raise InputError(f"--out {out} is the recording's folder FOLDER; write {what} elsewhere")
    prepare_output_folder(out)
    refuse_places(out, places)


def reproduce_options(acts: str) -> Callable[[Any], Any]:
    """DEMO, SCENE, ``--step`` (the user's robot ``acts``, e.g. "photographs", and asks again) and
    ``--operation`` of a reproducing command."""

    def decorate(function: Any) -> Any:
        function = click.option(
            "--operation",
            type=click.IntRange(min=1),
            default=1,
            show_default=True,
            help="Without --step: the operation to answer (1 = the first).",
        )(function)
        function = click.option(
            "--step",
            "session_file",
            type=click.Path(dir_okay=False),
            default=None,
            help="A session file (JSON, created when missing): answer its next operation and move on, so that "
            f'your robot acts, {acts} and asks again; {{"done": true}} when every operation is done.',
        )(function)
        function = click.argument("scene", type=click.Path(dir_okay=False))(function)
        return click.argument("demo", type=click.Path(file_okay=False))(function)

    return decorate


def reply(
    demo: str,
    scene: str,
    session_file: str | None,
    operation: int,
    count: int,
    ask: Callable[[int], dict],
    as_json: bool,
    told: Callable[[dict], list[str]],
) -> None:
    """Answer for the demonstration ``demo`` of ``count`` operations in ``scene`` and print it
    (one JSON object with ``as_json``, else the lines ``told`` makes of it): with a session file
    its next operation (and the file moved on, written atomically, only once the answer is
    complete), else operation ``operation`` (1-based); ``ask(k)`` answers operation ``k``
    (0-based); ``{"done": true}`` past the last."""
    from vslsp.vsl.learned import Session

    session = None
    if session_file is not None:
        prepare_output_file(session_file, "--step")
        session = Session.open(session_file, demo, count)
        k = session.next
    elif operation > count:
        raise InputError(f"--operation {operation}: the demonstration has {count} operations")
    else:
        k = operation - 1
    if k >= count:
        answer: dict = {"done": True, "operations": count}
    else:
        answer = ask(k)
        if session is not None and session_file is not None:
            session.next, session.given = k + 1, [*(session.given or []), {"scene": str(scene), **answer}]
            session.save(session_file)
    if as_json:
        click.echo(json.dumps(answer))
    elif answer["done"]:
        click.echo(f"done: all {answer['operations']} operations of the demonstration are done")
    else:
        click.echo("\n".join(told(answer)))
