"""One analysis of a domain and (optionally) its problem: read, declare, check every formula, warn
about what is declared and never used or used and never declared; everything in one pass."""

from __future__ import annotations

from dataclasses import dataclass, field

from vslsp.symbolic.budget import recursion_room
from vslsp.symbolic.language.context import Context
from vslsp.symbolic.language.declarations import (
    Body,
    action,
    constants,
    define_header,
    predicates,
    requirements,
    sections,
    types,
)
from vslsp.symbolic.language.diagnostics import Diagnostic, sort_key
from vslsp.symbolic.language.durative import TIMED_ROLES, check_timed, durative_action
from vslsp.symbolic.language.formulas import check_body
from vslsp.symbolic.language.index import Declaration, Index
from vslsp.symbolic.language.syntax import Document, Group, gc_paused, read_document
from vslsp.symbolic.language.vocabulary import DOMAIN_SECTIONS, PROBLEM_SECTIONS

#: Requirements every planner assumes, never worth a warning.
_ASSUMED = (":strips",)


@dataclass
class Analysis:
    """The result of :func:`analyse`: every diagnostic (sorted by file and place), the declaration
    index, and the documents read (tokens and tree, for a language server's context questions)."""

    diagnostics: list[Diagnostic]
    index: Index
    documents: dict[str, Document] = field(default_factory=dict)
    domain_name: str | None = None
    problem_name: str | None = None
    #: the problem's (:domain NAME), for a server that looks for the domain among open files
    problem_domain: str | None = None
    #: type -> its parent types, lower case (what a type written twice last said)
    type_parents: dict[str, tuple[str, ...]] = field(default_factory=dict)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.is_error]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if not d.is_error]

    @property
    def exit_code(self) -> int:
        """2 with any error, else 0 (the exit code of ``vslsp pddl check``)."""
        return 2 if self.errors else 0

    def sections(self, file: str) -> dict[str, Group]:
        """The first ``(:section ...)`` list of each kind in ``file`` (``:action`` lists: see the index)."""
        found: dict[str, Group] = {}
        document = self.documents.get(file)
        if document is None or not document.groups:
            return found
        for item in document.groups[0].items[2:]:
            if isinstance(item, Group) and item.key.startswith(":"):
                found.setdefault(item.key, item)
        return found


def analyse(
    domain_text: str | None,
    domain_file: str = "<domain>",
    problem_text: str | None = None,
    problem_file: str = "<problem>",
) -> Analysis:
    """Check a domain and, optionally, a problem: all errors and warnings of both files, each at the
    token written, and the index of declarations and references. Either text may hold a domain or a
    problem (the ``(define (domain|problem ...))`` header decides); a problem without its domain is
    checked for its syntax and sections only."""
    with gc_paused(), recursion_room():  # the checks recurse once or twice per level (at most MAX_NESTING)
        return _analyse(domain_text, domain_file, problem_text, problem_file)


def _analyse(domain_text: str | None, domain_file: str, problem_text: str | None, problem_file: str) -> Analysis:
    ctx = Context()
    documents: dict[str, Document] = {}
    domain: tuple[Document, Group, str] | None = None
    problem: tuple[Document, Group, str] | None = None
    for text, file in ((domain_text, domain_file), (problem_text, problem_file)):
        if text is None:
            continue
        document = read_document(text, file)
        documents[file] = document
        ctx.diagnostics.extend(document.diagnostics)
        define, kind, name = define_header(ctx, document)
        if define is None or not kind:
            continue
        entry = (document, define, name.text if name is not None else "")
        if name is not None:
            ctx.index.declare(
                Declaration(kind, name.text, name.span, define.span, document.comment_above(define.open.line))
            )
        if kind == "domain" and domain is None:
            domain = entry
        elif kind == "problem" and problem is None:
            problem = entry
        else:
            ctx.error(define.span, f"two {kind} files given; give a domain and a problem", "two-of-a-kind")
    analysis = Analysis(ctx.diagnostics, ctx.index, documents, type_parents=ctx.parents)
    bodies: list[Body] = []
    if domain is not None:
        analysis.domain_name = domain[2]
        bodies.extend(_read_domain(ctx, *domain[:2]))
    if problem is not None:
        analysis.problem_name = problem[2]
        ctx.in_problem = True
        bodies_problem, analysis.problem_domain = _read_problem(ctx, problem[0], problem[1], domain is not None)
        if domain is not None:
            bodies.extend(bodies_problem)
            if analysis.problem_domain and analysis.problem_domain.lower() != domain[2].lower():
                section = analysis.sections(problem[0].file).get(":domain")
                at = section.items[1].span if section is not None and len(section.items) > 1 else problem[1].open.span
                ctx.error(
                    at,
                    f"the problem is for domain '{analysis.problem_domain}', but the domain file defines "
                    f"'{domain[2]}'; give the domain file of '{analysis.problem_domain}', or write "
                    f"(:domain {domain[2]}) in the problem",
                    "other-domain",
                )
    for body in bodies:
        ctx.in_problem = (
            body.role in ("init", "goal", "constraints", "metric")
            and problem is not None
            and body.owner.open.file == problem[0].file
        )
        (check_timed if body.role in TIMED_ROLES else check_body)(ctx, body)
    if domain is not None:
        _unused(ctx, problem is not None)
        _requirements(ctx, domain[1])
    ctx.diagnostics.sort(key=sort_key)
    return analysis


