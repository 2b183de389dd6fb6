"""A user's predicates file runs in a child process with limits (vslsp/grounding/contained.py,
issue 42 "user code is contained"): whatever it does to signals, processes, memory, its output
or its environment, vslsp answers with one error naming the file, and nothing of it is left."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from helpers.cli import REPO
from helpers.events import process_gone, wait_until

import vslsp
from vslsp.errors import InputError
from vslsp.grounding import ground, load_predicates, with_builtins
from vslsp.grounding.contained import Limits, UserPredicates, ground_with_user_predicates
from vslsp.grounding.predicates import Box, Landmark, Scene, SceneObject, ground_atoms
from vslsp.grounding.synthetic import Square, tabletop_image
from vslsp.vision.landmark import Line

EXAMPLE = Path(__file__).parents[2] / "examples/grounding/predicates.py"
QUICK = Limits(call_s=2.0, predicate_s=30.0, load_s=30.0)  # the wall-clock deadline stops it, not the inner timer


def _scene() -> Scene:
    objects = {
        name: SceneObject(name, x, y, Box(x - 20, y - 20, x + 20, y + 20), 1600.0, 0.0)
        for name, x, y in (("red", 100.0, 400.0), ("blue", 500.0, 120.0))
    }
    return Scene(640, 480, objects, Landmark(Line((0.0, 300.0), (640.0, 260.0))))


def _file(folder: Path, body: str, prelude: str = "", name: str = "mine.py") -> Path:
    path = folder / name
    path.write_text(
        f"import os, signal, subprocess, sys, time\nfrom vslsp.grounding import predicate\n{prelude}\n"
        f"@predicate('odd')\ndef odd(obj, scene):\n{textwrap.indent(body, '    ')}\n"
    )
    return path


def _group(pgid: int) -> list[int]:
    """The live processes of process group ``pgid`` (a zombie, killed and not yet reaped by init, is gone)."""
    members = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                state, _, group = (entry / "stat").read_text().rsplit(")", 1)[1].split()[:3]
            except OSError:
                continue
            if int(group) == pgid and state != "Z":
                members.append(int(entry.name))
    return members


def _gone(pgid: int) -> None:
    wait_until(lambda: _group(pgid) == [], f"the processes of group {pgid} to end")


def _decide(path: Path, limits: Limits | None = None) -> tuple[dict, int]:
    """The atoms of ``path`` on a small scene, and the child's process group (gone after)."""
    user = UserPredicates.start(path, limits)
    pgid = user._process.pid
    try:
        return user.evaluate(_scene(), user.predicates), pgid
    finally:
        user.close()
        _gone(pgid)  # no process of the predicates file outlives it


def _refused(path: Path, limits: Limits | None = None) -> str:
    with pytest.raises(InputError) as refused:
        _decide(path, limits)
    return str(refused.value)


def test_a_normal_file_grounds_the_same_atoms_as_in_this_process():
    still = Square("blue", (500, 420))
    pre = tabletop_image([Square("purple", (200, 150)), still, Square("red", (100, 400))])
    post = tabletop_image([Square("purple", (220, 410)), still, Square("red", (100, 400))])
    here = ground(pre, post, predicates=with_builtins(load_predicates(EXAMPLE)))
    contained = ground_with_user_predicates(pre, post, "bottom", EXAMPLE)
    assert list(contained.atoms_pre.items()) == list(here.atoms_pre.items())  # the same values, in the same order
    assert list(contained.atoms_post.items()) == list(here.atoms_post.items())
    assert contained.to_dict() == here.to_dict()


def test_one_child_answers_many_scenes_and_a_direct_call(tmp_path):
    with UserPredicates.start(EXAMPLE) as user:
        pid = user._process.pid
        for _ in range(20):
            values = user.evaluate(_scene(), user.predicates)
        assert user._process.pid == pid and values[("warm", ("red",))] and not values[("warm", ("blue",))]
        warm = next(p for p in user.predicates if p.name == "warm")
        assert warm(_scene().objects["red"], _scene()) is True  # called like its function


def test_an_alarm_the_file_sets_and_a_loop_that_disarms_the_timer_are_stopped_at_the_deadline(tmp_path):
    path = _file(tmp_path, "while True:\n    signal.setitimer(signal.ITIMER_REAL, 0)", prelude="signal.alarm(1)")
    message = _refused(path, QUICK)
    # the file's own alarm (default action: end the process) or the deadline: either way one error
    assert "predicates file" in message and str(path) in message, message


