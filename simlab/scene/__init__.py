"""Interactive scenes: many environments of the same entities."""

from .interactive_scene import InteractiveScene, grid_origins
from .interactive_scene_cfg import InteractiveSceneCfg
