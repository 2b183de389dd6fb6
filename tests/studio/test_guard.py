"""The studio's guard (docs/studio.md, "Threat model"): what a web page the user visits, a rebound DNS
name or a careless client can send is refused before it does anything; the studio's own requests pass."""

from __future__ import annotations

import pytest
from helpers.events import wait_until
from helpers.studio import DOMAIN, TOKEN, client

from vslsp.studio.guard import Access, Guard

PORT = 8765
OWN = f"http://127.0.0.1:{PORT}"


def served(root, **access):
    """The API behind a guard bound to 127.0.0.1:PORT (as ``vslsp studio`` binds it), no token sent."""
    from fastapi import FastAPI
    from fastapi.testclient import TestClient

    from vslsp.studio import api

    app = FastAPI()
    api.install(app, root, Access(token=TOKEN, port=PORT, **access))
    return TestClient(app, base_url=OWN)


BEARER = {"authorization": f"Bearer {TOKEN}"}
SAVE = {"path": "evil.pddl", "text": "(define (domain evil))"}


def test_a_no_cors_text_plain_save_from_another_page_writes_nothing(studio_root):
    web = served(studio_root)
    web.cookies.set("vslsp_studio_8765", TOKEN)  # even with the cookie the browser adds
    for origin in ("http://attacker.example", f"http://127.0.0.1:{PORT + 1}", "null"):
        answer = web.post(
            "/api/save",
            content=b'{"path": "x.pddl", "text": "t"}',
            headers={"content-type": "text/plain", "origin": origin},
        )
        assert answer.status_code == 403 and answer.json()["exit_code"] == 2
    assert not (studio_root / "x.pddl").exists()


@pytest.mark.parametrize("kind", ["text/plain", "application/x-www-form-urlencoded", "multipart/form-data", ""])
def test_api_writes_take_json_only(studio_root, kind):
    web = served(studio_root)
    answer = web.post("/api/save", content=b'{"path": "x.pddl", "text": "t"}', headers={**BEARER, "content-type": kind})
    assert answer.status_code == 415 and "application/json" in answer.json()["error"]
    assert not (studio_root / "x.pddl").exists()


def test_the_cookie_alone_does_not_let_a_write_through(studio_root):
    web = served(studio_root)
    web.cookies.set("vslsp_studio_8765", TOKEN)
    assert web.post("/api/save", json=SAVE).status_code == 401  # same origin, but no header token
    assert web.post("/api/save", json=SAVE, headers={"origin": OWN}).status_code == 401
    assert web.post("/api/save", json=SAVE, headers={**BEARER, "origin": OWN}).status_code == 200


@pytest.mark.parametrize(
    "host",
    [
        f"attacker.example:{PORT}",
        "attacker.example",
        f"127.0.0.1.nip.io:{PORT}",
        f"localhost.attacker.example:{PORT}",
        f"127.0.0.1:{PORT + 1}",
        "",
        "a b",
        f"user@127.0.0.1:{PORT}",
    ],
)
def test_dns_rebinding_hosts_are_refused_for_reading_and_writing(studio_root, host):
    web = served(studio_root)
    for response in (
        web.get(f"/files/{DOMAIN}", headers={**BEARER, "host": host}),
        web.post("/api/save", json=SAVE, headers={**BEARER, "host": host}),
    ):
        assert response.status_code == 403 and response.json()["exit_code"] == 2
    assert not (studio_root / "evil.pddl").exists()


@pytest.mark.parametrize(
    "host",
    [f"127.0.0.1:{PORT}", f"localhost:{PORT}", f"[::1]:{PORT}", f"[0:0:0:0:0:0:0:1]:{PORT}", f"127.0.0.2:{PORT}"],
)
def test_loopback_hosts_in_every_form_are_served(studio_root, host):
    assert served(studio_root).get(f"/files/{DOMAIN}", headers={**BEARER, "host": host}).status_code == 200


def test_allowed_names_and_a_wildcard_bind(studio_root):
    named = served(studio_root, hosts=frozenset({"studio.lab"}))
    assert named.get(f"/files/{DOMAIN}", headers={**BEARER, "host": f"studio.lab:{PORT}"}).status_code == 200
    wildcard = served(studio_root, bound="0.0.0.0")
    assert wildcard.get(f"/files/{DOMAIN}", headers={**BEARER, "host": f"192.168.7.9:{PORT}"}).status_code == 200
    assert wildcard.get(f"/files/{DOMAIN}", headers={**BEARER, "host": f"evil.example:{PORT}"}).status_code == 403


