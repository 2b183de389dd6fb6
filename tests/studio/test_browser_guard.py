"""A web page of another origin, opened in the same Chromium as the studio (with the studio's cookie
set), cannot make the studio save a file, ground with a predicates file, start a run, or open its
websocket: the forgeries of issue 40, sent as a real browser sends them."""

from __future__ import annotations

import http.server
import threading
from pathlib import Path

import pytest
from helpers.studio import CHROMIUM, TOKEN

pytestmark = pytest.mark.skipif(not Path(CHROMIUM).exists(), reason=f"no {CHROMIUM} (apt-get install chromium)")
pytest.importorskip("playwright.sync_api", reason="pip install playwright")

ATTACK = """<!doctype html><title>attacker</title><script>
const studio = %r;
window.outcome = (async () => {
  const said = [];
  const post = (path, body, type) => fetch(studio + path, {method: "POST", mode: "no-cors", credentials: "include",
    headers: {"content-type": type}, body}).then(() => said.push(path + " sent"), (e) => said.push(path + " " + e));
  await post("/api/save", JSON.stringify({path: "forged.pddl", text: "(define (domain forged))"}), "text/plain");
  await post("/api/save", JSON.stringify({path: "pred.py", text: "open('RAN','w')"}), "text/plain");
  await post("/api/ground", JSON.stringify({pre: "examples/grounding/pre.png", post: "examples/grounding/post.png",
    predicates: "pred.py"}), "text/plain");
  await post("/api/runs", JSON.stringify({experiment: "house-roof"}), "text/plain");
  const form = new FormData(); form.append("file", new Blob(["x"]), "x.png");
  await fetch(studio + "/api/upload", {method: "POST", mode: "no-cors", credentials: "include", body: form})
    .catch(() => {});
  said.push(await new Promise((resolve) => {
    const socket = new WebSocket(studio.replace("http", "ws") + "/_nicegui_ws/socket.io/?EIO=4&transport=websocket");
    socket.onopen = () => resolve("websocket opened");
    socket.onerror = () => resolve("websocket refused");
    socket.onclose = () => resolve("websocket refused");
    setTimeout(() => resolve("websocket silent"), 5000);
  }));
  return said;
})();
</script>"""


@pytest.fixture
def attacker(studio: str, tmp_path: Path):
    """A page on another port of the same host (the same site, another origin)."""
    (tmp_path / "attack").mkdir()
    (tmp_path / "attack" / "index.html").write_text(ATTACK % studio)

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, directory=str(tmp_path / "attack"), **kwargs)

        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Quiet)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    yield f"http://127.0.0.1:{server.server_address[1]}/index.html"
    server.shutdown()


def test_a_page_of_another_origin_cannot_save_ground_run_or_connect(page, studio, attacker, studio_root):
    page.goto(f"{studio}/author?token={TOKEN}")  # the user has the studio open: its cookie is set
    page.locator(".editor-domain .cm-content").wait_for()
    page.goto(attacker)
    said = page.evaluate("window.outcome")
    assert "/api/save sent" in said and "/api/runs sent" in said, said  # the requests went out, and were refused
    assert "websocket refused" in said or "websocket silent" in said, said
    assert not (studio_root / "forged.pddl").exists() and not (studio_root / "pred.py").exists()
    assert not (studio_root / "RAN").exists()
    assert not (studio_root / "out" / "studio" / "runs").exists()
    assert not (studio_root / "out" / "studio" / "uploads").exists()
    page.goto(f"{studio}/author")  # and the studio still serves its own page with the cookie
    page.locator(".editor-domain .cm-content").wait_for()
