"""The native viewer: MuJoCo's own window (``mujoco.viewer.launch_passive``), where there is a display.

The followed env is MuJoCo's data of the window; its neighbours are drawn into the window's user
scene at their origins. Keys: space pauses / resumes, the right arrow steps once while paused,
``[`` / ``]`` follow the previous / next env, ``-`` / ``=`` draw less / more often, ``V`` turns
drawing off and on (training at full speed). Letter and digit keys that a teleoperation device
listens for (``simlab.devices.Se3Keyboard``: W, S, A, D, ...) go to it instead, through
:data:`simlab.devices.keys.key_hub`, as taps: MuJoCo's window reports presses, not releases.
"""

from __future__ import annotations

import copy

import mujoco

from simlab.devices.keys import KeyEvent, glfw_key_name, key_hub
from simlab.sim.renderer import EnvSceneBuilder, draw_decor, set_free_camera, view_znear
from simlab.viewer.choice import display_available
from simlab.viewer.live import LiveViewer, ViewerError
from simlab.viewer.source import EnvSnapshot, SimSource

__all__ = ["NativeViewer"]

_KEY_SPACE, _KEY_RIGHT = 32, 262


class NativeViewer(LiveViewer):
    """MuJoCo's passive viewer window showing the followed env and its neighbours."""

    kind = "native"

    def __init__(self, source: SimSource, realtime: bool = False, follow: int = 0):
        if not display_available():
            raise ViewerError("The native viewer needs a display (DISPLAY is not set); use --viewer web instead")
        super().__init__(source, realtime=realtime, follow=follow)
        import mujoco.viewer

        # the window's own copy of the model, whose near clipping plane is moved in to a few cm (on
        # a large terrain MuJoCo's, a share of the model's extent, cuts away the ground in front of
        # the camera); camera sensors keep the simulation model's
        self._model = model = copy.copy(source.model)
        model.vis.map.znear = view_znear(model)
        self._builder = EnvSceneBuilder(model)
        self._data = mujoco.MjData(model)
        try:
            # MuJoCo's side panels (its own simulation controls) are hidden: Tab / Shift+Tab show them.
            self._handle = mujoco.viewer.launch_passive(
                model, self._data, key_callback=self._on_key, show_left_ui=False, show_right_ui=False
            )
        except Exception as err:  # noqa: BLE001 - GLFW errors come in many types
            raise ViewerError(f"MuJoCo's viewer window did not open ({err}); use --viewer web instead") from err
        if source.eye_offset is not None:
            with self._handle.lock():
                set_free_camera(self._handle.cam, source.eye_offset, (0.0, 0.0, 0.0))
        self._start()

    def _on_key(self, key: int) -> None:
        if forward_key_to_listeners(key):
            return
        c = self.controls
        if key == _KEY_SPACE:
            c.paused = not c.paused
        elif key == _KEY_RIGHT and c.paused:
            c.steps_to_run += 1
        elif key in (ord("["), ord("]")):
            c.follow = (c.follow + (1 if key == ord("]") else -1)) % self.source.num_envs
        elif key in (ord("-"), ord("=")):
            c.render_every = max(1, c.render_every * 2 if key == ord("-") else c.render_every // 2)
        elif key == ord("V"):
            c.rendering = not c.rendering

    def _draw(self, snapshot: EnvSnapshot) -> None:
        if not self._handle.is_running():
            raise ViewerError("the window was closed")
        with self._handle.lock():
            for name, values in snapshot.states.items():  # the followed env is the window's own data
                getattr(self._data, name)[:] = values[0]
            mujoco.mj_forward(self._model, self._data)
            scene = self._handle.user_scn
            scene.ngeom = 0
            self._builder.add_neighbours(scene, snapshot.states, snapshot.offsets)
            draw_decor(scene, snapshot.decor)
        if snapshot.episode_length is not None:  # takes the viewer's lock itself
            self._handle.set_texts(
                (
                    mujoco.mjtFontScale.mjFONTSCALE_150,
                    mujoco.mjtGridPos.mjGRID_TOPLEFT,
                    f"env {snapshot.env_ids[0]}\nreturn\nlength",
                    f"\n{snapshot.episode_return:.2f}\n{snapshot.episode_length}",
                )
            )
        self._handle.sync()

    def _close(self) -> None:
        self._handle.close()


def forward_key_to_listeners(keycode: int) -> bool:
    """Send a key of MuJoCo's window to the teleoperation listeners, if one listens for it."""
    name = glfw_key_name(keycode)
    if name is None or not key_hub.wants(name):
        return False
    return key_hub.publish(KeyEvent(name, "tap"))