def test_the_secret_is_needed_even_on_loopback_and_only_as_bearer(studio_root):
    web = served(studio_root)
    assert web.get(f"/files/{DOMAIN}").status_code == 401
    assert web.get(f"/files/{DOMAIN}", headers={"authorization": TOKEN}).status_code == 401
    assert web.get(f"/files/{DOMAIN}", headers={"authorization": f"Basic {TOKEN}"}).status_code == 401
    assert web.get(f"/files/{DOMAIN}", headers={"x-vslsp-token": TOKEN + "x"}).status_code == 401
    assert web.get(f"/files/{DOMAIN}", headers={"x-vslsp-token": TOKEN}).status_code == 200


def test_opening_the_printed_address_sets_the_cookie_and_drops_the_token(studio_root):
    web = served(studio_root)
    opened = web.get(f"/files/{DOMAIN}?token={TOKEN}&x=1", headers={"accept": "text/html"}, follow_redirects=False)
    assert opened.status_code == 303 and opened.headers["location"] == f"/files/{DOMAIN}?x=1"
    cookie = opened.headers["set-cookie"]
    assert "HttpOnly" in cookie and "SameSite=Strict" in cookie and cookie.startswith(f"vslsp_studio_{PORT}=")
    assert web.get(f"/files/{DOMAIN}").status_code == 200


def test_a_cross_site_fetch_is_refused_even_with_the_cookie(studio_root):
    web = served(studio_root)
    web.cookies.set("vslsp_studio_8765", TOKEN)
    assert web.get("/api/experiments", headers={"sec-fetch-site": "same-site"}).status_code == 403
    assert web.get("/api/experiments", headers={"sec-fetch-site": "same-origin"}).status_code == 200


def test_a_websocket_from_another_origin_is_closed(studio_root):
    from starlette.testclient import WebSocketDenialResponse
    from starlette.websockets import WebSocketDisconnect

    web = served(studio_root)
    web.cookies.set("vslsp_studio_8765", TOKEN)
    for origin in ("http://attacker.example", f"http://localhost:{PORT + 1}", "null"):
        with pytest.raises((WebSocketDisconnect, WebSocketDenialResponse)):
            with web.websocket_connect("/_nicegui_ws/socket.io/?EIO=4&transport=websocket", headers={"origin": origin}):
                pass


async def _asgi_refusal(scope, body_chunks):
    """Drive the guard directly: the status of its answer and whether the app read past the limit."""
    reached = {"app": False}

    async def app(scope, receive, send):
        reached["app"] = True
        while (await receive()).get("more_body"):
            pass
        await send({"type": "http.response.start", "status": 200, "headers": []})
        await send({"type": "http.response.body", "body": b"{}"})

    chunks = iter(body_chunks)
    sent = []

    async def receive():
        chunk = next(chunks, None)
        return {"type": "http.request", "body": chunk or b"", "more_body": chunk is not None}

    async def send(message):
        sent.append(message)

    guard = Guard(app, Access(token=TOKEN, port=PORT))
    try:
        await guard(scope, receive, send)
    except Exception as error:  # the API's handler turns it into 413; here the app is bare
        return type(error).__name__, reached["app"]
    return sent[0]["status"], reached["app"]


def _scope(headers):
    base = [(b"host", f"127.0.0.1:{PORT}".encode()), (b"authorization", f"Bearer {TOKEN}".encode())]
    return {
        "type": "http",
        "method": "POST",
        "path": "/api/check",
        "query_string": b"",
        "headers": base + [(b"content-type", b"application/json")] + headers,
    }


@pytest.mark.asyncio
async def test_a_declared_huge_body_is_refused_before_it_is_read():
    status, reached = await _asgi_refusal(_scope([(b"content-length", b"104857600")]), [b"x" * 10])
    assert status == 413 and not reached


@pytest.mark.asyncio
async def test_a_chunked_body_is_cut_at_its_limit_while_read():
    chunk = b"x" * (1024 * 1024)
    status, reached = await _asgi_refusal(_scope([]), [chunk] * 100)
    assert status == "TooLarge" and reached


def test_a_chunked_body_over_the_limit_is_413_through_the_api(studio_root):
    web = client(studio_root)

    def stream():
        for _ in range(40):
            yield b" " * (1024 * 1024)

    answer = web.post("/api/check", content=stream(), headers={"content-type": "application/json"})
    assert answer.status_code == 413 and answer.json()["exit_code"] == 2


