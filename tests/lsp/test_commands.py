"""The commands vslsp.plan and vslsp.validate: the JSON of ``vslsp plan --json`` / ``vslsp validate --json``
on the editor's text (saved or not), the planner run off the server's event loop."""

import asyncio
import json
from pathlib import Path

import pytest
from helpers.cli import vslsp
from helpers.lsp import ident
from lsprotocol import types

from vslsp.lsp.workspace import uri_of

pytestmark = pytest.mark.asyncio(loop_scope="module")


async def _run(editor, command: str, *arguments: object) -> dict:
    return await editor.client.workspace_execute_command_async(
        types.ExecuteCommandParams(command=command, arguments=list(arguments))
    )


def _cli(capsys, *args: object) -> dict:
    _, out, _ = vslsp(capsys, *args, "--json")
    return json.loads(out)


def _without_time(result: dict) -> dict:
    return {k: v for k, v in result.items() if k != "time_s"}


async def test_the_server_announces_its_features_and_commands(editor):
    announced = editor.client.initialize_result.capabilities
    assert list(announced.execute_command_provider.commands) == ["vslsp.plan", "vslsp.validate"]
    assert {"(", "-", ":", "?"} <= set(announced.completion_provider.trigger_characters)
    assert announced.rename_provider.prepare_provider is True
    assert list(announced.code_action_provider.code_action_kinds) == [types.CodeActionKind.QuickFix]
    for feature in ("hover_provider", "definition_provider", "references_provider", "document_symbol_provider"):
        assert getattr(announced, feature)
    assert editor.client.initialize_result.server_info.name == "vslsp"


async def test_plan_gives_the_cli_s_json_and_finds_the_domain(editor, workspace: Path, capsys):
    shipped = workspace / "shipped"
    domain, problem = shipped / "domain.pddl", shipped / "pull-in-order.pddl"
    await editor.open(problem)
    result = await _run(editor, "vslsp.plan", uri_of(problem))  # the domain found by (:domain vsl-sp)
    expected = _cli(capsys, "plan", domain, problem)
    assert list(result) == list(expected)
    assert _without_time(result) == _without_time(expected)
    assert result["plan"] == ["pull orange", "pull green", "pull yellow"]
    # the domain given, as paths, options in one object
    options = {"compilation": "ground", "timeout": 120, "memory": 2048}
    result = await _run(editor, "vslsp.plan", {"domain": str(domain), "problem": str(problem), **options})
    expected = _cli(capsys, "plan", domain, problem, "--compilation", "ground", "--timeout", 120, "--memory", 2048)
    assert _without_time(result) == _without_time(expected) and result["compilation"] == "ground"
    await editor.close(problem)


async def test_without_arguments_the_last_problem_and_plan_and_the_user_is_told(editor, workspace: Path):
    kitchen = workspace / "kitchen"
    await editor.open(kitchen / "problem.pddl")
    editor.client.messages.clear()
    result = await _run(editor, "vslsp.plan")
    assert len(result["plan"]) == 6
    (told,) = editor.client.messages
    assert told.type == types.MessageType.Info
    assert (
        told.message.startswith("vslsp.plan: 6 steps (fast-downward, ")
        and "1. pick saucer; 2. wash saucer" in told.message
    )
    plan = kitchen / "unfinished.plan"
    await editor.open(plan, "(pick saucer)\n(wash saucer)\n", language="plan")
    result = await _run(editor, "vslsp.validate")
    assert result["valid"] is False and "goal" in result["reason"]
    assert editor.client.messages[-1].type == types.MessageType.Warning
    told = editor.client.messages[-1].message
    assert told.startswith("vslsp.validate: invalid: ")  # every violation, with its line
    assert all(f"{v['message']} (line {v['line']})" in told for v in result["violations"])
    await editor.close(plan)
    await editor.close(kitchen / "problem.pddl")


async def test_plan_reads_the_unsaved_text_of_open_documents(editor, workspace: Path):
    problem = workspace / "kitchen" / "problem.pddl"
    only_the_mug = problem.read_text().replace(
        "(:goal (and (clean mug) (clean saucer) (on-counter mug) (on-counter saucer)))", "(:goal (clean mug))"
    )
    await editor.open(problem, only_the_mug.replace("(:constraints (sometime-before (clean mug) (clean saucer)))", ""))
    result = await _run(editor, "vslsp.plan", uri_of(problem))
    assert result["plan"] == ["pick mug", "wash mug"] and result["warnings"] == []
    # an unsaved mistake is told at the document's own path (the command read a private copy)
    await editor.replace(problem, problem.read_text().replace("(:goal (and (clean mug)", "(:goal (and (clean cup1)"))
    result = await _run(editor, "vslsp.plan", uri_of(problem))
    assert result["plan"] is None and result["exit_code"] == 2
    assert result["error"].startswith(f"{problem}:7:") and "cup1" in result["error"]
    await editor.close(problem)


