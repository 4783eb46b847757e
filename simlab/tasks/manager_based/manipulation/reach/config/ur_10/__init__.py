"""UR10 reach tasks (Isaac Lab's ``Isaac-Reach-UR10-v0`` and its play variant)."""

import gymnasium as gym

from . import agents

for _suffix, _cfg in (("-v0", "UR10ReachEnvCfg"), ("-Play-v0", "UR10ReachEnvCfg_PLAY")):
    gym.register(
        id=f"simlab/Reach-UR10{_suffix}",
        entry_point="simlab.envs:ManagerBasedRLEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.joint_pos_env_cfg:{_cfg}",
            "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:UR10ReachNormalizedPPORunnerCfg",
            "success_criterion_entry_point": "simlab.tasks.manager_based.manipulation.reach.criterion:reaches_pose",
        },
    )
