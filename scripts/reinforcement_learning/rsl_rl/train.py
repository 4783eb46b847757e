"""Train an RL agent with rsl_rl: Isaac Lab's ``rsl_rl/train.py``, on simlab.

    python scripts/reinforcement_learning/rsl_rl/train.py --task simlab/Cartpole-v0 --headless [flags] [overrides]

It takes Isaac Lab's flags for this script and runs ``simlab train --library rsl_rl`` with them
(see simlab/cli/isaaclab_scripts.py); ``Isaac-*`` task ids are mapped to ``simlab/*``.
"""

import sys

from simlab.cli.isaaclab_scripts import train_main

if __name__ == "__main__":
    sys.exit(train_main("rsl_rl"))
