"""A user's predicates file: whatever it raises, exits, prints or loops on is reported as its error
(exit 2, one message, JSON under ``--json``), and its names are PDDL names (issue 27, items 2, 3, 5);
it runs in a child process, so what it does to signals, processes and its output leaves the command
whole (issue 42; the child itself: tests/grounding/test_user_code.py)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from helpers.cli import vslsp, vslsp_process
from helpers.events import became_true, wait_until

from vslsp.errors import InputError
from vslsp.grounding import contained, predicate
from vslsp.grounding.predicates import collecting
from vslsp.grounding.synthetic import Square, tabletop_image
from vslsp.vision.image import write_image

BODIES = {
    "str-raises": (
        "class Odd(Exception):\n    def __str__(self):\n        raise RuntimeError('no text')\n",
        "raise Odd()",
        "Odd: <its message cannot be shown",
    ),
    "repr-raises": (
        "class Odd:\n    def __repr__(self):\n        raise RuntimeError('no text')\n",
        "return Odd()",
        "returned Odd <a Odd whose __repr__ raised>",
    ),
    "base-exception": ("class Stop(BaseException):\n    pass\n", "raise Stop('out')", "raised Stop: out"),
    "sys-exit-0": ("import sys\n", "sys.exit(0)", "raised SystemExit (it called sys.exit(0)"),
    "prints": ("", "print('chatter'); return 1 / 0", "raised ZeroDivisionError"),
}


@pytest.fixture
def pair(tmp_path):
    still = Square("blue", (500, 420))
    write_image(tmp_path / "pre.png", tabletop_image([Square("purple", (200, 150)), still]))
    write_image(tmp_path / "post.png", tabletop_image([Square("purple", (220, 410)), still]))
    return tmp_path / "pre.png", tmp_path / "post.png"


def _file(folder, prelude: str, body: str, name: str = "preds.py"):
    path = folder / name
    path.write_text(
        f"from vslsp.grounding import predicate\n{prelude}\n"
        f"@predicate('odd')\ndef odd(obj, scene):\n{textwrap.indent(body, '    ')}\n"
    )
    return path


@pytest.mark.parametrize("case", BODIES, ids=str)
def test_whatever_a_predicate_does_is_reported_as_its_error(tmp_path, pair, case):
    prelude, body, message = BODIES[case]
    result = vslsp_process("ground", *pair, "--predicates", _file(tmp_path, prelude, body), "--json")
    assert result.returncode == 2, result.stderr
    assert message in result.stderr and "Traceback" not in result.stderr
    assert message in json.loads(result.stdout)["error"]  # stdout is the JSON alone, print() went to stderr


@pytest.mark.parametrize("case", ["base-exception", "sys-exit-0"])
def test_whatever_a_predicates_file_does_while_loading_is_reported_as_its_error(tmp_path, pair, case):
    prelude, body, _ = BODIES[case]
    path = tmp_path / "loading.py"
    path.write_text(f"{prelude}\n{body}\n")
    result = vslsp_process("ground", *pair, "--predicates", path, "--json")
    assert result.returncode == 2 and "cannot load predicates file" in result.stderr, result.stderr
    assert "error" in json.loads(result.stdout)


@pytest.mark.parametrize("where", ["call", "load"])
def test_a_predicate_that_loops_is_stopped_at_its_time_limit(capsys, monkeypatch, tmp_path, pair, where):
    monkeypatch.setattr(contained, "DEFAULT_LIMITS", contained.Limits(predicate_s=0.5, load_s=0.5))
    # except BaseException keeps the first stop: the timer fires again every second until it ends
    loop = "while True:\n    try:\n        pass\n    except BaseException:\n        pass"
    path = _file(tmp_path, loop if where == "load" else "", loop if where == "call" else "return True")
    code, _, err = vslsp(capsys, "ground", *pair, "--predicates", path)
    assert code == 2 and "was stopped" in err, err
    assert ("while loading" in err) == (where == "load")


@pytest.mark.parametrize("name", ["and", "not", "or", "forall", "sometime-before", "near\n", "Near", "9lives"])
def test_a_predicate_name_that_is_not_a_pddl_name_or_is_a_pddl_word_is_refused(name):
    with collecting(), pytest.raises(InputError, match="PDDL"):
        predicate(name)(lambda obj, scene: True)


def _group_alive(pgid: int) -> list[int]:
    alive = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                state, _, group = (entry / "stat").read_text().rsplit(")", 1)[1].split()[:3]
            except OSError:
                continue
            if int(group) == pgid and state != "Z":
                alive.append(int(entry.name))
    return alive


@pytest.mark.parametrize(
    "prelude, body",
    [
        ("import signal\nsignal.pthread_sigmask(signal.SIG_BLOCK, set(signal.Signals))\n", "while True:\n    pass"),
        ("import signal\nsignal.signal(signal.SIGALRM, signal.SIG_IGN)\n", "signal.alarm(0)\nwhile True:\n    pass"),
    ],
    ids=["blocked-signals", "alarm"],
)
def test_a_predicate_that_blocks_signals_or_takes_the_alarm_is_stopped_at_the_deadline(
    capsys, monkeypatch, tmp_path, pair, prelude, body
):
    monkeypatch.setattr(contained, "DEFAULT_LIMITS", contained.Limits(call_s=2.0))
    code, out, err = vslsp(capsys, "ground", *pair, "--predicates", _file(tmp_path, prelude, body), "--json")
    assert code == 2, err
    assert "did not answer within 2 s (it may block or loop)" in json.loads(out)["error"]


def test_processes_a_predicate_starts_do_not_outlive_the_command(tmp_path, pair):
    record = tmp_path / "group"
    body = (
        f"if not os.path.exists({str(record)!r}):\n"
        f"    open({str(record)!r}, 'w').write(str(os.getpgid(0)))\n"
        "    subprocess.Popen(['sleep', '300'])\n"
        "    if os.fork() == 0:\n        os.execvp('sleep', ['sleep', '301'])\n"
        "return True"
    )
    path = _file(tmp_path, "import os, subprocess\n", body)
    result = vslsp_process("ground", *pair, "--predicates", path, "--json")
    assert result.returncode == 0, result.stderr
    pgid = int(record.read_text())
    assert pgid != os.getpgid(0)
    wait_until(lambda: _group_alive(pgid) == [], "the predicates' processes to end")  # no orphan sleep


def test_a_predicate_that_closes_stdout_or_floods_it_leaves_the_answer_whole(tmp_path, pair):
    closing = _file(
        tmp_path,
        "import os, sys\n",
        "sys.stdout.close()\ntry:\n    os.close(1)\nexcept OSError:\n    pass\nreturn True",
        name="closing.py",
    )
    flooding = _file(tmp_path, "", "print('x' * 100_000)\nreturn True", name="flooding.py")
    for path in (closing, flooding):
        result = vslsp_process("ground", *pair, "--predicates", path, "--json")
        assert result.returncode == 0 and "Traceback" not in result.stderr, result.stderr
        assert "(odd blue)" in json.loads(result.stdout)["atoms"]["pre"]  # stdout is the one JSON object
        assert len(result.stderr) < 70_000  # the output is copied up to 64 kB, then counted


@pytest.mark.parametrize("number, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)], ids=["SIGINT", "SIGTERM"])
def test_an_interrupt_while_a_predicate_blocks_ends_the_command_and_the_predicates_process(
    tmp_path, pair, number, code
):
    record = tmp_path / "group"
    body = (
        f"open({str(record)!r}, 'w').write(str(os.getpgid(0)))\n"
        "signal.pthread_sigmask(signal.SIG_BLOCK, set(signal.Signals))\nwhile True:\n    pass"
    )
    path = _file(tmp_path, "import os, signal\n", body)
    checkout = str(Path(__file__).parents[2])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([checkout, os.environ.get("PYTHONPATH", "")])}
    process = subprocess.Popen(
        [sys.executable, "-m", "vslsp", "ground", *map(str, pair), "--predicates", str(path)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    try:
        assert became_true(lambda: record.exists() and record.read_text() != "", process), process.stderr
        process.send_signal(number)  # to vslsp alone, as `kill` would; a terminal's Ctrl-C reaches vslsp's group
        _, stderr = process.communicate(timeout=20)
    finally:
        process.kill()
    assert process.returncode == code and "Traceback" not in stderr, stderr
    pgid = int(record.read_text())
    wait_until(lambda: _group_alive(pgid) == [], "the predicates' processes to end")
