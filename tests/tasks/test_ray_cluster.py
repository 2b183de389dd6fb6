"""The Ray backend on a cluster it does not start: one started by `ray start --head`, as a user
would, and reached as HOST:PORT, ``auto`` and ``ray://`` (the Ray client); an address where
something else listens; a cluster that requires token authentication; Ray's messages kept off
stdout under ``--json``.

This module's process is never connected to Ray between tests (each run connects and, as the
backend must, disconnects), unlike test_ray_backend.py, whose tests share one connection.
"""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest
from example_tasks import DiceBelowFive
from helpers.cli import REPO, vslsp
from helpers.ray_head import RayHead, free_port, ray_head
from helpers.records import without_times

from vslsp.errors import InputError
from vslsp.tasks import TrialResult, run_trials

ray = pytest.importorskip("ray")
pytest.importorskip("grpc")  # ray[client]: the Ray client and the backend's check of an address

HERE = Path(__file__).resolve().parent
SEEDS = list(range(20, 26))


def records(results: list[TrialResult]) -> list[dict]:
    """The JSON records of the trials, times excepted."""
    return [without_times(r.to_dict()) for r in results]


@pytest.fixture(scope="module")
def head() -> Iterator[RayHead]:
    with ray_head([HERE, REPO]) as started:
        yield started


@pytest.fixture
def workers_import_the_tests(tmp_path):
    """The backend hands its PYTHONPATH to the Ray workers: they import the test tasks from it.
    HOME is a temporary folder (Ray reads and writes ~/.ray), and the environment is restored
    afterwards (``ray.init`` sets RAY_AUTH_MODE in it)."""
    saved = dict(os.environ)
    os.environ.update(PYTHONPATH=os.pathsep.join([str(HERE), str(REPO)]), HOME=str(tmp_path))
    try:
        yield
    finally:
        if ray.is_initialized():  # a failed test must not leave the next one connected
            ray.shutdown()
        os.environ.clear()
        os.environ.update(saved)


@pytest.mark.slow
@pytest.mark.parametrize("how", ["HOST:PORT", "auto", "ray://"])
def test_a_run_on_a_cluster_gives_the_local_results_then_disconnects(head, how, workers_import_the_tests):
    os.environ["RAY_TMPDIR"] = str(head.folder)  # where `auto` finds the address `ray start` wrote
    os.environ.pop("RAY_ADDRESS", None)
    address = {"HOST:PORT": head.gcs_address, "auto": "auto", "ray://": head.client_address}[how]
    try:
        on_cluster = run_trials(DiceBelowFive(), SEEDS, workers=2, backend="ray", address=address)
    except InputError as refused:  # say why from the head's side too (its logs go with the cluster)
        pytest.fail(f"{refused}\n{head.logs('ray_client_server')}")
    assert not ray.is_initialized()  # disconnected at the end of the run ...
    assert records(on_cluster.results) == records(run_trials(DiceBelowFive(), SEEDS).results)
    assert {r.success for r in on_cluster.results} == {True, False} and not on_cluster.partial
    # ... and the cluster runs on: a second run on it gives the same results
    again = run_trials(DiceBelowFive(), SEEDS[:2], workers=2, backend="ray", address=head.gcs_address)
    assert records(again.results) == records(on_cluster.results[:2]) and not ray.is_initialized()


