"""Cartpole, direct workflow: balance a pole on a cart pushed along a rail."""

import gymnasium as gym

from . import agents

gym.register(
    id="simlab/Cartpole-Direct-v0",
    entry_point="simlab.tasks.direct.cartpole.cartpole_env:CartpoleEnv",
    disable_env_checker=True,
    kwargs={
        "env_cfg_entry_point": "simlab.tasks.direct.cartpole.cartpole_env:CartpoleEnvCfg",
        "success_criterion_entry_point": "simlab.tasks.utils.criteria:pole_upright",
        "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:CartpolePPORunnerCfg",
        "skrl_cfg_entry_point": f"{agents.__name__}:skrl_ppo_cfg.yaml",
        "sb3_cfg_entry_point": f"{agents.__name__}:sb3_ppo_cfg.yaml",
        "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_cfg.yaml",
    },
)

for _kind in ("RGB", "Depth"):
    gym.register(
        id=f"simlab/Cartpole-{_kind}-Camera-Direct-v0",
        entry_point="simlab.tasks.direct.cartpole.cartpole_camera_env:CartpoleCameraEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"simlab.tasks.direct.cartpole.cartpole_camera_env:Cartpole{_kind}CameraEnvCfg",
            "success_criterion_entry_point": "simlab.tasks.utils.criteria:pole_upright",
            "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_camera_ppo_cfg.yaml",
            "skrl_cfg_entry_point": f"{agents.__name__}:skrl_camera_ppo_cfg.yaml",
            "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_camera_ppo_cfg:CartpoleCameraPPORunnerCfg",
        },
    )

# Isaac Lab 3.0's single camera task: the variants are presets (`presets=rgb`, `presets=depth`), RGB by default
_CAMERA_CFG = "simlab.tasks.direct.cartpole.cartpole_camera_env:Cartpole{}CameraEnvCfg"
gym.register(
    id="simlab/Cartpole-Camera-Direct-v0",
    entry_point="simlab.tasks.direct.cartpole.cartpole_camera_env:CartpoleCameraEnv",
    disable_env_checker=True,
    kwargs={
        "env_cfg_entry_point": _CAMERA_CFG.format("RGB"),
        "presets": {
            "rgb": {"env_cfg_entry_point": _CAMERA_CFG.format("RGB")},
            "depth": {"env_cfg_entry_point": _CAMERA_CFG.format("Depth")},
        },
        "success_criterion_entry_point": "simlab.tasks.utils.criteria:pole_upright",
        "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_camera_ppo_cfg.yaml",
        "skrl_cfg_entry_point": f"{agents.__name__}:skrl_camera_ppo_cfg.yaml",
        "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_camera_ppo_cfg:CartpoleCameraPPORunnerCfg",
    },
)
