"""Stack cubes with the Franka arm, joint-position actions (Isaac Lab's ``stack_joint_pos_env_cfg.py``).

Isaac Lab's cubes are its blue, red and green block USD props; simlab's are boxes of the edge the
task's checks assume (``CUBE_SIZE``, the stacked height difference of its terms), 100 g, friction 1,
resting on the table (Isaac Lab spawns them at z = 0.0203, 3 mm into simlab's table). A ported config
naming the block USDs gets the same boxes (simlab.sim.spawners.from_files.usd_stand_ins).
"""

import simlab.sim as sim_utils
from simlab.assets import RigidObjectCfg
from simlab.managers import EventTermCfg as EventTerm
from simlab.managers import SceneEntityCfg
from simlab.markers import FRAME_MARKER_CFG
from simlab.robots.franka import FRANKA_PANDA_CFG
from simlab.sensors import FrameTransformerCfg, OffsetCfg
from simlab.sim.spawners.from_files.usd_stand_ins import BLOCK_COLORS, BLOCK_SIZE
from simlab.utils import configclass

from ... import mdp
from ...mdp import franka_stack_events
from ...stack_env_cfg import StackEnvCfg

CUBE_SIZE = BLOCK_SIZE
"""Edge of a cube [m]: the height difference of two stacked cubes in Isaac Lab's stack checks."""

CUBE_COLORS = {"cube_1": BLOCK_COLORS["blue"], "cube_2": BLOCK_COLORS["red"], "cube_3": BLOCK_COLORS["green"]}
"""Blue, red and green, as Isaac Lab's blocks."""


def stack_cube_cfg(name: str, pos: tuple[float, float, float]) -> RigidObjectCfg:
    """One of the three cubes, at ``pos`` (env frame) before the reset event places it."""
    return RigidObjectCfg(
        prim_path="{ENV_REGEX_NS}/" + name.capitalize(),
        init_state=RigidObjectCfg.InitialStateCfg(pos=pos, rot=(1.0, 0.0, 0.0, 0.0)),
        spawn=sim_utils.CuboidCfg(
            size=(CUBE_SIZE, CUBE_SIZE, CUBE_SIZE),
            rigid_props=sim_utils.RigidBodyPropertiesCfg(
                solver_position_iteration_count=16,
                solver_velocity_iteration_count=1,
                max_angular_velocity=1000.0,
                max_linear_velocity=1000.0,
                max_depenetration_velocity=5.0,
                disable_gravity=False,
            ),
            mass_props=sim_utils.MassPropertiesCfg(mass=0.1),
            physics_material=sim_utils.RigidBodyMaterialCfg(static_friction=1.0, dynamic_friction=1.0),
            visual_material=sim_utils.PreviewSurfaceCfg(diffuse_color=CUBE_COLORS[name]),
        ),
    )


@configclass
class EventCfg:
    init_franka_arm_pose = EventTerm(
        func=franka_stack_events.set_default_joint_pose,
        mode="reset",
        params={"default_pose": [0.0444, -0.1894, -0.1107, -2.5148, 0.0044, 2.3775, 0.6952, 0.0400, 0.0400]},
    )
    randomize_franka_joint_state = EventTerm(
        func=franka_stack_events.randomize_joint_by_gaussian_offset,
        mode="reset",
        params={"mean": 0.0, "std": 0.02, "asset_cfg": SceneEntityCfg("robot")},
    )
    randomize_cube_positions = EventTerm(
        func=franka_stack_events.randomize_object_pose,
        mode="reset",
        params={
            "pose_range": {
                "x": (0.4, 0.6),
                "y": (-0.10, 0.10),
                "z": (CUBE_SIZE / 2, CUBE_SIZE / 2),
                "yaw": (-1.0, 1.0),
            },
            "min_separation": 0.1,
            "asset_cfgs": [SceneEntityCfg("cube_1"), SceneEntityCfg("cube_2"), SceneEntityCfg("cube_3")],
        },
    )


@configclass
class FrankaCubeStackEnvCfg(StackEnvCfg):
    def __post_init__(self):
        super().__post_init__()
        self.events = EventCfg()
        self.scene.robot = FRANKA_PANDA_CFG.replace(prim_path="{ENV_REGEX_NS}/Robot")
        self.actions.arm_action = mdp.JointPositionActionCfg(
            asset_name="robot", joint_names=["panda_joint.*"], scale=0.5, use_default_offset=True
        )
        self.actions.gripper_action = mdp.BinaryJointPositionActionCfg(
            asset_name="robot",
            joint_names=["panda_finger.*"],
            open_command_expr={"panda_finger_.*": 0.04},
            close_command_expr={"panda_finger_.*": 0.0},
        )
        self.gripper_joint_names = ["panda_finger_.*"]
        self.gripper_open_val = 0.04
        self.gripper_threshold = 0.005
        self.scene.cube_1 = stack_cube_cfg("cube_1", (0.4, 0.0, CUBE_SIZE / 2))
        self.scene.cube_2 = stack_cube_cfg("cube_2", (0.55, 0.05, CUBE_SIZE / 2))
        self.scene.cube_3 = stack_cube_cfg("cube_3", (0.60, -0.1, CUBE_SIZE / 2))
        marker_cfg = FRAME_MARKER_CFG.copy()
        marker_cfg.markers["frame"].scale = (0.1, 0.1, 0.1)
        marker_cfg.prim_path = "/Visuals/FrameTransformer"
        self.scene.ee_frame = FrameTransformerCfg(
            prim_path="{ENV_REGEX_NS}/Robot/panda_link0",
            debug_vis=False,
            visualizer_cfg=marker_cfg,
            target_frames=[
                FrameTransformerCfg.FrameCfg(
                    prim_path="{ENV_REGEX_NS}/Robot/panda_hand",
                    name="end_effector",
                    offset=OffsetCfg(pos=(0.0, 0.0, 0.1034)),
                ),
                FrameTransformerCfg.FrameCfg(
                    prim_path="{ENV_REGEX_NS}/Robot/panda_rightfinger",
                    name="tool_rightfinger",
                    offset=OffsetCfg(pos=(0.0, 0.0, 0.046)),
                ),
                FrameTransformerCfg.FrameCfg(
                    prim_path="{ENV_REGEX_NS}/Robot/panda_leftfinger",
                    name="tool_leftfinger",
                    offset=OffsetCfg(pos=(0.0, 0.0, 0.046)),
                ),
            ],
        )
