"""What the studio's tests share: the JSON API in process (FastAPI's TestClient) and the shipped
PDDL it serves; for the browser tests, Debian's Chromium, its flags, the waits, the token."""

from __future__ import annotations

import socket
from pathlib import Path
from typing import Any

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


DOMAIN = "pddl/domain.pddl"
PROBLEM = "pddl/pull-in-order.pddl"


def client(root: Path, token: str = TOKEN, *, send_token: bool = True, **settings: Any) -> Any:
    """The studio's API on ``root`` behind its guard (``token`` the session's secret, sent as
    ``Authorization: Bearer`` unless ``send_token`` is false), in this process: a FastAPI TestClient
    (imported here: the browser tests' fixtures need no FastAPI). Its Host is ``testserver``."""
    from fastapi import FastAPI
    from fastapi.testclient import TestClient

    from vslsp.studio import api
    from vslsp.studio.guard import Access
    from vslsp.studio.settings import Settings

    app = FastAPI()
    api.install(app, root, Access(token=token, hosts=frozenset({"testserver"})), Settings(**settings))
    headers = {"authorization": f"Bearer {token}"} if send_token else {}
    return TestClient(app, headers=headers)
