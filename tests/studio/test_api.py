"""The studio's JSON API in process (FastAPI's TestClient): every endpoint, the token, every way
out of the root refused, bad input a 4xx with the CLI's message."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from helpers.events import wait_until
from helpers.studio import DOMAIN, PROBLEM, client

from vslsp.studio import api


def texts(root: Path) -> dict:
    return {
        "domain": (root / DOMAIN).read_text(),
        "problem": (root / PROBLEM).read_text(),
        "domain_file": DOMAIN,
        "problem_file": PROBLEM,
    }


def test_experiments_as_the_cli_lists_them(studio_root):
    from vslsp.tasks import list_tasks

    answer = client(studio_root).get("/api/experiments").json()
    assert [e["name"] for e in answer["experiments"]] == [cls().describe()["name"] for cls in list_tasks()]
    assert "house-roof" in [e["name"] for e in answer["experiments"]]


def test_check_reports_a_typo_on_its_line_with_its_fix(studio_root):
    sent = texts(studio_root)
    sent["domain"] = sent["domain"].replace(":precondition (not (far ?b))", ":precondition (not (fars ?b))")
    answer = client(studio_root).post("/api/check", json=sent).json()
    assert answer["exit_code"] == 2
    [error] = [d for d in answer["diagnostics"] if d["severity"] == "error"]
    line = sent["domain"].splitlines().index("    :precondition (not (fars ?b))") + 1
    assert (error["file"], error["line"], error["code"]) == (DOMAIN, line, "unknown-predicate")
    assert error["fixes"][0]["text"] == "far"
    assert client(studio_root).post("/api/check", json=texts(studio_root)).json()["exit_code"] == 0


def test_plan_gives_steps_and_a_timeline(studio_root):
    answer = client(studio_root).post("/api/plan", json=texts(studio_root)).json()
    assert answer["plan"] == ["pull orange", "pull green", "pull yellow"]
    timeline = answer["timeline"]
    assert timeline["states"][0] == ["(far green)", "(far orange)", "(far yellow)"] and timeline["states"][-1] == []
    assert [c["kept"] for c in timeline["constraints"]] == [True, True]


def test_validate_marks_both_broken_constraints(studio_root):
    sent = {**texts(studio_root), "plan": "(pull yellow)\n(pull green)\n(pull orange)\n"}
    answer = client(studio_root).post("/api/validate", json=sent).json()
    assert answer["valid"] is False
    statuses = [c["status"] for c in answer["timeline"]["constraints"]]
    assert statuses == [["kept", "kept", "broken", "broken"], ["kept", "broken", "broken", "broken"]]


def test_a_bad_plan_step_is_a_400_with_the_cli_message(studio_root):
    sent = {**texts(studio_root), "plan": "(pul yellow)\n"}
    response = client(studio_root).post("/api/validate", json=sent)
    assert response.status_code == 400
    assert "pul" in response.json()["error"] and response.json()["exit_code"] == 2


def test_an_unsolvable_problem_names_its_conflict_on_its_lines(studio_root):
    sent = texts(studio_root)
    sent["problem"] = sent["problem"].replace("(:constraints (and", "(:constraints (and (always (far green))", 1)
    answer = client(studio_root).post("/api/plan", json=sent).json()
    assert answer["plan"] is None and answer["exit_code"] == 1 and "no plan" in answer["error"]
    kinds = {(item["kind"], item["line"]) for item in answer["conflict"]}
    assert ("constraint", 15) in kinds and any(kind == "goal" for kind, _ in kinds)


def test_validate_lists_every_violation_with_its_line_and_step(studio_root):
    sent = {**texts(studio_root), "plan": "(pull yellow)\n(pull green)\n(pull orange)\n"}
    answer = client(studio_root).post("/api/validate", json=sent).json()
    assert sorted((v["line"], v["step"]) for v in answer["violations"]) == [(16, 2), (17, 1)]


@pytest.mark.parametrize("body", [b"not json", b"[1, 2]", b'{"domain": 3}', b'{"problem": "x"}'])
def test_bad_bodies_are_400_never_500(studio_root, body):
    for endpoint in ("/api/check", "/api/plan", "/api/validate", "/api/ground", "/api/runs", "/api/save"):
        response = client(studio_root).post(endpoint, content=body)
        assert 400 <= response.status_code < 500, (endpoint, response.text)
        assert response.json()["error"]


def test_ground_the_example_pair_with_predicates_from_the_root(studio_root):
    sent = {
        "pre": "examples/grounding/pre.png",
        "post": "examples/grounding/post.png",
        "predicates": "examples/grounding/predicates.py",
    }
    answer = client(studio_root).post("/api/ground", json=sent).json()
    assert answer["atoms"]["pre"] and answer["atoms"]["post"]
    assert (studio_root / answer["overlay"]).is_file()


def test_ground_refuses_predicates_outside_the_root(studio_root, tmp_path):
    outside = tmp_path / "evil.py"
    outside.write_text("raise SystemExit('ran')\n")
    sent = {"pre": "examples/grounding/pre.png", "post": "examples/grounding/post.png", "predicates": str(outside)}
    assert client(studio_root).post("/api/ground", json=sent).status_code == 403
    sent["predicates"] = "../evil.py"
    assert client(studio_root).post("/api/ground", json=sent).status_code == 403


def test_files_and_text_and_save(studio_root):
    web = client(studio_root)
    assert web.get(f"/files/{DOMAIN}").text == (studio_root / DOMAIN).read_text()
    assert web.get("/api/text", params={"path": DOMAIN}).json()["text"].startswith(";")
    assert web.post("/api/save", json={"path": "mine/new.pddl", "text": "(define (domain d))"}).status_code == 200
    assert (studio_root / "mine" / "new.pddl").read_text() == "(define (domain d))"
    assert web.get("/files/nothing-here.png").status_code == 404
    assert DOMAIN in web.get("/api/list", params={"kind": "pddl"}).json()["files"]


@pytest.mark.parametrize(
    "path",
    ["../secret.txt", "%2e%2e/secret.txt", "%2E%2E/secret.txt", "pddl/../../secret.txt", "link/secret.txt", "escape"],
)
def test_every_way_out_of_the_root_is_refused(studio_root, tmp_path, path):
    (tmp_path / "secret.txt").write_text("secret")
    os.symlink(tmp_path, studio_root / "link")
    os.symlink(tmp_path / "secret.txt", studio_root / "escape")
    web = client(studio_root)
    for url in (f"/files/{path}", f"/api/text?path={path}"):
        response = web.get(url)
        assert response.status_code in (403, 404), url
        assert "secret" != response.text
    assert web.post(
        "/api/save", json={"path": path if path.endswith("txt") else "escape", "text": "x"}
    ).status_code in (
        400,
        403,
    )
    assert (tmp_path / "secret.txt").read_text() == "secret"


def test_absolute_paths_are_refused(studio_root, tmp_path):
    (tmp_path / "secret.txt").write_text("secret")
    web = client(studio_root)
    assert web.get("/api/text", params={"path": str(tmp_path / "secret.txt")}).status_code == 403
    assert web.get(f"/files/{tmp_path / 'secret.txt'}").status_code == 403
    assert web.post("/api/save", json={"path": str(tmp_path / "x.pddl"), "text": "x"}).status_code == 403
    assert not (tmp_path / "x.pddl").exists()


def test_the_token_is_required_on_every_request(studio_root):
    token = "t0ken-for-the-studio-tests"
    web = client(studio_root, token, send_token=False)
    assert web.get("/api/experiments").status_code == 401
    assert web.get(f"/files/{DOMAIN}", headers={"authorization": "Bearer wrong"}).status_code == 401
    assert web.get(f"/files/{DOMAIN}", headers={"authorization": token}).status_code == 401  # no "Bearer"
    assert web.get("/api/experiments", headers={"authorization": f"Bearer {token}"}).status_code == 200
    first = web.get(f"/api/experiments?token={token}")
    assert first.status_code == 200 and web.cookies.get("vslsp_studio_test") == token
    assert web.get(f"/files/{DOMAIN}").status_code == 200  # the cookie the first visit set


def test_uploads_are_limited_and_kept_under_the_root(studio_root):
    web = client(studio_root)
    png = (studio_root / "examples/grounding/pre.png").read_bytes()
    answer = web.post("/api/upload", files={"file": ("../../pre.png", png, "image/png")}).json()
    assert answer["path"] == "out/studio/uploads/pre.png" and (studio_root / answer["path"]).is_file()
    assert web.post("/api/upload", files={"file": ("x.exe", b"MZ", "application/octet-stream")}).status_code == 400
    big = b"\x89PNG" + bytes(api.MAX_UPLOAD_BYTES)
    assert web.post("/api/upload", files={"file": ("big.png", big, "image/png")}).status_code == 413


def test_runs_refuse_bad_requests_before_starting(studio_root):
    web = client(studio_root)
    assert web.post("/api/runs", json={"experiment": "no-such"}).status_code == 400
    assert web.post("/api/runs", json={"experiment": "house-roof", "trials": 0}).status_code == 400
    assert web.post("/api/runs", json={"experiment": "house-roof", "faults": True}).status_code == 400
    assert web.post("/api/runs", json={"experiment": "house-roof", "shell": "rm"}).status_code == 400
    assert web.get("/api/runs/../../etc").status_code == 404
    assert web.get("/api/runs/20260101-000000-abcdef").status_code == 404
    assert not (studio_root / "out" / "studio" / "runs").exists()


@pytest.mark.slow
def test_a_run_goes_to_done_with_its_report(studio_root):
    web = client(studio_root)
    run_id = web.post("/api/runs", json={"experiment": "house-roof", "trials": 1, "seed": 3}).json()["id"]
    status = web.get(f"/api/runs/{run_id}").json()
    assert status["state"] in ("queued", "running") and status["total"] == 1
    ended = ("done", "failed", "cancelled")
    wait_until(lambda: web.get(f"/api/runs/{run_id}").json()["state"] in ended, f"the run {run_id} to end")
    status = web.get(f"/api/runs/{run_id}").json()
    assert status["state"] == "done", status
    assert (status["done"], status["successes"]) == (1, 1)
    report = web.get(f"/api/reports/{status['report']}").json()
    assert report["summary"]["trials"] == 1 and report["images"]
    assert web.get(f"/files/{report['images'][0]}").status_code == 200


def test_a_rendered_scene_gives_images_under_the_root(studio_root):
    web = client(studio_root)
    answer = web.post("/api/scene", json={"seed": 2}).json()
    assert answer["folder"] == "out/studio/scenes/seed-2" and answer["images"]
    assert all((studio_root / image).read_bytes()[:4] == b"\x89PNG" for image in answer["images"])
    assert web.post("/api/scene", json={"seed": -1}).status_code == 400


def _at(text: str, marker: str, inside: int) -> int:
    return text.index(marker) + inside


def test_navigate_definition_references_rename_and_outline(studio_root):
    sent = texts(studio_root)
    at = _at(sent["domain"], "(not (far ?b))", len("(not (f"))
    web = client(studio_root)
    ask = {**sent, "in": "domain", "at": at}
    found = web.post("/api/navigate", json={**ask, "what": "definition"}).json()
    assert (found["name"], found["signature"]) == ("far", "(far ?b - block)")
    assert found["locations"][0]["line"] == 8 and found["locations"][0]["in"] == "domain"
    places = web.post("/api/navigate", json={**ask, "what": "references"}).json()["locations"]
    assert {p["in"] for p in places} == {"domain", "problem"} and len(places) == 15
    edits = web.post("/api/navigate", json={**ask, "what": "rename", "new_name": "distant"}).json()["edits"]
    assert len(edits) == 15 and all(e["text"] == "distant" for e in edits)
    for reserved in ("and", "either", "forall", "9lives", "a b"):
        refused = web.post("/api/navigate", json={**ask, "what": "rename", "new_name": reserved})
        assert refused.status_code == 400 and refused.json()["exit_code"] == 2, reserved
    outline = web.post("/api/navigate", json={**ask, "what": "outline"}).json()["outline"]
    shown = [(o["kind"], o["name"]) for o in outline][:3]
    assert shown == [("domain", "vsl-sp"), ("type", "block"), ("predicate", "far")]
    assert outline[3]["children"][0]["name"] == "?b"
    assert web.post("/api/navigate", json={**ask, "at": 0, "what": "definition"}).json()["name"] is None
    assert web.post("/api/navigate", json={**ask, "what": "teleport"}).status_code == 400


def test_completion_items_carry_their_kind_and_declaration(studio_root):
    sent = texts(studio_root)
    domain = sent["domain"].replace("(not (far ?b))", "(not (f ?b))", 1)
    at = _at(domain, "(not (f ", len("(not (f"))
    answer = client(studio_root).post("/api/complete", json={**sent, "domain": domain, "in": "domain", "at": at}).json()
    [far] = [e for e in answer["entries"] if e["label"] == "far"]
    assert far == {"label": "far", "kind": "predicate", "type": "function", "detail": "(far ?b - block)"}
    assert {e["kind"] for e in answer["entries"]} <= {"predicate", "keyword"}


def test_a_goal_that_can_never_hold_comes_with_its_reason(studio_root):
    sorting = Path(__file__).resolve().parents[1] / "data" / "sorting"
    sent = {"domain": (sorting / "domain.pddl").read_text(), "problem": (sorting / "wrong-bin.pddl").read_text()}
    answer = client(studio_root).post("/api/plan", json=sent).json()  # through the studio's worker pool
    assert [item["text"] for item in answer["conflict"]] == ["(in r1 green-bin)"]
    assert answer["reasons"][0].startswith("(in r1 green-bin) can never hold: the 2 actions that would make it true")
