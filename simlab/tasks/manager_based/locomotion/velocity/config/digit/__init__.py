"""Agility Digit V4 velocity tracking, flat and rough (Isaac Lab's ``Isaac-Velocity-*-Digit-v0``).

Solved when a played policy tracks the commands (planar speed and yaw rate, few falls); on rough
ground, when the terrain curriculum keeps the robots at level 3 or higher (the Play variant, without
the curriculum, is judged by tracking).
"""

import gymnasium as gym

from . import agents

_CRITERIA = "simlab.tasks.manager_based.locomotion.velocity.criterion"

for terrain in ("Flat", "Rough"):
    for suffix, play in (("", ""), ("-Play", "_PLAY")):
        criterion = "reaches_terrain_level" if terrain == "Rough" and not play else "biped_tracks_velocity"
        gym.register(
            id=f"simlab/Velocity-{terrain}-Digit{suffix}-v0",
            entry_point="simlab.envs:ManagerBasedRLEnv",
            disable_env_checker=True,
            kwargs={
                "env_cfg_entry_point": f"{__name__}.{terrain.lower()}_env_cfg:Digit{terrain}EnvCfg{play}",
                "success_criterion_entry_point": f"{_CRITERIA}:{criterion}",
                "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:Digit{terrain}PPORunnerCfg",
            },
        )
