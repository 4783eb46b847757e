"""Cartpole balancing, manager-based (Isaac Lab's ``Isaac-Cartpole-v0``)."""

import gymnasium as gym

from . import agents

# a student taught by the state cartpole's PPO policy (the camera tasks' reads the `teacher` group)
_DISTILLATION = f"{agents.__name__}.rsl_rl_distillation_cfg"

gym.register(
    id="simlab/Cartpole-v0",
    entry_point="simlab.envs:ManagerBasedRLEnv",
    disable_env_checker=True,
    kwargs={
        "env_cfg_entry_point": f"{__name__}.cartpole_env_cfg:CartpoleEnvCfg",
        "success_criterion_entry_point": "simlab.tasks.utils.criteria:pole_upright",
        "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:CartpolePPORunnerCfg",
        "rsl_rl_with_symmetry_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:CartpolePPORunnerWithSymmetryCfg",
        "rsl_rl_distillation_cfg_entry_point": f"{_DISTILLATION}:CartpoleDistillationRunnerCfg",
        "skrl_cfg_entry_point": f"{agents.__name__}:skrl_ppo_cfg.yaml",
        "sb3_cfg_entry_point": f"{agents.__name__}:sb3_ppo_cfg.yaml",
        "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_cfg.yaml",
    },
)

# From pixels (Isaac Lab's cartpole_camera_env_cfg). Isaac Lab registers an rl_games config only; the
# direct camera cartpole's agents (a CNN over the same 100 x 100 image) serve all three libraries here.
_CAMERA_AGENTS = "simlab.tasks.direct.cartpole.agents"
for _kind in ("RGB", "Depth"):
    gym.register(
        id=f"simlab/Cartpole-{_kind}-v0",
        entry_point="simlab.envs:ManagerBasedRLEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.cartpole_camera_env_cfg:Cartpole{_kind}CameraEnvCfg",
            "success_criterion_entry_point": "simlab.tasks.utils.criteria:pole_upright",
            "rl_games_cfg_entry_point": f"{_CAMERA_AGENTS}:rl_games_camera_ppo_cfg.yaml",
            "rsl_rl_cfg_entry_point": f"{_CAMERA_AGENTS}.rsl_rl_camera_ppo_cfg:CartpoleCameraPPORunnerCfg",
            "rsl_rl_distillation_cfg_entry_point": f"{_DISTILLATION}:CartpoleCameraDistillationRunnerCfg",
            "skrl_cfg_entry_point": f"{_CAMERA_AGENTS}:skrl_camera_ppo_cfg.yaml",
        },
    )
