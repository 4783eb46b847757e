"""Configurations of the command terms (Isaac Lab's names and fields)."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.managers.manager_term_cfg import CommandTermCfg
from simlab.markers import BLUE_ARROW_X_MARKER_CFG, FRAME_MARKER_CFG, GREEN_ARROW_X_MARKER_CFG, VisualizationMarkersCfg
from simlab.markers.visualization_markers import FrameCfg
from simlab.utils import configclass

from .null_command import NullCommand
from .pose_2d_command import UniformPose2dCommand
from .pose_command import UniformPoseCommand
from .velocity_command import UniformVelocityCommand


@configclass
class NullCommandCfg(CommandTermCfg):
    class_type: type = NullCommand

    def __post_init__(self):
        # Never resampled.
        self.resampling_time_range = (float("inf"), float("inf"))


@configclass
class UniformVelocityCommandCfg(CommandTermCfg):
    class_type: type = UniformVelocityCommand
    asset_name: str = MISSING
    heading_command: bool = False
    """Compute the yaw rate from a sampled heading instead of sampling it."""
    heading_control_stiffness: float = 1.0
    rel_standing_envs: float = 0.0
    """Fraction of envs commanded to stand still."""
    rel_heading_envs: float = 1.0
    """Fraction of envs following a heading (with ``heading_command``)."""

    @configclass
    class Ranges:
        lin_vel_x: tuple[float, float] = MISSING
        lin_vel_y: tuple[float, float] = MISSING
        ang_vel_z: tuple[float, float] = MISSING
        heading: tuple[float, float] | None = None

    ranges: Ranges = MISSING

    goal_vel_visualizer_cfg: VisualizationMarkersCfg = GREEN_ARROW_X_MARKER_CFG.replace(
        prim_path="/Visuals/Command/velocity_goal"
    )
    """The arrow of the commanded velocity (with ``debug_vis``), drawn above the robot in renders."""
    current_vel_visualizer_cfg: VisualizationMarkersCfg = BLUE_ARROW_X_MARKER_CFG.replace(
        prim_path="/Visuals/Command/velocity_current"
    )
    """The arrow of the robot's current velocity (with ``debug_vis``)."""


@configclass
class UniformPoseCommandCfg(CommandTermCfg):
    class_type: type = UniformPoseCommand
    asset_name: str = MISSING
    body_name: str = MISSING
    """The body whose pose is commanded (the metrics measure it)."""
    make_quat_unique: bool = False
    """Keep the quaternion's real part non-negative."""

    @configclass
    class Ranges:
        pos_x: tuple[float, float] = MISSING
        pos_y: tuple[float, float] = MISSING
        pos_z: tuple[float, float] = MISSING
        roll: tuple[float, float] = MISSING
        pitch: tuple[float, float] = MISSING
        yaw: tuple[float, float] = MISSING

    ranges: Ranges = MISSING
    goal_pose_visualizer_cfg: VisualizationMarkersCfg = FRAME_MARKER_CFG.replace(
        prim_path="/Visuals/Command/goal_pose", markers={"frame": FrameCfg(scale=(0.1, 0.1, 0.1))}
    )
    """The commanded frame (with ``debug_vis``), drawn in renders."""
    current_pose_visualizer_cfg: VisualizationMarkersCfg = FRAME_MARKER_CFG.replace(
        prim_path="/Visuals/Command/body_pose", markers={"frame": FrameCfg(scale=(0.1, 0.1, 0.1))}
    )
    """The body's current frame (with ``debug_vis``)."""


@configclass
class UniformPose2dCommandCfg(CommandTermCfg):
    class_type: type = UniformPose2dCommand
    asset_name: str = MISSING
    simple_heading: bool = MISSING
    """Face the goal (or away from it, whichever is closer) instead of drawing the heading."""

    @configclass
    class Ranges:
        pos_x: tuple[float, float] = MISSING
        """Goal x around the env's origin (m)."""
        pos_y: tuple[float, float] = MISSING
        """Goal y around the env's origin (m)."""
        heading: tuple[float, float] = MISSING
        """Goal heading (rad), used without ``simple_heading``."""

    ranges: Ranges = MISSING
    goal_pose_visualizer_cfg: VisualizationMarkersCfg = GREEN_ARROW_X_MARKER_CFG.replace(
        prim_path="/Visuals/Command/pose_goal"
    )
    """The goal's arrow along its heading (with ``debug_vis``), drawn in renders."""