@pytest.mark.parametrize(
    "path", ["pred.py", "x/.venv/lib/sitecustomize.py", ".venv/a.pddl", "pddl/.hidden.pddl", "a.sh"]
)
def test_no_code_and_nothing_hidden_is_written(studio_root, path):
    answer = client(studio_root).post("/api/save", json={"path": path, "text": "import os\n"})
    assert answer.status_code == 400 and answer.json()["exit_code"] == 2
    assert not (studio_root / path).exists()


def test_a_save_never_writes_over_a_file_it_did_not_see(studio_root):
    web = client(studio_root)
    before = (studio_root / DOMAIN).read_text()
    refused = web.post("/api/save", json={"path": DOMAIN, "text": "x"})
    assert refused.status_code == 409 and "overwrite" in refused.json()["error"]
    version = web.get("/api/text", params={"path": DOMAIN}).json()["version"]
    (studio_root / DOMAIN).write_text(before + "; changed on disk\n")
    changed = web.post("/api/save", json={"path": DOMAIN, "text": "x", "base": version})
    assert changed.status_code == 409 and "changed on disk" in changed.json()["error"]
    version = web.get("/api/text", params={"path": DOMAIN}).json()["version"]
    saved = web.post("/api/save", json={"path": DOMAIN, "text": before, "base": version})
    assert saved.status_code == 200 and (studio_root / DOMAIN).read_text() == before
    assert web.post("/api/save", json={"path": DOMAIN, "text": "y", "overwrite": True}).status_code == 200


def test_bad_requests_are_4xx_in_the_cli_format_without_server_paths(studio_root):
    web = client(studio_root)
    missing = web.get("/api/text")
    assert missing.status_code == 400 and missing.json() == {"error": "the parameter path is missing", "exit_code": 2}
    long = web.get("/api/text", params={"path": "a" * 300 + ".pddl"})
    assert long.status_code == 400 and "255 bytes" in long.json()["error"]
    assert web.get("/files/" + "b" * 300).status_code == 400
    for answer in (long, web.post("/api/ground", json={"pre": "nothing.png", "post": "x.png"})):
        assert str(studio_root) not in answer.text


def test_the_predicates_are_not_loaded_before_the_images_are_good(studio_root):
    (studio_root / "ran.py").write_text("open('RAN', 'w').write('ran')\n")
    sent = {"pre": "examples/grounding/pre.png", "post": "nothing.png", "predicates": "ran.py"}
    assert client(studio_root).post("/api/ground", json=sent).status_code == 404
    assert not (studio_root / "RAN").exists()


def test_each_grounding_draws_its_own_overlay(studio_root):
    web = client(studio_root)
    sent = {"pre": "examples/grounding/pre.png", "post": "examples/grounding/post.png"}
    first, second = (web.post("/api/ground", json=sent).json()["overlay"] for _ in range(2))
    assert first != second and (studio_root / first).is_file() and (studio_root / second).is_file()


def _wait(web, run_id, states):
    """The run's status once it is in one of ``states`` (how fast is bench_studio.py's to say); a run
    that ended in another state fails the test at once, with its status."""
    ended = ("done", "failed", "cancelled")
    wait_until(
        lambda: web.get(f"/api/runs/{run_id}").json()["state"] in (*states, *ended), f"run {run_id} to be {states}"
    )
    status = web.get(f"/api/runs/{run_id}").json()
    assert status["state"] in states, status
    return status


def test_runs_queue_beyond_the_limit_and_cancel_at_once(studio_root):
    web = client(studio_root, max_jobs=1)
    first, second, third = (
        web.post("/api/runs", json={"experiment": "house-roof", "trials": 50, "seed": s}).json()["id"] for s in range(3)
    )
    listed = web.get("/api/runs").json()
    assert listed["queued"] == 2
    assert [web.get(f"/api/runs/{i}").json()["position"] for i in (second, third)] == [1, 2]
    cancelled = web.post(f"/api/runs/{second}/cancel").json()
    assert cancelled["state"] == "cancelled" and web.get(f"/api/runs/{third}").json()["position"] == 1
    web.post(f"/api/runs/{first}/cancel")
    assert _wait(web, first, ("cancelled",))["state"] == "cancelled"
    _wait(web, third, ("running",))  # the queue moved on
    web.post(f"/api/runs/{third}/cancel")
    _wait(web, third, ("cancelled",))
    assert web.post(f"/api/runs/{third}/cancel").status_code == 400  # ended already
    assert web.post("/api/runs/20260101-000000-abcdef/cancel").status_code == 404


