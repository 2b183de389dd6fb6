"""``vslsp studio``'s bad input: exit 2 with one message, before anything is served."""

from __future__ import annotations

import socket
import subprocess
import sys

import pytest

from vslsp.studio.guard import is_loopback


def studio(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "vslsp", "studio", "--no-browser", *args], capture_output=True, text=True, timeout=120
    )


def test_a_missing_root_is_exit_2(tmp_path):
    done = studio("--root", str(tmp_path / "nowhere"))
    assert done.returncode == 2 and "--root" in done.stderr and "Traceback" not in done.stderr


def test_a_short_token_is_exit_2(tmp_path):
    done = studio("--root", str(tmp_path), "--host", "0.0.0.0", "--token", "short")
    assert done.returncode == 2 and "--token" in done.stderr


def test_a_port_in_use_is_exit_2(tmp_path):
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        done = studio("--root", str(tmp_path), "--port", str(taken.getsockname()[1]))
    assert done.returncode == 2 and "cannot serve" in done.stderr and "Traceback" not in done.stderr


@pytest.mark.parametrize(
    ("host", "loopback"),
    [("127.0.0.1", True), ("::1", True), ("localhost", True), ("0.0.0.0", False), ("192.168.1.5", False)],
)
def test_loopback_names_are_told_from_other_addresses(host, loopback):
    assert is_loopback(host) is loopback


@pytest.mark.parametrize("name", ["", "a/b", "host:80", "user@host"])
def test_a_bad_allowed_host_is_exit_2(tmp_path, name):
    done = studio("--root", str(tmp_path), "--allow-host", name)
    assert done.returncode == 2 and "--allow-host" in done.stderr and "Traceback" not in done.stderr
