"""The native viewer: MuJoCo's own window (``mujoco.viewer.launch_passive``), where there is a display.

The followed env is MuJoCo's data of the window; its neighbours are drawn into the window's user
scene at their origins. The camera starts where the env's videos look from and at (``cfg.viewer``,
``simlab.envs.utils.viewer.view_frame``) and moves with the followed env, or with the asset a camera
of ``origin_type="asset_root"`` / ``"asset_body"`` follows, keeping the person's turns and zoom.

Keys: space pauses / resumes, the right arrow steps once while paused, ``[`` / ``]`` follow the
previous / next env, ``-`` / ``=`` draw less / more often, ``V`` turns drawing off and on (training
at full speed). Letter and digit keys that a teleoperation device
listens for (``simlab.devices.Se3Keyboard``: W, S, A, D, ...) go to it instead, through
:data:`simlab.devices.keys.key_hub`, as taps: MuJoCo's window reports presses, not releases.

Playing a velocity task (``simlab.viewer.steering``), the arrow keys steer the followed env: up /
down raise / lower the forward speed, left / right the turn rate (to the left / right), and with
Shift held the sideways speed; Backspace stops the robot, Enter returns it to the task's commands.
Each press is one step (the window reports no releases: a command holds until changed). While
paused, the right arrow still steps once. The bottom-left corner lists these keys.
"""

from __future__ import annotations

import copy

import mujoco

from simlab.devices.keys import KeyEvent, glfw_key_name, key_hub
from simlab.sim.renderer import EnvSceneBuilder, draw_decor, set_free_camera, view_znear
from simlab.viewer.choice import display_available
from simlab.viewer.live import LiveViewer, ViewerError
from simlab.viewer.source import EnvSnapshot, SimSource
from simlab.viewer.steering import VelocitySteering

__all__ = ["NativeViewer"]

# GLFW key codes, as MuJoCo's window reports them
_KEY_SPACE, _KEY_ENTER, _KEY_BACKSPACE = 32, 257, 259
_KEY_RIGHT, _KEY_LEFT, _KEY_DOWN, _KEY_UP = 262, 263, 264, 265
_STEER_HELP = (
    "Up / Down\nLeft / Right\nShift+Left / Right\nBackspace\nEnter",
    "forward speed\nturn rate\nsideways speed\nstop\ntask's commands",
)


class NativeViewer(LiveViewer):
    """MuJoCo's passive viewer window showing the followed env and its neighbours."""

    kind = "native"

    def __init__(
        self, source: SimSource, realtime: bool = False, follow: int = 0, steering: VelocitySteering | None = None
    ):
        if not display_available():
            raise ViewerError("The native viewer needs a display (DISPLAY is not set); use --viewer web instead")
        super().__init__(source, realtime=realtime, follow=follow, steering=steering)
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
        # the env's viewer camera (cfg.viewer) as its videos have it; then moved with the followed env
        # (or asset) by as much as that moves, keeping the person's turns and zoom
        self._anchor = source.anchor(follow)
        camera = source.camera(follow)
        if camera is not None:
            with self._handle.lock():
                set_free_camera(self._handle.cam, *camera)
        self._start()

    def _on_key(self, key: int) -> None:
        if forward_key_to_listeners(key):
            return
        c = self.controls
        if key == _KEY_SPACE:
            c.paused = not c.paused
        elif key == _KEY_RIGHT and c.paused:
            c.steps_to_run += 1
        elif self.steering is not None and self._steer(key):
            return
        elif key in (ord("["), ord("]")):
            c.follow = (c.follow + (1 if key == ord("]") else -1)) % self.source.num_envs
        elif key in (ord("-"), ord("=")):
            c.render_every = max(1, c.render_every * 2 if key == ord("-") else c.render_every // 2)
        elif key == ord("V"):
            c.rendering = not c.rendering

    def _steer(self, key: int) -> bool:
        """Change the steered velocity command for a steering key; False for other keys."""
        steering = self.steering
        if key in (_KEY_UP, _KEY_DOWN):
            steering.nudge(0, 1 if key == _KEY_UP else -1)
        elif key in (_KEY_LEFT, _KEY_RIGHT):  # left: +w_z (turn left), or +v_y (the robot's left)
            steering.nudge(1 if _shift_held() else 2, 1 if key == _KEY_LEFT else -1)
        elif key == _KEY_BACKSPACE:
            steering.stop()
        elif key == _KEY_ENTER:
            steering.release()
        else:
            return False
        return True

    def _draw(self, snapshot: EnvSnapshot) -> None:
        if not self._handle.is_running():
            raise ViewerError("the window was closed")
        with self._handle.lock():
            for name, values in snapshot.states.items():  # the followed env is the window's own data
                getattr(self._data, name)[:] = values[0]
            mujoco.mj_forward(self._model, self._data)
            if snapshot.anchor is not None and self._anchor is not None:
                self._handle.cam.lookat[:] += snapshot.anchor - self._anchor
            self._anchor = snapshot.anchor
            scene = self._handle.user_scn
            scene.ngeom = 0
            self._builder.add_neighbours(scene, snapshot.states, snapshot.offsets)
            draw_decor(scene, snapshot.decor)
        texts = []
        if snapshot.episode_length is not None:
            texts.append(
                (
                    mujoco.mjtFontScale.mjFONTSCALE_150,
                    mujoco.mjtGridPos.mjGRID_TOPLEFT,
                    f"env {snapshot.env_ids[0]}\nreturn\nlength",
                    f"\n{snapshot.episode_return:.2f}\n{snapshot.episode_length}",
                )
            )
        if self.steering is not None:
            font, corner = mujoco.mjtFontScale.mjFONTSCALE_150, mujoco.mjtGridPos.mjGRID_BOTTOMLEFT
            keys, actions = _STEER_HELP
            texts.append((font, corner, f"command\n{keys}", f"{self.steering.describe()}\n{actions}"))
        if texts:
            self._handle.set_texts(texts)  # takes the viewer's lock itself
        self._handle.sync()

    def _close(self) -> None:
        self._handle.close()


def _shift_held() -> bool:
    """Whether a Shift key is down in MuJoCo's window (asked of GLFW: the key callback runs in the
    window's thread, where its context is current; the callback itself gets no modifiers)."""
    try:
        import glfw

        window = glfw.get_current_context()
        return bool(window) and any(
            glfw.get_key(window, key) == glfw.PRESS for key in (glfw.KEY_LEFT_SHIFT, glfw.KEY_RIGHT_SHIFT)
        )
    except Exception:  # noqa: BLE001 - no GLFW state: no modifier
        return False


def forward_key_to_listeners(keycode: int) -> bool:
    """Send a key of MuJoCo's window to the teleoperation listeners, if one listens for it."""
    name = glfw_key_name(keycode)
    if name is None or not key_hub.wants(name):
        return False
    return key_hub.publish(KeyEvent(name, "tap"))
