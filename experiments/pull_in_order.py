"""The paper's 'pull-in-order' experiment (VSL-SP results): seeded, randomised trials and a report.

Same as `vslsp experiment pull-in-order`; every option of that command works here, e.g.
    python experiments/pull_in_order.py --trials 20 --workers 2 --faults --out out/pull-in-order
See vslsp/experiments/icub_scripts.py for what a trial does and how success is judged.
"""

import sys

from vslsp.cli import main

if __name__ == "__main__":
    main(["experiment", "pull-in-order", *sys.argv[1:]])
