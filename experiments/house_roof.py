"""The paper's house-and-roof simulation ("Simulation"): seeded, randomised trials and a report.

Same as `vslsp experiment house-roof`; e.g.
    python experiments/house_roof.py --trials 20 --workers 2 --out out/house-roof
See vslsp/experiments/house_roof_trial.py for what a trial does and how it is judged.
"""

import sys

from vslsp.cli import main

if __name__ == "__main__":
    main(["experiment", "house-roof", *sys.argv[1:]])
