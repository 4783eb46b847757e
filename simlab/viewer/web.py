"""The web viewer: the scene in a browser, through viser and mjviser (``pip install "simlab[viewer]"``).

mjviser draws a MuJoCo model's bodies as batched meshes, several envs at once, from body poses
(``ViserMujocoScene.update_from_arrays``); simlab gives it the shown envs' poses, computed on the
host, and adds the controls a person needs while training: pause / single step, the followed env,
how often to draw, and the followed env's episode return and length. When a teleoperation device
listens for keys (``simlab.devices.Se3Keyboard``), a Teleop tab has a button per key: a motion
key's button acts while held down (viser repeats its event), the others act once per click.
Playing a velocity task, a Steer tab sets the followed env's command (``simlab.viewer.steering``):
a slider per component within the task's ranges, Stop, and a button back to the task's commands.

The camera starts where the env's videos look from and at (``cfg.viewer``, ``SimSource.camera``) and
moves with the followed env, or with the asset ``cfg.viewer`` follows (``SimSource.anchor``). mjviser
shifts the scene so that its tracked body sits at viser's origin, where the page's camera looks; here
that is the world body (its geoms are drawn once, not from its pose), posed at the look-at point.
"""

from __future__ import annotations

import contextlib
import errno
import io
import socket
import sys

import mujoco
import numpy as np

from simlab.devices.keys import KeyEvent, key_hub
from simlab.viewer.access import UngatedServerError, new_token, start_gated_viser
from simlab.viewer.choice import DEFAULT_HOST
from simlab.viewer.live import MAX_SHOWN_ENVS, LiveViewer, ViewerError
from simlab.viewer.source import EnvSnapshot, HostKinematics, SimSource
from simlab.viewer.steering import VelocitySteering

__all__ = ["WebViewer"]

TELEOP_REPEAT_HZ = 10.0  # a held teleop button's event rate; Se3Keyboard holds a tap for 0.2 s
LOOKAT_LABEL = "Look-at point (cfg.viewer)"  # the Track body choice that keeps the env's viewer camera


def _check_can_listen(host: str, port: int) -> None:
    """Raise ViewerError unless this machine can listen on ``host:port``."""
    try:
        family = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)[0][0]
    except socket.gaierror as err:
        raise ViewerError(f"--viewer_host {host!r} is not an address ({err.strerror})") from err
    with socket.socket(family, socket.SOCK_STREAM) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            probe.bind((host, port))
        except OSError as err:
            if err.errno == errno.EADDRINUSE:
                raise ViewerError(f"Port {port} is in use: choose a free one with --viewer_port") from err
            raise ViewerError(f"cannot listen on {host}:{port} ({err.strerror}): check --viewer_host") from err


def _url(host: str, port: int, token: str) -> str:
    """The address to open: this machine's name when listening on every address."""
    if host in ("0.0.0.0", "::", ""):
        host = socket.gethostname()
    elif host == "127.0.0.1":
        host = "localhost"
    elif ":" in host:
        host = f"[{host}]"
    return f"http://{host}:{port}/?token={token}"


