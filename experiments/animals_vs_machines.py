"""The paper's real-world task `animals-vs-machines` ("Real-world Experiments", Table 1) in the tabletop world
with the Panda: seeded, randomised trials and a report.

Same as `vslsp experiment animals-vs-machines`; e.g.
    python experiments/animals_vs_machines.py --trials 10 --workers 2 --out out/animals-vs-machines
See vslsp/experiments/tabletop_protocol.py for what a trial does and how it is judged.
"""

import sys

from vslsp.cli import main

if __name__ == "__main__":
    main(["experiment", "animals-vs-machines", *sys.argv[1:]])
