"""Outputs are never lost, mixed or written where they must not be (docs/bad-input.md,
"Outputs"): every file is replaced whole (a full disk leaves the previous one), a symbolic link
is never written through, an output folder serves one run at a time, an output is never one of
the inputs, and a full disk is one line and exit 1."""

from __future__ import annotations

import hashlib
import json
import resource
import shutil

import numpy as np
import pytest
from helpers.cli import REPO, vslsp
from helpers.events import became_true
from helpers.processes import start

from vslsp.errors import InputError
from vslsp.outputs import OutputFailed, atomic_file, lock_folder, write_text
from vslsp.skills import SkillLibrary, default_library_path
from vslsp.vision.image import write_image

DOMAIN = REPO / "pddl" / "domain.pddl"
PROBLEM = REPO / "pddl" / "pull-in-order.pddl"


def digest(folder):
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir()) if p.is_file()}


def file_size_limit(size: int):
    """A child's preexec: files larger than ``size`` bytes cannot be written (EFBIG), as on a full disk."""
    return lambda: resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))


def one_line_error(stderr: str) -> str:
    lines = [line for line in stderr.splitlines() if line.lower().startswith("error:")]
    assert len(lines) == 1 and "Traceback" not in stderr, stderr
    return lines[0]


# -- atomic writes ------------------------------------------------------------------------------
def test_a_failed_write_leaves_the_previous_file_whole(tmp_path):
    target = write_text(tmp_path / "report.json", "the previous report\n")
    with pytest.raises(RuntimeError), atomic_file(target, "w") as stream:
        stream.write("half a rep")
        raise RuntimeError("the disk filled up")
    assert target.read_text() == "the previous report\n" and [p.name for p in tmp_path.iterdir()] == ["report.json"]


def test_standard_output_on_a_full_disk_is_one_line_exit_1(tmp_path):
    with open("/dev/full", "w") as full:
        process = start(["experiment", "--list", "--json"], tmp_path, stdout=full)
        _, stderr = process.communicate(timeout=120)
    assert process.returncode == 1
    assert "No space left on device" in one_line_error(stderr)


def test_a_full_disk_in_scene_is_one_line_exit_1(tmp_path):
    out = tmp_path / "scene"
    process = start(["scene", "--out", out], tmp_path, preexec_fn=file_size_limit(20_000))
    _, stderr = process.communicate(timeout=600)
    assert process.returncode == 1
    line = one_line_error(stderr)
    assert "File too large" in line and "free some space" in line
    assert not [p for p in out.iterdir() if p.name.startswith(".vslsp-part-")]


def test_a_full_disk_under_the_planner_is_one_line_exit_1(tmp_path):
    process = start(["plan", DOMAIN, PROBLEM, "--json"], tmp_path, preexec_fn=file_size_limit(10))
    stdout, stderr = process.communicate(timeout=300)
    assert process.returncode == 1 and json.loads(stdout)["exit_code"] == 1
    assert "vslsp-fd-" in one_line_error(stderr) and "File too large" in stderr


def test_a_full_disk_in_an_experiment_keeps_the_trials_report(tmp_path):
    out = tmp_path / "report"
    process = start(
        ["experiment", "test-quick", "--trials", "2", "--out", out], tmp_path, preexec_fn=file_size_limit(8_000)
    )
    _, stderr = process.communicate(timeout=300)
    assert process.returncode == 1
    line = one_line_error(stderr)
    assert "noise.png" in line and "report of the 2 finished trials (without figures)" in line
    assert [r["seed"] for r in json.loads((out / "report.json").read_text())["results"]] == [0, 1]
    assert not (out / "noise.png").exists()


@pytest.mark.slow
def test_a_full_disk_while_teaching_into_a_library_keeps_the_working_skill(tmp_path):
    library = tmp_path / "skills"
    shutil.copytree(default_library_path(), library)
    before = digest(library)
    size = min((library / "push_demos.npz").stat().st_size, (library / "push_reach.npz").stat().st_size) - 1
    process = start(["teach", "push", "--out", library, "--demos", "2"], tmp_path, preexec_fn=file_size_limit(size))
    _, stderr = process.communicate(timeout=900)
    assert process.returncode == 1
    assert "File too large" in one_line_error(stderr)
    assert digest(library) == before
    assert sorted(SkillLibrary.load(library).skills) == ["pull", "push"]


# -- symbolic links -----------------------------------------------------------------------------
def test_a_report_md_link_in_out_is_refused_before_any_trial(tmp_path):
    out, target = tmp_path / "report", tmp_path / "precious.txt"
    out.mkdir()
    target.write_text("keep me\n")
    (out / "report.md").symlink_to(target)
    process = start(["experiment", "test-quick", "--out", out], tmp_path)
    _, stderr = process.communicate(timeout=300)
    assert process.returncode == 2
    line = one_line_error(stderr)
    assert f"{out / 'report.md'} is a symbolic link" in line and "--force" not in line
    assert target.read_text() == "keep me\n" and not (out / "report.json").exists()


