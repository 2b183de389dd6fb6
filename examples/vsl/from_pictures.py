"""VSL from a folder of pictures through the library API (docs/recordings.md, docs/api.md).

The tutor's alphabet-ordering demonstration on the simulated Panda table is photographed into a
folder the documented way (``01-pre.png``, ``01-mid.png``, ``01-post.png``, ...,
``calibration.json``, ``names.json``, ``heights.json``), as a user's camera would take it. The
demonstration is learned from the pictures alone (Algorithm 1 part I), then reproduced in a new
scene (part II): photograph, ask where to pick and place, let the robot act, photograph again.
The judge reads the simulator's ground truth, which the pictures never carry. Run it with

    python examples/vsl/from_pictures.py [OUT_FOLDER]
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

from vslsp import api
from vslsp.experiments.picture_folders import closed_loop, write_recording

TASK, SEED = "alphabet-ordering", 0


def main(folder: Path) -> list[dict]:
    goal = write_recording(TASK, SEED, folder / "recording")  # the user's photographs (and the truth)
    learned = api.learn_demonstration(folder / "recording", out=None)
    print(f"learned {len(learned)} operations: {', '.join(learned.names)}")
    (folder / "scenes").mkdir(exist_ok=True)
    done = [0]  # the operations answered so far: the robot does each one before the next picture

    def ask(scene: Path) -> dict:
        if done[0] == len(learned):
            return {"done": True}
        answer = api.reproduce(learned, scene, done[0])
        done[0] += 1
        print(
            f"operation {answer['operation']}: pick {answer['name']} at {answer['pick']['table_m']} m, "
            f"place at {answer['place']['table_m']} m"
        )
        return answer

    *operations, final = closed_loop(TASK, SEED, goal, folder / "scenes", ask)
    for op in final["final"]:
        print(f"{op['item']}: {1000 * op['position_error_m']:.1f} mm, {op['angle_error_deg']:.1f} deg off the goal")
    return final["final"]


if __name__ == "__main__":
    if len(sys.argv) > 1:
        main(Path(sys.argv[1]))
    else:
        with tempfile.TemporaryDirectory() as temporary:
            main(Path(temporary))
