"""The Ray backend of the trial runner: each seeded trial of a task as a Ray task, on a cluster.

The paper judges each system (VSL, VSL-3D, VSL-SP; sections "Simulation" and "Experiments")
by success rates over many randomised trials; this backend spreads those trials over the
machines of a Ray cluster (``vslsp experiment NAME --backend ray --address auto``), or over a
local Ray instance started for the run when no address is given. It keeps the runner's
contract (:mod:`vslsp.tasks.runner`):

- a trial runs :func:`vslsp.tasks.runner.run_one` in a Ray worker, so the same seed gives the
  same :class:`~vslsp.tasks.base.TrialResult` as the local backend, and a trial that raises is
  a failed result, never lost;
- the task (its options, and through it any shared inputs) goes to the object store once
  (``ray.put``); each trial then sends only its seed and receives only its result;
- at most ``workers`` trials are in flight; results are handed back as they finish;
- a trial whose worker process dies (crash, out of memory, node lost) is retried by Ray
  (:data:`RETRIES` task retries), then recorded as failed ("worker died ...");
- an interrupt while waiting (Ctrl-C, SIGTERM) cancels the outstanding Ray tasks, shuts down a
  Ray instance started here, and is re-raised so that the runner writes the partial report;
- Ray's own messages (e.g. "(raylet) A worker died ...") go to stderr, never to stdout, which
  carries only vslsp's output (one JSON object under ``--json``);
- an address is checked before ``ray.init``, which would retry for ever: nothing listening, a
  server that does not speak gRPC (not Ray) and a cluster that requires an authentication token
  this machine does not have are each refused within seconds, with their own message.

Ray is an optional extra (``pip install 'vslsp[ray]'``); without it :func:`check_ray` raises an
:class:`~vslsp.errors.InputError` before any work. See ``docs/ray.md`` for running on a cluster.
"""

from __future__ import annotations

import contextlib
import logging
import os
import re
import socket
import sys
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

from vslsp import interrupts
from vslsp.errors import InputError
from vslsp.tasks.base import Task, TrialResult, TrialStatus
from vslsp.tasks.task_files import by_value_for_ray
from vslsp.tasks.trial import run_one

RETRIES = 1  # Ray re-runs a trial whose worker died once (the local backend's rule), then it is failed
PROBE_S = 4.0  # how long a cluster's address may take to accept a connection, then to answer
INSTALL = "pip install 'vslsp[ray]'"
# The client's connection preface of HTTP/2 (RFC 9113, 3.4) and an empty SETTINGS frame: a gRPC
# server (Ray's GCS and its client server are) answers with a SETTINGS frame of its own.
_HTTP2_PREFACE = b"PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n" + bytes([0, 0, 0, 4, 0, 0, 0, 0, 0])
_SETTINGS = 4
# A GCS call that needs no arguments (an empty message): refused UNAUTHENTICATED by a cluster that
# requires token authentication (RAY_AUTH_MODE=token) when the caller sends no token.
_GCS_CLUSTER_ID = "/ray.rpc.NodeInfoGcsService/GetClusterId"
_HOST_PORT = re.compile(r"^(?P<host>[A-Za-z0-9._-]+|\[[0-9A-Fa-f:]+\]):(?P<port>\d{1,5})$")


def check_ray(address: str | None = None) -> ModuleType:
    """Check, before any work, that Ray can be imported and that ``address`` is a Ray address.

    ``address``: None (a local Ray instance for the run), ``'auto'`` (the cluster this machine
    belongs to), ``'ray://HOST:PORT'`` (Ray client, port 10001 by default) or ``'HOST:PORT'``
    (the head node's GCS, port 6379 by default). Returns the ``ray`` module.
    """
    try:
        import ray
    except ImportError:
        raise InputError(f"--backend ray needs Ray, which is not installed: {INSTALL}") from None
    if address is None or address == "auto":
        return ray
    target = address[len("ray://") :] if address.startswith("ray://") else address
    match = _HOST_PORT.match(target)
    if match is None or not 0 < int(match["port"]) < 65536:
        raise InputError(
            f"--address {address!r} is not a Ray cluster address: give 'auto' (the cluster this "
            "machine joined with `ray start`), HOST:PORT (the head's port, 6379 by default) or "
            "ray://HOST:PORT (Ray client, port 10001 by default)"
        )
    if address.startswith("ray://"):
        try:
            import grpc  # noqa: F401  (the Ray client's transport: ray[client])
        except ImportError:
            raise InputError(f"--address ray://... needs the Ray client, which is not installed: {INSTALL}") from None
    return ray


