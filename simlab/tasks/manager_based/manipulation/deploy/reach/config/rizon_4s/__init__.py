"""The deployed Rizon 4s reach (Isaac Lab's ``Isaac-Deploy-Reach-Rizon4s-v0``, its play variant and the
variant that names what the robot's ROS inference node reads)."""

import gymnasium as gym

from . import agents

for _suffix, _cfg in (
    ("-v0", "joint_pos_env_cfg:Rizon4sReachEnvCfg"),
    ("-Play-v0", "joint_pos_env_cfg:Rizon4sReachEnvCfg_PLAY"),
    ("-ROS-Inference-v0", "ros_inference_env_cfg:Rizon4sReachROSInferenceEnvCfg"),
):
    gym.register(
        id=f"simlab/Deploy-Reach-Rizon4s{_suffix}",
        entry_point="simlab.envs:ManagerBasedRLEnv",
        disable_env_checker=True,
        kwargs={
            "env_cfg_entry_point": f"{__name__}.{_cfg}",
            "rsl_rl_cfg_entry_point": f"{agents.__name__}.rsl_rl_ppo_cfg:Rizon4sReachPPORunnerCfg",
            "success_criterion_entry_point": (
                "simlab.tasks.manager_based.manipulation.reach.criterion:reaches_pose_in_base_frame"
            ),
        },
    )
