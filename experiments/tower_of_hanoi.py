"""The paper's real-world task `tower-of-hanoi` ("Real-world Experiments", Table 1) in the tabletop world
with the Panda: seeded, randomised trials and a report.

Same as `vslsp experiment tower-of-hanoi`; e.g.
    python experiments/tower_of_hanoi.py --trials 10 --workers 2 --out out/tower-of-hanoi
See vslsp/experiments/tabletop_protocol.py for what a trial does and how it is judged.
"""

import sys

from vslsp.cli import main

if __name__ == "__main__":
    main(["experiment", "tower-of-hanoi", *sys.argv[1:]])
