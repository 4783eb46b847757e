"""ANYmal-C velocity tracking, direct workflow (Isaac Lab's ``Isaac-Velocity-{Flat,Rough}-Anymal-C-Direct-v0``)."""

import gymnasium as gym

from . import agents

for terrain in ("Flat", "Rough"):
    gym.register(
        id=f"simlab/Velocity-{terrain}-Anymal-C-Direct-v0",
        entry_point=f"{__name__}.anymal_c_env:AnymalCEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.anymal_c_env:AnymalC{terrain}EnvCfg",
            "success_criterion_entry_point": f"{__name__}.criterion:tracks_velocity",
            "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:AnymalC{terrain}PPORunnerCfg",
        },
    )
