"""The PDDL language engine: one fast, exact reader and checker for authoring PDDL 3.0, used by
``vslsp pddl check``, the shell and the language server (``vslsp lsp``).

Pure Python, no unified-planning (the planner path keeps :func:`vslsp.symbolic.read_pddl`); linear
in the size of the files. Paper: "Implementation" (the domain and problem files VSL-SP writes and
reads).

API (stable: fields are only added)
-----------------------------------
- :func:`analyse` ``(domain_text, domain_file="<domain>", problem_text=None, problem_file="<problem>")
  -> Analysis``: every error and warning of both files in one pass, and the index. Either text may
  hold the domain or the problem (the header decides).
- :func:`check_files` ``(domain_path, problem_path=None) -> Analysis``: the same on files, read within
  :data:`MAX_PDDL_BYTES` (UTF-8, regular files; otherwise :class:`~vslsp.errors.InputError`).
- :class:`Analysis`: ``diagnostics`` (sorted by file, line, column), ``errors``, ``warnings``,
  ``exit_code`` (2 with an error, else 0), ``index``, ``documents`` (file -> :class:`Document`),
  ``domain_name``, ``problem_name``, ``problem_domain`` (the problem's ``(:domain NAME)``),
  ``type_parents`` (type -> parent types),
  ``sections(file)`` (``":init"`` -> its :class:`Group`).
- :class:`Diagnostic`: ``span`` (:class:`Span`), ``file``, ``line``, ``column``, ``severity``
  (``"error"``/``"warning"``), ``message``, ``code`` (``unknown-predicate``, ``undefined-type``,
  ``duplicate``, ``unclosed-parenthesis``, ``arity``, ``argument-type``, ``unused-predicate``,
  ``undeclared-requirement`` ...), ``suggestion`` (the did-you-mean name or None), ``fixes``
  (:class:`Fix`: ``title``, ``span``, ``text``: replace the span by the text; an empty span inserts;
  the did-you-mean replacement first, then "declare predicate/type" insertions), ``format()``
  (``FILE:LINE:COL: error: message (did you mean 'x'?)``), ``to_dict()`` (the ``--json`` object).
- :class:`Span`: ``file``, ``line``, ``column``, ``end_line``, ``end_column``: 1-based, the end
  exclusive, in characters (an LSP range is each minus one).
- :class:`Index`: ``declarations``, ``references``, ``find(kind, name)``, ``names(kind)``,
  ``of_kind(kind)``, ``in_file(file)``, ``symbol_at(file, line, column)``, ``references_to(decl)``.
- :class:`Declaration`: ``kind`` (:data:`KINDS`: domain, problem, requirement, type, constant,
  predicate, function, action, object, parameter, variable), ``name``, ``span`` (the name),
  ``extent`` (the whole declaration), ``comment`` (the comment lines above it), ``parameters``
  (:class:`Parameter`: ``name``, ``types``, ``span``), ``types`` (an object's types, a type's
  parents), ``scope`` (where a parameter is visible), ``signature`` (for hover).
- :class:`Reference`: ``kind``, ``name``, ``span``, ``declaration`` (None when unknown).
- :class:`Document`: ``tokens`` (:class:`Token`: ``kind``, ``text``, ``key``, ``line``, ``column``,
  ``end_column``, ``offset``, ``span``), ``comments``, ``groups`` (:class:`Group`: ``open``,
  ``close``, ``items``, ``head``, ``key``, ``span``), ``comment_above(line)``.
- :func:`analyse_plan` ``(analysis, plan_text, plan_file="<plan>") -> PlanAnalysis``: a plan's steps
  checked against the analysis's domain and problem (unknown action or object with did-you-mean,
  arity, argument types); ``PlanAnalysis``: ``diagnostics``, ``references`` (actions and objects
  named, resolved), ``steps``.
- :func:`read_document` ``(text, file) -> Document``, :func:`closest` ``(name, candidates)``,
  :func:`text_of` ``(node)`` (normalised text), and the vocabulary: :data:`REQUIREMENTS`,
  :data:`PDDL3_NAMES`, :data:`GOAL_OPERATORS`, :data:`EFFECT_OPERATORS`.
- :data:`RESERVED_NAMES`, :func:`is_reserved_name` ``(name) -> bool``, :func:`reserved_name_message`
  ``(name, what) -> str``: the words of PDDL that cannot name an object, constant, type, predicate or
  action (``and``, ``or``, ``not``, ``forall`` ...; not ``at``, a common predicate), shared by every reader.
"""

from vslsp.symbolic.language.analysis import Analysis, analyse
from vslsp.symbolic.language.diagnostics import ERROR, WARNING, Diagnostic, Fix, Span, closest
from vslsp.symbolic.language.files import MAX_PDDL_BYTES, check_files, read_text
from vslsp.symbolic.language.index import KINDS, Declaration, Index, Parameter, Reference
from vslsp.symbolic.language.plans import PlanAnalysis, analyse_plan
from vslsp.symbolic.language.syntax import Document, Group, Token, read_document, text_of
from vslsp.symbolic.language.vocabulary import (
    EFFECT_OPERATORS,
    GOAL_OPERATORS,
    PDDL3_NAMES,
    REQUIREMENTS,
    RESERVED_NAMES,
    is_reserved_name,
    reserved_name_message,
)

__all__ = [
    "ERROR",
    "EFFECT_OPERATORS",
    "GOAL_OPERATORS",
    "KINDS",
    "MAX_PDDL_BYTES",
    "PDDL3_NAMES",
    "REQUIREMENTS",
    "RESERVED_NAMES",
    "WARNING",
    "Analysis",
    "Declaration",
    "Diagnostic",
    "Document",
    "Fix",
    "Group",
    "Index",
    "Parameter",
    "PlanAnalysis",
    "Reference",
    "Span",
    "Token",
    "analyse",
    "analyse_plan",
    "check_files",
    "closest",
    "is_reserved_name",
    "read_document",
    "read_text",
    "reserved_name_message",
    "text_of",
]
