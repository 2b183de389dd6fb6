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
  Ray instance started here, and is re-raised so that the runner writes the partial report.

Ray is an optional extra (``pip install 'vslsp[ray]'``); without it :func:`check_ray` raises an
:class:`~vslsp.errors.InputError` before any work. See ``docs/ray.md`` for running on a cluster.
"""

from __future__ import annotations

import logging
import os
import re
import socket
from collections import deque
from collections.abc import Callable, Sequence
from types import ModuleType
from typing import Any

from vslsp.errors import InputError
from vslsp.tasks.base import Task, TrialResult
from vslsp.tasks.trial import run_one

RETRIES = 1  # Ray re-runs a trial whose worker died once (the local backend's rule), then it is failed
PROBE_S = 5.0  # how long a cluster's address may take to accept a connection
WAIT_S = 0.5  # longest wait for a result before the driver looks at signals again
INSTALL = "pip install 'vslsp[ray]'"
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
    None starts a local Ray instance with ``workers`` CPUs for the run (shut down at the end; a
    cluster's connection is closed at the end), unless this process is already connected to Ray
    (``ray.init`` called by the caller), whose connection is then used and left open.
    Raises :class:`InputError` when Ray is missing or the cluster cannot be reached; re-raises an
    interrupt after cancelling the outstanding trials.
    """
    ray = check_ray(address)
    connected = _connect(ray, address, workers)
    pending: dict[Any, int] = {}
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
            ready, _ = ray.wait(list(pending), num_returns=1, timeout=WAIT_S)
            for ref in ready:
                finished(_outcome(ray, ref, task.name, pending.pop(ref)))
    except BaseException:  # an interrupt (KeyboardInterrupt, runner.Interrupted) or an error: stop every trial
        _cancel(ray, list(pending))
        raise
    finally:
        if connected:
            ray.shutdown()  # stops a local instance started here; leaves a cluster running


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
    _probe(ray, address)
    try:
        ray.init(address=address, **quiet)
    except (ConnectionError, TimeoutError, RuntimeError, ValueError, ray.exceptions.RayError) as error:
        reason = " ".join(str(error).split())[:400] or type(error).__name__
        raise InputError(
            f"cannot connect to the Ray cluster at --address {address}: {reason}; start its head with "
            "`ray start --head --port 6379` (and workers with `ray start --address HEAD:6379`), "
            "or leave --address out for a local Ray instance"
        ) from None
    return False


def _probe(ray: ModuleType, address: str) -> None:
    """Refuse an address where no Ray cluster answers (``ray.init`` would retry for ever)."""
    target = address[len("ray://") :] if address.startswith("ray://") else address
    if address == "auto":
        try:
            found = ray._private.services.canonicalize_bootstrap_address(address)
        except (AttributeError, ConnectionError, ValueError):  # Ray's own lookup; let ray.init say the rest
            return
        if found is None:
            raise InputError(
                "--address auto: no Ray cluster was started on this machine (`ray start --head "
                "--port 6379`, or `ray start --address HEAD:6379` to join one); or leave --address "
                "out for a local Ray instance"
            )
        target = found
    host, _, port = target.rpartition(":")
    try:
        socket.create_connection((host.strip("[]"), int(port)), timeout=PROBE_S).close()
    except OSError as error:
        via = f" (found by 'auto': {target})" if address == "auto" else ""
        raise InputError(
            f"no Ray cluster answers at --address {address}{via}: {error.strerror or error}; start "
            "its head with `ray start --head --port 6379`, or leave --address out for a local Ray "
            "instance"
        ) from None


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
        )
    except errors.RayError as error:
        first = (str(error).strip().splitlines() or [""])[0][:300]
        return TrialResult(name, seed, False, f"ray: {type(error).__name__}: {first}")


def _cancel(ray: ModuleType, refs: list[Any]) -> None:
    """Cancel the outstanding trials (their workers are killed); never masks the error being raised."""
    for ref in refs:
        try:
            ray.cancel(ref, force=True)
        except Exception:  # noqa: BLE001, S110  (already finished, or the cluster is gone)
            pass
