"""A seed gives the same trial in another process: VSL-3D (table-cleaning) and VSL-SP
(keep-all-near) trials run in two fresh interpreters with different hash seeds (set and dict
orders of strings differ between them) give the same record, to the last digit."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest
from helpers.cli import REPO
from helpers.events import HANG_S
from helpers.records import without_times

pytestmark = pytest.mark.slow

PROGRAM = """
import json, sys
from vslsp.tasks import get_task
from vslsp.tasks.trial import run_one
result = run_one(get_task(sys.argv[1]), int(sys.argv[2]), False).to_dict()
print(json.dumps(result))
"""


@pytest.mark.parametrize(("name", "seed"), [("table-cleaning", 5), ("keep-all-near", 7)])
def test_a_trial_is_the_same_in_two_processes(name, seed):
    processes = [
        subprocess.Popen(
            [sys.executable, "-c", PROGRAM, name, str(seed)],
            env={
                **os.environ,
                "PYTHONHASHSEED": hash_seed,
                "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
            },
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for hash_seed in ("1", "2")
    ]
    outputs = [process.communicate(timeout=HANG_S) for process in processes]
    for process, (_, err) in zip(processes, outputs):
        assert process.returncode == 0, err
    first, second = (without_times(json.loads(out)) for out, _ in outputs)
    assert first["seed"] == seed and first["operations"]  # a real trial ran
    assert first == second
