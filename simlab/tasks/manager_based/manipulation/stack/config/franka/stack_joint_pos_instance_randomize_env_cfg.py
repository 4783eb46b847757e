"""Stack cubes with the Franka arm, a random pick of cubes in each env, joint-position actions (Isaac
Lab's ``stack_joint_pos_instance_randomize_env_cfg.py``).

Candidates, as Isaac Lab's: cube 1 blue or red, cube 2 red or yellow, cube 3 yellow or green (its block
USDs, simlab's boxes of the same edge). Isaac Lab spawns the second candidate of each 2 cm higher and
the blocks at z = 0.0203 on its table; simlab's rest on its table at half an edge (the reset event
places them anyway). Isaac Lab runs 2 envs (camera resources) and so does this config by default.
"""

import torch

import simlab.sim as sim_utils
from simlab.assets import RigidObjectCfg, RigidObjectCollectionCfg
from simlab.managers import EventTermCfg as EventTerm
from simlab.managers import SceneEntityCfg
from simlab.sim.spawners.from_files.usd_stand_ins import BLOCK_COLORS
from simlab.utils import configclass

from ... import mdp
from ...mdp import franka_stack_events
from ...stack_instance_randomize_env_cfg import StackInstanceRandomizeEnvCfg
from . import stack_joint_pos_env_cfg
from .stack_joint_pos_env_cfg import CUBE_SIZE, stack_cube_cfg

CANDIDATES = {
    "cube_1": {"blue_cube": ("blue", (0.4, 0.0)), "red_cube": ("red", (0.4, 0.0))},
    "cube_2": {"red_cube": ("red", (0.55, 0.05)), "yellow_cube": ("yellow", (0.55, 0.05))},
    "cube_3": {"yellow_cube": ("yellow", (0.60, -0.1)), "green_cube": ("green", (0.60, -0.1))},
}
"""Each cube's candidates: name -> (Isaac Lab's block colour, spawn x, y in the env frame [m])."""

OUT_OF_FOCUS_STATE = (10.0, 10.0, 10.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
"""Where the unpicked candidates go (world position, quaternion, velocities), as Isaac Lab's."""


def candidate_cfg(cube: str, name: str) -> RigidObjectCfg:
    """One candidate of ``cube``: simlab's stack cube in the block's colour, at its spawn position."""
    color, (x, y) = CANDIDATES[cube][name]
    cfg = stack_cube_cfg("cube_1", (x, y, CUBE_SIZE / 2))
    cfg.prim_path = "{ENV_REGEX_NS}/" + f"{cube.capitalize()}_{color.capitalize()}"
    cfg.spawn.visual_material = sim_utils.PreviewSurfaceCfg(diffuse_color=BLOCK_COLORS[color])
    return cfg


@configclass
class EventCfg:
    init_franka_arm_pose = EventTerm(
        func=franka_stack_events.set_default_joint_pose,
        mode="startup",
        params={"default_pose": [0.0444, -0.1894, -0.1107, -2.5148, 0.0044, 2.3775, 0.6952, 0.0400, 0.0400]},
    )
    randomize_franka_joint_state = EventTerm(
        func=franka_stack_events.randomize_joint_by_gaussian_offset,
        mode="reset",
        params={"mean": 0.0, "std": 0.02, "asset_cfg": SceneEntityCfg("robot")},
    )
    randomize_cubes_in_focus = EventTerm(
        func=franka_stack_events.randomize_rigid_objects_in_focus,
        mode="reset",
        params={
            "asset_cfgs": [SceneEntityCfg("cube_1"), SceneEntityCfg("cube_2"), SceneEntityCfg("cube_3")],
            "out_focus_state": torch.tensor(OUT_OF_FOCUS_STATE),
            "pose_range": {
                "x": (0.4, 0.6),
                "y": (-0.10, 0.10),
                "z": (CUBE_SIZE / 2, CUBE_SIZE / 2),
                "yaw": (-1.0, 1.0),
            },
            "min_separation": 0.1,
        },
    )


@configclass
class FrankaCubeStackInstanceRandomizeEnvCfg(StackInstanceRandomizeEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        # the robot, its actions, gripper settings and end-effector frame are the stack task's
        franka = stack_joint_pos_env_cfg.FrankaCubeStackEnvCfg()
        self.events = EventCfg()
        self.scene.robot = franka.scene.robot
        self.scene.ee_frame = franka.scene.ee_frame
        self.scene.num_envs = 2
        self.actions.arm_action = mdp.JointPositionActionCfg(
            asset_name="robot", joint_names=["panda_joint.*"], scale=0.5, use_default_offset=True
        )
        self.actions.gripper_action = franka.actions.gripper_action
        self.gripper_joint_names = ["panda_finger_.*"]
        self.gripper_open_val = 0.04
        self.gripper_threshold = 0.005
        for cube, candidates in CANDIDATES.items():
            objects = {name: candidate_cfg(cube, name) for name in candidates}
            setattr(self.scene, cube, RigidObjectCollectionCfg(rigid_objects=objects))