def test_a_run_cancelled_as_its_process_starts_reads_cancelled(studio_root):
    """The cancel lands while the worker is still starting (before or while it writes its first
    status), once it runs, and once a trial has finished: it ends cancelled, never failed (the cancel
    mark is a file the worker's writes leave alone)."""
    import json

    from vslsp.studio import runs

    def status(run_id):
        path = studio_root / runs.RUNS / run_id / "status.json"
        return json.loads(path.read_text()) if path.exists() else {}

    web = client(studio_root, max_jobs=1)
    moments = (lambda s: True, lambda s: "pid" in s, lambda s: s.get("done", 0) >= 1)  # start, running, a trial done
    for seed, moment in enumerate(moments):
        run_id = web.post("/api/runs", json={"experiment": "house-roof", "trials": 50, "seed": seed}).json()["id"]
        wait_until(lambda m=moment, r=run_id: m(status(r)), f"run {run_id} to reach moment {seed}")
        assert web.post(f"/api/runs/{run_id}/cancel").json()["state"] in ("cancelling", "cancelled")
        assert _wait(web, run_id, ("cancelled",))["state"] == "cancelled"


def test_a_cancel_survives_the_workers_own_status_write(studio_root):
    """The studio marks a cancel; the worker, which read its status before, then writes that copy (its
    pid): the job, once its process is gone, still reads cancelled."""
    import json

    from vslsp.studio import runs

    folder = studio_root / runs.RUNS / "20260101-000000-abcdef"
    folder.mkdir(parents=True)
    workers_copy = {"id": folder.name, "state": "running", "started": 1.0e9, "done": 0, "total": 5}
    (folder / "status.json").write_text(json.dumps(workers_copy))
    runs.request_cancel(folder)
    runs.write_status(folder / "status.json", {**workers_copy, "pid": 2**22 + 12345})  # no such process
    assert runs.read_job(studio_root, runs.RUNS, folder.name, "run")["state"] == "cancelled"


@pytest.mark.slow
def test_a_cancelled_run_keeps_its_finished_trials(studio_root):
    web = client(studio_root)
    run_id = web.post("/api/runs", json={"experiment": "house-roof", "trials": 20, "seed": 0}).json()["id"]
    wait_until(lambda: web.get(f"/api/runs/{run_id}").json()["done"] >= 1, "the run's first trial")
    web.post(f"/api/runs/{run_id}/cancel")
    status = _wait(web, run_id, ("cancelled",))
    report = web.get(f"/api/reports/{status['report']}").json()
    assert report["summary"]["trials"] >= 1 and report["summary"]["interrupted"]


def test_children_run_isolated_from_the_root(studio_root):
    """A ``vslsp/`` folder under the root (a checkout) never stands in for the installed package."""
    from vslsp.studio import runs

    command = runs.worker_command(studio_root / "status.json")
    assert command[:3] == [__import__("sys").executable, "-I", "-c"]
    (studio_root / "vslsp" / "studio").mkdir(parents=True)
    (studio_root / "vslsp" / "__init__.py").write_text("raise SystemExit('shadowed')\n")
    answer = client(studio_root).post("/api/scene", json={"seed": 1})
    assert answer.status_code == 200, answer.text


def test_predicates_run_in_a_child_without_the_studio_or_the_root(studio_root, monkeypatch):
    """A predicates file under the root runs in a process of its own: not the studio's, without its
    environment's secrets, not with the root as its folder or on its import path."""
    import os

    monkeypatch.setenv("VSLSP_SECRET_FOR_TEST", "s3cret")
    (studio_root / "helper_module.py").write_text("X = 1\n")
    example = (studio_root / "examples/grounding/predicates.py").read_text()
    spy = (
        "import os, sys\n"
        f"assert os.getpid() != {os.getpid()}, 'ran in the studio'\n"
        "assert 'VSLSP_SECRET_FOR_TEST' not in os.environ, 'secret inherited'\n"
        f"assert os.getcwd() != {str(studio_root)!r}, 'cwd is the root'\n"
        "try:\n    import helper_module\nexcept ImportError:\n    pass\n"
        "else:\n    raise AssertionError('root importable')\n"
    )
    (studio_root / "examples/grounding/spy_predicates.py").write_text(spy + example)
    sent = {
        "pre": "examples/grounding/pre.png",
        "post": "examples/grounding/post.png",
        "predicates": "examples/grounding/spy_predicates.py",
    }
    answer = client(studio_root).post("/api/ground", json=sent)
    assert answer.status_code == 200, answer.json()
    assert answer.json()["atoms"]["pre"]
