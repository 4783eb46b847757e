"""Shadow Hand in-hand cube reorientation, direct workflow (Isaac Lab's ``direct/shadow_hand``)."""

import gymnasium as gym

from . import agents

inhand_task_entry = "simlab.tasks.direct.inhand_manipulation"

gym.register(
    id="simlab/Repose-Cube-Shadow-Direct-v0",
    entry_point=f"{inhand_task_entry}.inhand_manipulation_env:InHandManipulationEnv",
    disable_env_checker=True,
    kwargs={
        "env_cfg_entry_point": f"{__name__}.shadow_hand_env_cfg:ShadowHandEnvCfg",
        "success_criterion_entry_point": f"{inhand_task_entry}.criterion:reorients_cube",
        "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_cfg.yaml",
        "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:ShadowHandPPORunnerCfg",
        "skrl_cfg_entry_point": f"{agents.__name__}:skrl_ppo_cfg.yaml",
    },
)

# OpenAI's variant (arXiv:1808.00177): asymmetric critic, noise and domain randomization
gym.register(
    id="simlab/Repose-Cube-Shadow-OpenAI-FF-Direct-v0",
    entry_point=f"{inhand_task_entry}.inhand_manipulation_env:InHandManipulationEnv",
    disable_env_checker=True,
    kwargs={
        "env_cfg_entry_point": f"{__name__}.shadow_hand_env_cfg:ShadowHandOpenAIEnvCfg",
        "success_criterion_entry_point": f"{inhand_task_entry}.criterion:reorients_cube",
        "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_ff_cfg.yaml",
        "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:ShadowHandAsymFFPPORunnerCfg",
        "skrl_cfg_entry_point": f"{agents.__name__}:skrl_ff_ppo_cfg.yaml",
    },
)

gym.register(
    id="simlab/Repose-Cube-Shadow-OpenAI-LSTM-Direct-v0",
    entry_point=f"{inhand_task_entry}.inhand_manipulation_env:InHandManipulationEnv",
    disable_env_checker=True,
    kwargs={
        "env_cfg_entry_point": f"{__name__}.shadow_hand_env_cfg:ShadowHandOpenAIEnvCfg",
        "success_criterion_entry_point": f"{inhand_task_entry}.criterion:reorients_cube",
        "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_lstm_cfg.yaml",
    },
)

# from a camera: a CNN trained beside the policy reads the cube's pose from the images
for _suffix, _cfg in (("", "ShadowHandVisionEnvCfg"), ("-Play", "ShadowHandVisionEnvPlayCfg")):
    gym.register(
        id=f"simlab/Repose-Cube-Shadow-Vision-Direct{_suffix}-v0",
        entry_point=f"{__name__}.shadow_hand_vision_env:ShadowHandVisionEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.shadow_hand_vision_env:{_cfg}",
            "success_criterion_entry_point": f"{inhand_task_entry}.criterion:reorients_cube",
            "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:ShadowHandVisionFFPPORunnerCfg",
            "rl_games_cfg_entry_point": f"{agents.__name__}:rl_games_ppo_vision_cfg.yaml",
        },
    )
