"""What the browser tests share: Debian's Chromium, its flags, the waits, the token."""

from __future__ import annotations

import socket

CHROMIUM = "/usr/bin/chromium"
ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--no-first-run",
    "--disable-sync",
]
#: How long a page may take to show what a step did (the machine may be loaded; not a speed test).
WAIT_MS = 60_000
TOKEN = "a-token-for-the-browser-test"


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]
