"""``vslsp shell``: the interactive user interface to author a PDDL 3.0 domain and problem, plan and
validate (docs/shell.md); beside the language server (:mod:`vslsp.lsp`), the other user interface of
the symbolic layer, and standing on it alone.

- :mod:`~vslsp.shell.session`: the shell (:class:`Shell`, one ``do_NAME`` per command);
- :mod:`~vslsp.shell.commands`: the table of commands (help, usage, completion; imports nothing heavy);
- :mod:`~vslsp.shell.check`: what is typed, checked in the shell's words;
- :mod:`~vslsp.shell.complete`: tab completion;
- :mod:`~vslsp.shell.save`: saving a loaded file in place, only what changed rewritten;
- :mod:`~vslsp.shell.terminal`: line editing and the history file.

This ``__init__`` imports nothing, so that ``vslsp shell --help`` stays fast.
"""
