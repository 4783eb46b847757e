"""Isaac Lab's debug-drawing switch, shared by direct envs, command terms and sensors."""

from __future__ import annotations

from typing import Any


class DebugVisHooks:
    """``set_debug_vis(True)`` shows what the object draws in offscreen renders and videos.

    As in Isaac Lab, a class that draws overrides ``_set_debug_vis_impl`` (create or hide its
    ``VisualizationMarkers``) and ``_debug_vis_callback`` (place them). simlab calls the callback
    before each rendered image (Isaac Lab: at each viewport update), so a step does no drawing work.
    The class names the simulation to hook into (``_debug_vis_simulation``) and may say when it can
    draw (``_debug_vis_ready``).
    """

    _debug_vis: bool = False
    _debug_vis_hooked: bool = False

    @property
    def has_debug_vis_implementation(self) -> bool:
        """Whether the class draws anything (it overrides ``_set_debug_vis_impl``)."""
        return not getattr(type(self)._set_debug_vis_impl, "draws_nothing", False)

    def set_debug_vis(self, debug_vis: bool) -> bool:
        """Show or hide the markers; False when the class draws nothing."""
        if not self.has_debug_vis_implementation:
            return False
        self._debug_vis = bool(debug_vis)
        self._set_debug_vis_impl(self._debug_vis)
        if self._debug_vis and not self._debug_vis_hooked:
            self._debug_vis_simulation().add_render_callback(self._draw_debug_vis)
            self._debug_vis_hooked = True
        return True

    def _draw_debug_vis(self) -> None:
        if self._debug_vis and self._debug_vis_ready():
            self._debug_vis_callback(None)

    def _debug_vis_simulation(self) -> Any:
        raise NotImplementedError(f"{type(self).__name__} names no simulation to draw in")

    def _debug_vis_ready(self) -> bool:
        return True

    def _set_debug_vis_impl(self, debug_vis: bool) -> None:
        raise NotImplementedError(f"Debug visualization is not implemented for {type(self).__name__}.")

    _set_debug_vis_impl.draws_nothing = True

    def _debug_vis_callback(self, event) -> None:
        raise NotImplementedError(f"Debug visualization is not implemented for {type(self).__name__}.")
