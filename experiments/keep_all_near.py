"""The paper's 'keep-all-near' experiment (VSL-SP results): seeded, randomised trials and a report.

Same as `vslsp experiment keep-all-near`; every option of that command works here, e.g.
    python experiments/keep_all_near.py --trials 20 --workers 2 --faults --out out/keep-all-near
See vslsp/experiments/icub_scripts.py for what a trial does and how success is judged.
"""

import sys

from vslsp.cli import main

if __name__ == "__main__":
    main(["experiment", "keep-all-near", *sys.argv[1:]])
