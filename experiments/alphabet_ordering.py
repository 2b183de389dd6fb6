"""The paper's real-world task `alphabet-ordering` ("Real-world Experiments", Table 1) in the tabletop world
with the Panda: seeded, randomised trials and a report.

Same as `vslsp experiment alphabet-ordering`; e.g.
    python experiments/alphabet_ordering.py --trials 10 --workers 2 --out out/alphabet-ordering
See vslsp/experiments/tabletop_protocol.py for what a trial does and how it is judged.
"""

import sys

from vslsp.cli import main

if __name__ == "__main__":
    main(["experiment", "alphabet-ordering", *sys.argv[1:]])
