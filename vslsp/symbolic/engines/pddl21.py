"""PDDL 2.1/2.2 beyond STRIPS: numeric fluents, durative actions, timed initial literals.

Paper: "Implementation" (the learned domain handed to an off-the-shelf planner); issue 41 (the
domains of robotics researchers have durations and resources). vslsp's own model
(:mod:`vslsp.symbolic.model`) stays STRIPS + PDDL 3.0; a domain with ``:functions`` other than
``(total-cost)`` or ``:durative-action`` is read by unified-planning's PDDLReader as it is,
planned by the unified-planning engine that supports its kind (:data:`AUTOMATIC`: ENHSP for
numeric problems, Aries for temporal ones, TAMER after them) and its plans checked by
unified-planning's validators (:mod:`vslsp.symbolic.validation.pddl21`). Every planner run is
bounded as Fast Downward's is: wall-clock seconds and megabytes of address space, in a process
group of its own that is killed at the limit. What no engine here reads or plans (derived
predicates: unified-planning 1.3's reader has none; PDDL+ processes and events, continuous
effects) is refused with one line naming the construct and its place.
"""

from __future__ import annotations

import multiprocessing
import os
import re
import resource
import shutil
import signal
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from vslsp.errors import InputError
from vslsp.symbolic.engines.outcomes import InternalError, NoPlan, PlanStatus, Unsolvable
from vslsp.symbolic.io.pddl_errors import located_error
from vslsp.symbolic.language.files import MAX_PDDL_BYTES, read_text
from vslsp.symbolic.model.up_model import environment

#: The engines tried for a problem's kind when no ``--planner`` is named: the first installed one
#: that declares the problem's kind, else the first installed. Measured on tests/data/pddl21
#: (docs/planning.md): ENHSP (Java, ~1.5 s of JVM start) plans every numeric problem there; TAMER
#: plans small numeric ones in 0.2 s but has no time limit of its own and declares fewer kinds;
#: Aries plans the temporal ones in 0.2 s but fails on numeric fluents, which TAMER then plans.
AUTOMATIC = {"numeric": ("enhsp", "tamer"), "temporal": ("aries", "tamer")}
#: Engines whose planner is a Java program.
JAVA_ENGINES = ("enhsp", "enhsp-opt", "enhsp-any")
#: The pip extra that installs the engines.
EXTRA = "pip install 'vslsp[pddl21]'"
_BEYOND_STRIPS = re.compile(r"\(\s*(:durative-action|:derived|:functions)\b", re.IGNORECASE)
_ONLY_COST = re.compile(r"\(\s*:functions\s*\(\s*total-cost\s*\)(\s*-\s*number)?\s*\)", re.IGNORECASE)
_OUTSIDE = {
    ":derived": "derived predicates (:derived ...)",
    ":process": "PDDL+ processes (:process ...)",
    ":event": "PDDL+ events (:event ...)",
    "#t": "continuous effects (#t)",
}
_OUTSIDE_PATTERN = re.compile(r"\(\s*(:process|:event|:derived)\b|(#t)\b", re.IGNORECASE)


def _code(text: str) -> str:
    """``text`` with comments blanked out (same length, so places stay)."""
    return re.sub(r";[^\n]*", lambda m: " " * len(m.group(0)), text)


def is_beyond_strips(domain_text: str) -> bool:
    """Whether the domain declares numeric functions (other than ``(total-cost)``), durative actions,
    derived predicates or PDDL+ constructs: what this module reads (or refuses) instead of vslsp's model."""
    code = _code(domain_text)
    if _OUTSIDE_PATTERN.search(code):
        return True
    return any(
        m.group(1).lower() != ":functions" or not _ONLY_COST.match(code, m.start())
        for m in _BEYOND_STRIPS.finditer(code)
    )


