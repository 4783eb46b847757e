"""Play (and export) a policy trained with sb3: Isaac Lab's ``sb3/play.py``, on simlab.

    python scripts/reinforcement_learning/sb3/play.py --task simlab/Cartpole-v0 --headless [flags] [overrides]

It takes Isaac Lab's flags for this script and runs ``simlab play --library sb3`` with them
(see simlab/cli/isaaclab_scripts.py); ``Isaac-*`` task ids are mapped to ``simlab/*``.
"""

import sys

from simlab.cli.isaaclab_scripts import play_main

if __name__ == "__main__":
    sys.exit(play_main("sb3"))