def test_blocked_signals_and_an_endless_loop_are_stopped_at_the_deadline(tmp_path):
    body = "signal.pthread_sigmask(signal.SIG_BLOCK, set(signal.Signals))\nwhile True:\n    pass"
    message = _refused(_file(tmp_path, body), QUICK)
    assert "did not answer within 2 s (it may block or loop)" in message, message


def test_processes_the_file_starts_end_with_it(tmp_path):
    prelude = (
        "subprocess.Popen(['sleep', '300'])\n"
        "if os.fork() == 0:\n    os.execvp('sleep', ['sleep', '301'])\n"
        f"open({str(tmp_path / 'group')!r}, 'w').write(str(os.getpgid(0)))\n"
    )
    path = _file(tmp_path, "return True", prelude)
    user = UserPredicates.start(path)
    pgid = user._process.pid
    assert int((tmp_path / "group").read_text()) == pgid
    assert len(_group(pgid)) == 4  # the guard (vslsp.interrupts), the child and two sleeps
    user.close()
    _gone(pgid)


def test_a_killed_vslsp_leaves_neither_the_files_processes_nor_its_folder(tmp_path):
    """SIGKILL of the process that started the child: the guard kills the child and what it
    started, and removes the child's temporary folder."""
    pids = tmp_path / "pids"
    prelude = (
        "sleeper = subprocess.Popen(['sleep', '303'])\n"
        f"open({str(pids)!r}, 'w').write(f'{{os.getpid()}} {{sleeper.pid}}')\n"
    )
    path = _file(tmp_path, "return True", prelude)
    program = (
        "import sys; from vslsp.grounding.contained import UserPredicates; "
        "user = UserPredicates.start(sys.argv[1]); print(user._folder, flush=True); sys.stdin.read()"
    )
    holder = subprocess.Popen(
        [sys.executable, "-c", program, str(path)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(REPO)},
    )
    assert holder.stdout is not None
    folder = Path(holder.stdout.readline().strip())
    assert folder.is_dir()
    started = [int(pid) for pid in pids.read_text().split()]
    holder.kill()
    holder.wait()
    wait_until(lambda: all(process_gone(pid) for pid in started), f"the child and its sleep {started} to end")
    wait_until(lambda: not folder.exists(), f"the child's folder {folder} to be removed")


def test_a_predicate_that_forks_and_hangs_leaves_no_orphan(tmp_path):
    body = "if os.fork() == 0:\n    os.execvp('sleep', ['sleep', '302'])\ntime.sleep(1000)"
    message = _refused(_file(tmp_path, body), QUICK)
    assert "did not answer within 2 s" in message  # _decide checked that the group is gone


def test_an_exception_is_one_line_naming_the_file_the_line_and_the_exception(tmp_path):
    path = _file(tmp_path, "x = 1\nreturn x / 0")
    message = _refused(path)
    assert message.startswith("predicate odd raised ZeroDivisionError: division by zero while grounding (odd ")
    assert f"{path}:4" in message and "line 7 raised it" in message and "\n" not in message


def test_a_process_that_ends_is_reported_with_its_exit_code(tmp_path):
    message = _refused(_file(tmp_path, "print('leaving'); sys.stdout.flush(); os._exit(3)"))
    assert "its process ended (exit code 3); its last output: leaving" in message, message


def test_a_memory_hog_meets_the_address_space_limit(tmp_path):
    body = "hoard = []\nwhile True:\n    hoard.append(bytearray(10_000_000))"
    message = _refused(_file(tmp_path, body), Limits(memory_mb=700))
    assert "raised MemoryError" in message and "its memory limit is 700 MB" in message, message


