"""Isaac Lab 3.0's unified train entry point (``isaaclab train``), on simlab.

    python scripts/reinforcement_learning/train.py --rl_library rsl_rl --task Isaac-Cartpole [flags] [physics=...]

It runs ``simlab train`` with the same words; simlab/cli/isaaclab3.py translates Isaac Lab 3.0's
(``--rl_library``, version-less task ids, ``--viz``, ``physics=``, ``renderer=``, ``presets=``).
"""

import sys

from simlab.cli.main import main

if __name__ == "__main__":
    sys.argv = ["simlab", "train", *sys.argv[1:]]
    sys.exit(main())