async def test_a_bad_problem_gets_the_cli_s_error_object(editor, workspace: Path, tmp_path: Path, capsys):
    shipped = workspace / "shipped"
    broken = tmp_path / "broken.pddl"
    broken.write_text((shipped / "pull-in-order.pddl").read_text().replace("(far orange)", "(far orange", 1))
    result = await _run(editor, "vslsp.plan", uri_of(shipped / "domain.pddl"), uri_of(broken))
    assert result == _cli(capsys, "plan", shipped / "domain.pddl", broken)
    assert result["plan"] is None and result["exit_code"] == 2 and str(broken) in result["error"]
    lonely = tmp_path / "lonely.pddl"
    lonely.write_text(broken.read_text().replace("(:domain vsl-sp)", "(:domain elsewhere)"))
    result = await _run(editor, "vslsp.plan", str(lonely))
    assert result["exit_code"] == 2 and "no domain 'elsewhere'" in result["error"]


async def test_validate_gives_the_cli_s_json_for_a_plan_document(editor, workspace: Path, capsys):
    kitchen = workspace / "kitchen"
    domain, problem, plan = kitchen / "domain.pddl", kitchen / "problem.pddl", kitchen / "tidy.plan"
    steps = ["pick saucer", "wash saucer", "put-down saucer", "pick mug", "wash mug", "put-down mug"]
    plan.write_text("".join(f"({step})\n" for step in steps))
    await editor.open(plan, language="plan")
    await editor.open(problem)
    result = await _run(editor, "vslsp.validate", uri_of(problem), uri_of(plan))
    assert result == _cli(capsys, "validate", domain, problem, plan)
    assert result["valid"] is True
    # the mug washed first breaks (sometime-before (clean mug) (clean saucer)): the open, unsaved plan
    await editor.replace(plan, "".join(f"({step})\n" for step in steps[3:] + steps[:3]))
    result = await _run(editor, "vslsp.validate", {"problem": str(problem), "plan": uri_of(plan)})
    plan.write_text(editor.texts[uri_of(plan)])
    assert result == _cli(capsys, "validate", domain, problem, plan)
    assert result["valid"] is False and "sometime-before" in result["reason"]
    # the broken constraint is shown where the problem states it
    (shown,) = await editor.diagnostics(uri_of(problem))
    assert (shown.code, shown.range.start.line, shown.severity) == ("violation", 7, types.DiagnosticSeverity.Warning)
    assert shown.message == result["violations"][0]["message"]
    await editor.close(problem)
    await editor.close(plan)


async def test_the_server_answers_while_the_planner_runs(editor, workspace: Path):
    shipped = workspace / "shipped"
    domain, problem = shipped / "domain.pddl", shipped / "keep-all-near.pddl"
    await editor.open(domain)
    planning = asyncio.ensure_future(_run(editor, "vslsp.plan", uri_of(problem)))
    await asyncio.sleep(0)  # the request is on its way
    at = editor.position_of(domain, "(far ?b)", occurrence=2, offset=1)
    shown = await editor.client.text_document_hover_async(types.HoverParams(ident(domain), at))
    assert "(far ?b - block)" in shown.contents.value
    assert not planning.done()  # the hover was answered while Fast Downward was still at work
    result = await planning
    assert result["plan"] is not None
    await editor.close(domain)


@pytest.mark.slow
async def test_no_plan_names_the_conflict_as_the_cli_does(editor, workspace: Path, capsys):
    kitchen = workspace / "kitchen"
    never = kitchen / "never-clean.pddl"
    never.write_text(
        (kitchen / "problem.pddl")
        .read_text()
        .replace("(define (problem tidy-up)", "(define (problem never-clean)")
        .replace(
            "(:constraints (sometime-before (clean mug) (clean saucer)))", "(:constraints (always (not (clean mug))))"
        )
    )
    await editor.open(never)
    editor.client.messages.clear()
    result = await _run(editor, "vslsp.plan", uri_of(never))
    assert result == _cli(capsys, "plan", kitchen / "domain.pddl", never)
    assert result["exit_code"] == 1 and result["conflict_minimal"] is True
    assert [(c["kind"], c["text"], c["line"]) for c in result["conflict"]] == [
        ("goal", "(clean mug)", 7),
        ("constraint", "(always (not (clean mug)))", 8),
    ]
    (told,) = editor.client.messages
    assert told.type == types.MessageType.Warning
    assert told.message.endswith("these cannot all hold: (clean mug) (line 7); (always (not (clean mug))) (line 8)")
    # the conflict is shown in the problem, each formula's whole extent, until the next edit
    shown = await editor.diagnostics(uri_of(never))
    assert [(d.code, d.range.start.line, d.range.start.character, d.range.end.character) for d in shown] == [
        ("conflict", 6, 14, 25),
        ("conflict", 7, 16, 42),
    ]
    assert shown[1].message == "no plan: this constraint cannot hold together with (clean mug)"
    assert await editor.replace(never, editor.texts[uri_of(never)] + "\n") == []
    await editor.close(never)
