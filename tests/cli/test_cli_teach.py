"""``vslsp teach`` writes into the working directory by default, never into the shipped
library unless asked, and its advice for a damaged library works (slow: real demonstrations)."""

from __future__ import annotations

import hashlib
import re
import shlex
import shutil

import pytest
from helpers.cli import vslsp

from vslsp.skills import SkillLibrary, default_library_path


def shipped_digest() -> str:
    return hashlib.sha256(b"".join(p.read_bytes() for p in sorted(default_library_path().glob("*.*")))).hexdigest()


@pytest.mark.slow
def test_teach_writes_out_skills_in_the_working_directory(capsys, monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)
    before = shipped_digest()
    code, out, _ = vslsp(capsys, "teach", "push", "--demos", "1")
    assert code == 0 and "out/skills/library.json" in out
    library = SkillLibrary.load(tmp_path / "out" / "skills")
    assert sorted(library.skills) == ["push"] and library["push"].reach.n_demos == 1
    assert shipped_digest() == before


@pytest.mark.slow
def test_the_advice_for_a_damaged_library_works(capsys, tmp_path):
    """The error names a command; running it re-teaches the damaged skill and keeps the other."""
    folder = tmp_path / "skills"
    shutil.copytree(default_library_path(), folder)
    (folder / "push_reach.npz").write_bytes(b"not an npz")
    pull_before = SkillLibrary.load(default_library_path())["pull"]
    code, _, err = vslsp(capsys, "demo", "--skills", folder, "--out", tmp_path / "report")
    assert code == 2 and "skill 'push'" in err
    advice = re.search(r"re-create it with `(vslsp teach push [^`]*)`", err)
    assert advice, err
    command = shlex.split(advice.group(1))[1:]
    assert command == ["teach", "push", "--out", str(folder), "--force"]
    code, _, err = vslsp(capsys, *command, "--demos", "1")
    assert code == 0 and "replaced (--force)" in err
    library = SkillLibrary.load(folder)
    assert library["push"].reach.n_demos == 1
    assert library["pull"].reach.weights.tolist() == pull_before.reach.weights.tolist()
