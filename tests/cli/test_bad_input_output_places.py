"""Where outputs go (docs/bad-input.md, "Outputs"): vslsp writes only regular files (a device
node, a FIFO or a socket at an output path is refused, never replaced by the atomic rename), never
through a link or onto a file among an output folder's subfolders, never into its own shipped
folders, never to a default when ``--out ''`` was typed; and a number is written in the digits
0-9. Each is exit 2, one line, before any work."""

from __future__ import annotations

import os
import stat

import helpers.interrupt_tasks  # noqa: F401  (registers test-quick)
import pytest
from helpers.cli import REPO, checkout_copy, tree_digest, vslsp, vslsp_process

from vslsp.errors import InputError
from vslsp.outputs import atomic_file, output_subfolder

DOMAIN = REPO / "pddl" / "domain.pddl"
PROBLEM = REPO / "pddl" / "pull-in-order.pddl"


def one_line_error(stderr: str) -> str:
    """The one error line (a usage error's is click's ``Error: Invalid value ...`` after its usage)."""
    lines = [line for line in stderr.splitlines() if line.lower().startswith("error:")]
    assert len(lines) == 1 and "Traceback" not in stderr, stderr
    return lines[0]


def node(tmp_path, kind: str):
    """A node of ``kind`` made in ``tmp_path``: ``fifo``, or ``full`` (a character device like
    /dev/full, made with mknod: root only, as CI runs)."""
    path = tmp_path / kind
    if kind == "fifo":
        os.mkfifo(path)
    else:
        if os.geteuid() != 0:
            pytest.skip("making a device node needs root")
        os.mknod(path, 0o666 | stat.S_IFCHR, os.makedev(1, 7))
    return path


def unchanged(path, kind: str) -> bool:
    mode = os.lstat(path).st_mode
    return stat.S_ISFIFO(mode) if kind == "fifo" else stat.S_ISCHR(mode)


# -- nodes: never replaced -------------------------------------------------------------------
@pytest.mark.parametrize("kind", ["full", "fifo"])
def test_plan_out_to_a_device_or_fifo_is_refused_before_planning(tmp_path, capsys, kind):
    target = node(tmp_path, kind)
    code, out, err = vslsp(capsys, "plan", DOMAIN, PROBLEM, "--out", target)
    assert code == 2 and out == ""
    line = one_line_error(err)
    assert "not a regular file; vslsp writes only regular files" in line and str(target) in line
    assert unchanged(target, kind)


@pytest.mark.parametrize("kind", ["full", "fifo"])
def test_the_shells_save_to_a_device_or_fifo_is_refused_and_the_script_fails(tmp_path, kind):
    target = node(tmp_path, kind)
    script = f"load {DOMAIN} {PROBLEM}\nsave {target}\n"
    done = vslsp_process("shell", input=script, cwd=tmp_path, timeout=300)
    assert done.returncode == 2, done.stdout + done.stderr
    assert "not a regular file" in done.stdout and "Traceback" not in done.stderr
    assert "a save failed" in one_line_error(done.stderr)
    assert unchanged(target, kind)


def test_an_atomic_write_never_replaces_a_node(tmp_path):
    target = node(tmp_path, "fifo")
    with pytest.raises(InputError, match="FIFO"), atomic_file(target, "w") as stream:
        stream.write("a plan")
    assert unchanged(target, "fifo") and sorted(p.name for p in tmp_path.iterdir()) == ["fifo"]


# -- an output folder's subfolders -----------------------------------------------------------
@pytest.mark.parametrize("inside", ["images", "images/raw", "videos"])
def test_a_link_among_the_report_folders_is_refused_before_the_trials(tmp_path, capsys, inside):
    out, elsewhere = tmp_path / "report", tmp_path / "elsewhere"
    elsewhere.mkdir()
    (out / inside).parent.mkdir(parents=True, exist_ok=True)
    (out / inside).symlink_to(elsewhere)
    code, _, err = vslsp(capsys, "experiment", "test-quick", "--out", out)
    assert code == 2
    assert "is a symbolic link" in one_line_error(err)
    assert list(elsewhere.iterdir()) == [] and not (out / "report.json").exists()


