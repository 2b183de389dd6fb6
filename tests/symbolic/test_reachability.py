"""Why a goal conjunct can never hold (relaxed reachability) on a sorting domain: the actions that
could add it and the precondition that never holds, in `vslsp plan` (text and JSON), the shell's
`why`, and the language server's message; the deletes named as the cause when the relaxation
reaches every atom; no "under the constraints" for a problem without constraints."""

import json
from pathlib import Path

from helpers.cli import vslsp, vslsp_process

from vslsp.lsp.commands import findings, told
from vslsp.symbolic import read_pddl
from vslsp.symbolic.validation.conflict import explain
from vslsp.symbolic.validation.reachability import relaxed_reach

SORTING = Path(__file__).resolve().parents[1] / "data" / "sorting"
DOMAIN, WRONG_BIN, SWAP = SORTING / "domain.pddl", SORTING / "wrong-bin.pddl", SORTING / "swap.pddl"
REASON = (
    "(in r1 green-bin) can never hold: the 2 actions that would make it true cannot run: "
    "(sort r1 green-bin red) needs (bin-colour green-bin red), which no action changes and is not true initially "
    "((bin-colour green-bin green) is); (sort r1 green-bin green) needs (colour-of r1 green), which no action "
    "changes and is not true initially ((colour-of r1 red) is)"
)


def test_plan_says_why_a_red_item_never_gets_into_the_green_bin(capsys):
    code, _, err = vslsp(capsys, "plan", DOMAIN, WRONG_BIN)
    assert code == 1
    assert "no plan: the goal cannot be reached from the initial state (proved by Fast Downward)" in err
    assert "under the constraints" not in err
    assert f"wrong-bin.pddl:5:33: goal (in r1 green-bin)\n  because: {REASON}" in err
    code, out, _ = vslsp(capsys, "plan", DOMAIN, WRONG_BIN, "--json")
    data = json.loads(out)
    assert code == 1 and data["reasons"] == [REASON] and [c["text"] for c in data["conflict"]] == ["(in r1 green-bin)"]


def test_when_every_atom_is_reachable_the_deletes_are_named_as_the_cause():
    domain, problem = read_pddl(DOMAIN, SWAP)
    conflict = explain(domain, problem)
    assert conflict is not None and conflict.without_constraints
    assert conflict.reasons(domain, problem) == [
        "each of these goal atoms can be made true on its own, but no sequence of actions makes them hold "
        "together (an action needed for one undoes another)"
    ]
    reach = relaxed_reach(domain, problem)
    assert reach is not None
    assert {a.to_pddl() for a in reach.reached} >= {"(in r1 red-bin)", "(in r1 green-bin)", "(on-table r1)"}


def test_the_shell_why_and_the_language_server_give_the_reason():
    done = vslsp_process("shell", DOMAIN, WRONG_BIN, input="why\nquit\n", timeout=300)
    assert f"  goal: (in r1 green-bin)\n  because: {REASON}\n" in done.stdout
    result = json.loads(vslsp_process("plan", DOMAIN, WRONG_BIN, "--json").stdout)
    assert told("vslsp.plan", result).message.endswith(f"; because: {REASON}")
    diagnostics = findings(result, lambda uri: WRONG_BIN.read_text())
    (message,) = [d.message for found in diagnostics.values() for d in found]
    assert message == f"no plan: this goal cannot hold together with the rest; {REASON}"