def test_a_scene_view_that_is_a_link_is_refused_before_rendering(capsys, tmp_path):
    out, target = tmp_path / "scene", tmp_path / "precious.png"
    out.mkdir()
    target.write_bytes(b"keep me")
    (out / "overhead.png").symlink_to(target)
    code, _, err = vslsp(capsys, "scene", "--out", out)
    assert code == 2 and f"{out / 'overhead.png'} is a symbolic link" in err
    assert target.read_bytes() == b"keep me" and not (out / "scene.json").exists()


def test_plan_out_through_a_link_is_refused(capsys, tmp_path):
    target = tmp_path / "precious.txt"
    target.write_text("keep me\n")
    (tmp_path / "plan.txt").symlink_to(target)
    code, _, err = vslsp(capsys, "plan", DOMAIN, PROBLEM, "--out", tmp_path / "plan.txt")
    assert code == 2 and "is a symbolic link" in err and target.read_text() == "keep me\n"


def test_a_library_file_that_is_a_link_is_refused_without_advising_force(capsys, tmp_path):
    library, target = tmp_path / "skills", tmp_path / "precious.npz"
    shutil.copytree(default_library_path(), library)
    target.write_bytes(b"keep me")
    (library / "push_reach.npz").unlink()
    (library / "push_reach.npz").symlink_to(target)
    with pytest.raises(InputError) as refused:
        SkillLibrary.load(library)
    assert "symbolic link" in str(refused.value) and "--force" not in str(refused.value)
    code, _, err = vslsp(capsys, "teach", "push", "--out", library, "--force", "--demos", "1")
    assert code == 2 and "push_reach.npz is a symbolic link" in err and "--force" not in err
    assert target.read_bytes() == b"keep me"


# -- one run per output folder ------------------------------------------------------------------
def test_a_second_run_into_a_folder_in_use_is_refused_naming_the_first(tmp_path):
    out = tmp_path / "report"
    first = start(["experiment", "test-waits-after-the-first", "--trials", "2", "--out", out], tmp_path)
    try:
        assert became_true(lambda: (tmp_path / "markers" / "waiting-1").exists(), first)
        second = start(["scene", "--out", out], tmp_path)
        _, stderr = second.communicate(timeout=300)
    finally:
        first.kill()
        first.communicate()
    assert second.returncode == 2
    line = one_line_error(stderr)
    assert f"in use by another vslsp run (pid {first.pid}: vslsp experiment test-waits-after-the-first" in line
    assert not (out / "head.png").exists()


def test_a_folder_is_free_again_once_its_run_was_killed(tmp_path):
    out = tmp_path / "report"
    first = start(["experiment", "test-waits-after-the-first", "--trials", "2", "--out", out], tmp_path)
    assert became_true(lambda: (tmp_path / "markers" / "waiting-1").exists(), first)
    first.kill()  # SIGKILL: no clean-up runs, the lock file stays; the system released its lock
    first.communicate()
    second = start(["experiment", "test-quick", "--out", out], tmp_path)
    _, stderr = second.communicate(timeout=300)
    assert second.returncode == 0, stderr
    assert json.loads((out / "report.json").read_text())["experiment"] == "test-quick"


def test_a_folder_is_free_again_once_its_run_ended(tmp_path):
    lock_folder(tmp_path)  # this process holds it: taking it again is no conflict
    lock_folder(tmp_path)
    process = start(["experiment", "test-quick", "--out", tmp_path / "other"], tmp_path)
    assert process.wait(timeout=300) == 0
    process = start(["experiment", "test-quick", "--out", tmp_path / "other"], tmp_path)
    assert process.wait(timeout=300) == 0


# -- outputs that are inputs --------------------------------------------------------------------
def test_plan_out_that_is_the_domain_is_refused(capsys, tmp_path):
    domain = tmp_path / "d.pddl"
    shutil.copy(DOMAIN, domain)
    code, _, err = vslsp(capsys, "plan", domain, PROBLEM, "--out", domain)
    assert code == 2 and f"--out {domain} is the domain {domain}" in err
    assert domain.read_text() == DOMAIN.read_text()


def test_ground_overlay_that_is_the_pre_image_is_refused(capsys, tmp_path):
    pre, post = tmp_path / "pre.png", tmp_path / "post.png"
    for path in (pre, post):
        write_image(path, np.zeros((64, 64, 3), np.uint8))
    before = pre.read_bytes()
    code, _, err = vslsp(capsys, "ground", pre, post, "--overlay", pre)
    assert code == 2 and "--overlay" in err and "is the pre-action image" in err
    assert pre.read_bytes() == before


def test_a_full_disk_is_exit_1_and_any_other_write_failure_exit_2():
    assert OutputFailed.exit_code == 1 and InputError.exit_code == 2
