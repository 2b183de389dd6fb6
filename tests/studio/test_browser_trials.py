"""The studio's report trials, clouds and live runs in a real headless Chromium (Debian's
/usr/bin/chromium, through Playwright): a trial's page opened by its address with its pictures in
order and its clouds in 3-D (the points loaded into three.js), a running run's newest picture on the
experiments page, and a one-trial VSL-3D run watched live to its trial's 3-D view."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
from helpers.studio import CHROMIUM

from vslsp.studio import runs
from vslsp.vision.image import write_image

pytestmark = pytest.mark.skipif(not Path(CHROMIUM).exists(), reason=f"no {CHROMIUM} (apt-get install chromium)")
pytest.importorskip("playwright.sync_api", reason="pip install playwright")

#: The points three.js holds in the page's 3-D view (its geometry, not what the server sent).
POINTS_DRAWN = """() => {
  const view = getElement(document.querySelector('.cloud-view'));
  let count = 0;
  for (const object of view.objects.values()) {
    if (object.mesh && object.mesh.isPoints) count += object.mesh.geometry.attributes.position.count;
  }
  return count;
}"""


def points_in(path: Path) -> int:
    with np.load(path, allow_pickle=False) as data:
        return len(data["points"])


def test_a_trial_page_opened_by_its_address_shows_its_pictures_in_order(page, studio, studio_root, trial_report):
    page.goto(f"{studio}/reports/{trial_report}/trials/3")
    page.locator(".trial-title").wait_for()
    assert "trial 3 succeeded" in page.locator(".trial-title").inner_text()
    titles = page.locator(".trial-image-title").all_inner_texts()
    assert titles == ["1. demonstration 1", "2. reproduction 1", "3. final"]
    page.wait_for_function("() => [...document.querySelectorAll('.trial-image img')].every(i => i.naturalWidth > 0)")
    widths = page.evaluate("() => [...document.querySelectorAll('.trial-image img')].map(i => i.naturalWidth)")
    assert widths == [120, 90, 60]  # each picture is its own file, in the report's order
    assert page.locator(".trial-plan").all_inner_texts()[1].split() == ["replan", "1", "1.", "(pull", "green)"]
    page.locator(".cloud-view canvas").wait_for()
    first, second = (
        studio_root / trial_report / "clouds" / name for name in ("demonstration_1_pre.npz", "reproduction_1.npz")
    )
    page.wait_for_function(f"() => ({POINTS_DRAWN})() === {points_in(first)}")
    page.locator(".pick-cloud").click()
    page.get_by_role("option", name="reproduction_1.npz").click()
    page.wait_for_function(f"() => ({POINTS_DRAWN})() === {points_in(second)}")
    assert f"{points_in(second)} points" in page.locator(".cloud-caption").inner_text()


def test_a_trial_without_pictures_says_so_and_the_report_links_each_trial(page, studio, trial_report):
    page.goto(f"{studio}/reports/{trial_report}")
    page.locator(".trial-link", has_text="seed 4").click()
    page.locator(".trial-title").wait_for()
    assert page.url.endswith(f"/reports/{trial_report}/trials/4")
    assert "trial 4 FAILED" in page.locator(".trial-title").inner_text()
    assert "grasp failed" in page.locator(".trial-error").inner_text()
    assert page.locator(".trial-image").count() == 0 and page.locator(".trial-video").count() == 1
    page.goto(f"{studio}/reports/{trial_report}/trials/9")
    assert "no trial with seed 9" in page.locator(".page-error").inner_text()


def test_a_running_runs_newest_picture_is_shown_and_renewed(page, studio, studio_root):
    folder = studio_root / runs.RUNS / "20260101-000000-abcdef"
    folder.mkdir(parents=True)
    status = {
        "id": folder.name,
        "state": "running",
        "done": 1,
        "total": 3,
        "successes": 1,
        "request": {"experiment": "house-roof"},
        "pid": os.getpid(),  # a live process: the run is running
    }
    (folder / "status.json").write_text(json.dumps(status))
    write_image(folder / runs.LIVE, np.full((96, 128, 3), 200, np.uint8))
    page.goto(f"{studio}/experiments")
    picture = page.locator(".run-running .live-picture img")
    picture.wait_for()
    assert "1/3 trials, 1 succeeded, trial 2 of 3 running" in page.locator(".run-running .run-text").inner_text()
    first = picture.get_attribute("src")
    assert "live.png" in first
    write_image(folder / runs.LIVE, np.full((96, 128, 3), 20, np.uint8))
    os.utime(folder / runs.LIVE, ns=(10**18, 10**18))  # a later view
    page.wait_for_function(
        "(first) => document.querySelector('.run-running .live-picture img').getAttribute('src') !== first", arg=first
    )


@pytest.mark.slow
def test_a_vsl3d_run_watched_live_to_its_trials_3d_view(page, studio, studio_root, tmp_path):
    page.goto(f"{studio}/experiments")
    page.locator(".pick-experiment").click()
    page.get_by_role("option", name="table-cleaning", exact=True).click()
    page.locator("#start").click()
    page.locator(".run-running .live-picture img").wait_for(timeout=300_000)  # a camera's view, mid-trial
    page.locator(".run-done").wait_for(timeout=900_000)
    assert "1/1 trials" in page.locator(".run-done .run-text").inner_text()
    page.locator(".report-link").click()
    page.locator(".trial-link", has_text="seed 0").click()
    page.locator(".trial-image img").first.wait_for()
    page.locator(".cloud-view canvas").wait_for()
    report = next((studio_root / runs.RUNS).glob("*/report"))
    clouds = json.loads((report / "report.json").read_text())["shown_trial"]["clouds"]
    assert clouds[0] == "clouds/demonstration_1_pre.npz" and "clouds/reproduction_1.npz" in clouds
    page.wait_for_function(f"() => ({POINTS_DRAWN})() === {points_in(report / clouds[0])}")
    page.locator(".cloud-card").screenshot(path=str(tmp_path / "studio-clouds.png"))  # README's, copied once


@pytest.mark.slow
def test_draw_the_pictures_of_the_trial_the_report_did_not_draw(page, studio, studio_root, roof_report):
    page.goto(f"{studio}/reports/{roof_report}")
    page.locator(".trial-link", has_text="seed 1").click()
    page.locator(".trial-title").wait_for()
    assert "the report drew its figures for trial 0 only" in page.locator(".trial-note").inner_text()
    assert page.locator(".trial-image").count() == 0
    page.locator(".draw-pictures").click()
    page.locator(".draw-state", has_text="re-running trial 1").wait_for()
    page.locator(".trial-image img").first.wait_for(timeout=600_000)  # the job done, the page reloaded
    assert page.url.endswith(f"/reports/{roof_report}/trials/1")
    assert "record matches the recorded one" in page.locator(".trial-check").inner_text()
    titles = page.locator(".trial-image-title").all_inner_texts()
    assert titles == ["1. demonstration", "2. final worlds", "3. trajectory", "4. matches fixed", "5. matches adaptive"]
    sources = page.evaluate("() => [...document.querySelectorAll('.trial-image img')].map(i => i.src)")
    for source in sources:  # each the trial's own picture, served as a PNG
        assert f"/files/{roof_report}/trials/1/images/" in source
        answer = page.request.get(source)
        assert answer.ok and answer.body()[:8] == b"\x89PNG\r\n\x1a\n"
    assert page.locator(".draw-pictures").count() == 0
    page.goto(f"{studio}/reports/{roof_report}")
    page.locator(".trial-link", has_text="seed 1 🖼").wait_for()
