"""Reach with both OpenArm arms, joint-position actions (Isaac Lab's
``config/openarm/bimanual/joint_pos_env_cfg.py``)."""

from simlab.robots.openarm import OPENARM_BI_HIGH_PD_CFG
from simlab.utils import configclass

from .... import mdp
from .reach_openarm_bi_env_cfg import ReachEnvCfg


@configclass
class OpenArmReachEnvCfg(ReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        # Isaac Lab's stiffer drives with gravity off
        self.scene.robot = OPENARM_BI_HIGH_PD_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        for side in ("left", "right"):
            for term in ("position_tracking", "position_tracking_fine_grained", "orientation_tracking"):
                reward = getattr(self.rewards, f"{side}_end_effector_{term}")
                reward.params["asset_cfg"].body_names = [f"openarm_{side}_hand"]
            action = mdp.JointPositionActionCfg(
                asset_name="robot",
                joint_names=[f"openarm_{side}_joint{i}" for i in range(1, 8)],
                scale=0.5,
                use_default_offset=True,
            )
            setattr(self.actions, f"{side}_arm_action", action)
            # the hands' z axes run along the fingers
            getattr(self.commands, f"{side}_ee_pose").body_name = f"openarm_{side}_hand"


@configclass
class OpenArmReachEnvCfg_PLAY(OpenArmReachEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.scene.num_envs = 50
        self.scene.env_spacing = 2.5
        self.observations.policy.enable_corruption = False
