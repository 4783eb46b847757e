"""Franka cabinet, direct workflow: open a cabinet's top drawer with the Franka arm."""

import gymnasium as gym

from . import agents

for _suffix, _cfg in (("-v0", "FrankaCabinetEnvCfg"), ("-Play-v0", "FrankaCabinetEnvCfg_PLAY")):
    gym.register(
        id=f"simlab/Franka-Cabinet-Direct{_suffix}",
        entry_point=f"{__name__}.franka_cabinet_env:FrankaCabinetEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.franka_cabinet_env:{_cfg}",
            "success_criterion_entry_point": f"{__name__}.criterion:drawer_opens",
            "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:FrankaCabinetPPORunnerCfg",
            "skrl_cfg_entry_point": f"{agents.__name__}:skrl_ppo_cfg.yaml",
            "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_cfg.yaml",
        },
    )
