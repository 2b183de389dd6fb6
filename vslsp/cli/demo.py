"""``vslsp demo``: the main job, the full VSL-SP pipeline on the embedded pybullet scene.

The robot loads its learned push and pull skills, tries them and learns their symbolic
models from what it sees, watches the tutor pull the orange, green and yellow cubes in
order, learns the goal and the order (PDDL 3.0 ``sometime-before``), plans with Fast
Downward in a new scene, executes the plan with its skills while checking every step, and
also reproduces the demonstration with VSL's match finding. A report folder is written.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import click

from vslsp.cli.experiment import OUTPUT_FOLDERS, REPORT_FILES
from vslsp.cli.params import OUTPUT_FOLDER, check_display, seed_option
from vslsp.cli.rerun import check_recording, finish_recording, rerun_option, start_recording
from vslsp.outputs import refuse_places


@click.command()
@click.option(
    "--out",
    type=OUTPUT_FOLDER,
    default="out/demo",
    show_default=True,
    help="Report folder (created and checked for writing before the run).",
)
@seed_option(help="Seed of the embedded scene (0 to 4294967295).")
@click.option("--gui", is_flag=True, help="Show the pybullet GUI (needs a display).")
@click.option(
    "--skills",
    "skills_dir",
    type=click.Path(file_okay=False),
    default=None,
    help="Skill library folder (default: the shipped skills).",
)
@click.option("--video", is_flag=True, help="Film the trial into videos/trial-SEED.mp4 (H.264) in the report folder.")
@click.option(
    "--durative",
    is_flag=True,
    help="Also write the learned domain with durative actions (durative-domain.pddl: each skill lasting its "
    "reach DMP's 2τ) and each step's planned against executed duration (durations.json).",
)
@rerun_option(
    "Log the trial (camera images, the arm and the hand's path, plan steps, symbolic state) on one "
    "timeline into FILE.rrd for rerun's viewer (pip install 'vslsp[rerun]')."
)
def demo(
    out: Path, seed: int, gui: bool, skills_dir: str | None, video: bool, durative: bool, rerun_file: str | None
) -> None:
    """Run the full VSL-SP pipeline (pull-in-order) on the embedded scene and write a report."""
    check_display(gui)
    recording = check_recording(rerun_file) if rerun_file is not None else None
    from rich.console import Console

    from vslsp import stages
    from vslsp.experiments.icub import PullInOrder
    from vslsp.loop.durations import DURATIONS, DURATIVE_DOMAIN
    from vslsp.tasks import Run, write_report
    from vslsp.tasks.base import cpu_seconds

    refuse_places(out, (*REPORT_FILES, *((DURATIVE_DOMAIN, DURATIONS) if durative else ())), OUTPUT_FOLDERS)
    console = Console(stderr=True)
    start, cpu = time.perf_counter(), cpu_seconds()
    stages.reset()
    task = PullInOrder(skills=skills_dir, video=str(Path(out).resolve()) if video else None)
    task.check()
    if recording is not None:
        task.settings["rerun"] = start_recording(recording)
    with console.status("loading the skill library") as status:
        console.log(f"skills from {task.library_path}")

        def stage(what: str) -> None:
            console.log(what)
            status.update(what)

        try:
            result = task.run_trial(seed, keep=True, on_stage=stage, gui=gui)
        finally:
            if recording is not None:
                finish_recording(recording, task.settings["rerun"])
        result.time_s = time.perf_counter() - start
        result.cpu_s = cpu_seconds() - cpu
        result.stages_s = stages.split(result.time_s)
    write_report(out, task, Run([result], [seed]))
    trial, details = result.artefacts, result.details
    if trial.domain is not None:
        console.log("learned action models:\n" + trial.domain.to_pddl())
    if trial.task is not None:
        console.log(f"learned task: {len(trial.task.constraints)} ordering constraints")
    if durative and trial.domain is not None:
        from vslsp.loop.durations import write_durations
        from vslsp.skills.library import SkillLibrary

        for line in write_durations(out, trial, SkillLibrary.load(task.library_path)):
            console.log(line)
    if details.get("plan"):
        console.log(f"plan (Fast Downward): {', '.join(details['plan'])}")
    console.log(
        f"executed order: VSL-SP {details.get('vsl_sp_order')}, VSL {details.get('vsl_order')}; "
        f"{details.get('replans', 0)} replans"
    )
    verdict = "succeeded" if result.success else f"failed: {result.error}"
    click.echo(f"demo {verdict} in {time.perf_counter() - start:.0f} s; report: {Path(out) / 'report.md'}")
    sys.exit(0 if result.success else 1)
