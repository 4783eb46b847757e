"""Two Shadow Hands pass a ball, direct multi-agent workflow (Isaac Lab's ``direct/shadow_hand_over``)."""

import gymnasium as gym

from . import agents

gym.register(
    id="simlab/Shadow-Hand-Over-Direct-v0",
    entry_point=f"{__name__}.shadow_hand_over_env:ShadowHandOverEnv",
    disable_env_checker=True,
    kwargs={
        "env_cfg_entry_point": f"{__name__}.shadow_hand_over_env_cfg:ShadowHandOverEnvCfg",
        "success_criterion_entry_point": f"{__name__}.criterion:ball_caught",
        "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_cfg.yaml",
        "skrl_cfg_entry_point": f"{agents.__name__}:skrl_ppo_cfg.yaml",
        "skrl_ippo_cfg_entry_point": f"{agents.__name__}:skrl_ippo_cfg.yaml",
        "skrl_mappo_cfg_entry_point": f"{agents.__name__}:skrl_mappo_cfg.yaml",
    },
)
