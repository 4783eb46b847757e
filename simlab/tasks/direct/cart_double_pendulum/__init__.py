"""Cart double pendulum, direct multi-agent workflow: a cart agent and a pendulum agent."""

import gymnasium as gym

from . import agents

_ENV = "simlab.tasks.direct.cart_double_pendulum.cart_double_pendulum_env"

gym.register(
    id="simlab/Cart-Double-Pendulum-Direct-v0",
    entry_point=f"{_ENV}:CartDoublePendulumEnv",
    disable_env_checker=True,
    kwargs={
        "env_cfg_entry_point": f"{_ENV}:CartDoublePendulumEnvCfg",
        "success_criterion_entry_point": "simlab.tasks.direct.cart_double_pendulum.criterion:both_poles_upright",
        "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:CartDoublePendulumPPORunnerCfg",
        "skrl_cfg_entry_point": f"{agents.__name__}:skrl_ppo_cfg.yaml",
        "skrl_ippo_cfg_entry_point": f"{agents.__name__}:skrl_ippo_cfg.yaml",
        "skrl_mappo_cfg_entry_point": f"{agents.__name__}:skrl_mappo_cfg.yaml",
        "sb3_cfg_entry_point": f"{agents.__name__}:sb3_ppo_cfg.yaml",
        "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_cfg.yaml",
    },
)
