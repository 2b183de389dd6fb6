"""The studio's new JSON API in process: a trial of a report (``GET /api/reports/REL/trials/SEED``),
completion (``POST /api/complete``), a run's newest picture (``latest``), and the paths out of the
root refused for each."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers.studio import DOMAIN, PROBLEM, client

from vslsp.studio import runs


def test_a_trial_of_a_report_its_pictures_in_the_reports_order(studio_root, trial_report, tmp_path):
    (tmp_path / "secret.png").write_bytes(b"\x89PNG")  # what the report's "outside" entry names
    trial = client(studio_root).get(f"/api/reports/{trial_report}/trials/3").json()
    assert trial["shown"] is True and trial["record"]["seed"] == 3
    assert [image["title"] for image in trial["images"]] == ["demonstration 1", "reproduction 1", "final"]
    assert all(image["file"].startswith(f"{trial_report}/images/") for image in trial["images"])
    assert [plan["title"] for plan in trial["plans"]] == ["plan", "replan 1", "goal check"]
    assert trial["plans"][1]["plan"] == ["pull green"]
    assert trial["files"] == [{"title": "plan", "file": f"{trial_report}/plan.txt"}]
    assert trial["clouds"] == [
        f"{trial_report}/clouds/demonstration_1_pre.npz",
        f"{trial_report}/clouds/reproduction_1.npz",
    ]
    assert trial["video"] is None
    assert "secret" not in json.dumps(trial)


def test_a_trial_the_report_did_not_draw_has_its_record_and_video(studio_root, trial_report):
    trial = client(studio_root).get(f"/api/reports/{trial_report}/trials/4").json()
    assert trial["shown"] is False and trial["shown_seed"] == 3
    assert trial["images"] == [] and trial["clouds"] == [] and trial["plans"] == []
    assert trial["video"] == f"{trial_report}/videos/trial-4.mp4"
    assert trial["record"]["error"] == "operation 1 (duck): grasp failed"


def test_the_report_lists_its_trials_with_their_pages(studio_root, trial_report):
    report = client(studio_root).get(f"/api/reports/{trial_report}").json()
    assert [(t["seed"], t["success"], t["link"]) for t in report["trials"]] == [
        (3, True, f"/reports/{trial_report}/trials/3"),
        (4, False, f"/reports/{trial_report}/trials/4"),
    ]
    assert len(report["clouds"]) == 2 and len(report["images"]) == 3


@pytest.mark.parametrize(
    "path",
    [
        "out/reports/demo/trials/9",  # no such trial
        "out/reports/nothing/trials/3",  # no such report
        "../out/reports/demo/trials/3",
        "%2e%2e/out/reports/demo/trials/3",
        "out/reports/demo/../../../trials/3",
    ],
)
def test_a_missing_trial_or_a_way_out_is_refused(studio_root, trial_report, path):
    response = client(studio_root).get(f"/api/reports/{path}")
    assert response.status_code in (403, 404), response.text  # (a plain '..' the client folds away first)
    assert "record" not in response.json()


def test_a_trial_link_out_of_the_root_is_refused(studio_root, trial_report, tmp_path):
    import shutil

    outside = tmp_path / "elsewhere"
    shutil.copytree(studio_root / trial_report, outside)
    (studio_root / "out" / "link").symlink_to(outside)
    assert client(studio_root).get("/api/reports/out/link/trials/3").status_code == 403


def completion(studio_root, editor: str, marker: str, **changes) -> dict:
    sent = {"domain": (studio_root / DOMAIN).read_text(), "problem": (studio_root / PROBLEM).read_text()}
    sent.update(changes)
    text = sent[editor]
    return client(studio_root).post(
        "/api/complete", json={**sent, "in": editor, "at": text.index(marker) + len(marker)}
    )


def test_complete_a_predicate_in_the_domain(studio_root):
    domain = (studio_root / DOMAIN).read_text().replace("(not (far ?b))", "(not (f ?b))", 1)
    answer = completion(studio_root, "domain", "(not (f", domain=domain).json()
    assert "far" in answer["items"] and domain[answer["from"] : answer["from"] + 1] == "f"


def test_complete_an_object_in_the_problem_with_the_domains_names(studio_root):
    problem = (studio_root / PROBLEM).read_text().replace("(far orange)", "(far or)", 1)
    answer = completion(studio_root, "problem", "(far or", problem=problem).json()
    assert answer["items"] == ["orange"]


@pytest.mark.parametrize("change", [{"in": "plan"}, {"at": -1}, {"at": 10**9}, {"at": "3"}, {"domain": 5}])
def test_bad_completion_requests_are_400(studio_root, change):
    sent = {"domain": (studio_root / DOMAIN).read_text(), "in": "domain", "at": 0, **change}
    response = client(studio_root).post("/api/complete", json=sent)
    assert response.status_code == 400 and response.json()["error"]


def test_a_runs_latest_picture_is_its_newest(studio_root):
    from vslsp.vision.image import write_image

    folder = studio_root / runs.RUNS / "20260101-000000-abcdef"
    (folder / "report" / "images").mkdir(parents=True)
    status = {"id": folder.name, "state": "done", "done": 1, "total": 1, "successes": 1, "request": {}}
    (folder / "status.json").write_text(json.dumps(status))
    web = client(studio_root)
    assert web.get(f"/api/runs/{folder.name}").json()["latest"] is None
    write_image(folder / runs.LIVE, np.zeros((64, 64, 3), np.uint8))
    assert web.get(f"/api/runs/{folder.name}").json()["latest"] == f"{runs.RUNS}/{folder.name}/live.png"
    write_image(folder / "report" / "images" / "final.png", np.zeros((64, 64, 3), np.uint8))
    import os

    os.utime(folder / runs.LIVE, (1, 1))  # the figure written after the last view
    latest = web.get(f"/api/runs/{folder.name}").json()["latest"]
    assert latest == f"{runs.RUNS}/{folder.name}/report/images/final.png"
    assert web.get(f"/files/{latest}").status_code == 200
