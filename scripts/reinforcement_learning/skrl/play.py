"""Play (and export) a policy trained with skrl: Isaac Lab's ``skrl/play.py``, on simlab.

    python scripts/reinforcement_learning/skrl/play.py --task simlab/Cartpole-v0 --headless [flags] [overrides]

It takes Isaac Lab's flags for this script and runs ``simlab play --library skrl`` with them
(see simlab/cli/isaaclab_scripts.py); ``Isaac-*`` task ids are mapped to ``simlab/*``.
"""

import sys

from simlab.cli.isaaclab_scripts import play_main

if __name__ == "__main__":
    sys.exit(play_main("skrl"))
