"""What every live viewer does around its drawing: pacing, pause / single step, the followed env,
episode statistics, and keeping training alive when the viewer fails.

The training (or play) thread calls :meth:`LiveViewer.after_step` once per env step. That costs a
few vector operations on the device; at most ``fps`` times a second it also copies the shown envs'
state (a few rows) and hands it to the viewer's own thread, which computes the poses on the host
and draws. A slow or closed viewer therefore never slows the step loop: a frame not yet drawn is
replaced by the newer one. Pause and single-step are the exceptions a person asks for: they hold
the step loop until resumed. A velocity command steered from the viewer (``steering``) is handed to
the env here too, between steps. Any viewer error prints one warning and the run goes on headless.
"""

from __future__ import annotations

import contextlib
import queue
import sys
import threading
import time
from dataclasses import dataclass

import torch

from simlab.viewer.source import EnvSnapshot, SimSource
from simlab.viewer.steering import VelocitySteering

__all__ = ["LiveViewer", "ViewerControls", "ViewerError"]

MAX_SHOWN_ENVS = 16


class ViewerError(RuntimeError):
    """A viewer cannot be opened here (no display, port in use, package missing)."""


@dataclass
class ViewerControls:
    """What the person at the viewer chose; written by the viewer's GUI, read by the step loop."""

    paused: bool = False
    steps_to_run: int = 0  # single steps asked for while paused
    follow: int = 0  # the env the camera follows and whose episode is shown
    render_every: int = 1  # draw every k-th env step (at most ``fps`` a second)
    rendering: bool = True  # False: draw nothing, train at full speed
    realtime_factor: float | None = None  # play: sim seconds per wall second; None: as fast as it runs


class LiveViewer:
    """Base of the native and web viewers; subclasses implement ``_draw`` and ``_close``."""

    kind = "base"

    def __init__(
        self,
        source: SimSource,
        fps: float = 30.0,
        realtime: bool = False,
        follow: int = 0,
        steering: VelocitySteering | None = None,
    ):
        self.source = source
        self.fps = fps
        self.steering = steering  # the followed env's velocity command, where the person may steer it
        self.controls = ViewerControls(follow=follow, realtime_factor=1.0 if realtime else None)
        self.failed = False
        self.closed = False
        self.frames_drawn = 0
        self._steps = 0
        self._next_frame = 0.0
        self._last_step_time: float | None = None
        device = source.env_origins.device
        self._returns = torch.zeros(source.num_envs, device=device)
        self._lengths = torch.zeros(source.num_envs, device=device, dtype=torch.long)
        self._shown: tuple[int, list[int], object] | None = None
        self._mailbox: queue.Queue[EnvSnapshot | None] = queue.Queue(maxsize=1)
        self._worker = threading.Thread(target=self._draw_loop, name=f"simlab-{self.kind}-viewer", daemon=True)

    def _start(self) -> None:
        """Subclasses call this once their window / server is up."""
        self._worker.start()

    # -- the step loop's side -------------------------------------------------------------------

    def after_step(self, reward: torch.Tensor | None = None, done: torch.Tensor | None = None) -> None:
        """Call once per env step (``reward``, ``done``: per env, for the episode text)."""
        if self.failed or self.closed:
            return
        try:
            self._steps += 1
            if reward is not None:
                self._track_episodes(reward, done)
            self._hold_while_paused()
            if self.controls.realtime_factor:
                self._pace()
            if self.steering is not None:  # what the person chose applies from the next step on
                self.steering.sync(self.controls.follow)
            now = time.monotonic()
            c = self.controls
            if c.rendering and self._steps % max(1, c.render_every) == 0 and now >= self._next_frame:
                self._next_frame = now + 1.0 / self.fps
                self._post(self._snapshot())
        except Exception as err:  # noqa: BLE001 - a viewer never stops a run
            self._fail(err)

    def _track_episodes(self, reward: torch.Tensor, done: torch.Tensor | None) -> None:
        """Running return and length of every env, on the device (no host sync per step)."""
        self._returns += reward.reshape(-1).to(self._returns.device, self._returns.dtype)
        self._lengths += 1
        if done is not None:
            keep = ~done.reshape(-1).to(self._returns.device, torch.bool)
            self._returns *= keep
            self._lengths *= keep

    def _snapshot(self) -> EnvSnapshot:
        follow = self.controls.follow
        if self._shown is None or self._shown[0] != follow:
            ids, offsets = self.source.shown_envs(follow, MAX_SHOWN_ENVS)
            self._shown = (follow, ids, offsets)
        _, ids, offsets = self._shown
        snap = self.source.snapshot(ids, offsets)
        snap.episode_return = float(self._returns[follow])
        snap.episode_length = int(self._lengths[follow])
        return snap

    def _post(self, snapshot: EnvSnapshot) -> None:
        """Hand the newest frame to the drawing thread, replacing one it has not drawn yet."""
        with contextlib.suppress(queue.Empty):
            self._mailbox.get_nowait()
        self._mailbox.put_nowait(snapshot)

    def _hold_while_paused(self) -> None:
        c = self.controls
        while c.paused and not self.closed and not self.failed:
            if c.steps_to_run > 0:
                c.steps_to_run -= 1
                self._post(self._snapshot())
                return
            time.sleep(0.02)

    def _pace(self) -> None:
        """Play in real time: one env step per ``step_dt / realtime_factor`` seconds."""
        period = self.source.step_dt / self.controls.realtime_factor
        now = time.monotonic()
        if self._last_step_time is not None and now < self._last_step_time + period:
            time.sleep(self._last_step_time + period - now)
        self._last_step_time = time.monotonic()

    # -- the drawing thread ---------------------------------------------------------------------

    def _draw_loop(self) -> None:
        while True:
            snapshot = self._mailbox.get()
            if snapshot is None:  # close()
                return
            try:
                self._draw(snapshot)
                self.frames_drawn += 1
            except Exception as err:  # noqa: BLE001 - a viewer never stops a run
                self._fail(err)
                return

    def _draw(self, snapshot: EnvSnapshot) -> None:
        raise NotImplementedError

    # -- failure and shutdown -------------------------------------------------------------------

    def _fail(self, err: BaseException) -> None:
        if self.failed:
            return
        self.failed = True
        message = f"the {self.kind} viewer failed ({err!r}); the run goes on without it."
        print(f"[simlab] WARNING: {message}", file=sys.stderr)
        with contextlib.suppress(Exception):  # already failing
            self._close()

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        if self._worker.is_alive():  # the frame already posted is drawn, then the thread ends
            with contextlib.suppress(queue.Full):
                self._mailbox.put(None, timeout=5.0)
            self._worker.join(timeout=5.0)
        if not self.failed:
            self._close()

    def _close(self) -> None:
        """Release the window / server."""
