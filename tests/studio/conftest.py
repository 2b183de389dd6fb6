"""A studio root in tmp_path with the shipped PDDL and the grounding example pair."""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest
from helpers.events import became_true
from helpers.studio import ARGS, CHROMIUM, TOKEN, WAIT_MS, free_port

REPO = Path(__file__).resolve().parents[2]

pytest.importorskip("nicegui", reason="the studio extra is not installed (pip install 'vslsp[studio]')")


@pytest.fixture
def studio_root(tmp_path: Path) -> Path:
    """A root with pddl/ (the shipped domain and problems) and examples/grounding/."""
    root = tmp_path / "root"
    shutil.copytree(REPO / "pddl", root / "pddl", ignore=shutil.ignore_patterns("*.py", "__pycache__"))
    shutil.copytree(
        REPO / "examples" / "grounding",
        root / "examples" / "grounding",
        ignore=shutil.ignore_patterns("test_*", "__pycache__"),
    )
    return root


@pytest.fixture
def trial_report(studio_root: Path) -> str:
    """A report folder ``out/reports/demo`` under the root, as a VSL-3D run writes one: two trials
    (seed 3 drawn, with its pictures, plan and replan, and clouds; seed 4 failed, with a video file),
    made with the report's own writers. Returns the folder relative to the root."""
    import json

    import numpy as np

    from vslsp.vision.image import write_image
    from vslsp.vsl3d.pictures import labelled_cloud, write_clouds

    folder = studio_root / "out" / "reports" / "demo"
    (folder / "images").mkdir(parents=True)
    drawn = {}
    for number, (key, width) in enumerate((("demonstration_1", 120), ("reproduction_1", 90), ("final", 60))):
        image = np.full((48, width, 3), 40 * number, dtype=np.uint8)
        drawn[key] = f"images/{key}.png"
        write_image(folder / drawn[key], image)
    table = np.stack(np.meshgrid(np.linspace(0.3, 0.7, 60), np.linspace(-0.2, 0.2, 60), [0.01]), -1).reshape(-1, 3)
    duck = np.stack(np.meshgrid(np.linspace(0.5, 0.54, 12), np.linspace(0, 0.04, 12), [0.03, 0.05]), -1).reshape(-1, 3)
    clouds = {
        "demonstration_1_pre": labelled_cloud(np.vstack([table, duck]), duck, "the pre-action scene"),
        "reproduction_1": labelled_cloud(table, duck + 0.1, "the capture"),
    }
    drawn.update(write_clouds(folder, clouds))
    (folder / "plan.txt").write_text("(pull orange)\n(pull green)\n")
    (folder / "videos").mkdir()
    (folder / "videos" / "trial-4.mp4").write_bytes(b"\x00\x00\x00\x18ftypmp42")
    summary = {
        "experiment": "table-cleaning",
        "system": "VSL-3D",
        "trials": 2,
        "seed": 3,
        "successes": 1,
        "results": [
            {
                "experiment": "table-cleaning",
                "seed": 3,
                "success": True,
                "error": None,
                "time_s": 1.5,
                "operations": [{"index": 0, "moved": "duck", "success": True}],
            },
            {
                "experiment": "table-cleaning",
                "seed": 4,
                "success": False,
                "time_s": 2.5,
                "error": "operation 1 (duck): grasp failed",
                "video": "videos/trial-4.mp4",
            },
        ],
        "shown_trial": {
            "seed": 3,
            "success": True,
            **drawn,
            "plan": "plan.txt",
            "outside": "../../../secret.png",
            "executions": [
                {"plans": [{"plan": ["pull orange", "pull green"]}, {"plan": ["pull green"]}, {"plan": []}]}
            ],
        },
    }
    (folder / "report.json").write_text(json.dumps(summary))
    return "out/reports/demo"


def _serves(port: int) -> bool:
    """Whether something accepts connections on ``port`` of 127.0.0.1."""
    try:
        socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
    except OSError:
        return False
    return True


@pytest.fixture
def studio(studio_root: Path, request: pytest.FixtureRequest) -> Iterator[str]:
    """``vslsp studio --root ROOT --no-browser --token TOKEN`` on a free port; its address once it serves."""
    port = free_port()
    token = ["--token", TOKEN]
    process = subprocess.Popen(
        [sys.executable, "-m", "vslsp", "studio", "--root", str(studio_root), "--port", str(port), "--no-browser"]
        + token,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        env={k: v for k, v in os.environ.items() if not k.startswith("PYTEST")},  # NiceGUI reads them as its own tests
    )
    address = f"http://127.0.0.1:{port}"
    said: list[bytes] = []  # its stderr, read as it comes (a full pipe would stall the studio)
    reader = threading.Thread(target=lambda: said.extend(iter(process.stderr.readline, b"")), daemon=True)
    reader.start()
    try:
        if not became_true(lambda: _serves(port), process):
            process.kill()
            reader.join(timeout=20)
            raise AssertionError(f"the studio never served on port {port}:\n{b''.join(said).decode()}")
        yield address
    finally:
        process.terminate()
        process.wait(timeout=20)


@pytest.fixture
def page(studio: str, tmp_path_factory: pytest.TempPathFactory, request: pytest.FixtureRequest) -> Iterator:
    """A headless Chromium tab (Debian's, driven by Playwright), with a home of its own (Chromium
    writes ~/.config/chromium and ~/.cache/dconf)."""
    from playwright.sync_api import sync_playwright

    home = tmp_path_factory.mktemp("chromium-home")
    with sync_playwright() as driver:
        browser = driver.chromium.launch(
            executable_path=CHROMIUM, args=ARGS, headless=True, env={**os.environ, "HOME": str(home)}
        )
        tab = browser.new_page(viewport={"width": 1500, "height": 1100})
        tab.set_default_timeout(WAIT_MS)
        if not request.node.get_closest_marker("token"):  # the address the studio opens: its cookie set
            tab.goto(f"{studio}/author?token={TOKEN}")
        yield tab
        browser.close()


@pytest.fixture(scope="session")
def house_roof_report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A real two-trial house-roof report (seeds 0 and 1; the report draws trial 0's figures), made
    once by ``vslsp experiment`` (tests copy it: drawing a trial writes into the folder)."""
    folder = tmp_path_factory.mktemp("house-roof") / "report"
    subprocess.run(
        [
            sys.executable,
            "-m",
            "vslsp",
            "experiment",
            "house-roof",
            "--trials",
            "2",
            "--seed",
            "0",
            "--out",
            str(folder),
        ],
        check=True,
        capture_output=True,
        timeout=900,
    )
    return folder


@pytest.fixture
def roof_report(studio_root: Path, house_roof_report: Path) -> str:
    """The house-roof report copied to ``out/reports/roof`` under the root; its path relative to the root."""
    shutil.copytree(house_roof_report, studio_root / "out" / "reports" / "roof")
    return "out/reports/roof"