def worker_env() -> dict[str, str]:
    """The environment variables of the Ray workers: one thread each for pybullet/torch/OpenMP,
    and the driver's ``PYTHONPATH`` when it has one (development checkouts), so that the workers
    import the same vslsp."""
    env = {"OMP_NUM_THREADS": "1"}
    if os.environ.get("PYTHONPATH"):
        env["PYTHONPATH"] = os.environ["PYTHONPATH"]
    return env


def run_on_ray(
    task: Task,
    seeds: Sequence[int],
    keep: set[int],
    workers: int,
    address: str | None,
    finished: Callable[[TrialResult], None],
) -> None:
    """Run the trial of every seed in ``seeds`` as a Ray task, at most ``workers`` at a time, and
    call ``finished(result)`` once per seed as the results come back (in any order).

    ``keep``: the seeds whose trials keep their artefacts. ``address``: see :func:`check_ray`;
    None starts a local Ray instance with ``workers`` CPUs for the run (shut down at the end); a
    cluster's address is connected to for the run and disconnected from at the end (the cluster
    keeps running). When this process is already connected to Ray (``ray.init`` called by the
    caller), that connection is used and left open.
    Raises :class:`InputError` when Ray is missing or the cluster cannot be reached; re-raises an
    interrupt after cancelling the outstanding trials.
    """
    ray = check_ray(address)
    with _ray_output_on_stderr():
        connected = _connect(ray, address, workers)
        try:
            _run(ray, task, seeds, keep, workers, finished)
        finally:
            if connected:
                ray.shutdown()  # stops a local instance started here; leaves a cluster running


def _run(
    ray: ModuleType,
    task: Task,
    seeds: Sequence[int],
    keep: set[int],
    workers: int,
    finished: Callable[[TrialResult], None],
) -> None:
    """Submit the trials (at most ``workers`` in flight) and hand back their results."""
    pending: dict[Any, int] = {}
    by_value_for_ray(task)  # a task of a user's tasks file: its module travels with it
    try:
        task_ref = ray.put(task)  # once: the workers fetch it from the object store
        trial = ray.remote(_trial).options(
            num_cpus=1, max_retries=RETRIES, retry_exceptions=False, runtime_env={"env_vars": worker_env()}
        )
        queue = deque(seeds)
        while queue or pending:
            while queue and len(pending) < workers:
                seed = queue.popleft()
                pending[trial.remote(task_ref, seed, seed in keep)] = seed
            ready, _ = ray.wait(list(pending), num_returns=1, timeout=interrupts.WAIT_SLICE_S)
            for ref in ready:
                finished(_outcome(ray, ref, task.name, pending.pop(ref)))
    except BaseException:  # an interrupt (KeyboardInterrupt, runner.Interrupted) or an error: stop every trial
        _cancel(ray, list(pending))
        raise


@contextlib.contextmanager
def _ray_output_on_stderr() -> Iterator[None]:
    """Send what is written to stdout while Ray runs here to stderr: Ray's driver threads print
    its messages ("(raylet) ...") to ``sys.stdout``, and the processes that ``ray.init`` starts
    inherit file descriptor 1. Restored once Ray is shut down (its threads have stopped)."""
    sys.stdout.flush()
    try:
        saved = os.dup(1)
    except OSError:  # no file descriptor 1 (a closed stdout): only Python's stream is redirected
        saved = None
    if saved is not None:
        os.dup2(2, 1)
    try:
        with contextlib.redirect_stdout(sys.stderr):
            yield
    finally:
        sys.stderr.flush()
        if saved is not None:
            os.dup2(saved, 1)
            os.close(saved)


def _trial(task: Task, seed: int, keep: bool) -> TrialResult:
    """One trial in a Ray worker (the task arrives from the object store)."""
    return run_one(task, seed, keep)


