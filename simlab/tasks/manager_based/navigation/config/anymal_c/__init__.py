"""ANYmal-C navigation on flat ground (Isaac Lab's ``Isaac-Navigation-Flat-Anymal-C-v0``)."""

import gymnasium as gym

from . import agents

for suffix, play in (("", ""), ("-Play", "_PLAY")):
    gym.register(
        id=f"simlab/Navigation-Flat-Anymal-C{suffix}-v0",
        entry_point="simlab.envs:ManagerBasedRLEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.navigation_env_cfg:NavigationEnvCfg{play}",
            "success_criterion_entry_point": "simlab.tasks.manager_based.navigation.criterion:reaches_goal_pose",
            "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:NavigationEnvPPORunnerCfg",
        },
    )
