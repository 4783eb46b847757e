"""Ant running forward, manager-based (Isaac Lab's ``Isaac-Ant-v0``)."""

import gymnasium as gym

from . import agents

gym.register(
    id="simlab/Ant-v0",
    entry_point="simlab.envs:ManagerBasedRLEnv",
    disable_env_checker=True,
    kwargs={
        "env_cfg_entry_point": f"{__name__}.ant_env_cfg:AntEnvCfg",
        "success_criterion_entry_point": "simlab.tasks.utils.criteria:runs_forward",
        "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:AntPPORunnerCfg",
    },
)
