"""Isaac Sim's torch helpers (``isaacsim.core.utils.torch``), which Isaac Lab 2.x task files import
(``import isaacsim.core.utils.torch as torch_utils``; map it to ``simlab.utils.torch_utils``).

Quaternions are ``(w, x, y, z)``, as in Isaac Sim 4.x and the rest of simlab. Most are simlab's
``simlab.utils.math`` functions under Isaac Sim's names; the locomotion helpers
(``compute_heading_and_up``, ``compute_rot``) are IsaacGymEnvs'.
"""

from simlab.utils.seed import set_seed

from . import maths, rotations, transformations
from .maths import *  # noqa: F403
from .rotations import *  # noqa: F403
from .transformations import *  # noqa: F403

__all__ = ["maths", "rotations", "set_seed", "transformations", *maths.__all__, *rotations.__all__]
__all__ += transformations.__all__
