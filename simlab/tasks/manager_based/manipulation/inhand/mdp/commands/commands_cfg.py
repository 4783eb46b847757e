"""Config of the goal-orientation command (Isaac Lab's ``InHandReOrientationCommandCfg``)."""

from dataclasses import MISSING

from simlab.managers import CommandTermCfg
from simlab.markers import VisualizationMarkersCfg
from simlab.robots.dex_cube import dex_cube_marker_cfg
from simlab.utils import configclass

from .orientation_command import InHandReOrientationCommand


@configclass
class InHandReOrientationCommandCfg(CommandTermCfg):
    """A random goal orientation for an object, redrawn when it is reached (not on a timer)."""

    class_type: type = InHandReOrientationCommand
    resampling_time_range: tuple[float, float] = (1e6, 1e6)  # no resampling based on time

    asset_name: str = MISSING
    """The object whose orientation the command sets."""
    init_pos_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """The goal position: the object's default position plus this offset (it spawns above the palm)."""
    make_quat_unique: bool = MISSING
    """Whether goal quaternions have a non-negative real part."""
    orientation_success_threshold: float = MISSING
    """Orientation error [rad] under which the goal counts as reached."""
    update_goal_on_success: bool = MISSING
    """Whether a reached goal is replaced by a new one at once."""
    marker_pos_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    """Where the goal marker is drawn, relative to the goal position (beside the hand, not over the object)."""
    goal_pose_visualizer_cfg: VisualizationMarkersCfg = VisualizationMarkersCfg(
        prim_path="/Visuals/Command/goal_marker", markers={"goal": dex_cube_marker_cfg(scale=1.0)}
    )
    """The goal marker: a DexCube."""
