"""The terminal side of ``vslsp shell``: line editing, the history file.

The history is kept in ``~/.vslsp_history`` and is the only file the shell writes in the home
folder. It is written here rather than with readline's ``write_history_file``, which writes a
temporary ``~/.vslsp_history-PID.tmp`` and renames it: a shell stopped between the two leaves
that file behind. Piped sessions (standard input not a terminal) neither read
nor write it.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

#: Lines of history kept in ``~/.vslsp_history``.
HISTORY_LINES = 1000


def history_file() -> Path:
    """``~/.vslsp_history`` (read when the shell starts, so that HOME may change in between)."""
    return Path.home() / ".vslsp_history"


def line_editing() -> Any:
    """The ``readline`` module (GNU readline or libedit), or None where Python has none."""
    try:
        import readline
    except ImportError:  # no line editing on this Python: plain input
        return None
    if "libedit" in (readline.__doc__ or ""):  # macOS: libedit does not read GNU's "tab: complete"
        readline.parse_and_bind("bind ^I rl_complete")
    return readline


def read_history(readline: Any) -> None:
    try:
        if history_file().exists():
            readline.read_history_file(history_file())
    except OSError:
        pass


def write_history(readline: Any) -> None:
    """The last :data:`HISTORY_LINES` lines typed, written in place (no temporary file)."""
    count = readline.get_current_history_length()
    lines = [readline.get_history_item(i) for i in range(max(1, count - HISTORY_LINES + 1), count + 1)]
    text = "".join(f"{line}\n" for line in lines if line).encode()
    try:
        descriptor = os.open(history_file(), os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)  # private, as readline's
        with os.fdopen(descriptor, "wb") as file:
            file.write(text)
    except OSError:
        pass
