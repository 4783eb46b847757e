"""Unitree G1 motion tracking on flat ground (``simlab/Tracking-Flat-G1-v0``)."""

import gymnasium as gym

from . import agents

for suffix, play in (("", ""), ("-Play", "_PLAY")):
    gym.register(
        id=f"simlab/Tracking-Flat-G1{suffix}-v0",
        entry_point="simlab.envs:ManagerBasedRLEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.flat_env_cfg:G1FlatTrackingEnvCfg{play}",
            "success_criterion_entry_point": "simlab.tasks.manager_based.tracking.criterion:tracks_clip",
            "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:G1FlatTrackingPPORunnerCfg",
        },
    )
