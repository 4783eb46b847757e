"""Franka cube-stacking tasks (Isaac Lab's ``Isaac-Stack-Cube-Franka-v0``, ``-IK-Rel-v0``, ``-IK-Abs-v0``,
and ``Isaac-Stack-Cube-Instance-Randomize-Franka-v0`` and ``-IK-Rel-v0``, a random pick of cubes per env).

Isaac Lab trains these from demonstrations (robomimic's BC-RNN), not with RL, so no RL agent is
registered; the criterion judges any policy by the share of episodes that end with the three cubes
stacked. The IK-Abs task and both IK-Rel tasks (plain and instance-randomized) register simlab's
behaviour cloning (``bc_cfg_entry_point``, where Isaac Lab registers ``robomimic_bc_cfg_entry_point``):
their policies are shipped (``simlab play --library bc``).
"""

import gymnasium as gym

from . import agents

_CRITERION = "simlab.tasks.manager_based.manipulation.stack.criterion:stacks_cubes"
# cloned from each task's own demonstrations (the IK-Abs targets, the IK-Rel deltas)
_AGENTS = {
    "Stack-Cube-Franka-IK-Abs-v0": {"bc_cfg_entry_point": f"{agents.__name__}.bc_cfg:StackCubeBCCfg"},
    "Stack-Cube-Franka-IK-Rel-v0": {"bc_cfg_entry_point": f"{agents.__name__}.bc_cfg:StackCubeIKRelBCCfg"},
    "Stack-Cube-Instance-Randomize-Franka-IK-Rel-v0": {
        "bc_cfg_entry_point": f"{agents.__name__}.bc_cfg:StackCubeIKRelBCCfg"
    },
}

for _id, _cfg in (
    ("Stack-Cube-Franka-v0", "stack_joint_pos_env_cfg:FrankaCubeStackEnvCfg"),
    ("Stack-Cube-Franka-IK-Rel-v0", "stack_ik_rel_env_cfg:FrankaCubeStackEnvCfg"),
    ("Stack-Cube-Franka-IK-Abs-v0", "stack_ik_abs_env_cfg:FrankaCubeStackEnvCfg"),
    (
        "Stack-Cube-Instance-Randomize-Franka-v0",
        "stack_joint_pos_instance_randomize_env_cfg:FrankaCubeStackInstanceRandomizeEnvCfg",
    ),
    (
        "Stack-Cube-Instance-Randomize-Franka-IK-Rel-v0",
        "stack_ik_rel_instance_randomize_env_cfg:FrankaCubeStackInstanceRandomizeEnvCfg",
    ),
):
    gym.register(
        id=f"simlab/{_id}",
        entry_point="simlab.envs:ManagerBasedRLEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.{_cfg}",
            "success_criterion_entry_point": _CRITERION,
            **_AGENTS.get(_id, {}),
        },
    )