@pytest.mark.parametrize("inside", ["images/noise.png", "images/raw/01_pre.png", "videos/trial-0.mp4"])
def test_a_link_among_the_pictures_is_refused_before_the_trials(tmp_path, capsys, inside):
    out, elsewhere = tmp_path / "report", tmp_path / "elsewhere.png"
    elsewhere.write_bytes(b"mine")
    (out / inside).parent.mkdir(parents=True)
    (out / inside).symlink_to(elsewhere)
    code, _, err = vslsp(capsys, "experiment", "test-quick", "--out", out)
    assert code == 2
    assert "is a symbolic link" in one_line_error(err)
    assert elsewhere.read_bytes() == b"mine" and not (out / "report.json").exists()


def test_a_report_file_that_is_a_fifo_is_refused_before_the_trials(tmp_path, capsys):
    out = tmp_path / "report"
    out.mkdir()
    os.mkfifo(out / "report.md")
    code, _, err = vslsp(capsys, "experiment", "test-quick", "--out", out)
    assert code == 2
    assert "is a FIFO (named pipe), not a regular file" in one_line_error(err)
    assert unchanged(out / "report.md", "fifo") and not (out / "report.json").exists()


def test_a_file_where_the_pictures_go_is_refused_before_the_trials(tmp_path, capsys):
    out = tmp_path / "report"
    out.mkdir()
    (out / "images").write_text("notes")
    code, _, err = vslsp(capsys, "experiment", "test-quick", "--out", out)
    assert code == 2
    assert "images is a file, where vslsp writes a folder" in one_line_error(err)
    assert (out / "images").read_text() == "notes" and not (out / "report.json").exists()


def test_a_subfolder_is_made_only_as_a_real_folder(tmp_path):
    (tmp_path / "images").symlink_to(tmp_path)
    with pytest.raises(InputError, match="symbolic link"):
        output_subfolder(tmp_path, "images", "raw")
    assert output_subfolder(tmp_path, "pictures", "raw") == tmp_path / "pictures" / "raw"


# -- vslsp's own folders, the empty path -----------------------------------------------------
@pytest.mark.parametrize("command", [["experiment", "house-roof"], ["demo"], ["scene"]])
def test_the_shipped_skills_folder_is_no_report_folder(tmp_path, command):
    copy = checkout_copy(tmp_path / "checkout")
    before = tree_digest(copy / "skills")
    done = vslsp_process(*command, "--out", "skills", cwd=copy, checkout=copy, timeout=300)
    assert done.returncode == 2, done.stderr
    assert "shipped skills folder" in one_line_error(done.stderr)
    assert tree_digest(copy / "skills") == before


@pytest.mark.parametrize(
    "command",
    [
        ["experiment", "test-quick"],
        ["teach", "push"],
        ["demo"],
        ["scene"],
        ["plan", DOMAIN, PROBLEM],
    ],
)
def test_an_empty_out_is_refused_not_read_as_the_default(tmp_path, capsys, command, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, _, err = vslsp(capsys, *command, "--out", "")
    assert code == 2
    assert "empty path" in one_line_error(err)
    assert list(tmp_path.iterdir()) == []


# -- numbers: the digits 0-9 -----------------------------------------------------------------
@pytest.mark.parametrize(
    "arguments",
    [
        ["experiment", "test-quick", "--seed", "\u0663"],  # Arabic-Indic three
        ["experiment", "test-quick", "--trials", "\uff12"],  # a fullwidth two
        ["experiment", "test-quick", "--seed", "1_0"],
        ["plan", DOMAIN, PROBLEM, "--timeout", "\u0663"],
        ["plan", DOMAIN, PROBLEM, "--memory", "\u0661\u0660\u0662\u0664"],
        ["plan", DOMAIN, PROBLEM, "--conflict-budget", "\u0663"],
        ["experiment", "test-quick", "--tutor-slips", "\u0660.\u0665"],
    ],
)
def test_a_number_in_other_digits_is_refused(tmp_path, capsys, arguments, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, _, err = vslsp(capsys, *arguments)
    assert code == 2
    assert "digits 0-9" in one_line_error(err)
