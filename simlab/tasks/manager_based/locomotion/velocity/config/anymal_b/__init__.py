"""ANYmal-B velocity tracking, flat and rough (Isaac Lab's ``Isaac-Velocity-*-Anymal-B-v0``)."""

import gymnasium as gym

from . import agents

_CRITERION = "simlab.tasks.manager_based.locomotion.velocity.criterion:tracks_velocity"

for terrain in ("Flat", "Rough"):
    for suffix, play in (("", ""), ("-Play", "_PLAY")):
        gym.register(
            id=f"simlab/Velocity-{terrain}-Anymal-B{suffix}-v0",
            entry_point="simlab.envs:ManagerBasedRLEnv",
            disable_env_checker=True,
            kwargs={
                "env_cfg_entry_point": f"{__name__}.{terrain.lower()}_env_cfg:AnymalB{terrain}EnvCfg{play}",
                "success_criterion_entry_point": _CRITERION,
                "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:AnymalB{terrain}PPORunnerCfg",
                "rsl_rl_with_symmetry_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:"
                f"AnymalB{terrain}PPORunnerWithSymmetryCfg",
            },
        )
