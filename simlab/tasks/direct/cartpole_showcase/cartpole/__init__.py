"""The spaces showcase on the direct cartpole (Isaac Lab's ``Isaac-Cartpole-Showcase-<Obs>-<Act>-Direct-v0``):
every pair of a Box, Discrete, MultiDiscrete, Dict or Tuple observation space and a Box, Discrete or
MultiDiscrete action space."""

import gymnasium as gym

from . import agents

OBSERVATIONS = ("Box", "Discrete", "MultiDiscrete", "Dict", "Tuple")
ACTIONS = ("Box", "Discrete", "MultiDiscrete")

for _obs in OBSERVATIONS:
    for _act in ACTIONS:
        gym.register(
            id=f"simlab/Cartpole-Showcase-{_obs}-{_act}-Direct-v0",
            entry_point=f"{__name__}.cartpole_env:CartpoleShowcaseEnv",
            disable_env_checker=True,
            kwargs={
                "env_cfg_entry_point": f"{__name__}.cartpole_env_cfg:{_obs}{_act}EnvCfg",
                "success_criterion_entry_point": "simlab.tasks.utils.criteria:pole_upright",
                "skrl_cfg_entry_point": f"{agents.__name__}.skrl_ppo_cfg:{_obs.lower()}_{_act.lower()}",
            },
        )
