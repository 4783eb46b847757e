"""Humanoid AMP, direct workflow: imitate a walk, run or dance clip with adversarial motion priors (skrl's AMP).

Train with ``simlab train --task simlab/Humanoid-AMP-Walk-Direct-v0 --library skrl --algorithm AMP``.
"""

import gymnasium as gym

from . import agents

for _motion in ("Dance", "Run", "Walk"):
    gym.register(
        id=f"simlab/Humanoid-AMP-{_motion}-Direct-v0",
        entry_point=f"{__name__}.humanoid_amp_env:HumanoidAmpEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.humanoid_amp_env_cfg:HumanoidAmp{_motion}EnvCfg",
            "success_criterion_entry_point": f"{__name__}.criterion:imitates_clip",
            "skrl_amp_cfg_entry_point": f"{agents.__name__}:skrl_{_motion.lower()}_amp_cfg.yaml",
        },
    )
