"""Ant, direct workflow: run forward without falling (LocomotionEnv)."""

import gymnasium as gym

from . import agents

gym.register(
    id="simlab/Ant-Direct-v0",
    entry_point="simlab.tasks.direct.ant.ant_env:AntEnv",
    disable_env_checker=True,
    kwargs={
        "env_cfg_entry_point": "simlab.tasks.direct.ant.ant_env:AntEnvCfg",
        "success_criterion_entry_point": "simlab.tasks.utils.criteria:runs_forward",
        "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:AntPPORunnerCfg",
        "skrl_cfg_entry_point": f"{agents.__name__}:skrl_ppo_cfg.yaml",
        "sb3_cfg_entry_point": f"{agents.__name__}:sb3_ppo_cfg.yaml",
        "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_cfg.yaml",
    },
)
