"""The paper's real-world task `animal-puzzle` ("Real-world Experiments", Table 1) in the tabletop world
with the Panda: seeded, randomised trials and a report.

Same as `vslsp experiment animal-puzzle`; e.g.
    python experiments/animal_puzzle.py --trials 10 --workers 2 --out out/animal-puzzle
See vslsp/experiments/tabletop_protocol.py for what a trial does and how it is judged.
"""

import sys

from vslsp.cli import main

if __name__ == "__main__":
    main(["experiment", "animal-puzzle", *sys.argv[1:]])
