"""Unitree G1 velocity tracking on flat ground (Isaac Lab's ``Isaac-Velocity-Flat-G1-v0``)."""

from simlab.managers import SceneEntityCfg
from simlab.utils import configclass

from ..common import flat_ground, play
from .rough_env_cfg import G1RoughEnvCfg


@configclass
class G1FlatEnvCfg(G1RoughEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        flat_ground(self)
        # MuJoCo Warp's buffers per world from the measured worst case, the robot fallen on the ground
        # (15 contacts, 64 rows; tests/test_humanoid_velocity.py), 1.5 times over and up to a multiple
        # of 16 (its row tiles): its estimate reserved 48 and 138
        self.sim.mujoco.nconmax = 24
        self.sim.mujoco.njmax = 112
        # rewards (the yaw rate keeps the rough task's weight 2, not Isaac Lab's flat 1: see rough_env_cfg)
        self.rewards.lin_vel_z_l2.weight = -0.2
        self.rewards.action_rate_l2.weight = -0.005
        self.rewards.dof_acc_l2.weight = -1.0e-7
        self.rewards.feet_air_time.weight = 0.75
        self.rewards.feet_air_time.params["threshold"] = 0.4
        self.rewards.dof_torques_l2.weight = -2.0e-6
        self.rewards.dof_torques_l2.params["asset_cfg"] = SceneEntityCfg(
            "robot", joint_names=[".*_hip_.*", ".*_knee_joint"]
        )
        # commands: sideways steps too
        self.commands.base_velocity.ranges.lin_vel_x = (0.0, 1.0)
        self.commands.base_velocity.ranges.lin_vel_y = (-0.5, 0.5)
        self.commands.base_velocity.ranges.ang_vel_z = (-1.0, 1.0)


@configclass
class G1FlatEnvCfg_PLAY(G1FlatEnvCfg):  # noqa: N801 - Isaac Lab's name
    def __post_init__(self) -> None:
        super().__post_init__()
        play(self)
