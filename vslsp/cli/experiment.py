"""``vslsp experiment NAME``: any registered experiment of the paper as seeded, randomised trials.

Every experiment takes the same options and writes the same report folder (``report.json``,
``report.md``, figures); ``--list`` lists them. Options that only some experiments take
(``--faults``, ``--planner``, ``--skills``, ``--predicates``, ``--method``, ``--tutor-slips``,
``--slip-detection``, ``--views``, ``--intervention``) are refused by the others.
"""

from __future__ import annotations

import json
import signal
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import click

from vslsp.cli.params import PROBABILITY, count, int_range, prepare_output_folder, seed_option
from vslsp.cli.rerun import check_recording, finish_recording, rerun_option, start_recording
from vslsp.errors import Interrupted
from vslsp.interrupts import SIGNALS
from vslsp.outputs import OutputFailed, refuse_places

REPORT_FILES = ("report.json", "report.md")
OUTPUT_FOLDERS = ("images", "images/raw", "videos")  # what a report folder may hold besides its files

MAX_TRIALS = 10_000  # docs/bad-input.md states these limits
MAX_WORKERS = 64


@click.command()
@click.argument("name", required=False)
@click.option("--list", "list_them", is_flag=True, help="List the experiments (with --json: as JSON) and exit.")
@click.option("--trials", type=count(MAX_TRIALS), default=1, show_default=True, help="Trials (1 to 10000).")
@seed_option(help="Seed of the first trial (then seed+1, ...), 0 to 4294967295.")
@click.option(
    "--workers",
    type=count(MAX_WORKERS),
    default=1,
    show_default=True,
    help="Trials running in parallel, 1 to 64 (processes, or Ray tasks with --backend ray).",
)
@click.option(
    "--backend",
    type=click.Choice(["local", "ray"]),
    default="local",
    show_default=True,
    help="local: this machine's processes; ray: a Ray cluster (pip install 'vslsp[ray]').",
)
@click.option(
    "--address",
    default=None,
    help="With --backend ray: the cluster's address ('auto', 'ray://HOST:10001', HOST:PORT); "
    "default: a local Ray instance started for the run.",
)
@click.option(
    "--faults", is_flag=True, help="VSL-SP: inject an execution fault per trial (cube nudged back, step skipped)."
)
@click.option(
    "--video",
    is_flag=True,
    help="VSL-SP: film every trial from a scene camera into videos/trial-SEED.mp4 (H.264) in the report folder.",
)
@rerun_option(
    "VSL-SP and VSL-3D: log every trial (camera images, point clouds, the arm and the hand's path, plan "
    "steps, symbolic state) on one timeline into FILE.rrd for rerun's viewer (pip install 'vslsp[rerun]')."
)
@click.option("--planner", default=None, help="VSL-SP: unified-planning oneshot planner [default: fast-downward].")
@click.option(
    "--skills",
    "skills_dir",
    type=click.Path(file_okay=False),
    default=None,
    help="VSL-SP: skill library folder (default: the shipped skills).",
)
@click.option("--method", default=None, help="VSL-3D: match finding (prerejective_ransac, sac_ia, icp).")
@click.option(
    "--tutor-slips",
    type=PROBABILITY,
    default=None,
    help="The probability, per demonstrated operation, that the tutor also disturbs another object "
    "(a nudge of 1-4 cm and up to 20 deg, seeded) [default: 0].",
)
@click.option(
    "--perturb",
    "perturb",
    metavar="NAME=LEVEL",
    multiple=True,
    help="The reproduction's world differs from the demonstration's (repeatable): camera=CM_AND_DEG "
    "(moved and turned), scale=X, brightness=%, contrast=%, temperature=K, shadow=SHARE, noise=SIGMA, "
    "salt=SHARE, jpeg=QUALITY, depth_noise=MM, holes=SHARE, occlusion=%, clutter=N (docs/cli.md).",
)
@click.option(
    "--slip-detection",
    type=click.Choice(["on", "off"]),
    default=None,
    help="on: find every object that moved in an operation and tell the operated one from those "
    "disturbed; off: the paper's VSL, which takes the change for the operation [default: on].",
)
@click.option(
    "--views",
    type=int_range(1, 2),
    default=None,
    help="VSL-3D: depth cameras, 1 (the paper's single view) or 2 (a second one across the table, "
    "clouds fused) [default: 1].",
)
@click.option(
    "--intervention",
    default=None,
    help="tower-of-hanoi: the user's intervention, by-seed (the user makes the first move on odd seeds), "
    "none or first-move (in every trial) [default: by-seed].",
)
@click.option(
    "--out", type=click.Path(file_okay=False), default=None, help="Report folder (default: out/experiments/NAME)."
)
@click.option(
    "--predicates",
    "predicates_file",
    type=click.Path(dir_okay=False),
    default=None,
    help="VSL-SP: a Python file of your predicates (@predicate from vslsp.grounding), grounded with far at "
    "every observed step and learned into the action models, rules and goals. It runs as Python with "
    "your rights, like a pytest conftest.py.",
)
@click.option(
    "--tasks",
    "task_files",
    type=click.Path(dir_okay=False),
    multiple=True,
    help="A Python file of your own tasks (@register from vslsp.tasks, docs/tasks.md), loaded before NAME "
    "is looked up and in every worker; repeatable. It runs as Python with your rights: use only files you trust.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the summary as one JSON object on stdout.")
