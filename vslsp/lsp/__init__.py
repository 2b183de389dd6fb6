"""The PDDL language server (``vslsp lsp``, LSP 3.17 over stdio): diagnostics as you type, completion
in context, hover, go to definition, references, rename, the outline, quick fixes and the commands
``vslsp.plan`` / ``vslsp.validate``, all on the language engine :mod:`vslsp.symbolic.language`
(docs/authoring.md). Paper: "Implementation" (the PDDL 3.0 domain and problem files of VSL-SP).

Modules: :mod:`~vslsp.lsp.workspace` (open documents and the files beside them),
:mod:`~vslsp.lsp.analysis` (the engine's analysis per document), :mod:`~vslsp.lsp.context` (where the
cursor is), :mod:`~vslsp.lsp.completion`, :mod:`~vslsp.lsp.navigation`, :mod:`~vslsp.lsp.fixes`,
:mod:`~vslsp.lsp.operators` (the PDDL 3.0 operators' meanings), :mod:`~vslsp.lsp.commands` (plan and
validate: the CLI itself), :mod:`~vslsp.lsp.rpc` (the base protocol's frames on stdin),
:mod:`~vslsp.lsp.protocol` (JSON-RPC 2.0 and the LSP lifecycle: error codes, exit code),
:mod:`~vslsp.lsp.server` (pygls wiring).
Nothing is imported here: ``vslsp lsp`` loads the server only when it starts.
"""
