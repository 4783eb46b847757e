"""Boston Dynamics Spot velocity tracking on Isaac Lab's cobblestone road (``Isaac-Velocity-Flat-Spot-v0``)."""

import gymnasium as gym

from . import agents

_CRITERION = "simlab.tasks.manager_based.locomotion.velocity.criterion:tracks_velocity"

for suffix, play in (("", ""), ("-Play", "_PLAY")):
    gym.register(
        id=f"simlab/Velocity-Flat-Spot{suffix}-v0",
        entry_point="simlab.envs:ManagerBasedRLEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.flat_env_cfg:SpotFlatEnvCfg{play}",
            "success_criterion_entry_point": _CRITERION,
            "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:SpotFlatPPORunnerCfg",
        },
    )
