"""Unitree H1 velocity tracking, flat and rough (Isaac Lab's ``Isaac-Velocity-*-H1-v0``)."""

import gymnasium as gym

from . import agents

for terrain in ("Flat", "Rough"):
    for suffix, play in (("", ""), ("-Play", "_PLAY")):
        gym.register(
            id=f"simlab/Velocity-{terrain}-H1{suffix}-v0",
            entry_point="simlab.envs:ManagerBasedRLEnv",
            disable_env_checker=True,
            kwargs={
                "env_cfg_entry_point": f"{__name__}.{terrain.lower()}_env_cfg:H1{terrain}EnvCfg{play}",
                "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:H1{terrain}PPORunnerCfg",
            },
        )
