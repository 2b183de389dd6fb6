"""The Neovim set-up of docs/authoring.md ("Neovim 0.7 to 0.10"), run as written in the Neovim
that Debian installs (0.7.2; `apt-get install neovim`, done by tools/system-deps.sh as root):
headless, it starts `vslsp lsp` for a PDDL buffer, shows the server's diagnostics of a broken
domain, and `:PddlPlan` on a problem without a plan prints the server's answer with its reason."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from helpers.cli import REPO

NVIM = shutil.which("nvim")
pytestmark = pytest.mark.skipif(NVIM is None, reason="Neovim is not installed (apt-get install neovim)")
SORTING = REPO / "tests" / "data" / "sorting"


def documented_init() -> str:
    """The Lua block under the heading "Neovim 0.7 to 0.10" of docs/authoring.md."""
    text = (REPO / "docs" / "authoring.md").read_text()
    section = text.split("### Neovim 0.7 to 0.10", 1)[1]
    return re.search(r"```lua\n(.*?)```", section, re.S).group(1)


def nvim(folder: Path, file: str, probe: str) -> subprocess.CompletedProcess[str]:
    """Neovim headless in ``folder`` with the documented init.lua on ``file``, then ``probe`` (Lua);
    everything it writes stays in ``folder`` (its home, state and cache)."""
    (folder / "init.lua").write_text(documented_init())
    (folder / "probe.lua").write_text(probe)
    home = folder / "home"
    env = {
        **os.environ,
        "HOME": str(home),
        "XDG_CONFIG_HOME": str(home / "config"),
        "XDG_STATE_HOME": str(home / "state"),
        "XDG_CACHE_HOME": str(home / "cache"),
        "XDG_DATA_HOME": str(home / "data"),
        "PATH": os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")]),
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
    }
    command = [NVIM, "--headless", "-n", "-i", "NONE", "-u", "init.lua", "-c", "luafile probe.lua", file]
    return subprocess.run(command, cwd=folder, env=env, capture_output=True, text=True, timeout=300)


WAIT_FOR_DIAGNOSTICS = """
vim.wait(120000, function() return #vim.diagnostic.get(0) > 0 end, 100)
local lines = {}
for _, d in ipairs(vim.diagnostic.get(0)) do
  table.insert(lines, (d.lnum + 1) .. ":" .. (d.col + 1) .. ": " .. d.message)
end
vim.fn.writefile(lines, "said.txt")
vim.cmd("qa!")
"""

PLAN = """
vim.wait(120000, function()
  local clients = vim.lsp.get_active_clients()
  return #clients > 0 and clients[1].initialized
end, 100)
local said = {}
print = function(...) table.insert(said, table.concat(vim.tbl_map(tostring, { ... }), " ")) end
vim.cmd("PddlPlan")
vim.wait(120000, function() return #said > 0 end, 100)
vim.fn.writefile(said, "said.txt")
vim.cmd("qa!")
"""


def test_the_documented_set_up_shows_the_servers_diagnostics(tmp_path):
    broken = (SORTING / "domain.pddl").read_text().replace("(bin-colour ?b ?c))", "(bin-colour ?b ?c) (bogus ?i))")
    (tmp_path / "domain.pddl").write_text(broken)
    done = nvim(tmp_path, "domain.pddl", WAIT_FOR_DIAGNOSTICS)
    said = (tmp_path / "said.txt").read_text() if (tmp_path / "said.txt").exists() else ""
    assert "7:" in said and "unknown predicate 'bogus'" in said, done.stderr + said


def test_pddl_plan_prints_the_servers_answer_with_the_reason(tmp_path):
    for name in ("domain.pddl", "wrong-bin.pddl"):
        shutil.copy(SORTING / name, tmp_path / name)
    done = nvim(tmp_path, "wrong-bin.pddl", PLAN)
    said = (tmp_path / "said.txt").read_text() if (tmp_path / "said.txt").exists() else ""
    answer = json.loads(said.splitlines()[0]) if said else {}
    assert answer.get("exit_code") == 1, done.stderr + said
    assert [c["text"] for c in answer["conflict"]] == ["(in r1 green-bin)"]
    assert answer["reasons"][0].startswith("(in r1 green-bin) can never hold")
