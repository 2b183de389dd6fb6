"""Drawing the pictures of a trial the report did not draw (``POST /api/reports/REL/trials/SEED/figures``,
:mod:`vslsp.studio.trial_figures`): its refusals (a seed not in the report, the report's own trial, a
report of an unknown experiment, paths out of the root), the record check, and a real house-roof trial
re-run in a background job, its pictures in ``trials/SEED/`` of the report, the report's own untouched."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest
from helpers.events import wait_until
from helpers.studio import client

from vslsp.studio import trial_figures


def digests(folder: Path) -> dict[str, str]:
    return {
        p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in folder.rglob("*")
        if p.is_file()
    }


@pytest.mark.parametrize(
    ("path", "status", "words"),
    [
        ("out/reports/demo/trials/9/figures", 404, "no trial with seed 9"),
        ("out/reports/demo/trials/3/figures", 409, "drew trial 3's pictures itself"),
        ("out/reports/nothing/trials/3/figures", 404, "no such file"),
        ("%2e%2e/out/reports/demo/trials/4/figures", 403, "outside the studio's root"),
        ("out/reports/demo/trials/4", 404, "trials/SEED/figures"),
    ],
)
def test_drawing_is_refused_with_one_line_before_any_work(studio_root, trial_report, path, status, words):
    response = client(studio_root).post(f"/api/reports/{path}")
    assert response.status_code == status, response.text
    assert words in response.json()["error"] and "\n" not in response.json()["error"]
    assert not (studio_root / trial_figures.FIGURES).exists()  # no job started
    assert not (studio_root / trial_report / "trials").exists()


def test_a_report_of_an_unknown_experiment_is_refused(studio_root, trial_report):
    summary_file = studio_root / trial_report / "report.json"
    summary = json.loads(summary_file.read_text())
    summary_file.write_text(json.dumps({**summary, "experiment": "no-such-experiment"}))
    response = client(studio_root).post(f"/api/reports/{trial_report}/trials/4/figures")
    assert response.status_code == 400 and "unknown experiment 'no-such-experiment'" in response.json()["error"]
    assert not (studio_root / trial_figures.FIGURES).exists()


def test_a_trials_folder_linked_out_of_the_root_is_refused(studio_root, trial_report, tmp_path):
    (tmp_path / "elsewhere").mkdir()
    (studio_root / trial_report / "trials").symlink_to(tmp_path / "elsewhere")
    response = client(studio_root).post(f"/api/reports/{trial_report}/trials/4/figures")
    assert response.status_code == 403, response.text
    assert not list((tmp_path / "elsewhere").iterdir())


def test_no_job_yet_is_a_404_and_an_unknown_job_too(studio_root, trial_report):
    web = client(studio_root)
    answer = web.get(f"/api/reports/{trial_report}/trials/4/figures")
    assert answer.status_code == 404 and "no pictures drawn" in answer.json()["error"]
    assert web.get("/api/figures/20260101-000000-abcdef").status_code == 404
    assert web.get("/api/figures/..%2f..%2fetc").status_code == 404
    trial = web.get(f"/api/reports/{trial_report}/trials/4").json()
    assert trial["pictures"] is None and trial["job"] is None and trial["check"] is None
    report = web.get(f"/api/reports/{trial_report}").json()
    assert [(t["seed"], t["pictures"]) for t in report["trials"]] == [(3, True), (4, False)]


def test_the_record_check_leaves_out_the_times_and_the_video_and_names_what_differs():
    recorded = {"seed": 1, "time_s": 3.0, "video": "videos/trial-1.mp4", "ops": [{"x": 1.5, "cpu_s": 2}], "ok": True}
    again = {"seed": 1, "time_s": 4.1, "ops": [{"x": 1.5, "cpu_s": 9}], "ok": True}
    compare = trial_figures.comparable
    assert trial_figures.differences(compare(recorded), compare(again)) == []
    again["ops"][0]["x"] = 1.75
    again["extra"] = 1
    assert trial_figures.differences(compare(recorded), compare(again)) == [
        "ops[0].x: recorded 1.5, re-run 1.75",
        "extra: only in the re-run",
    ]


def wait_for(web, job_id: str) -> dict:
    """The job's status once it is no longer running."""
    wait_until(lambda: web.get(f"/api/figures/{job_id}").json()["state"] != "running", f"the job {job_id} to end")
    return web.get(f"/api/figures/{job_id}").json()


@pytest.mark.slow
def test_a_trial_is_redrawn_in_its_folder_and_a_changed_record_is_told(studio_root, roof_report):
    folder = studio_root / roof_report
    summary = json.loads((folder / "report.json").read_text())
    assert summary["shown_trial"]["seed"] == 0
    own = digests(folder)
    summary["results"][1]["adaptive"]["operations"][0]["diagnosis"] = "edited by hand"
    (folder / "report.json").write_text(json.dumps(summary))
    web = client(studio_root)
    job_id = web.post(f"/api/reports/{roof_report}/trials/1/figures").json()["id"]
    assert web.post(f"/api/reports/{roof_report}/trials/1/figures").json()["id"] == job_id  # the same job
    status = wait_for(web, job_id)
    assert status["state"] == "done", (status, (studio_root / trial_figures.FIGURES / job_id / "log.txt").read_text())
    assert status["folder"] == f"{roof_report}/trials/1" and status["matches"] is False
    assert status["differences"] == ['adaptive.operations[0].diagnosis: recorded "edited by hand", re-run "ok"']
    assert web.get(f"/api/reports/{roof_report}/trials/1/figures").json() == status
    trial = web.get(f"/api/reports/{roof_report}/trials/1").json()
    assert trial["pictures"] == "studio" and trial["check"]["matches"] is False and trial["job"] == status
    titles = [image["title"] for image in trial["images"]]
    assert titles == ["demonstration", "final worlds", "trajectory", "matches fixed", "matches adaptive"]
    for image in trial["images"]:
        assert image["file"].startswith(f"{roof_report}/trials/1/images/")
        assert (studio_root / image["file"]).read_bytes()[:4] == b"\x89PNG"
    own.pop("report.json")
    assert {k: v for k, v in digests(folder).items() if k in own} == own  # the report's own files untouched
    report = web.get(f"/api/reports/{roof_report}").json()
    assert [(t["seed"], t["pictures"]) for t in report["trials"]] == [(0, True), (1, True)]
    assert not any("/trials/" in image for image in report["images"])  # a trial's pictures are on its page
    again = web.post(f"/api/reports/{roof_report}/trials/1/figures")
    assert again.status_code == 409 and "drawn already" in again.json()["error"]


def test_the_options_the_report_recorded_are_the_re_runs(studio_root):
    from vslsp.tasks import task_class

    def options(name: str, summary: dict, folder: Path | None = None) -> dict:
        takes = {o.value for o in task_class(name).options}
        return trial_figures.recorded_options(studio_root, folder or studio_root / "x", summary, takes)

    assert options("table-cleaning", {"method": "fpfh_fast", "faults": True}) == {"method": "fpfh_fast"}
    assert options("pull-in-order", {"faults": True, "method": "x"}) == {"faults": True}
    assert options("pull-in-order", {"faults": False}) == {}
    assert options("house-roof", {"faults": True}) == {}  # house-roof takes no faults
    run = studio_root / "out" / "studio" / "runs" / "20260101-000000-abcdef"
    (run / "report").mkdir(parents=True)
    (run / "status.json").write_text(json.dumps({"request": {"experiment": "pull-in-order", "faults": True}}))
    assert options("pull-in-order", {}, run / "report") == {"faults": True}  # a studio run's request
