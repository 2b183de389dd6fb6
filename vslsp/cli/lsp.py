"""``vslsp lsp``: the PDDL language server on stdin/stdout, for any editor (``docs/authoring.md``)."""

from __future__ import annotations

import click


@click.command(context_settings={"help_option_names": ["-h", "--help"]})
@click.option(
    "--stdio", is_flag=True, help="Talk over stdin/stdout (the only transport; accepted because clients pass it)."
)
def lsp(stdio: bool) -> None:
    """Run the PDDL language server (LSP 3.17) over stdin/stdout until the editor closes it.

    Editors start it themselves: configure the command `vslsp lsp` for PDDL files (`*.pddl`) and
    plans (`*.plan`). It gives diagnostics as you type, completion, hover, go to definition, find
    references, rename, the outline, quick fixes and the commands vslsp.plan and vslsp.validate.
    The exact settings for VS Code, Neovim, Helix and Emacs are in docs/authoring.md. Logs go to
    stderr; stdout carries only the protocol.
    """
    from vslsp.lsp.server import serve

    serve()