@pytest.mark.slow
def test_ray_messages_go_to_stderr_and_json_stays_one_object(head, tmp_path):
    # A dying worker makes Ray print "(raylet) A worker died ..." in the driver; under --json
    # stdout must still be the one JSON object.
    program = "import sys, example_tasks\nfrom vslsp.cli import main\nmain(sys.argv[1:])"
    done = subprocess.run(
        [sys.executable, "-c", program, "experiment", "crashes-on-odd", "--trials", "2", "--workers", "2"]
        + ["--backend", "ray", "--address", head.gcs_address, "--json", "--out", str(tmp_path)],
        env={**clean_environment(), "PYTHONPATH": os.pathsep.join([str(HERE), str(REPO)]), "HOME": str(tmp_path)},
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 1, done.stderr
    data = json.loads(done.stdout)  # the whole of stdout
    assert [r["success"] for r in data["results"]] == [True, False]
    assert data["results"][1]["error"].startswith("worker died")
    assert "(raylet)" in done.stderr and "A worker died" in done.stderr


def clean_environment() -> dict[str, str]:
    """This environment without Ray's authentication settings (a command sets its own)."""
    return {k: v for k, v in os.environ.items() if not k.startswith("RAY_AUTH")}


class Listener:
    """A TCP server on 127.0.0.1 that is not Ray: it accepts and then stays silent, or answers
    every connection with ``reply`` and closes it."""

    def __init__(self, reply: bytes | None) -> None:
        self.server = socket.create_server(("127.0.0.1", 0))
        self.port = self.server.getsockname()[1]
        self.reply = reply
        self.held: list[socket.socket] = []
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self) -> None:
        while True:
            try:
                connection, _ = self.server.accept()
            except OSError:  # closed
                return
            if self.reply is None:
                self.held.append(connection)  # silent: neither answers nor closes
            else:
                connection.sendall(self.reply)
                connection.close()

    def close(self) -> None:
        self.server.close()
        for connection in self.held:
            connection.close()


