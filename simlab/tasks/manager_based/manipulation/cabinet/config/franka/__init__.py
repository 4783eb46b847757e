"""Franka cabinet tasks (Isaac Lab's ``Isaac-Open-Drawer-Franka-v0`` and its IK variants)."""

import gymnasium as gym

from . import agents

_CRITERION = "simlab.tasks.manager_based.manipulation.cabinet.criterion:drawer_opens"
_RSL_RL = f"{agents.__name__}.rsl_rl_ppo_cfg:CabinetPPORunnerCfg"

for _task, _module in (("", "joint_pos_env_cfg"), ("-IK-Abs", "ik_abs_env_cfg"), ("-IK-Rel", "ik_rel_env_cfg")):
    for _suffix, _cfg in (("-v0", "FrankaCabinetEnvCfg"), ("-Play-v0", "FrankaCabinetEnvCfg_PLAY")):
        # Isaac Lab now ships agent configs for the joint-position task only; its earlier (Orbit)
        # releases gave the IK variants the same rsl_rl config, as simlab does (and for lift's), so
        # every drawer task trains and ships a policy
        gym.register(
            id=f"simlab/Open-Drawer-Franka{_task}{_suffix}",
            entry_point="simlab.envs:ManagerBasedRLEnv",
            disable_env_checker=True,
            kwargs={
                "env_cfg_entry_point": f"{__name__}.{_module}:{_cfg}",
                "rsl_rl_cfg_entry_point": _RSL_RL,
                "success_criterion_entry_point": _CRITERION,
            },
        )
