"""Franka reach tasks (Isaac Lab's ``Isaac-Reach-Franka-v0`` and its IK and OSC variants)."""

import gymnasium as gym

from . import agents

# Isaac Lab's agent with normalized observations and larger networks (see its docstring), for every
# action space: each policy has to read the same commanded pose
_CRITERION = "simlab.tasks.manager_based.manipulation.reach.criterion:reaches_pose"
_RSL_RL = f"{agents.__name__}.rsl_rl_ppo_cfg:FrankaReachNormalizedPPORunnerCfg"

_VARIANTS = (
    ("", "joint_pos_env_cfg"),
    ("-IK-Abs", "ik_abs_env_cfg"),
    ("-IK-Rel", "ik_rel_env_cfg"),
    ("-OSC", "osc_env_cfg"),
)

for _task, _module in _VARIANTS:
    for _suffix, _cfg in (("-v0", "FrankaReachEnvCfg"), ("-Play-v0", "FrankaReachEnvCfg_PLAY")):
        gym.register(
            id=f"simlab/Reach-Franka{_task}{_suffix}",
            entry_point="simlab.envs:ManagerBasedRLEnv",
            disable_env_checker=True,
            kwargs={
                "env_cfg_entry_point": f"{__name__}.{_module}:{_cfg}",
                "rsl_rl_cfg_entry_point": _RSL_RL,
                "success_criterion_entry_point": _CRITERION,
            },
        )