@pytest.mark.parametrize(
    "reply", [None, b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n", b"+OK redis\r\n"], ids=str
)
@pytest.mark.parametrize("scheme", ["", "ray://"])
def test_an_address_where_something_else_listens_is_refused(reply, scheme, capsys, tmp_path):
    listener = Listener(reply)
    try:
        address = f"{scheme}127.0.0.1:{listener.port}"
        code, out, _ = vslsp(
            capsys,
            "experiment",
            "dice-below-five",
            "--backend",
            "ray",
            "--address",
            address,
            "--json",
            "--out",
            tmp_path,
        )
    finally:
        listener.close()
    assert code == 2 and not ray.is_initialized()
    error = json.loads(out)["error"]
    assert f"--address {address}: the server there is not a Ray cluster" in error
    assert ("10001" if scheme else "6379") in error  # the port to give instead
    assert not (tmp_path / "report.json").exists()


def test_an_address_where_nothing_listens_is_refused(capsys, tmp_path):
    address = f"127.0.0.1:{free_port()}"
    arguments = ["--backend", "ray", "--address", address, "--json", "--out", tmp_path / "report"]
    code, out, _ = vslsp(capsys, "experiment", "dice-below-five", *arguments)
    assert code == 2 and f"no Ray cluster answers at --address {address}" in json.loads(out)["error"]


TOKEN = "vslsp-test-token-" + "0" * 32


@pytest.fixture(scope="module")
def head_with_token() -> Iterator[RayHead]:
    with ray_head([HERE, REPO], env={"RAY_AUTH_MODE": "token", "RAY_AUTH_TOKEN": TOKEN}) as started:
        yield started


def experiment_on(address: str, out: Path, **env: str) -> subprocess.CompletedProcess[str]:
    """``vslsp experiment dice-below-five`` on the cluster at ``address``, with only ``env`` of
    Ray's authentication variables (HOME: a folder without ~/.ray/auth_token)."""
    base = clean_environment()
    program = "import sys, example_tasks\nfrom vslsp.cli import main\nmain(sys.argv[1:])"
    return subprocess.run(
        [sys.executable, "-c", program, "experiment", "dice-below-five", "--trials", "2", "--backend", "ray"]
        + ["--address", address, "--json", "--out", str(out)],
        env={**base, "PYTHONPATH": os.pathsep.join([str(HERE), str(REPO)]), "HOME": str(out.parent), **env},
        capture_output=True,
        text=True,
        timeout=600,
    )


@pytest.mark.slow
def test_a_cluster_that_requires_a_token_is_named_as_such(head_with_token, tmp_path):
    done = experiment_on(head_with_token.gcs_address, tmp_path / "none")
    assert done.returncode == 2, done.stderr
    error = json.loads(done.stdout)["error"]
    assert error.startswith(f"the Ray cluster at --address {head_with_token.gcs_address} requires token authentication")
    assert "RAY_AUTH_TOKEN" in error and "start its head" not in error
    # a wrong token: refused by the cluster, said so
    wrong = experiment_on(
        head_with_token.gcs_address, tmp_path / "wrong", RAY_AUTH_MODE="token", RAY_AUTH_TOKEN="x" * 40
    )
    assert wrong.returncode == 2, wrong.stderr
    assert "requires token authentication and refused this machine's token" in json.loads(wrong.stdout)["error"]
    # the cluster's token: the run goes through
    right = experiment_on(head_with_token.gcs_address, tmp_path / "right", RAY_AUTH_MODE="token", RAY_AUTH_TOKEN=TOKEN)
    assert right.returncode in (0, 1), right.stderr
    assert json.loads(right.stdout)["trials"] == 2


def test_a_token_counts_as_given_as_ray_would_send_it(monkeypatch, tmp_path):
    from vslsp.tasks.ray_backend import _token_configured

    for name in ("RAY_AUTH_MODE", "RAY_AUTH_TOKEN", "RAY_AUTH_TOKEN_PATH"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("HOME", str(tmp_path))
    assert not _token_configured()
    (tmp_path / ".ray").mkdir()
    (tmp_path / ".ray" / "auth_token").write_text(TOKEN)
    assert _token_configured()  # Ray turns token authentication on by itself when a token exists
    monkeypatch.setenv("RAY_AUTH_MODE", "disabled")
    assert not _token_configured()
    monkeypatch.setenv("RAY_AUTH_MODE", "token")
    (tmp_path / ".ray" / "auth_token").unlink()
    assert not _token_configured()
    monkeypatch.setenv("RAY_AUTH_TOKEN", TOKEN)
    assert _token_configured()


class FailingStarts:
    """Stands in for the ``ray`` module in :func:`vslsp.tasks.ray_backend._init`: its ``init``
    fails as Ray's client does when the head's proxy could not start a client server, ``failures``
    times, then connects."""

    def __init__(self, failures: int, message: str) -> None:
        self.failures, self.message, self.inits, self.shutdowns = failures, message, 0, 0

    def init(self, **_: object) -> None:
        self.inits += 1
        if self.inits <= self.failures:
            raise ConnectionAbortedError(self.message)

    def shutdown(self) -> None:
        self.shutdowns += 1


SERVER_FAILED = (
    'Initialization failure from server:\nTraceback (most recent call last):\n  File "proxier.py", line 772, '
    "in Datapath\nRuntimeError: Starting Ray client server failed. See ray_client_server_23000.err for detailed logs."
)


def test_a_client_server_that_failed_to_start_is_retried_and_said_in_one_line():
    from vslsp.tasks.ray_backend import CLIENT_SERVER_STARTS, _init, _reason

    busy_head = FailingStarts(CLIENT_SERVER_STARTS - 1, SERVER_FAILED)
    _init(busy_head, "ray://127.0.0.1:10001", {})  # connects on the last try
    assert busy_head.inits == CLIENT_SERVER_STARTS and busy_head.shutdowns == CLIENT_SERVER_STARTS - 1
    broken_head = FailingStarts(CLIENT_SERVER_STARTS, SERVER_FAILED)
    with pytest.raises(ConnectionAbortedError) as refused:
        _init(broken_head, "ray://127.0.0.1:10001", {})
    assert broken_head.inits == CLIENT_SERVER_STARTS and broken_head.shutdowns == CLIENT_SERVER_STARTS
    reason = _reason(refused.value)
    assert reason == (
        f"the head could not start a Ray client server for this connection in {CLIENT_SERVER_STARTS} tries "
        "(the head's log: ray_client_server_23000.err in its session's logs folder)"
    )
    other = FailingStarts(1, "Initialization failure from server: version mismatch")
    with pytest.raises(ConnectionAbortedError):
        _init(other, "ray://127.0.0.1:10001", {})  # any other refusal is final
    assert other.inits == 1 and other.shutdowns == 1 and _reason(ConnectionAbortedError("a\n  b")) == "a b"
