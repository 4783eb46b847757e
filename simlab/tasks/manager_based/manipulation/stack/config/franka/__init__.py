"""Franka cube-stacking tasks (Isaac Lab's ``Isaac-Stack-Cube-Franka-v0``, ``-IK-Rel-v0``, ``-IK-Abs-v0``).

Isaac Lab trains these from demonstrations (robomimic's BC-RNN), not with RL, so no RL agent is
registered; the criterion judges any policy by the share of episodes that end with the three cubes
stacked.
"""

import gymnasium as gym

_CRITERION = "simlab.tasks.manager_based.manipulation.stack.criterion:stacks_cubes"

for _suffix, _module in (
    ("", "stack_joint_pos_env_cfg"),
    ("-IK-Rel", "stack_ik_rel_env_cfg"),
    ("-IK-Abs", "stack_ik_abs_env_cfg"),
):
    gym.register(
        id=f"simlab/Stack-Cube-Franka{_suffix}-v0",
        entry_point="simlab.envs:ManagerBasedRLEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.{_module}:FrankaCubeStackEnvCfg",
            "success_criterion_entry_point": _CRITERION,
        },
    )
