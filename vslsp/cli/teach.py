"""``vslsp teach {push,pull}``: kinesthetic demonstrations in the simulator, then the DMP skill."""

from __future__ import annotations

from pathlib import Path

import click


@click.command()
@click.argument("skill", type=click.Choice(["push", "pull"]))
@click.option("--demos", type=click.IntRange(1, 100), default=5, show_default=True,
              help="Number of demonstrations from different start poses.")
@click.option("--seed", type=int, default=0, show_default=True)
@click.option("--out", type=click.Path(file_okay=False), default=None,
              help="Skill library folder to write into (default: the shipped skills/ folder).")
def teach(skill: str, demos: int, seed: int, out: str | None) -> None:
    """Record kinesthetic-style demonstrations of SKILL and learn it; write the library and a figure."""
    from rich.progress import Progress

    from vslsp.errors import TaskFailed, UnreachableError
    from vslsp.skills.library import SkillLibrary, default_library_path
    from vslsp.skills.teach import learn_skill, plot_skill, record_demonstration

    folder = Path(out) if out else default_library_path()
    library = SkillLibrary.load(folder) if (folder / "library.json").exists() else SkillLibrary()
    recorded, skipped = [], []
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
        raise TaskFailed(f"only {len(recorded)} of {demos} {skill} demonstrations could be recorded: "
                         + "; ".join(skipped[:3]))
    learned = learn_skill(skill, recorded)
    learned.meta["seed"] = seed
    library.skills[skill] = learned
    library.save(folder)
    figure = folder / f"{skill}_reach.png"
    plot_skill(learned, figure)
    for line in skipped:
        click.echo(f"redone: {line}", err=True)
    click.echo(f"{skill}: {learned.reach.n_demos} demonstrations, fit RMSE "
               f"{learned.reach.fit_rmse * 1000:.1f} mm -> {folder / 'library.json'}, {figure}")
