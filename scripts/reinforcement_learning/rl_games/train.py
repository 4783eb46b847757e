"""Train an RL agent with rl_games: Isaac Lab's ``rl_games/train.py``, on simlab.

    python scripts/reinforcement_learning/rl_games/train.py --task simlab/Cartpole-v0 --headless [flags] [overrides]

It takes Isaac Lab's flags for this script and runs ``simlab train --library rl_games`` with them
(see simlab/cli/isaaclab_scripts.py); ``Isaac-*`` task ids are mapped to ``simlab/*``.
"""

import sys

from simlab.cli.isaaclab_scripts import train_main

if __name__ == "__main__":
    sys.exit(train_main("rl_games"))