def _connect(ray: ModuleType, address: str | None, workers: int) -> bool:
    """Connect to the cluster at ``address`` or start a local instance; True when connected here
    (False: this process was connected already)."""
    if ray.is_initialized():
        return False
    quiet = {"log_to_driver": False, "logging_level": logging.ERROR}
    if address is None:
        try:
            ray.init(address="local", num_cpus=workers, _node_ip_address="127.0.0.1", include_dashboard=False, **quiet)
        except BaseException:  # Ctrl-C while it starts: leave nothing running
            ray.shutdown()
            raise
        return True
    needs_token = _probe(ray, address)
    if needs_token and not _token_configured():
        raise InputError(
            f"the Ray cluster at --address {address} requires token authentication and this machine "
            "has no token: set RAY_AUTH_MODE=token and the cluster's token in RAY_AUTH_TOKEN (or a file "
            "named by RAY_AUTH_TOKEN_PATH, or ~/.ray/auth_token)"
        )
    try:
        _init(ray, address, quiet)
    except (ConnectionError, TimeoutError, RuntimeError, ValueError, ray.exceptions.RayError) as error:
        reason = _reason(error)
        if needs_token:
            raise InputError(
                f"the Ray cluster at --address {address} requires token authentication and refused "
                f"this machine's token ({reason}): give the cluster's token in RAY_AUTH_TOKEN, "
                "RAY_AUTH_TOKEN_PATH or ~/.ray/auth_token, with RAY_AUTH_MODE=token"
            ) from None
        raise InputError(
            f"cannot connect to the Ray cluster at --address {address}: {reason}; start its head with "
            "`ray start --head --port 6379` (and workers with `ray start --address HEAD:6379`), "
            "or leave --address out for a local Ray instance"
        ) from None
    return True  # a cluster's connection made here: closed at the end of the run


# A ray:// connection gets a Ray client server of its own, started by the head's proxy for it; on
# a busy head that start can fail ("Starting Ray client server failed"), and the next connection
# gets a new one: such a failure is retried, every other refusal is final.
CLIENT_SERVER_STARTS = 3
_CLIENT_SERVER_FAILED = (
    "Starting Ray client server failed",
    "Proxy failed to Connect to backend",
    "in start_specific_server",  # the proxy's start of it raised (CI: psutil on a process just gone)
)


def _init(ray: ModuleType, address: str, quiet: dict) -> None:
    """``ray.init(address)``, retried (``CLIENT_SERVER_STARTS`` tries in all) while the head fails
    to start this connection's Ray client server."""
    for attempt in range(1, CLIENT_SERVER_STARTS + 1):
        try:
            ray.init(address=address, **quiet)
            return
        except ConnectionError as error:
            ray.shutdown()  # a refused connection leaves nothing half-connected (the next try, the next run)
            if attempt == CLIENT_SERVER_STARTS or not any(words in str(error) for words in _CLIENT_SERVER_FAILED):
                raise


def _reason(error: BaseException) -> str:
    """Why Ray refused, in one line: a Ray client server's failed start without the server's
    traceback (it names the head's log file), any other error's text, at most 400 characters."""
    text = " ".join(str(error).split())
    for words in _CLIENT_SERVER_FAILED:
        if words in text:
            logs = re.search(r"ray_client_server_\d+\.err", text)
            where = f" (the head's log: {logs.group(0)} in its session's logs folder)" if logs else ""
            tries = f"in {CLIENT_SERVER_STARTS} tries"
            return f"the head could not start a Ray client server for this connection {tries}{where}"
    return text[:400] or type(error).__name__


