"""``vslsp vsl3d``: VSL-3D, Visuospatial Skill Learning on point clouds (paper, section "VSL-3D")."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import click

METHODS = ("prerejective_ransac", "sac_ia", "icp")  # as vslsp.vsl3d.alignment.METHODS (heavy to import)


@click.group()
def vsl3d() -> None:
    """VSL-3D: learn object reconfigurations from RGB-D point clouds."""


@vsl3d.command("table-cleaning")
@click.option("--trials", type=click.IntRange(1, 1000), default=1, show_default=True)
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the first trial (then seed+1, ...).")
@click.option("--method", type=click.Choice(METHODS), default="prerejective_ransac", show_default=True,
              help="Match finding: pre-rejective RANSAC, SAC-IA or ICP (each refined by point-to-plane ICP).")
@click.option("--out", type=click.Path(file_okay=False), default=None,
              help="Report folder (default: out/experiments/table-cleaning).")
@click.option("--json", "as_json", is_flag=True, help="Print the summary as one JSON object on stdout.")
def table_cleaning(trials: int, seed: int, method: str, out: str | None, as_json: bool) -> None:
    """The table-cleaning experiment: the tutor puts two objects into the box and one in front
    of it; the objects are reshuffled and VSL-3D reproduces the task from the point clouds.

    Writes per trial the demonstration images (pre/post with the object's frame), the final
    image and report.json; exit 0 when every trial succeeded, 1 otherwise.
    """
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from vslsp.vsl3d.table_cleaning import run_table_cleaning

    folder = Path(out) if out else Path("out") / "experiments" / "table-cleaning"
    results = []
    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=Console(stderr=True), transient=True) as progress:
        task = progress.add_task("table-cleaning", total=trials)
        for trial in range(seed, seed + trials):
            results.append(run_table_cleaning(trial, method, folder / f"seed_{trial}"))
            progress.advance(task)
    operations = [op for result in results for op in result.operations]
    errors_mm = [op.final_error_mm for op in operations if op.success]
    errors_deg = [op.final_error_deg for op in operations if op.success]
    data = {
        "experiment": "table-cleaning", "trials": trials, "successes": sum(r.success for r in results),
        "success_rate": sum(r.success for r in results) / trials, "method": method,
        "operations": len(operations), "operations_succeeded": sum(op.success for op in operations),
        "median_error_mm": float(sorted(errors_mm)[len(errors_mm) // 2]) if errors_mm else None,
        "median_error_deg": float(sorted(errors_deg)[len(errors_deg) // 2]) if errors_deg else None,
        "failures": [{"seed": r.seed, "operation": op.index, "object": op.moved,
                      "error": op.error or f"ended {op.final_error_mm} mm / {op.final_error_deg} deg from the "
                                           f"demonstrated pose (picked {op.picked})"}
                     for r in results for op in r.operations if not op.success],
        "report": str(folder),
    }
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "summary.json").write_text(json.dumps(data, indent=2))
    if as_json:
        click.echo(json.dumps(data))
    else:
        click.echo(f"table-cleaning: {data['successes']}/{trials} trials succeeded, "
                   f"{data['operations_succeeded']}/{data['operations']} operations "
                   f"(median final error {data['median_error_mm']} mm, {data['median_error_deg']} deg); "
                   f"report: {folder}")
        for failure in data["failures"][:10]:
            click.echo(f"  seed {failure['seed']} operation {failure['operation']} ({failure['object']}): "
                       f"{failure['error']}", err=True)
    sys.exit(0 if data["successes"] == trials else 1)
