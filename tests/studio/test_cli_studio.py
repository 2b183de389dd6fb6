"""``vslsp studio``'s bad input: exit 2 with one message, before anything is served."""

from __future__ import annotations

import socket
import subprocess
import sys

import pytest

from vslsp.cli.studio import _loopback


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
def test_only_loopback_addresses_go_without_a_token(host, loopback):
    assert _loopback(host) is loopback
