"""Reading PDDL 3.0 files into our model, through unified-planning's PDDLReader.

Paper: "Implementation" (VSL-SP writes the learned actions to the planner's domain file and
the demonstrated order as PDDL 3.0 constraints of the problem file). Writing is the model's
own ``to_pddl``; reading is unified-planning's reader, converted by
:mod:`vslsp.symbolic.model.up_model`, with what the reader cannot explain checked first and its
errors turned into :class:`~vslsp.errors.InputError` with FILE:LINE:COL
(:mod:`vslsp.symbolic.io.pddl_errors`). Files are read within a budget: at most
:data:`MAX_PDDL_BYTES` bytes unless told otherwise, UTF-8, and the reading phase's budget
(:data:`vslsp.symbolic.budget.PHASE_BUDGET_S` seconds).
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path
from typing import Any

from vslsp.errors import InputError
from vslsp.files import shown
from vslsp.outputs import write_text
from vslsp.symbolic.budget import OverBudget, phase
from vslsp.symbolic.io.engine_reader import read_with_engine
from vslsp.symbolic.io.flat_problem import flat_problem
from vslsp.symbolic.io.pddl_errors import (
    at_end_as_sometime_after,
    check_constraints_form,
    check_domain_name,
    check_text,
    check_types,
    either_widened,
    located_error,
    preferences_removed,
    sections_in_order,
    types_declared_once,
    warn,
)
from vslsp.symbolic.language.files import MAX_PDDL_BYTES, read_text
from vslsp.symbolic.language.vocabulary import is_reserved_name, reserved_name_message
from vslsp.symbolic.model.domain import Domain, Problem
from vslsp.symbolic.model.up_model import domain_from_up, environment, problem_from_up

__all__ = ["MAX_PDDL_BYTES", "parse_pddl", "read_domain", "read_pddl", "read_problem", "read_text", "save"]


def read_pddl(
    domain_path: str | Path, problem_path: str | Path | None = None, max_bytes: int = MAX_PDDL_BYTES
) -> tuple[Domain, Problem | None]:
    """Read a domain (and a problem) file through unified-planning's PDDLReader.

    Malformed input raises InputError ``FILE:LINE:COL: what is wrong`` (a problem for another domain,
    a name that is a word of PDDL too); what vslsp reads leniently (preferences) is a
    :class:`PddlWarning`. The reading phase's budget covers the whole read: the files, the checks and
    the reader; each file is of at most ``max_bytes`` (:data:`MAX_PDDL_BYTES`). A flat problem that
    checks clean is read from the language engine's tree (:mod:`vslsp.symbolic.io.flat_problem`), any other
    through unified-planning's reader.
    """
    with phase("reading", shown(problem_path if problem_path is not None else domain_path)):
        domain_text = read_text(domain_path, max_bytes=max_bytes)
        problem_text = read_text(problem_path, max_bytes=max_bytes) if problem_path is not None else None
        return _read(
            domain_text, problem_text, shown(domain_path), shown(problem_path) if problem_path is not None else None
        )


def read_domain(path: str | Path) -> Domain:
    """The domain in the PDDL file ``path`` (``vslsp.symbolic.read_domain("pddl/domain.pddl")``);
    raises InputError naming the file and line of what it cannot read."""
    return read_pddl(path)[0]


def read_problem(domain_path: str | Path, problem_path: str | Path) -> Problem:
    """The problem in the PDDL file ``problem_path``, read against the domain in ``domain_path``;
    raises InputError naming the file and line of what it cannot read."""
    problem = read_pddl(domain_path, problem_path)[1]
    assert problem is not None
    return problem


def parse_pddl(domain_text: str, problem_text: str | None = None) -> tuple[Domain, Problem | None]:
    """:func:`read_pddl` on strings (errors name ``<domain>`` / ``<problem>``)."""
    with phase("reading", "<problem>" if problem_text is not None else "<domain>"):
        return _read(domain_text, problem_text, "<domain>", "<problem>" if problem_text is not None else None)


def save(text: str, path: str | Path) -> Path:
    """Write PDDL ``text`` to ``path`` (folders created; atomically, never through a link)."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise InputError(f"{path}: cannot write the file ({error.strerror}); choose a writable place") from None
    return write_text(path, text)


