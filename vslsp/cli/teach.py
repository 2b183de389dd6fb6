"""``vslsp teach {push,pull}``: kinesthetic demonstrations in the simulator, then the DMP skill.

The skill goes into ``--out`` (default ``out/skills`` in the working directory). The shipped
library, the installed package and the source tree are written only when asked explicitly:
``--out skills --force``. ``--force`` also re-teaches into a damaged library (its readable
skills are kept).
"""

from __future__ import annotations

from pathlib import Path

import click

from vslsp.cli.params import count, prepare_output_folder, protected_folder, seed_option
from vslsp.errors import InputError

DEFAULT_OUT = Path("out") / "skills"


@click.command()
@click.argument("skill", type=click.Choice(["push", "pull"]))
@click.option(
    "--demos",
    type=count(100),
    default=5,
    show_default=True,
    help="Number of demonstrations from different start poses.",
)
@seed_option()
@click.option(
    "--out",
    type=click.Path(file_okay=False),
    default=str(DEFAULT_OUT),
    show_default=True,
    help="Skill library folder to write into (the skill is added to a library already there).",
)
@click.option(
    "--force",
    is_flag=True,
    help="Allow writing into the shipped skills/ (or the package, the source tree) and replace a "
    "damaged library's unreadable parts.",
)
def teach(skill: str, demos: int, seed: int, out: str, force: bool) -> None:
    """Record kinesthetic-style demonstrations of SKILL and learn it; write the library and a figure."""
    if out == "":
        raise InputError("--out: an empty path is not a folder; give a folder name")
    protected = protected_folder(Path(out))
    if protected and not force:
        raise InputError(
            f"--out: {protected}; vslsp teach writes there only with --force "
            f"(or give another folder, default {DEFAULT_OUT})"
        )
    folder = prepare_output_folder(out, vslsp_own=force)

    from rich.progress import Progress

    from vslsp.errors import TaskFailed, UnreachableError
    from vslsp.skills.library import SkillLibrary
    from vslsp.skills.teach import KinestheticDemonstration, learn_skill, plot_skill, record_demonstration

    library, damaged = SkillLibrary.salvage(folder)
    if damaged and not force:
        raise InputError(f"--out: {folder} holds a damaged skill library: {damaged[0]}")
    recorded: list[KinestheticDemonstration] = []
    skipped: list[str] = []
    with Progress(transient=True) as progress:
        task = progress.add_task(f"demonstrating {skill}", total=demos)
        # A demonstration whose start the arm cannot reach is redone from another start, as a
        # tutor would; at most 3 tries per demonstration asked.
        for k in range(3 * demos):
            if len(recorded) == demos:
                break
            try:
                recorded.append(record_demonstration(skill, seed * 1000 + k))
                progress.advance(task)
            except UnreachableError as unreachable:
                skipped.append(f"demonstration {k}: {unreachable}")
    if len(recorded) < demos:
        too_few = f"only {len(recorded)} of {demos} {skill} demonstrations could be recorded"
        raise TaskFailed(f"{too_few}: " + "; ".join(skipped[:3]), cause=too_few)
    learned = learn_skill(skill, recorded)
    learned.meta["seed"] = seed
    library.skills[skill] = learned
    library.save(folder)
    figure = folder / f"{skill}_reach.png"
    plot_skill(learned, figure)
    for line in skipped:
        click.echo(f"redone: {line}", err=True)
    for problem in damaged:
        click.echo(f"replaced (--force): {problem}", err=True)
    click.echo(
        f"{skill}: {learned.reach.n_demos} demonstrations, fit RMSE "
        f"{learned.reach.fit_rmse * 1000:.1f} mm -> {folder / 'library.json'}, {figure}"
    )