def domain_is_beyond_strips(path: str | Path, max_bytes: int = MAX_PDDL_BYTES) -> bool:
    """:func:`is_beyond_strips` of the domain file ``path`` (InputError when it cannot be read)."""
    return is_beyond_strips(read_text(path, max_bytes=max_bytes))


def _refuse_outside(text: str, name: str) -> None:
    """InputError ``FILE:LINE:COL`` at the first construct no engine here plans."""
    match = _OUTSIDE_PATTERN.search(_code(text))
    if match is None:
        return
    start = match.start(1) if match.group(1) else match.start(2)
    line = text.count("\n", 0, start) + 1
    column = start - text.rfind("\n", 0, start)
    what = _OUTSIDE[(match.group(1) or match.group(2)).lower()]
    raise InputError(
        f"{name}:{line}:{column}: {what} are not supported; vslsp plans numeric fluents, durative actions "
        "and timed initial literals (PDDL 2.1/2.2)"
        + ("; write the derived predicate's formula where it is used" if "derived" in what else ", not PDDL+")
    )


@dataclass(frozen=True)
class Read:
    """A domain and problem read by unified-planning: ``problem`` its ``Problem``, with the texts."""

    problem: Any
    domain_text: str
    problem_text: str
    problem_name: str = "<problem>"

    @property
    def domain_name(self) -> str:
        """The name in ``(domain NAME)``."""
        found = re.search(r"\(\s*domain\s+([^\s()]+)", _code(self.domain_text), re.IGNORECASE)
        return found.group(1).lower() if found else ""

    @property
    def temporal(self) -> bool:
        """Whether actions have durations (or literals are timed): the plan is time-triggered."""
        return bool(self.problem.kind.has_continuous_time() or self.problem.kind.has_discrete_time())

    @property
    def kind_name(self) -> str:
        """``temporal`` or ``numeric``."""
        return "temporal" if self.temporal else "numeric"


def read(domain: str | Path, problem: str | Path | None, max_bytes: int = MAX_PDDL_BYTES) -> Read:
    """The domain (and problem) files through unified-planning's PDDLReader; malformed input is
    InputError ``FILE:LINE:COL: what``."""
    texts = []
    for path in (domain, problem) if problem is not None else (domain,):
        text = read_text(path, max_bytes=max_bytes).replace("\r\n", "\n").replace("\r", "\n")
        _refuse_outside(text, str(path))
        texts.append(text)
    try:
        up_problem = _parsed(*texts)
    except RecursionError:
        raise InputError(f"{problem or domain}: formulas nest too deeply for the reader; flatten them") from None
    except Exception as error:  # SyntaxError, pyparsing and UP exceptions alike
        raise _located(error, texts, domain, problem) from None
    return Read(up_problem, texts[0], texts[1] if problem is not None else "", str(problem))


def _parsed(domain_text: str, problem_text: str | None = None) -> Any:
    from unified_planning.io import PDDLReader

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        return PDDLReader(environment()).parse_problem_string(domain_text, problem_text)


def _located(error: Exception, texts: list[str], domain: str | Path, problem: str | Path | None) -> InputError:
    """The reader's error placed in the file it is in: the domain when the domain alone fails too."""
    if problem is not None:
        try:
            _parsed(texts[0])
        except Exception as domain_error:
            return located_error(domain_error, texts[0], str(domain))
        return located_error(error, texts[1], str(problem))
    return located_error(error, texts[0], str(domain))


@dataclass(frozen=True)
class TimedStep:
    """One step of a plan: ``action`` and ``args`` in lower case; ``start`` and ``duration`` in the
    problem's time units (None in a sequential plan; ``duration`` None for an instantaneous action)."""

    action: str
    args: tuple[str, ...]
    start: float | None = None
    duration: float | None = None

    def to_pddl(self) -> str:
        """``(drive r a b)``, or ``0.000: (drive r a b) [4.000]`` as VAL and IPC planners write it."""
        atom = f"({' '.join((self.action, *self.args))})"
        if self.start is None:
            return atom
        return f"{self.start:.3f}: {atom}" + (f" [{self.duration:.3f}]" if self.duration is not None else "")


