"""``vslsp lsp`` as a command: its help says how editors start it, and the server loads nothing heavy
(no planner, simulator, vision or torch) until a command asks for the planner."""

import json
import subprocess
import sys

from helpers.cli import vslsp, vslsp_process


def test_help_says_how_editors_start_it(capsys):
    code, out, _ = vslsp(capsys, "lsp", "--help")
    assert code == 0
    assert "vslsp lsp" in out and "docs/authoring.md" in out and "--stdio" in out
    code, out, _ = vslsp(capsys, "--help")
    assert "lsp" in out.split()


def test_the_server_imports_nothing_heavy():
    heavy = ("unified_planning", "torch", "pybullet", "cv2", "scipy")
    probe = (
        "import json, sys; import vslsp.lsp.server as s; s.build_server(); "
        f"print(json.dumps(sorted(m for m in {heavy!r} if m in sys.modules)))"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert json.loads(done.stdout) == []


def test_a_client_that_closes_stdin_ends_the_server():
    done = vslsp_process("lsp", "--stdio", input="", timeout=60)
    assert done.returncode == 0
    assert "Traceback" not in done.stderr
