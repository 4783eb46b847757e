"""Agility Digit loco-manipulation tracking (Isaac Lab's ``Isaac-Tracking-LocoManip-Digit-v0``).

Solved when a played policy tracks the velocity commands as the velocity tasks' bipeds must, with few
falls, and the hands end their command windows near the commanded positions (``../../criterion.py``).
"""

import gymnasium as gym

from . import agents

for suffix, play in (("", ""), ("-Play", "_PLAY")):
    gym.register(
        id=f"simlab/Tracking-LocoManip-Digit{suffix}-v0",
        entry_point="simlab.envs:ManagerBasedRLEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.loco_manip_env_cfg:DigitLocoManipEnvCfg{play}",
            "success_criterion_entry_point": (
                "simlab.tasks.manager_based.locomanipulation.tracking.criterion:tracks_velocity_and_hands"
            ),
            "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:DigitLocoManipPPORunnerCfg",
        },
    )