@dataclass(frozen=True)
class TimedPlan:
    """A plan of a numeric or temporal problem, by ``planner`` in ``time_s`` seconds of wall clock."""

    steps: tuple[TimedStep, ...]
    planner: str
    time_s: float
    temporal: bool

    @property
    def makespan(self) -> float | None:
        """The end of the last step (temporal plans), None for a sequential plan."""
        if not self.temporal:
            return None
        return max(((s.start or 0.0) + (s.duration or 0.0) for s in self.steps), default=0.0)

    def lines(self) -> list[str]:
        return [s.to_pddl() for s in self.steps]

    def to_pddl(self) -> str:
        """The plan file (the PLAN of ``vslsp validate``)."""
        return "".join(f"{line}\n" for line in self.lines())

    def to_dict(self) -> dict:
        return {
            "plan": self.lines(),
            "steps": [
                {"action": s.action, "args": list(s.args), "start": s.start, "duration": s.duration} for s in self.steps
            ],
            "planner": self.planner,
            "time_s": round(self.time_s, 3),
            "kind": "temporal" if self.temporal else "numeric",
            "makespan": self.makespan,
        }


def choose_planner(problem: Read, planner: str | None) -> str:
    """``planner``, or the engine of :data:`AUTOMATIC` for the problem's kind; InputError when no
    such engine is installed (naming the extra) or it needs Java and there is none."""
    from unified_planning.engines.mixins import OneshotPlannerMixin

    factory = environment().factory

    def installed(name: str) -> bool:
        try:
            return issubclass(factory.engine(name), OneshotPlannerMixin)
        except Exception:  # not registered, or its package broken
            return False

    if planner is not None and planner.startswith("fast-downward"):
        raise InputError(
            f"planner {planner} plans STRIPS and ADL without numbers or time; for this {problem.kind_name} "
            f"problem use --planner {' or '.join(AUTOMATIC[problem.kind_name])} (or leave --planner out)"
        )
    candidates = [planner] if planner else [n for n in AUTOMATIC[problem.kind_name] if installed(n)]
    if not candidates or not installed(candidates[0]):
        wanted = planner or " or ".join(AUTOMATIC[problem.kind_name])
        raise InputError(
            f"planner {wanted} is not installed (numeric and temporal problems: enhsp, tamer, aries; "
            f"{EXTRA} installs them)"
        )
    kind = problem.problem.kind
    name = next((n for n in candidates if factory.engine(n).supports(kind)), candidates[0])
    if name in JAVA_ENGINES and shutil.which("java") is None:
        raise InputError(
            f"planner {name} (ENHSP) needs Java 17 or later and no 'java' is on PATH; install a JDK "
            "(e.g. apt-get install openjdk-17-jre-headless) or choose --planner tamer"
        )
    return name


