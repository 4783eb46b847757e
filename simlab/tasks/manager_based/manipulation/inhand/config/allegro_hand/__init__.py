"""Allegro Hand in-hand cube reorientation (Isaac Lab's ``Isaac-Repose-Cube-Allegro-v0`` and variants)."""

import gymnasium as gym

from . import agents

_CRITERION = "simlab.tasks.manager_based.manipulation.inhand.criterion:reorients_cube"

for _name, _cfg, _runner in (
    ("Repose-Cube-Allegro", "AllegroCubeEnvCfg", "AllegroCubePPORunnerCfg"),
    ("Repose-Cube-Allegro-NoVelObs", "AllegroCubeNoVelObsEnvCfg", "AllegroCubeNoVelObsPPORunnerCfg"),
):
    for _suffix, _variant in (("-v0", ""), ("-Play-v0", "_PLAY")):
        gym.register(
            id=f"simlab/{_name}{_suffix}",
            entry_point="simlab.envs:ManagerBasedRLEnv",
            disable_env_checker=True,
            kwargs={
                "env_cfg_entry_point": f"{__name__}.allegro_env_cfg:{_cfg}{_variant}",
                "success_criterion_entry_point": _CRITERION,
                "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:{_runner}",
                "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_cfg.yaml",
                "skrl_cfg_entry_point": f"{agents.__name__}:skrl_ppo_cfg.yaml",
            },
        )
