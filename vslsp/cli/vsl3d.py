"""``vslsp vsl3d``: VSL-3D's experiments, an alias of ``vslsp experiment`` for its tasks."""

from __future__ import annotations

import click

from vslsp.cli.experiment import experiment


@click.group()
def vsl3d() -> None:
    """VSL-3D: learn object reconfigurations from RGB-D point clouds (alias of vslsp experiment)."""


@vsl3d.command("table-cleaning", context_settings={"ignore_unknown_options": True})
@click.argument("args", nargs=-1, type=click.UNPROCESSED)
@click.pass_context
def table_cleaning(ctx: click.Context, args: tuple[str, ...]) -> None:
    """The table-cleaning experiment: the same as `vslsp experiment table-cleaning ARGS`."""
    experiment.main(["table-cleaning", *args], prog_name="vslsp experiment", standalone_mode=False)
