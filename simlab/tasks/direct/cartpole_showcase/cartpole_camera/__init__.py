"""The spaces showcase on the direct RGB camera cartpole (Isaac Lab's
``Isaac-Cartpole-Camera-Showcase-<Obs>-<Act>-Direct-v0``): a Box (the image), Dict or Tuple (the image
and the joint velocities) observation space with a Box, Discrete or MultiDiscrete action space."""

import gymnasium as gym

from ..cartpole import agents

OBSERVATIONS = ("Box", "Dict", "Tuple")
ACTIONS = ("Box", "Discrete", "MultiDiscrete")

for _obs in OBSERVATIONS:
    for _act in ACTIONS:
        gym.register(
            id=f"simlab/Cartpole-Camera-Showcase-{_obs}-{_act}-Direct-v0",
            entry_point=f"{__name__}.cartpole_camera_env:CartpoleCameraShowcaseEnv",
            disable_env_checker=True,
            kwargs={
                "env_cfg_entry_point": f"{__name__}.cartpole_camera_env_cfg:{_obs}{_act}EnvCfg",
                "success_criterion_entry_point": "simlab.tasks.utils.criteria:pole_upright",
                "skrl_cfg_entry_point": f"{agents.__name__}.skrl_ppo_cfg:camera_{_obs.lower()}_{_act.lower()}",
            },
        )