def experiment(
    name: str | None,
    list_them: bool,
    trials: int,
    seed: int,
    workers: int,
    backend: str,
    address: str | None,
    faults: bool,
    video: bool,
    rerun_file: str | None,
    planner: str | None,
    skills_dir: str | None,
    method: str | None,
    tutor_slips: float | None,
    slip_detection: str | None,
    perturb: tuple[str, ...],
    views: int | None,
    intervention: str | None,
    predicates_file: str | None,
    out: str | None,
    task_files: tuple[str, ...],
    as_json: bool,
) -> None:
    """Run experiment NAME (see --list) and write a report folder.

    Exit 0 when every trial succeeded, 1 when a trial failed, 2 for bad input (found before any
    trial runs), 130 / 143 when Ctrl-C / SIGTERM stopped the run (the finished trials' report is
    written first).
    """
    from vslsp.errors import InputError
    from vslsp.tasks import get_task, list_tasks, load_task_files

    load_task_files(task_files)  # the user's tasks join the registry (and reach the workers)
    if list_them:
        entries = [cls().describe() for cls in list_tasks()]
        if as_json:
            click.echo(json.dumps({"experiments": entries}))
        else:
            for entry in entries:
                click.echo(f"{entry['name']:<22} {entry['system']:<7} {entry['paper_section']}")
        return
    if name is None:
        raise InputError("name an experiment (vslsp experiment --list shows them)")
    if address is not None and backend != "ray":
        raise InputError("--address applies to --backend ray")
    if backend == "ray":  # Ray installed and the address well formed, before any work
        from vslsp.tasks.ray_backend import check_ray

        check_ray(address)
    if out == "":
        raise InputError("--out: an empty path is not a folder; give a folder name")
    folder = Path(out) if out is not None else Path("out") / "experiments" / name
    recording = check_recording(rerun_file) if rerun_file is not None else None
    task = get_task(
        name,
        faults=faults,
        video=str(folder.resolve()) if video else None,
        planner=planner,
        skills=skills_dir,
        method=method,
        tutor_slips=tutor_slips,
        slip_detection=None if slip_detection is None else slip_detection == "on",
        perturb=_perturbation(perturb),
        views=views,
        intervention=intervention,
        rerun="(checked)" if recording is not None else None,
        predicates=str(Path(predicates_file).resolve()) if predicates_file else None,
    )
    if backend == "local" and trials > 1:
        from vslsp.tasks.task_files import check_main_guard

        check_main_guard(workers)  # a runner script without a main guard: refused before the folder
    prepare_output_folder(folder)
    refuse_places(folder, REPORT_FILES, OUTPUT_FOLDERS)
    if recording is not None:
        task.settings["rerun"] = start_recording(recording)
    try:
        data = run_experiment(
            task, range(seed, seed + trials), folder, workers=workers, backend=backend, address=address
        )
    finally:
        if recording is not None:
            finish_recording(recording, task.settings["rerun"])
    if as_json:
        click.echo(json.dumps(data))
    else:
        partial = f" (interrupted after {data['trials']} of {data['trials_requested']})" if data.get("partial") else ""
        click.echo(
            f"{name}: {data['successes']}/{data['trials']} trials succeeded "
            f"({100 * data['success_rate']:.1f} %){partial}, {data['mean_time_s']} s per trial; "
            f"report: {folder / 'report.md'}"
        )
        for failure in data["failures"][:10]:
            click.echo(f"  seed {failure['seed']}: {failure['error']}", err=True)
    if data.get("interrupted"):
        sys.exit(Interrupted(data["interrupted"]).exit_code)
    sys.exit(0 if data["successes"] == data["trials"] and not data.get("partial") else 1)


