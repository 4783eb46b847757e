"""``isaaclab.scene`` of Isaac Lab 3.0: simlab's scene, made from a config whose quaternions are (x, y, z, w)."""

from __future__ import annotations

from typing import Any

from simlab import scene as _scene
from simlab.scene import InteractiveSceneCfg, grid_origins
from simlab.v3 import assets as _assets3
from simlab.v3 import sensors as _sensors3
from simlab.v3._order import replace_fields, to_simlab

__all__ = ["InteractiveScene", "InteractiveSceneCfg", "grid_origins", "with_v3_api"]


def with_v3_api(scene_cfg: Any) -> Any:
    """``scene_cfg`` with its articulations, rigid objects and sensors built as the classes of
    :mod:`simlab.v3.assets` and :mod:`simlab.v3.sensors`, 2.x robot and sensor configs included: 3.0 code
    reads every entity of a 3.0 scene through 3.0's API, and 2.x code reads the same entities as before.
    A config whose ``class_type`` is a class of its own (a subclass) is left as it is; the user's
    config is not changed."""
    classes = {**_assets3.V3_CLASSES, **_sensors3.V3_CLASSES}
    changes = {}
    for name, value in vars(scene_cfg).items():
        class_type = getattr(value, "class_type", None)
        if isinstance(class_type, type) and class_type in classes:
            changes[name] = replace_fields(value, class_type=classes[class_type])
    return replace_fields(scene_cfg, **changes) if changes else scene_cfg


class InteractiveScene(_scene.InteractiveScene):
    """simlab's scene; the (x, y, z, w) configs in ``cfg`` are converted to simlab's order first, and its
    articulations, rigid objects and sensors carry Isaac Lab 3.0's API (:func:`with_v3_api`)."""

    def __init__(self, cfg: InteractiveSceneCfg):
        super().__init__(with_v3_api(to_simlab(cfg)))


def _register_for_instantiate() -> None:
    """``instantiate(scene_cfg)`` (Isaac Lab 3.0's tutorials) makes this scene once 3.0 code imported it."""
    from simlab.utils.instantiate import register_instance_class

    name = f"{InteractiveSceneCfg.__module__}.{InteractiveSceneCfg.__qualname__}"
    register_instance_class(name, f"{__name__}:InteractiveScene")


_register_for_instantiate()
