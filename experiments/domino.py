"""The paper's real-world task `domino` ("Real-world Experiments", Table 1) in the tabletop world
with the Panda: seeded, randomised trials and a report.

Same as `vslsp experiment domino`; e.g.
    python experiments/domino.py --trials 10 --workers 2 --out out/domino
See vslsp/experiments/tabletop_protocol.py for what a trial does and how it is judged.
"""

import sys

from vslsp.cli import main

if __name__ == "__main__":
    main(["experiment", "domino", *sys.argv[1:]])
