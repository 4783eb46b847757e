"""Configuration of the ray caster (Isaac Lab's ``RayCasterCfg``)."""

from __future__ import annotations

from dataclasses import MISSING

from simlab.markers import RAY_CASTER_MARKER_CFG, VisualizationMarkersCfg
from simlab.sensors.sensor_base import SensorBaseCfg
from simlab.utils import configclass

from .patterns.patterns_cfg import PatternBaseCfg
from .ray_caster import RayCaster

RAY_ALIGNMENTS = ("base", "yaw", "world")


@configclass
class RayCasterCfg(SensorBaseCfg):
    """Rays cast from a body (``prim_path``, e.g. ``{ENV_REGEX_NS}/Robot/base``) against static
    geometry (``mesh_prim_paths``, e.g. ``["/World/ground"]``)."""

    @configclass
    class OffsetCfg:
        """Pose of the rays' frame in the body's frame."""

        pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
        rot: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
        """(w, x, y, z)."""

    class_type: type = RayCaster
    mesh_prim_paths: list[str] = MISSING
    """What the rays hit: static geometry of the scene, e.g. the terrain ``/World/ground``. The robot
    carrying the sensor is never hit."""
    offset: OffsetCfg = OffsetCfg()
    attach_yaw_only: bool | None = None
    """Deprecated in Isaac Lab: True means ``ray_alignment="yaw"``, False ``"base"``; None leaves
    ``ray_alignment`` as it is."""
    ray_alignment: str = "yaw"
    """"base": starts and directions follow the body's full orientation; "yaw": starts turn with its
    yaw only, directions stay in the world frame (height maps); "world": neither turns."""
    pattern_cfg: PatternBaseCfg = MISSING
    max_distance: float = 1e6
    """Hits farther than this along the ray count as misses (``inf``) [m]."""
    drift_range: tuple[float, float] = (0.0, 0.0)
    """Uniform drift of ``pos_w`` and the ray starts (x, y and z), drawn per env at each reset [m]."""
    ray_cast_drift_range: dict[str, tuple[float, float]] = {"x": (0.0, 0.0), "y": (0.0, 0.0), "z": (0.0, 0.0)}
    """Uniform drift of the ray starts in the rays' frame (x, y) and of the hit heights (z) [m]."""
    visualizer_cfg: VisualizationMarkersCfg = RAY_CASTER_MARKER_CFG.replace(prim_path="/Visuals/RayCaster")
    """The markers ``debug_vis`` draws at every ray hit (red spheres), in renders, videos and the native viewer."""