def _probe(ray: ModuleType, address: str) -> bool:
    """Refuse an address where no Ray cluster answers (``ray.init`` would retry for ever): nothing
    listening, or a server that is not gRPC. True when the cluster requires token authentication
    (it refused a call without a token)."""
    target = address[len("ray://") :] if address.startswith("ray://") else address
    if address == "auto":
        try:
            found = ray._private.services.canonicalize_bootstrap_address(address)
        except (AttributeError, ConnectionError, ValueError):  # Ray's own lookup; let ray.init say the rest
            return False
        if found is None:
            raise InputError(
                "--address auto: no Ray cluster was started on this machine (`ray start --head "
                "--port 6379`, or `ray start --address HEAD:6379` to join one); or leave --address "
                "out for a local Ray instance"
            )
        target = found
    host, _, port = target.rpartition(":")
    host = host.strip("[]")
    via = f" (found by 'auto': {target})" if address == "auto" else ""
    try:
        with socket.create_connection((host, int(port)), timeout=PROBE_S) as connection:
            connection.settimeout(PROBE_S)
            answer = _answer_to_http2(connection)
    except OSError as error:
        raise InputError(
            f"no Ray cluster answers at --address {address}{via}: {error.strerror or error}; start "
            "its head with `ray start --head --port 6379`, or leave --address out for a local Ray "
            "instance"
        ) from None
    if len(answer) < 9 or answer[3] != _SETTINGS:
        port_hint = (
            "the Ray client server's port (10001 by default)"
            if address.startswith("ray://")
            else ("the head's GCS port (6379 by default)")
        )
        raise InputError(
            f"--address {address}{via}: the server there is not a Ray cluster (it does not answer as "
            f"a gRPC server); give {port_hint}, or leave --address out for a local Ray instance"
        )
    return not address.startswith("ray://") and _refuses_without_token(host, int(port))


def _answer_to_http2(connection: socket.socket) -> bytes:
    """The first 9 bytes (a frame header) a server sends back after the HTTP/2 preface; fewer
    when it closes the connection or stays silent for ``PROBE_S``."""
    connection.sendall(_HTTP2_PREFACE)
    answer = b""
    with contextlib.suppress(TimeoutError, OSError):
        while len(answer) < 9:
            chunk = connection.recv(9 - len(answer))
            if not chunk:
                break
            answer += chunk
    return answer


def _refuses_without_token(host: str, port: int) -> bool:
    """Whether the GCS at ``host:port`` refuses a call that carries no authentication token
    (False when gRPC, Ray's client transport, is not installed: ``ray.init`` then says it)."""
    try:
        import grpc
    except ImportError:
        return False
    target = f"[{host}]:{port}" if ":" in host else f"{host}:{port}"
    with grpc.insecure_channel(target) as channel:
        try:
            channel.unary_unary(_GCS_CLUSTER_ID)(b"", timeout=PROBE_S)
        except grpc.RpcError as error:
            return bool(error.code() == grpc.StatusCode.UNAUTHENTICATED)
    return False


def _token_configured() -> bool:
    """Whether Ray on this machine sends an authentication token: a token in the environment, a
    file it names or ~/.ray/auth_token, unless RAY_AUTH_MODE turns authentication off (Ray turns
    it on by itself when RAY_AUTH_MODE is unset and a token exists)."""
    mode = os.environ.get("RAY_AUTH_MODE")
    if mode is not None and mode.lower() != "token":
        return False
    return bool(
        os.environ.get("RAY_AUTH_TOKEN")
        or os.environ.get("RAY_AUTH_TOKEN_PATH")
        or (Path.home() / ".ray" / "auth_token").is_file()
    )


def _outcome(ray: ModuleType, ref: Any, name: str, seed: int) -> TrialResult:
    """The result of a finished Ray task; a task Ray could not complete becomes a failed trial."""
    errors = ray.exceptions
    try:
        result: TrialResult = ray.get(ref)
        return result
    except (
        errors.WorkerCrashedError,
        errors.NodeDiedError,
        errors.OutOfMemoryError,
        errors.LocalRayletDiedError,
    ) as error:
        return TrialResult(
            name,
            seed,
            False,
            f"worker died: its process ended during the trial {RETRIES + 1} "
            f"times ({type(error).__name__}: crash, out of memory or node lost)",
            failure_cause="worker died",
            status=TrialStatus.LOST,
        )
    except errors.RayError as error:
        first = (str(error).strip().splitlines() or [""])[0][:300]
        return TrialResult(
            name, seed, False, f"ray: {type(error).__name__}: {first}", failure_cause="ray", status=TrialStatus.LOST
        )


def _cancel(ray: ModuleType, refs: list[Any]) -> None:
    """Cancel the outstanding trials (their workers are killed); never masks the error being raised."""
    for ref in refs:
        try:
            ray.cancel(ref, force=True)
        except Exception:  # noqa: BLE001, S110  (already finished, or the cluster is gone)
            pass
