"""Unitree G1 motion tracking on flat ground, one policy per clip: ``simlab/Tracking-Flat-G1-v0`` tracks
the walk clip, ``simlab/Tracking-Flat-G1-{Turn,Wave,Twist}-v0`` the other shipped clips."""

import gymnasium as gym

from . import agents

for clip in ("", "Turn", "Wave", "Twist"):
    for suffix, play in (("", ""), ("-Play", "_PLAY")):
        gym.register(
            id=f"simlab/Tracking-Flat-G1{'-' + clip if clip else ''}{suffix}-v0",
            entry_point="simlab.envs:ManagerBasedRLEnv",
            disable_env_checker=True,
            kwargs={
                "env_cfg_entry_point": f"{__name__}.flat_env_cfg:G1FlatTracking{clip}EnvCfg{play}",
                "success_criterion_entry_point": "simlab.tasks.manager_based.tracking.criterion:tracks_clip",
                "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:G1FlatTrackingPPORunnerCfg",
            },
        )
