# Isaac Lab 3.0's isaaclab_tasks/core/velocity/config/go2/rough_env_cfg.py (develop), written out under the
# 3.0 import mapping (isaaclab_assets.robots.unitree -> simlab.v3.robots.unitree). Nothing else differs:
# ``sim.use_newton_actuators`` (Newton runs the DC motors natively) is held; simlab's actuators run in torch.

from simlab.v3.robots.unitree import UNITREE_GO2_CFG

from simlab.utils import configclass

from ...velocity_env_cfg import LocomotionVelocityRoughEnvCfg


@configclass
class UnitreeGo2RoughEnvCfg(LocomotionVelocityRoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.sim.use_newton_actuators = True
        self.scene.robot = UNITREE_GO2_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        self.scene.height_scanner.prim_path = "{ENV_REGEX_NS}/Robot/base"
        # a small robot: lower terrains
        terrains = self.scene.terrain.terrain_generator.sub_terrains
        terrains["boxes"].grid_height_range = (0.025, 0.1)
        terrains["random_rough"].noise_range = (0.01, 0.06)
        terrains["random_rough"].noise_step = 0.01
        terrains["pyramid_stairs"].step_height_range = (0.025, 0.12)
        terrains["pyramid_stairs_inv"].step_height_range = (0.025, 0.12)
        self.actions.joint_pos.scale = 0.25
        self.rewards.feet_air_time.params["sensor_cfg"].body_names = ".*_foot"
        self.rewards.feet_air_time.weight = 0.01
        self.rewards.undesired_contacts = None
        self.rewards.dof_torques_l2.weight = -0.0002
        self.rewards.track_lin_vel_xy_exp.weight = 1.5
        self.rewards.track_ang_vel_z_exp.weight = 0.75
        self.rewards.dof_acc_l2.weight = -2.5e-7
        self.terminations.base_contact.params["sensor_cfg"].body_names = "base"
