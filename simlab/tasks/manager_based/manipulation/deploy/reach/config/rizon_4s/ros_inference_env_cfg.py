"""The Rizon 4s reach with the names Isaac Manipulator's on-robot inference reads (Isaac Lab's
``ros_inference_env_cfg.py``): the observation order, the joints, the action scale and the start pose."""

from simlab.utils import configclass

from .joint_pos_env_cfg import Rizon4sReachEnvCfg


@configclass
class Rizon4sReachROSInferenceEnvCfg(Rizon4sReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.obs_order = ["arm_dof_pos", "arm_dof_vel", "target_pos", "target_quat"]
        self.policy_action_space = "joint"
        self.arm_joint_names = ["joint1", "joint2", "joint3", "joint4", "joint5", "joint6", "joint7"]
        self.action_space = 7
        self.state_space = 21
        self.observation_space = 21
        self.joint_action_scale = self.actions.arm_action.scale
        self.action_scale_joint_space = [self.joint_action_scale] * 7
        self.initial_joint_pos = [self.scene.robot.init_state.joint_pos[name] for name in self.arm_joint_names]
