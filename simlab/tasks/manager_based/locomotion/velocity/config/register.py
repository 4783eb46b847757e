"""Registers one robot's velocity tasks: ``simlab/Velocity-<Terrain>-<Robot>(-Play)-v0`` for each terrain.

Each robot's package holds Isaac Lab's file layout and class names, which the ids follow: the task
``Velocity-Rough-Unitree-Go1-Play-v0`` is ``rough_env_cfg:UnitreeGo1RoughEnvCfg_PLAY`` with the runner
``agents/rsl_rl_ppo_cfg:UnitreeGo1RoughPPORunnerCfg`` (the class prefix is the robot's id name without
its hyphens).
"""

from __future__ import annotations

import gymnasium as gym

_CRITERIA = "simlab.tasks.manager_based.locomotion.velocity.criterion"


def register_velocity_tasks(
    package: str,
    robot: str,
    terrains: tuple[str, ...] = ("Flat", "Rough"),
    biped: bool = False,
    symmetry: bool = False,
    distillation: tuple[str, ...] = (),
) -> None:
    """Register ``robot``'s tasks from the configs in ``package`` (the robot's ``__name__``).

    A quadruped is solved when it tracks the planar velocity; a biped when it tracks the planar velocity
    and the yaw rate with few falls, and on rough ground (but for Play, which has no curriculum) when the
    terrain curriculum keeps it at level 3 or higher. ``symmetry`` adds the runner with symmetry
    augmentation (``...PPORunnerWithSymmetryCfg``); ``distillation`` names the terrains with a student-teacher
    runner (``agents/rsl_rl_distillation_cfg:...DistillationRunnerCfg``, ``--agent
    rsl_rl_distillation_cfg_entry_point``)."""
    prefix = robot.replace("-", "")
    runners = f"{package}.agents.rsl_rl_ppo_cfg"
    for terrain in terrains:
        for suffix, play in (("", ""), ("-Play", "_PLAY")):
            if not biped:
                criterion = "tracks_velocity"
            elif terrain == "Rough" and not play:
                criterion = "reaches_terrain_level"
            else:
                criterion = "biped_tracks_velocity"
            kwargs = {
                "env_cfg_entry_point": f"{package}.{terrain.lower()}_env_cfg:{prefix}{terrain}EnvCfg{play}",
                "success_criterion_entry_point": f"{_CRITERIA}:{criterion}",
                "rsl_rl_cfg_entry_point": f"{runners}:{prefix}{terrain}PPORunnerCfg",
            }
            if symmetry:
                kwargs["rsl_rl_with_symmetry_cfg_entry_point"] = f"{runners}:{prefix}{terrain}PPORunnerWithSymmetryCfg"
            if terrain in distillation:
                distiller = f"{package}.agents.rsl_rl_distillation_cfg:{prefix}{terrain}DistillationRunnerCfg"
                kwargs["rsl_rl_distillation_cfg_entry_point"] = distiller
            gym.register(
                id=f"simlab/Velocity-{terrain}-{robot}{suffix}-v0",
                entry_point="simlab.envs:ManagerBasedRLEnv",
                disable_env_checker=True,
                kwargs=kwargs,
            )
