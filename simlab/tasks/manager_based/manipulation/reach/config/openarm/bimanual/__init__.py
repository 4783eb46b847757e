"""Two-arm OpenArm reach (Isaac Lab's ``Isaac-Reach-OpenArm-Bi-v0`` and its play variant)."""

import gymnasium as gym

from . import agents

for _suffix, _cfg in (("-v0", "OpenArmReachEnvCfg"), ("-Play-v0", "OpenArmReachEnvCfg_PLAY")):
    gym.register(
        id=f"simlab/Reach-OpenArm-Bi{_suffix}",
        entry_point="simlab.envs:ManagerBasedRLEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.joint_pos_env_cfg:{_cfg}",
            "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:OpenArmReachPPORunnerCfg",
            "skrl_cfg_entry_point": f"{agents.__name__}:skrl_ppo_cfg.yaml",
            "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_cfg.yaml",
            "success_criterion_entry_point": (
                "simlab.tasks.manager_based.manipulation.reach.criterion:reaches_pose_with_both_hands"
            ),
        },
    )
