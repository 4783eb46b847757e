"""Quadcopter, direct workflow: fly a Crazyflie to a goal position."""

import gymnasium as gym

from . import agents

gym.register(
    id="simlab/Quadcopter-Direct-v0",
    entry_point="simlab.tasks.direct.quadcopter.quadcopter_env:QuadcopterEnv",
    disable_env_checker=True,
    kwargs={
        "env_cfg_entry_point": "simlab.tasks.direct.quadcopter.quadcopter_env:QuadcopterEnvCfg",
        "success_criterion_entry_point": "simlab.tasks.direct.quadcopter.criterion:reaches_goal",
        "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:QuadcopterPPORunnerCfg",
        "skrl_cfg_entry_point": f"{agents.__name__}:skrl_ppo_cfg.yaml",
        "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_cfg.yaml",
    },
)