def _read(
    domain_text: str, problem_text: str | None, domain_name: str, problem_name: str | None
) -> tuple[Domain, Problem | None]:
    # Lines end in LF, CRLF or a lone CR (old Mac files): all read as LF, so comments end and places count alike.
    domain_text = domain_text.replace("\r\n", "\n").replace("\r", "\n")
    if problem_text is not None:
        problem_text = problem_text.replace("\r\n", "\n").replace("\r", "\n")
    check_text(domain_text, domain_name)
    check_types(domain_text, domain_name)
    domain_text = either_widened(
        sections_in_order(preferences_removed(domain_text, domain_name), domain_name), domain_name
    )
    domain_text = types_declared_once(domain_text)
    if problem_text is not None and problem_name is not None:
        check_text(problem_text, problem_name)
        check_constraints_form(problem_text, problem_name)
        text = at_end_as_sometime_after(preferences_removed(problem_text, problem_name))
    else:
        text = None
    # Files that check clean and use what vslsp plans with are read from the language engine's tree (no
    # unified-planning import, no second parse: vslsp.symbolic.io.engine_reader); any other by the reader.
    read = read_with_engine(domain_text, text, domain_name, problem_name or "<problem>")
    if read is not None:
        if read[1] is not None:
            _check_requirements(domain_text, read[0], read[1], domain_name)
        return read
    domain = domain_from_up(_parse(domain_text, None, domain_name, None))
    for what, names in (
        ("type", [t for t, _ in domain.types if t != "object"]),  # (:types object) names the built-in type
        ("constant", [c for c, _ in domain.constants]),
        ("predicate", [p.name for p in domain.predicates]),
        ("action", [a.name for a in domain.actions]),
    ):
        _refuse_reserved(names, what, domain_text, domain_name, ":types" if what == "type" else "")
    if text is None or problem_name is None:
        return domain, None
    check_domain_name(text, domain.name, problem_name)
    text = re.sub(r"(\(\s*:domain\s+)[^\s()]+", lambda m: m.group(1) + domain.name, text, count=1, flags=re.I)
    # A flat problem (ground goal, no constraints) that checks clean is read from the language engine's
    # tree in linear time; any other goes through unified-planning's reader, which words the errors too.
    problem = flat_problem(domain, domain_text, text)
    if problem is None:
        up_problem = _parse(domain_text, text, domain_name, problem_name)
        try:
            problem = problem_from_up(up_problem, domain)
        except InputError as error:  # a limit of the problem as a whole (its ground instances): no place in it
            raise InputError(f"{problem_name}: {error}") from None
    _refuse_reserved([o for o, _ in problem.objects], "object", text, problem_name, ":objects")
    _check_requirements(domain_text, domain, problem, domain_name)
    return domain, problem


def _refuse_reserved(names: list[str], what: str, text: str, name: str, section: str) -> None:
    """InputError at the first of ``names`` that is a word of PDDL (``and``, ``or``, ``not`` ...), placed
    where it is written (after ``section``, when given)."""
    reserved = next((n for n in names if is_reserved_name(n)), None)
    if reserved is None:
        return
    start = re.search(rf"\(\s*{re.escape(section)}\b", text, re.IGNORECASE) if section else None
    found = re.compile(rf"(?<![\w?-]){re.escape(reserved)}(?![\w-])", re.IGNORECASE).search(
        text, start.end() if start else 0
    )
    line = text.count("\n", 0, found.start()) + 1 if found else 0
    column = found.start() - text.rfind("\n", 0, found.start()) if found else 0
    where = f"{name}:{line}:{column}" if found else name
    raise InputError(f"{where}: {reserved_name_message(reserved, what)}")


def _check_requirements(domain_text: str, domain: Domain, problem: Problem, name: str) -> None:
    """Warn about requirements the files use but the domain does not declare (VAL warns too)."""
    match = re.search(r"\(\s*:requirements([^()]*)\)", domain_text, re.IGNORECASE)
    declared = set(match.group(1).lower().split()) if match else set()
    implied = {
        ":adl": {
            ":negative-preconditions",
            ":disjunctive-preconditions",
            ":equality",
            ":conditional-effects",
            ":existential-preconditions",
            ":universal-preconditions",
            ":quantified-preconditions",
        },
        ":quantified-preconditions": {":existential-preconditions", ":universal-preconditions"},
    }
    for word in list(declared):
        declared |= implied.get(word, set())
    needed = [r for r in domain.requirements() if r not in (":strips", ":typing", ":constraints")]
    if problem.constraints:
        needed.append(":constraints")
    missing = [r for r in needed if r not in declared]
    if missing:
        warn(
            f"{name}: the domain uses {', '.join(missing)} without declaring "
            f"{'it' if len(missing) == 1 else 'them'} in (:requirements ...)"
        )


def _parse(domain_text: str, problem_text: str | None, domain_name: str, problem_name: str | None) -> Any:
    from unified_planning.io import PDDLReader

    text, name = (problem_text, problem_name) if problem_text is not None else (domain_text, domain_name)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)  # pyparsing's notes about the reader's own calls
            return PDDLReader(environment()).parse_problem_string(domain_text, problem_text)
    except OverBudget:  # the budget of the whole read (the reading phase)
        raise
    except RecursionError:
        raise InputError(
            f"{name}: formulas nest too deeply for vslsp's reader; flatten them ((and a (and b c)) is (and a b c))"
        ) from None
    except InputError:
        raise
    except Exception as error:  # UP raises SyntaxError, pyparsing and UP exceptions alike
        raise located_error(error, text or "", name or "") from None
