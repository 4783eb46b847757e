"""Humanoid running forward, manager-based (Isaac Lab's ``Isaac-Humanoid-v0``)."""

import gymnasium as gym

from . import agents

gym.register(
    id="simlab/Humanoid-v0",
    entry_point="simlab.envs:ManagerBasedRLEnv",
    disable_env_checker=True,
    kwargs={
        "env_cfg_entry_point": f"{__name__}.humanoid_env_cfg:HumanoidEnvCfg",
        "success_criterion_entry_point": "simlab.tasks.utils.criteria:runs_forward",
        "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:HumanoidPPORunnerCfg",
    },
)
