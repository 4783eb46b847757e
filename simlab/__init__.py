"""simlab: Isaac Lab's robot-learning API on MuJoCo (CPU, via mjbatch) and MuJoCo Warp (GPU)."""

import time as _time

_IMPORTED_AT = _time.time()  # when this program's own code began (simlab.utils.startup)

from simlab.utils.gl_backend import set_aside_missing_backend as _set_aside_missing_backend  # noqa: E402

__version__ = "0.1.0"

_set_aside_missing_backend()  # before anything imports mujoco
