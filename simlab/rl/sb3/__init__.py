"""Stable-Baselines3 (2.x) support: ``Sb3VecEnvWrapper`` and ``process_sb3_cfg``.

Needs ``pip install "simlab[sb3]"``.
"""

from .vecenv_wrapper import Sb3VecEnvWrapper, process_sb3_cfg

__all__ = ["Sb3VecEnvWrapper", "process_sb3_cfg"]
