"""vslsp.cli.params: the shared option types reject bad values before any work (exit 2)."""

from __future__ import annotations

import re
from pathlib import Path

import click
import pytest
from helpers.cli import read_only_folder, unwritable_folder

from vslsp.cli.params import (
    MAX_SEED,
    OUTPUT_FILE,
    OUTPUT_FOLDER,
    count,
    positive_float,
    prepare_output_file,
    prepare_output_folder,
    seed_option,
)
from vslsp.errors import InputError
from vslsp.outputs import LOCK_NAME


@click.command()
@seed_option()
@click.option("--out", type=OUTPUT_FOLDER, default=None)
@click.option("--file", "file_", type=OUTPUT_FILE, default=None)
@click.option("--size", type=count(4096), default=1)
@click.option("--tau", type=positive_float(10.0), default=1.0)
def probe(seed: int, out: Path | None, file_: Path | None, size: int, tau: float) -> None:
    click.echo(f"{seed} {out} {file_} {size} {tau}")


def run(*args: object) -> tuple[int, str]:
    """(exit code, output) of the probe command, as the vslsp CLI would run it."""
    try:
        probe.main([str(a) for a in args], standalone_mode=False)
    except click.ClickException as error:
        return error.exit_code, error.format_message()
    return 0, ""


@pytest.mark.parametrize("seed", ["-1", "-5", str(MAX_SEED + 1), "x", "1.5", "nan"])
def test_a_bad_seed_is_a_usage_error_naming_the_range(seed):
    code, message = run("--seed", seed)
    assert code == 2 and "--seed" in message and f"0 to {MAX_SEED}" in message


@pytest.mark.parametrize("seed", ["0", "7", str(MAX_SEED)])
def test_good_seeds_pass(seed, capsys):
    assert run("--seed", seed) == (0, "")
    assert capsys.readouterr().out.split()[0] == seed


def test_the_output_folder_is_created_and_probed(tmp_path, capsys):
    folder = tmp_path / "a" / "b"
    assert run("--out", folder) == (0, "")
    # The probe file is gone; the lock that says which run uses the folder stays while it runs.
    assert folder.is_dir() and [p.name for p in folder.iterdir()] == [LOCK_NAME]


def test_an_output_folder_under_a_file_names_the_file(tmp_path):
    (tmp_path / "plain").write_text("x")
    code, message = run("--out", tmp_path / "plain" / "report")
    assert code == 2 and f"{tmp_path / 'plain'} is a file" in message


def test_an_unwritable_output_folder_names_the_path(tmp_path):
    folder = unwritable_folder(tmp_path)
    code, message = run("--out", folder / "report")
    assert code == 2 and f"cannot write into the folder {folder / 'report'}" in message
    with pytest.raises(InputError, match="--report: cannot write into the folder"):
        prepare_output_folder(folder, option="--report")


def test_an_output_file_needs_a_writable_folder_and_a_name(tmp_path):
    assert prepare_output_file(tmp_path / "new" / "plan.txt") == tmp_path / "new" / "plan.txt"
    assert (tmp_path / "new").is_dir()
    with pytest.raises(InputError, match="is a folder; give a file name"):
        prepare_output_file(tmp_path)
    (tmp_path / "plain").write_text("x")
    code, message = run("--file", tmp_path / "plain" / "overlay.png")
    assert code == 2 and "is a file" in message


@pytest.mark.parametrize(
    ("option", "value"),
    [
        ("--size", "0"),
        ("--size", "-5"),
        ("--size", "4097"),
        ("--tau", "0"),
        ("--tau", "-1"),
        ("--tau", "nan"),
        ("--tau", "inf"),
        ("--tau", "11"),
        ("--tau", "fast"),
    ],
)
def test_sizes_and_durations_must_be_positive_and_bounded(option, value):
    code, message = run(option, value)
    assert code == 2 and option in message


def test_an_existing_read_only_folder_is_refused_with_the_reason(tmp_path):
    folder = read_only_folder(tmp_path)
    assert folder.is_dir()  # it exists: the write probe, not the mkdir, finds the problem
    with pytest.raises(InputError) as refused:
        prepare_output_folder(folder)
    assert re.fullmatch(
        rf"--out: cannot write into the folder {re.escape(str(folder))} "
        r"\((Permission denied|Read-only file system|Operation not permitted)\); choose a writable output folder",
        str(refused.value),
    ), str(refused.value)
    assert not list(folder.glob(".vslsp-write-probe-*"))
