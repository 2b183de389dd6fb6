"""The paper's 'simple-vsl-task' experiment (VSL-SP results): seeded, randomised trials and a report.

Same as `vslsp experiment simple-vsl-task`; every option of that command works here, e.g.
    python experiments/simple_vsl_task.py --trials 20 --workers 2 --faults --out out/simple-vsl-task
See vslsp/experiments/icub_scripts.py for what a trial does and how success is judged.
"""

import sys

from vslsp.cli import main

if __name__ == "__main__":
    main(["experiment", "simple-vsl-task", *sys.argv[1:]])