def test_the_child_sees_no_secret_and_works_in_its_own_folder(tmp_path, monkeypatch):
    monkeypatch.setenv("VSLSP_STUDIO_TOKEN", "secret")
    monkeypatch.setenv("AWS_SECRET_ACCESS_KEY", "secret")
    monkeypatch.setenv("PYTHONPATH", str(tmp_path))
    monkeypatch.chdir(tmp_path)
    report = tmp_path / "seen.json"
    prelude = (
        f"open({str(report)!r}, 'w').write(__import__('json').dumps("
        "{'env': dict(os.environ), 'cwd': os.getcwd(), 'path': sys.path, 'stdin': sys.stdin.read()}))"
    )
    _decide(_file(tmp_path, "return True", prelude))
    seen = json.loads(report.read_text())
    given = {"PATH", "LANG", "HOME", "TMPDIR", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"}
    set_by_imports = {"OPENCV_IO_MAX_IMAGE_PIXELS", "LD_LIBRARY_PATH", "LC_CTYPE"}  # vslsp's and cv2's own, inside
    assert set(seen["env"]) <= given | set_by_imports
    assert "secret" not in json.dumps(seen["env"])
    assert seen["cwd"] != str(tmp_path) and seen["env"]["HOME"] == seen["cwd"] and not Path(seen["cwd"]).exists()
    assert str(tmp_path) not in seen["path"] and seen["stdin"] == ""  # no PYTHONPATH, stdin is /dev/null
    assert "" not in seen["path"] and seen["cwd"] not in seen["path"]  # nor its working folder
    assert seen["path"][0] == str(Path(vslsp.__file__).resolve().parent.parent)  # but vslsp's own


def test_closing_and_flooding_its_output_does_not_touch_ours(tmp_path, capfd):
    flood = _file(tmp_path, "print('x' * 1_000_000); return True", name="flood.py")
    _decide(flood, Limits(output_bytes=1000))
    err = capfd.readouterr().err
    assert len(err) < 2000 and "more bytes of the predicates' output not shown" in err
    closing = "for close in (sys.stdout.close, sys.__stdout__.close, lambda: os.close(1), lambda: os.close(2)):\n"
    closes = _file(tmp_path, closing + "    try:\n        close()\n    except OSError:\n        pass\nreturn True")
    values, _ = _decide(closes)
    assert all(values.values())
    print("still ours")
    assert capfd.readouterr().out == "still ours\n"


def test_the_session_has_a_deadline_of_its_own(tmp_path):
    path = _file(tmp_path, "time.sleep(0.6); return True")
    with UserPredicates.start(path, Limits(session_s=3.0)) as user:
        with pytest.raises(InputError, match=r"its calls took more than 3 s in all"):
            for _ in range(5):
                user.evaluate(_scene(), user.predicates)  # 2 atoms: 1.2 s each, within the 30 s per call


def test_predicates_sent_to_another_process_are_that_process_s_own(tmp_path):
    import pickle

    from vslsp.grounding.contained import shared_predicates

    shared = shared_predicates(EXAMPLE)
    again = pickle.loads(pickle.dumps(shared))  # as an experiment's result comes back from a worker
    assert [p.name for p in again] == [p.name for p in shared] and again[0].source is shared[0].source
    assert pickle.loads(pickle.dumps(shared[2]))(_scene().objects["red"], _scene()) is True  # warm red


def test_a_stopped_child_answers_every_later_call_with_the_same_error_and_is_not_restarted(tmp_path, monkeypatch):
    from vslsp.grounding import contained

    path = _file(tmp_path, "while True:\n    pass")
    with contained.UserPredicates.start(path, QUICK) as user:
        with pytest.raises(InputError, match="did not answer within 2 s") as first:
            user.evaluate(_scene(), user.predicates)
        with pytest.raises(InputError) as again:
            user.evaluate(_scene(), user.predicates)
        assert str(again.value) == str(first.value)
    shared = contained.shared_predicates(path, QUICK)  # an experiment's trials: the first one waits
    with pytest.raises(InputError, match="did not answer"):
        ground_atoms(_scene(), shared)

    def no_restart(*args: object) -> None:
        raise AssertionError("restarted: the next trial would wait as long")

    monkeypatch.setattr(contained.UserPredicates, "start", no_restart)
    with pytest.raises(InputError, match="did not answer"):
        contained.shared_predicates(path, QUICK)


def test_code_that_breaks_the_process_itself_ends_it_with_one_line_and_no_traceback(tmp_path, capfd):
    # the bootstrap's arguments: vslsp's folder, then the requests', replies' and lifeline's descriptors
    message = _refused(_file(tmp_path, "os.close(int(sys.argv[3]))\nreturn True"))
    assert "its process ended (exit code 70); its last output: the predicates' process broke: OSError" in message
    assert "Traceback" not in capfd.readouterr().err


def test_a_predicate_that_burns_cpu_meets_the_cpu_time_limit(tmp_path):
    message = _refused(_file(tmp_path, "while True:\n    pass"), Limits(cpu_s=2, predicate_s=60.0, call_s=60.0))
    assert "its process ended (killed by SIGXCPU (at its CPU-time limit of 2 s" in message, message
