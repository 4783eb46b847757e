"""simlab: Isaac Lab's robot-learning API on MuJoCo (CPU, via mjbatch) and MuJoCo Warp (GPU)."""

from simlab.utils.gl_backend import set_aside_missing_backend as _set_aside_missing_backend

__version__ = "0.1.0"

_set_aside_missing_backend()  # before anything imports mujoco