def _read_domain(ctx: Context, document: Document, define: Group) -> list[Body]:
    found = sections(ctx, define, DOMAIN_SECTIONS, "domain")
    header = define.items[1]
    if isinstance(header, Group) and header.close is not None:
        ctx.header_end["domain"] = header.span
    for section in found:
        if section.key in (":requirements", ":types", ":constants") and section.close is not None:
            ctx.header_end.setdefault(section.key, section.span)
    order = {":requirements": 0, ":types": 1, ":constants": 2, ":predicates": 2, ":functions": 2}
    bodies: list[Body] = []
    for section in sorted(found, key=lambda s: order.get(s.key, 3)):  # types before what uses them
        key = section.key
        if key == ":requirements":
            requirements(ctx, section, document)
        elif key == ":types":
            types(ctx, section, document)
        elif key == ":constants":
            constants(ctx, section, document, "constant")
        elif key == ":predicates":
            predicates(ctx, section, document)
        elif key == ":functions":
            predicates(ctx, section, document, "function")
        elif key == ":action":
            bodies.extend(action(ctx, section, document))
        elif key == ":constraints":
            for item in section.items[1:]:
                bodies.append(Body("constraints", item, {}, section))
        elif key == ":durative-action":
            bodies.extend(durative_action(ctx, section, document))
        else:
            head = section.head
            assert head is not None
            ctx.error(
                head.span,
                "derived predicates (:derived ...) are not supported; write the formula where it is used "
                "(vslsp reads STRIPS with types, negation, equality, quantifiers, conditional effects, "
                "constants, PDDL 3.0 constraints, numeric fluents and durative actions)",
                "unsupported",
            )
    return bodies


def _read_problem(ctx: Context, document: Document, define: Group, with_domain: bool) -> tuple[list[Body], str | None]:
    found = sections(ctx, define, PROBLEM_SECTIONS, "problem")
    bodies: list[Body] = []
    domain_name: str | None = None
    has_goal = False
    for section in sorted(found, key=lambda s: 0 if s.key == ":objects" else 1):
        key = section.key
        if key == ":domain":
            name = section.items[1] if len(section.items) > 1 else None
            if name is None or isinstance(name, Group):
                ctx.error(section.span, "(:domain NAME) names the problem's domain", "bad-section")
            else:
                domain_name = name.text
                ctx.index.refer("domain", name.text, name.span, ctx.index.find("domain", name.key))
        elif key == ":requirements":
            requirements(ctx, section, document)
        elif key == ":objects":
            constants(ctx, section, document, "object", with_types=with_domain)
        elif key == ":init":
            bodies.append(Body("init", section, {}, section))
        elif key in (":goal", ":constraints", ":metric"):
            has_goal = has_goal or key == ":goal"
            items = section.items[1:]
            if key == ":metric":
                direction = items[0] if items else None
                if direction is None or isinstance(direction, Group) or direction.key not in ("minimize", "maximize"):
                    ctx.error(section.span, "(:metric minimize|maximize EXPRESSION)", "bad-metric")
                items = items[1:]
            elif key == ":constraints" and len(items) > 1:
                ctx.warning(
                    section.span,
                    f"(:constraints ...) lists {len(items)} constraints without (and ...); read "
                    "as their conjunction (VAL drops such constraints)",
                    "constraints-without-and",
                )
            elif len(items) != 1:
                ctx.error(section.span, f"({key} ...) takes one formula; join several with (and ...)", "bad-section")
            for item in items:
                bodies.append(Body(key[1:] if key != ":goal" else "goal", item, {}, section))
    if not has_goal and with_domain:
        ctx.error(define.open.span, "the problem has no (:goal ...) section", "no-goal")
    return bodies, domain_name


def _unused(ctx: Context, with_problem: bool) -> None:
    """Warn about predicates and types declared in the domain and used nowhere."""
    used = {id(r.declaration) for r in ctx.index.references if r.declaration is not None}
    for kind in ("predicate", "type"):
        for declaration in ctx.index.of_kind(kind):
            if id(declaration) in used:
                continue
            if kind == "type" and any(id(d) in used for d in ctx.index.of_kind("type") if d.key == declaration.key):
                continue
            where = "in the domain or the problem" if with_problem else "in the domain"
            ctx.warning(
                declaration.span, f"{kind} '{declaration.name}' is declared but never used {where}", f"unused-{kind}"
            )


def _requirements(ctx: Context, define: Group) -> None:
    """Warn, at the first use, about each requirement the files use and do not declare."""
    declared = ctx.declared_requirements
    for requirement, span in ctx.used.items():
        if requirement in declared or requirement in _ASSUMED:
            continue
        ctx.warning(
            span,
            f"this needs {requirement}, which the domain does not declare in (:requirements ...)",
            "undeclared-requirement",
        )