def _perturbation(items: tuple[str, ...]) -> tuple[str, ...] | None:
    """``--perturb``'s items, checked (exit 2 on a bad one); None when none is given or every
    level is neutral (the runs without the option)."""
    from vslsp.perturbations import Perturbation

    return None if Perturbation.parse(items).none else items


def run_experiment(
    task, seeds, folder: Path, *, workers: int = 1, backend: str = "local", address: str | None = None
) -> dict:
    """Run the trials with a progress bar on stderr and write the report; returns the summary."""
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    from vslsp.tasks import run_trials, write_report

    seeds = list(seeds)
    console = Console(stderr=True)
    with Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TextColumn("{task.fields[ok]} ok"),
        console=console,
        transient=True,
    ) as progress:
        bar = progress.add_task(task.name, total=len(seeds), ok=0)
        done = {"ok": 0, "finished": 0}

        def advance(result) -> None:
            done["ok"] += result.success
            done["finished"] += 1
            progress.update(bar, advance=1, ok=done["ok"])

        def interrupted(signal_name: str) -> None:
            console.print(
                f"{signal_name}: stopping now: cancelling the outstanding trials, ending the workers, "
                f"writing the report of the {done['finished']} finished trials"
            )

        run = run_trials(
            task, seeds, workers=workers, backend=backend, address=address, on_done=advance, on_interrupt=interrupted
        )
        progress.update(bar, description=f"{task.name}: report")
        try:
            return write_report(folder, task, run)
        except OutputFailed as error:  # a full disk: say which trials' report, if any, was kept
            raise OutputFailed(f"{error}{_kept(folder, run)}") from None
        except (Interrupted, KeyboardInterrupt) as stop:  # during the figures: the trials' report stays
            run.interrupted = getattr(stop, "signal_name", "SIGINT")
            interrupted(run.interrupted)
            with _signals_held():  # a second Ctrl-C must not cut the report's last write short
                return write_report(folder, task, run, figures=False)


def _kept(folder: Path, run) -> str:
    """Where the report of the finished trials is, when it was written before the failure."""
    try:
        kept = json.loads((folder / "report.json").read_text())
    except (OSError, ValueError):
        return f"; none of the {len(run.results)} finished trials' report could be written"
    if len(kept.get("results", [])) == len(run.results):
        return f"; the report of the {len(run.results)} finished trials (without figures) is in {folder}"
    return f"; {folder / 'report.json'} is from an earlier run"


@contextmanager
def _signals_held() -> Iterator[None]:
    """SIGINT, SIGTERM, SIGHUP and SIGQUIT held back (delivered when the block ends, and ignored by then)."""
    held = set(SIGNALS)
    signal.pthread_sigmask(signal.SIG_BLOCK, held)
    try:
        yield
    finally:
        previous = {number: signal.signal(number, signal.SIG_IGN) for number in held}
        signal.pthread_sigmask(signal.SIG_UNBLOCK, held)
        for number, handler in previous.items():
            signal.signal(number, handler)
