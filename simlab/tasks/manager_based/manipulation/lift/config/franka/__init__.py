"""Franka lift tasks (Isaac Lab's ``Isaac-Lift-Cube-Franka-v0`` and its IK variants)."""

import gymnasium as gym

from . import agents

_CRITERION = "simlab.tasks.manager_based.manipulation.lift.criterion:cube_reaches_goal"
_RSL_RL = f"{agents.__name__}.rsl_rl_ppo_cfg:LiftCubePPORunnerCfg"

for _task, _module in (("", "joint_pos_env_cfg"), ("-IK-Abs", "ik_abs_env_cfg"), ("-IK-Rel", "ik_rel_env_cfg")):
    for _suffix, _cfg in (("-v0", "FrankaCubeLiftEnvCfg"), ("-Play-v0", "FrankaCubeLiftEnvCfg_PLAY")):
        gym.register(
            id=f"simlab/Lift-Cube-Franka{_task}{_suffix}",
            entry_point="simlab.envs:ManagerBasedRLEnv",
            disable_env_checker=True,
            kwargs={
                "env_cfg_entry_point": f"{__name__}.{_module}:{_cfg}",
                "rsl_rl_cfg_entry_point": _RSL_RL,
                "success_criterion_entry_point": _CRITERION,
            },
        )