def solve(problem: Read, planner: str | None = None, timeout: float = 300.0, memory_mb: int | None = 4096) -> TimedPlan:
    """A plan for ``problem`` by ``planner`` (None: :data:`AUTOMATIC`), within ``timeout`` seconds and
    ``memory_mb`` MB of address space; NoPlan (exit 1) without one, Unsolvable when proved."""
    if problem.problem.trajectory_constraints:
        found = re.search(r"\(\s*:constraints\b", _code(problem.problem_text), re.IGNORECASE)
        line = problem.problem_text.count("\n", 0, found.start()) + 1 if found else 0
        column = found.start() - problem.problem_text.rfind("\n", 0, found.start()) if found else 0
        raise InputError(
            f"{problem.problem_name}:{line}:{column}: PDDL 3.0 constraints (:constraints ...) are not planned "
            "with numeric fluents or durative actions (no engine here takes both); plan the instantaneous "
            "domain for the order, or leave the constraints out"
        )
    name = choose_planner(problem, planner)
    start = time.perf_counter()
    context = multiprocessing.get_context("fork")
    receiver, sender = context.Pipe(duplex=False)
    child = context.Process(target=_solve_in_child, args=(problem.problem, name, timeout, memory_mb, sender))
    child.start()
    sender.close()
    try:
        if not receiver.poll(timeout + 5.0):  # the engine's own limit first (ENHSP's); TAMER has none
            raise _time_limit(timeout)
        try:
            outcome = receiver.recv()
        except EOFError:  # killed: the address-space limit (a failed allocation aborts the engine)
            limit = f"memory limit of {memory_mb} MB" if memory_mb else "memory"
            raise NoPlan(f"the planner's {limit} reached (raise it with --memory)", PlanStatus.MEMOUT) from None
    finally:
        if child.pid is not None:
            try:
                os.killpg(child.pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass
        child.join()
    status, payload = outcome
    declared = environment().factory.engine(name).supports(problem.problem.kind)
    if status in ("error", "INTERNAL_ERROR", "UNSUPPORTED_PROBLEM") and not declared:
        why = f" ({payload.rstrip(': ')})" if payload else ""
        others = [n for n in AUTOMATIC[problem.kind_name] if n != name]
        raise InputError(
            f"planner {name} cannot plan this {problem.kind_name} problem{why}"
            + (f"; try --planner {' or '.join(others)}" if others else "")
        )
    if status == "error":
        raise InternalError(f"{name} failed: {payload}")
    if status == "unsolvable":
        raise Unsolvable(f"the goal cannot be reached from the initial state (proved by {name})")
    if status == "TIMEOUT":
        raise _time_limit(timeout)
    if status != "SOLVED":
        raise NoPlan(
            f"{name} stopped with status {status}", PlanStatus.__members__.get(status, PlanStatus.INTERNAL_ERROR)
        )
    steps = tuple(TimedStep(*step) for step in payload)
    return TimedPlan(steps, name, time.perf_counter() - start, problem.temporal)


def _time_limit(timeout: float) -> NoPlan:
    return NoPlan(f"the planner's time limit of {timeout:g} s reached (raise it with --timeout)", PlanStatus.TIMEOUT)


def _solve_in_child(up_problem: Any, name: str, timeout: float, memory_mb: int | None, sender: Any) -> None:
    """Run the engine in a process group of its own under ``memory_mb``; send (status, steps)."""
    os.setsid()  # the engine's own processes (ENHSP's JVM) go with this one when killed
    if memory_mb:
        limit = memory_mb * 1024 * 1024
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    try:
        from unified_planning.shortcuts import OneshotPlanner

        with warnings.catch_warnings(), OneshotPlanner(name=name) as engine:
            warnings.simplefilter("ignore")  # "does not support timeout", "cannot establish whether"
            engine.skip_checks = True  # choose_planner checked supports()
            result = engine.solve(up_problem, timeout=timeout)
        status = result.status.name
        if status in ("SOLVED_SATISFICING", "SOLVED_OPTIMALLY"):
            sender.send(("SOLVED", _steps(result.plan)))
        elif status == "UNSOLVABLE_PROVEN":
            sender.send(("unsolvable", None))
        else:
            sender.send((status, None))
    except MemoryError:
        pass  # the parent reads the closed pipe as the memory limit reached
    except Exception as error:
        sender.send(("error", f"{type(error).__name__}: {error}"))
    finally:
        sender.close()
        os._exit(0)


def _steps(plan: Any) -> list[tuple]:
    """(action, args, start, duration) of each step of a unified-planning plan."""

    def named(instance: Any) -> tuple[str, tuple[str, ...]]:
        return instance.action.name.lower(), tuple(str(p).lower() for p in instance.actual_parameters)

    if hasattr(plan, "timed_actions"):
        return [
            (*named(a), float(start), float(duration) if duration is not None else None)
            for start, a, duration in plan.timed_actions
        ]
    return [(*named(a), None, None) for a in plan.actions]
