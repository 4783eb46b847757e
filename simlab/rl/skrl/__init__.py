"""skrl (2.x) support: ``SkrlVecEnvWrapper`` for single- and multi-agent simlab envs.

Needs ``pip install "simlab[skrl]"``. Agents, models, memories and trainers come from skrl's
``Runner`` and the task's ``skrl_*_cfg.yaml``.
"""

from .vecenv_wrapper import SkrlVecEnvWrapper

__all__ = ["SkrlVecEnvWrapper"]
