"""Ready-made marker configs with Isaac Lab's names (``isaaclab.markers.config``)."""

from simlab.sim.spawners import CuboidCfg, PreviewSurfaceCfg, SphereCfg

from .visualization_markers import ArrowCfg, FrameCfg, VisualizationMarkersCfg


def _color(rgb: tuple[float, float, float]) -> PreviewSurfaceCfg:
    return PreviewSurfaceCfg(diffuse_color=rgb)


RAY_CASTER_MARKER_CFG = VisualizationMarkersCfg(
    prim_path="/Visuals/RayCaster",
    markers={"hit": SphereCfg(radius=0.02, visual_material=_color((1.0, 0.0, 0.0)))},
)
"""Red spheres at ray hits."""

CONTACT_SENSOR_MARKER_CFG = VisualizationMarkersCfg(
    prim_path="/Visuals/ContactSensor",
    markers={
        "contact": SphereCfg(radius=0.02, visual_material=_color((1.0, 0.0, 0.0))),
        "no_contact": SphereCfg(radius=0.02, visual_material=_color((0.0, 1.0, 0.0))),
    },
)
"""Red spheres on bodies in contact, green on the others."""

FRAME_MARKER_CFG = VisualizationMarkersCfg(
    prim_path="/Visuals/FrameVisualizerFromScript", markers={"frame": FrameCfg(scale=(0.5, 0.5, 0.5))}
)
"""Coordinate frames (x red, y green, z blue)."""

RED_ARROW_X_MARKER_CFG = VisualizationMarkersCfg(
    prim_path="/Visuals/Command/velocity_current",
    markers={"arrow": ArrowCfg(scale=(1.0, 0.1, 0.1), visual_material=_color((1.0, 0.0, 0.0)))},
)
BLUE_ARROW_X_MARKER_CFG = VisualizationMarkersCfg(
    prim_path="/Visuals/Command/velocity_goal",
    markers={"arrow": ArrowCfg(scale=(1.0, 0.1, 0.1), visual_material=_color((0.0, 0.0, 1.0)))},
)
GREEN_ARROW_X_MARKER_CFG = VisualizationMarkersCfg(
    prim_path="/Visuals/Command/heading_goal",
    markers={"arrow": ArrowCfg(scale=(1.0, 0.1, 0.1), visual_material=_color((0.0, 1.0, 0.0)))},
)
"""Arrows along +x (e.g. commanded and actual velocities)."""

CUBOID_MARKER_CFG = VisualizationMarkersCfg(
    prim_path="/Visuals/Command/position_goal",
    markers={"cuboid": CuboidCfg(size=(0.1, 0.1, 0.1), visual_material=_color((1.0, 0.0, 0.0)))},
)

POSITION_GOAL_MARKER_CFG = VisualizationMarkersCfg(
    prim_path="/Visuals/Command/position_goal",
    markers={
        "target_far": SphereCfg(radius=0.01, visual_material=_color((1.0, 0.0, 0.0))),
        "target_near": SphereCfg(radius=0.01, visual_material=_color((0.0, 1.0, 0.0))),
        "target_invisible": SphereCfg(radius=0.01, visual_material=PreviewSurfaceCfg(opacity=0.0)),
    },
)
"""Goal spheres: red when far, green when near, invisible."""
