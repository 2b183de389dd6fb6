"""benchmarks/bench_trial_cost.py's machinery on one family and one trial: the stages it charges
add up to the trial's CPU time, the floor replays the trial's own steps and camera images, and
the trial's record is the one ``run_one`` gives (the hooks only time calls)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from helpers.records import without_times

from vslsp.tasks import get_task, run_one

REPO = Path(__file__).resolve().parents[2]
BENCH = REPO / "benchmarks" / "bench_trial_cost.py"
FAMILY, SEED = "pull-in-order", 7_400_000


def bench(args: list[str], tmp_path: Path) -> subprocess.CompletedProcess:
    env = {
        **os.environ,
        "TMPDIR": str(tmp_path),
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
    }
    return subprocess.run([sys.executable, str(BENCH), *args], capture_output=True, text=True, env=env, cwd=tmp_path)


def test_one_trial_is_split_into_stages_against_its_own_replayed_floor(tmp_path):
    out = tmp_path / "cost.json"
    done = bench(
        ["--families", FAMILY, "--trials", "1", "--seed", str(SEED), "--no-report", "--json", str(out)], tmp_path
    )
    assert done.returncode == 0, done.stderr
    data = json.loads(out.read_text())
    (row,) = data["families"]
    (trial,) = row["trials"]
    assert row["experiment"] == FAMILY and data["seeds"] == [SEED]
    assert trial["steps"] > 1000 and trial["renders"] > 0 and trial["unreplayed_steps"] == 0
    assert 0 < trial["floor_s"] < trial["cpu_s"]
    stages = trial["stages_s"]
    assert set(stages) == set(data["stages"])
    assert all(seconds >= -0.05 for seconds in stages.values()), stages
    assert stages["physics"] > 0 and stages["rendering"] > 0 and stages["planning"] > 0
    assert abs(sum(stages.values()) - trial["cpu_s"]) < 1e-6
    assert stages["report figures"] == 0 and row["totals_s"]["start-up"] > 0
    assert abs(sum(row["shares"].values()) - 1) < 1e-9
    assert FAMILY in done.stdout  # the table

    # The hooked trial's record is the plain one, times excepted.
    plain = run_one(get_task(FAMILY), SEED).to_dict()
    assert trial["record"] == json.loads(json.dumps(without_times(plain)))


def test_an_unknown_family_is_refused_with_one_line(tmp_path):
    done = bench(["--families", "no-such-family", "--trials", "1"], tmp_path)
    assert done.returncode == 2
    assert "unknown experiment(s) no-such-family" in done.stderr and "Traceback" not in done.stderr
