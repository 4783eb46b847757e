"""Play (and export) a policy trained with rsl_rl: Isaac Lab's ``rsl_rl/play.py``, on simlab.

    python scripts/reinforcement_learning/rsl_rl/play.py --task simlab/Cartpole-v0 --headless [flags] [overrides]

It takes Isaac Lab's flags for this script and runs ``simlab play --library rsl_rl`` with them
(see simlab/cli/isaaclab_scripts.py); ``Isaac-*`` task ids are mapped to ``simlab/*``.
"""

import sys

from simlab.cli.isaaclab_scripts import play_main

if __name__ == "__main__":
    sys.exit(play_main("rsl_rl"))
