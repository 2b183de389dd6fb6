"""A Ray cluster started the way a user starts one (``ray start --head``) for the tests of the
Ray backend's addresses: HOST:PORT, ``auto`` and ``ray://`` (the Ray client).

Everything the cluster writes (its sessions, logs, the address file that ``auto`` reads, what
Ray puts in ``~``) goes to one temporary folder, removed with the cluster. Stopping it ends only
the processes it started: its process group, then any process left whose command line names
that folder (Ray's workers start sessions of their own).
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from helpers.events import became_true

STARTED = "Ray runtime started"
HANG_S = 180.0  # guards against a hang only: a head starts in seconds, a few tens on a loaded machine


@dataclass(frozen=True)
class RayHead:
    folder: Path  # the cluster's temporary folder (RAY_TMPDIR and HOME of the head)
    gcs_address: str  # HOST:PORT of the head's GCS: --address HOST:PORT
    client_address: str  # ray://HOST:PORT of its Ray client server

    def logs(self, prefix: str, tail: int = 2000) -> str:
        """The last ``tail`` characters of each of the head's log files named ``prefix*``
        (e.g. "ray_client_server"), for a failed test's message."""
        found = sorted(self.folder.glob(f"ray/session_latest/logs/{prefix}*"))
        return "\n".join(f"== {p.name}\n{p.read_text(errors='replace')[-tail:]}" for p in found) or "(no logs)"


def free_port() -> int:
    """A TCP port that nothing listens on at the moment."""
    return free_ports(1)[0]


def free_ports(count: int) -> list[int]:
    """``count`` different TCP ports that nothing listens on at the moment (all held open while
    they are chosen: one closed before the next is bound may be handed out again)."""
    probes = [socket.socket() for _ in range(count)]
    try:
        for probe in probes:
            probe.bind(("127.0.0.1", 0))
        return [int(probe.getsockname()[1]) for probe in probes]
    finally:
        for probe in probes:
            probe.close()


def listens(port: int) -> bool:
    """Whether something accepts TCP connections on 127.0.0.1:``port``."""
    try:
        with socket.create_connection(("127.0.0.1", port), timeout=1.0):
            return True
    except OSError:
        return False


@contextmanager
def ray_head(pythonpath: list[Path], env: dict[str, str] | None = None, cpus: int = 2) -> Iterator[RayHead]:
    """Start a one-node Ray cluster (``ray start --head --block``) on 127.0.0.1 whose workers
    import from ``pythonpath``; ``env``: more environment variables of the head (e.g. its
    authentication). Stops it, and removes its folder, on leaving."""
    folder = Path(tempfile.mkdtemp(prefix="vslsp-ray-"))  # short: Ray's socket paths must stay < 108 bytes
    port, client_port = free_ports(2)
    head_env = {
        **os.environ,
        "HOME": str(folder),
        "RAY_TMPDIR": str(folder),
        "PYTHONPATH": os.pathsep.join(str(p) for p in pythonpath),
        # a Ray client's own server may start slowly on a loaded machine (Ray's default: 30 s)
        "RAY_CLIENT_SERVER_CHECK_CHANNEL_TIMEOUT_S": str(int(HANG_S)),
        **(env or {}),
    }
    command = [
        str(Path(sys.executable).parent / "ray"),
        "start",
        "--head",
        f"--port={port}",
        f"--ray-client-server-port={client_port}",
        f"--num-cpus={cpus}",
        "--node-ip-address=127.0.0.1",
        "--include-dashboard=false",
        "--disable-usage-stats",
        "--block",
    ]
    head = subprocess.Popen(
        command, env=head_env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True
    )
    try:
        _wait_until_started(head)
        # `ray start` says "started" once the GCS and the raylet run; the Ray client's server is a
        # process of its own that may listen only seconds later on a loaded machine (CI: a
        # ray:// run right after the start was refused). The cluster is ready when it listens.
        if not became_true(lambda: listens(client_port), head, hang_s=HANG_S):
            raise RuntimeError(f"the head's Ray client server never listened on port {client_port}")
        yield RayHead(folder, f"127.0.0.1:{port}", f"ray://127.0.0.1:{client_port}")
    finally:
        _stop(head, folder)


def _wait_until_started(head: subprocess.Popen[str]) -> None:
    """Read the head's output until it says the cluster runs (then drain it in the background)."""
    assert head.stdout is not None
    seen: list[str] = []
    timer = threading.Timer(HANG_S, head.kill)  # a head that never starts ends the read below
    timer.start()
    try:
        for line in head.stdout:
            seen.append(line)
            if STARTED in line:
                break
    finally:
        timer.cancel()
    if not seen or STARTED not in seen[-1]:
        raise RuntimeError("`ray start --head` did not start:\n" + "".join(seen[-30:]))
    threading.Thread(target=head.stdout.read, daemon=True).start()  # a full pipe must not block it


def _stop(head: subprocess.Popen[str], folder: Path) -> None:
    """End the head's process group and every process left that names ``folder``; remove it."""
    try:
        os.killpg(head.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    head.wait(timeout=HANG_S)
    _end_processes_naming(folder)
    shutil.rmtree(folder, ignore_errors=True)


def _end_processes_naming(folder: Path) -> None:
    """End every process left whose command line names ``folder`` (Ray's, started for a test)."""

    def none_left() -> bool:
        left = _processes_naming(folder)
        for pid in left:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        return not left

    became_true(none_left, hang_s=HANG_S)


def _processes_naming(folder: Path) -> list[int]:
    """The processes whose command line holds ``folder`` (those this cluster started)."""
    needle = str(folder).encode()
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit() and int(entry.name) != os.getpid():
            try:
                if needle in (entry / "cmdline").read_bytes():
                    found.append(int(entry.name))
            except OSError:  # gone meanwhile, or not ours to read
                continue
    return found


@contextmanager
def ray_folder() -> Iterator[Path]:
    """A short temporary folder for what a local Ray instance writes (its sessions: give it as
    RAY_TMPDIR); on leaving, the processes left that name it are ended and it is removed."""
    folder = Path(tempfile.mkdtemp(prefix="vslsp-ray-"))  # short: Ray's socket paths must stay < 108 bytes
    try:
        yield folder
    finally:
        _end_processes_naming(folder)
        shutil.rmtree(folder, ignore_errors=True)
