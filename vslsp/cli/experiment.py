"""``vslsp experiment NAME``: the paper's VSL-SP experiments as seeded, randomised trials."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import click

EXPERIMENTS = ("simple-vsl-task", "keep-all-near", "pull-in-order",  # as vslsp.experiments (heavy to import)
               "house-roof",  # VSL without a robot: vslsp.vsl.tasks
               "alphabet-ordering", "animal-puzzle", "tower-of-hanoi", "animals-vs-machines", "domino")  # tabletop


@click.command()
@click.argument("name", type=click.Choice(EXPERIMENTS))
@click.option("--trials", type=click.IntRange(1, 10000), default=1, show_default=True)
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the first trial (then seed+1, ...).")
@click.option("--workers", type=click.IntRange(1, 64), default=1, show_default=True,
              help="Processes running trials in parallel.")
@click.option("--faults", is_flag=True, help="Inject an execution fault per trial (cube nudged back, step skipped).")
@click.option("--planner", default="fast-downward", show_default=True, help="unified-planning oneshot planner.")
@click.option("--skills", "skills_dir", type=click.Path(file_okay=False), default=None,
              help="Skill library folder (default: the shipped skills/).")
@click.option("--out", type=click.Path(file_okay=False), default=None,
              help="Report folder (default: out/experiments/NAME).")
@click.option("--json", "as_json", is_flag=True, help="Print the summary as one JSON object on stdout.")
@click.option("--predicates", "predicates_file", type=click.Path(dir_okay=False), default=None,
              help="A Python file of your predicates (@predicate from vslsp.grounding), grounded with far at every "
                   "observed step and learned into the action models, rules and goals (simple-vsl-task, "
                   "keep-all-near, pull-in-order). It runs as Python with your rights, like a pytest conftest.py.")
def experiment(name: str, trials: int, seed: int, workers: int, faults: bool, planner: str,
               skills_dir: str | None, out: str | None, as_json: bool, predicates_file: str | None) -> None:
    """Run experiment NAME (simple-vsl-task, keep-all-near, pull-in-order, house-roof, alphabet-ordering,
    animal-puzzle, tower-of-hanoi, animals-vs-machines, domino) and write a report.

    Exit 0 when every trial succeeded, 1 otherwise.
    """
    if predicates_file is not None:
        from vslsp.errors import InputError
        from vslsp.grounding import load_predicates

        if name not in EXPERIMENTS[:3]:
            raise InputError(f"--predicates applies to {', '.join(EXPERIMENTS[:3])} (VSL-SP), not to {name}")
        load_predicates(predicates_file)  # a file that does not load is reported before any work
        predicates_file = str(Path(predicates_file).resolve())
    if name == "house-roof":
        from vslsp.vsl.house_roof_report import command

        return command(trials, seed, workers, out, as_json, faults)
    if name in EXPERIMENTS[4:]:
        from vslsp.vsl.tabletop_report import command as tabletop_command

        return tabletop_command(name, trials, seed, workers, out, as_json, faults)
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from vslsp.experiments import run_trials
    from vslsp.report import summary, write_report
    from vslsp.skills.library import SkillLibrary, default_library_path

    library_path = Path(skills_dir) if skills_dir else default_library_path()
    SkillLibrary.load(library_path)  # a missing or corrupt library is reported before any work
    folder = Path(out) if out else Path("out") / "experiments" / name
    console = Console(stderr=True)
    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  TextColumn("{task.fields[ok]} ok"), console=console, transient=True) as progress:
        task = progress.add_task(name, total=trials, ok=0)
        done = {"ok": 0}

        def advance(trial) -> None:
            done["ok"] += trial.success
            progress.update(task, advance=1, ok=done["ok"])

        results = run_trials(name, trials, seed, library_path, workers=workers, faults=faults, planner=planner,
                             on_done=advance, predicates_file=predicates_file)
    write_report(folder, name, results, faults)
    data = summary(name, results, faults)
    data["report"] = str(folder)
    if as_json:
        click.echo(json.dumps(data))
    else:
        click.echo(f"{name}: {data['successes']}/{data['trials']} trials succeeded "
                   f"({100 * data['success_rate']:.1f} %), {data['replans']} replans; report: {folder}")
        for failure in data["failures"][:10]:
            click.echo(f"  seed {failure['seed']}: {failure['error']}", err=True)
    sys.exit(0 if data["successes"] == data["trials"] else 1)
