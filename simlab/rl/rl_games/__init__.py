"""rl_games (1.6.5) support: ``RlGamesVecEnvWrapper``, ``RlGamesGpuEnv`` and their registration.

Needs ``pip install "simlab[rl_games]"`` (kept optional: rl-games pins ``psutil<6`` and pulls
pygame-ce). Its ``torch_compile`` option defaults to on and needs a C++ compiler; the task configs
set ``torch_compile: False``.
"""

from .rl_games import RlGamesGpuEnv, RlGamesVecEnvWrapper, SimlabAlgoObserver, register_rl_games_env

__all__ = ["RlGamesGpuEnv", "RlGamesVecEnvWrapper", "SimlabAlgoObserver", "register_rl_games_env"]