class WebViewer(LiveViewer):
    """A viser server on ``host:port`` showing the followed env and its neighbours, to whoever opens
    its URL with the token in it (``simlab.viewer.access``)."""

    kind = "web"

    def __init__(
        self,
        source: SimSource,
        port: int = 8080,
        realtime: bool = False,
        follow: int = 0,
        host: str = DEFAULT_HOST,
        steering: VelocitySteering | None = None,
    ):
        try:
            import viser  # noqa: F401 - the server, started by simlab.viewer.access
            from mjviser import ViserMujocoScene
        except ImportError as err:
            raise ViewerError(f'The web viewer needs viser and mjviser: pip install "simlab[viewer]" ({err})') from err
        if not 1 <= port <= 65535:
            raise ViewerError(f"--viewer_port must be a TCP port (1..65535), got {port}")
        _check_can_listen(host, port)
        super().__init__(source, realtime=realtime, follow=follow, steering=steering)
        self.host = host
        self._kinematics = HostKinematics(source.model)
        self.num_shown = min(MAX_SHOWN_ENVS, source.num_envs)
        self.token = new_token()
        try:
            with contextlib.redirect_stdout(io.StringIO()):  # viser prints its address without the token
                self.server = start_gated_viser(host, port, self.token, verbose=False)
        except UngatedServerError as err:
            raise ViewerError(str(err)) from err
        self.port = self.server.get_port()  # viser moves to the next port if this one was taken meanwhile
        # mjviser edits visual scales of the model it is given; it gets its own copy.
        self.scene = ViserMujocoScene(self.server, _copy_model(source.model), num_envs=self.num_shown)
        self.scene.env_idx = 0  # row 0 is always the followed env
        camera = source.camera(follow)
        self._eye_offset = None if camera is None else camera[0] - camera[1]
        self._lookat_from_anchor = None  # where the camera looks, relative to the point it moves with
        if camera is not None:
            self._lookat_from_anchor = camera[1] - source.anchor(follow)
            self.scene._tracked_body_id = 0  # the world body, drawn at the look-at point (see _draw)
        self._neighbour_fixed = self._add_neighbour_fixed_geometry()
        self._offsets_drawn: np.ndarray | None = None
        self._build_gui()
        self.server.on_client_connect(lambda client: print("[simlab] Web viewer: a browser connected", file=sys.stderr))
        self.url = _url(host, self.port, self.token)
        print(f"[simlab] Web viewer: {self.url}", file=sys.stderr, flush=True)
        self._start()

    # -- scene ----------------------------------------------------------------------------------

    def _add_neighbour_fixed_geometry(self) -> list[tuple[object, np.ndarray]]:
        """Geoms welded to the world (a cart's rail) for the neighbours: mjviser draws them once."""
        from mjviser.conversions import is_fixed_body, merge_geoms

        model = self.scene.mj_model
        data = mujoco.MjData(model)
        mujoco.mj_kinematics(model, data)
        bodies: dict[int, list[int]] = {}
        for geom in range(model.ngeom):
            body = int(model.geom_bodyid[geom])
            if (
                is_fixed_body(model, body)
                and model.geom_type[geom] != mujoco.mjtGeom.mjGEOM_PLANE
                and model.geom_rgba[geom, 3] > 0
                and model.geom_group[geom] < 3
            ):
                bodies.setdefault(body, []).append(geom)
        handles = []
        n = self.num_shown - 1
        if n <= 0:
            return handles
        for body, geoms in bodies.items():
            handle = self.server.scene.add_batched_meshes_trimesh(
                f"/fixed_bodies/simlab_neighbours/body{body}",
                merge_geoms(model, geoms),
                batched_wxyzs=np.tile(data.xquat[body], (n, 1)),
                batched_positions=np.tile(data.xpos[body], (n, 1)),
            )
            handles.append((handle, data.xpos[body].copy()))
        return handles

    def _draw(self, snapshot: EnvSnapshot) -> None:
        if not self.server.get_clients():
            return  # nobody is looking: no work (a page that connects later gets the next frame)
        xpos, xmat = self._kinematics.body_poses(snapshot)
        if self._lookat_from_anchor is not None and snapshot.anchor is not None:
            xpos[0, 0] = snapshot.anchor + self._lookat_from_anchor  # mjviser centres the tracked body
        mocap_pos = mocap_quat = None
        if "mocap_pos" in snapshot.states:
            mocap_pos = snapshot.states["mocap_pos"] + snapshot.offsets[:, None]
            mocap_quat = snapshot.states["mocap_quat"]
        if self._offsets_drawn is None or not np.array_equal(self._offsets_drawn, snapshot.offsets):
            for handle, body_pos in self._neighbour_fixed:
                handle.batched_positions = body_pos + snapshot.offsets[1:]
            self._offsets_drawn = snapshot.offsets
        self.scene.update_from_arrays(xpos, xmat, mocap_pos, mocap_quat, env_idx=0)
        self._status.content = self._status_text(snapshot)
        if self.steering is not None:
            self._steer_status.content = f"**Command of env {snapshot.env_ids[0]}**: {self.steering.describe()}"

    def _status_text(self, snapshot: EnvSnapshot) -> str:
        text = f"**Env {snapshot.env_ids[0]}** of {self.source.num_envs}"
        if snapshot.episode_length is not None:
            text += f"  \nEpisode: return {snapshot.episode_return:.2f}, length {snapshot.episode_length} steps"
        return text + f"  \nEnv step {self._steps}"

    # -- controls -------------------------------------------------------------------------------

    def _build_gui(self) -> None:
        gui, c = self.server.gui, self.controls
        tabs = gui.add_tab_group()
        with tabs.add_tab("Run"):
            self._status = gui.add_markdown("Waiting for the first step")
            pause = gui.add_button("Pause")
            step = gui.add_button("Step", disabled=True, hint="One env step while paused")

            @pause.on_click
            def _(_) -> None:
                c.paused = not c.paused
                pause.label = "Resume" if c.paused else "Pause"
                step.disabled = not c.paused

            @step.on_click
            def _(_) -> None:
                c.steps_to_run += 1

            follow = gui.add_number("Follow env", initial_value=c.follow, min=0, max=self.source.num_envs - 1, step=1)

            @follow.on_update
            def _(_) -> None:
                c.follow = int(np.clip(follow.value, 0, self.source.num_envs - 1))

            drawing = gui.add_checkbox("Draw", initial_value=True, hint="Off: training runs at full speed")

            @drawing.on_update
            def _(_) -> None:
                c.rendering = drawing.value

            every = gui.add_slider("Draw every k steps", min=1, max=100, step=1, initial_value=1)

            @every.on_update
            def _(_) -> None:
                c.render_every = int(every.value)

            if c.realtime_factor is not None:
                speed = gui.add_slider("Real-time factor", min=0.1, max=4.0, step=0.1, initial_value=1.0)

                @speed.on_update
                def _(_) -> None:
                    c.realtime_factor = float(speed.value)

            bodies = [mujoco.mj_id2name(self.source.model, mujoco.mjtObj.mjOBJ_BODY, b) or f"body {b}"
                      for b in range(self.source.model.nbody)]  # fmt: skip
            bodies[0] = LOOKAT_LABEL  # the world body stands for the viewer camera's look-at point
            options = bodies if self._lookat_from_anchor is not None else bodies[1:]
            tracked = self.scene._tracked_body_id  # mjviser's: the body the camera keeps centred
            if tracked is not None:
                track = gui.add_dropdown("Track body", options=options, initial_value=bodies[tracked])

                @track.on_update
                def _(_) -> None:
                    self.scene._tracked_body_id = bodies.index(track.value)
                    self.scene.request_update()

        if self.steering is not None:
            with tabs.add_tab("Steer"):
                self._build_steer_gui()
        with tabs.add_tab("Camera"):
            # Row 0 is always the followed env: hide mjviser's own env slider (shown for num_envs > 1).
            shown, self.scene.num_envs = self.scene.num_envs, 1
            self.scene.create_scene_gui(*_camera_angles(self._eye_offset))
            self.scene.num_envs = shown
        with tabs.add_tab("Visualization"):
            self.scene.create_overlay_gui()
        with tabs.add_tab("Groups"):
            self.scene.create_groups_gui()
        self._tabs = tabs
        self._teleop_buttons: dict[str, object] = {}
        self._add_teleop_buttons()
        self._watch = key_hub.watch(self._add_teleop_buttons)

    def _build_steer_gui(self) -> None:
        """Sliders for the followed env's ``(v_x, v_y, w_z)``, Stop, and back to the task's commands."""
        gui, steering = self.server.gui, self.steering
        self._steer_status = gui.add_markdown(f"**Command**: {steering.describe()}")
        labels = ("Forward (m/s)", "Sideways (m/s)", "Turn (rad/s)")
        sliders = [
            gui.add_slider(label, min=lo, max=hi, step=step / 5, initial_value=min(hi, max(lo, 0.0)))
            for label, (lo, hi), step in zip(labels, steering.ranges, steering.steps)
        ]
        for slider in sliders:

            @slider.on_update
            def _(_) -> None:
                steering.set([s.value for s in sliders])

        stop = gui.add_button("Stop", hint="Hold a zero command: the robot stands")
        release = gui.add_button("Task's commands", hint="Back to the task's random commands")

        @stop.on_click
        def _(_) -> None:
            for slider in sliders:  # shows the zero command (each assignment calls on_update)
                slider.value = min(slider.max, max(slider.min, 0.0))
            steering.stop()

        @release.on_click
        def _(_) -> None:
            steering.release()

        self._steer_sliders = sliders

    # -- teleoperation keys ---------------------------------------------------------------------

    def _add_teleop_buttons(self) -> None:
        """A button for each key a teleoperation listener wants (added once; kept while the page lives)."""
        keys, held = key_hub.keys(), key_hub.held_keys()
        new = [key for key in keys if key not in self._teleop_buttons]
        if not new:
            return
        if not hasattr(self, "_teleop_tab"):
            self._teleop_tab = self._tabs.add_tab("Teleop")
            with self._teleop_tab:
                self.server.gui.add_markdown("Hold a motion key's button to move; click the others.")
        with self._teleop_tab:
            for key in new:
                button = self.server.gui.add_button(f"{key}: {keys[key]}")
                if key in held:
                    button.on_hold(lambda _, k=key: key_hub.publish(KeyEvent(k, "tap")), callback_hz=TELEOP_REPEAT_HZ)
                else:
                    button.on_click(lambda _, k=key: key_hub.publish(KeyEvent(k, "tap")))
                self._teleop_buttons[key] = button

    def _close(self) -> None:
        key_hub.unwatch(self._watch)
        self.server.stop()


def _camera_angles(eye_offset: np.ndarray | None) -> tuple[float, float, float]:
    """mjviser's ``(distance, azimuth, elevation)`` of a camera at ``eye_offset`` from its target."""
    if eye_offset is None or np.linalg.norm(eye_offset) < 1e-6:
        return -1.0, 120.0, 20.0  # mjviser's defaults
    distance = float(np.linalg.norm(eye_offset))
    azimuth = float(np.degrees(np.arctan2(-eye_offset[1], -eye_offset[0])))
    elevation = float(np.degrees(np.arcsin(eye_offset[2] / distance)))
    return distance, azimuth, elevation


def _copy_model(model: mujoco.MjModel) -> mujoco.MjModel:
    import copy

    return copy.deepcopy(model)
