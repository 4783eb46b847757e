"""Isaac Lab's environment GUI windows (``isaaclab.envs.ui``), for configs and task files that name them.

Isaac Lab builds these omni.ui windows only when the simulation has a GUI. simlab is headless
(``SimulationContext.has_gui()`` is False), so its envs never build one: the classes exist so that
``ui_window_class_type = BaseEnvWindow`` and subclasses in task files import, and constructing one
raises an error that says what to use instead.
"""

from __future__ import annotations

from typing import Any

__all__ = ["BaseEnvWindow", "EmptyWindow", "ManagerBasedRLEnvWindow", "ViewportCameraController"]

_NO_GUI = (
    "simlab has no GUI (SimulationContext.has_gui() is False), so environment windows are never built."
    " Watch a run with env.render() / --video, and turn on debug markers with the config's debug_vis flags."
)


class BaseEnvWindow:
    """Isaac Lab's debug window of an env; refused in simlab (headless)."""

    def __init__(self, env: Any, window_name: str = "IsaacLab"):
        raise RuntimeError(f"{type(self).__name__}: {_NO_GUI}")

    def _create_debug_vis_ui_element(self, name: str, elem: Any) -> None:
        raise RuntimeError(f"{type(self).__name__}: {_NO_GUI}")


class ManagerBasedRLEnvWindow(BaseEnvWindow):
    """Isaac Lab's window of a manager-based RL env; refused in simlab (headless)."""


class EmptyWindow:
    """Isaac Lab's empty window; refused in simlab (headless)."""

    def __init__(self, env: Any, window_name: str):
        raise RuntimeError(f"EmptyWindow: {_NO_GUI}")


class ViewportCameraController:
    """Isaac Lab's viewport camera controller; simlab's camera is the env config's ``viewer`` (ViewerCfg)."""

    def __init__(self, env: Any, cfg: Any):
        raise RuntimeError(
            "ViewportCameraController: simlab has no viewport. The render camera follows env.cfg.viewer"
            " (eye, lookat, origin_type 'world' / 'env' / 'asset_root' / 'asset_body', env_index)."
        )
