"""Steering a velocity policy from a live viewer: a person's command instead of the task's random ones.

When ``simlab play`` shows a velocity task (a command term whose config has ``ranges.lin_vel_x``,
``lin_vel_y`` and ``ang_vel_z``, as ``UniformVelocityCommand``), the viewer's keys (native) or
controls (web) set the command ``(v_x, v_y, w_z)`` of the followed env: each press moves one
component by a quarter of its range, kept within the range the policy was trained on; stop holds
zero (the robot stands); release hands the env back to the task's commands, which draw a new one.

The viewer's threads only write the wanted command here, as host values. The step loop hands it to
the command term between steps (:meth:`VelocitySteering.sync`), as the term's *user command*: a
device tensor and an env mask that the step reads (``CommandTerm.set_user_command``), so a graphed
step follows it too and nothing is read back.
"""

from __future__ import annotations

import sys

__all__ = ["AXES", "VelocitySteering"]

AXES = ("lin_vel_x", "lin_vel_y", "ang_vel_z")
"""The command's components, in its column order; their ranges are the term's ``cfg.ranges``."""

_UNITS = ("m/s", "m/s", "rad/s")
_NAMES = ("v_x", "v_y", "w_z")


class VelocitySteering:
    """The command a person wants for the followed env (None: the task's own), and handing it over."""

    def __init__(self, term, name: str = "base_velocity"):
        self.term = term
        self.name = name
        self.ranges = tuple((float(getattr(term.cfg.ranges, axis)[0]), float(getattr(term.cfg.ranges, axis)[1]))
                            for axis in AXES)  # fmt: skip
        self.steps = tuple((hi - lo) / 4.0 for lo, hi in self.ranges)
        self.wanted: tuple[float, float, float] | None = None  # written by the viewer's threads
        self._given: tuple[int, tuple[float, float, float] | None] = (-1, None)  # what the term has
        term.enable_user_command()

    @classmethod
    def of_env(cls, env) -> VelocitySteering | None:
        """Steering for the env's velocity command term, or None where it has none (a warning says
        why one cannot be steered)."""
        manager = getattr(env, "command_manager", None)
        for name in getattr(manager, "active_terms", []):
            term = manager.get_term(name)
            ranges = getattr(term.cfg, "ranges", None)
            if not all(getattr(ranges, axis, None) is not None for axis in AXES):
                continue
            try:
                if tuple(term.command.shape[1:]) != (3,):
                    continue
                return cls(term, name)
            except (RuntimeError, TypeError) as err:
                print(f"[simlab] WARNING: the command '{name}' cannot be steered: {err}", file=sys.stderr)
                return None
        return None

    # -- the viewer's side ------------------------------------------------------------------------

    def nudge(self, axis: int, direction: int) -> None:
        """Move component ``axis`` (0: v_x, 1: v_y, 2: w_z) one step up (``direction`` 1) or down (-1),
        from zero if the task's command was in use."""
        command = list(self.wanted or (0.0, 0.0, 0.0))
        command[axis] = round(command[axis] + direction * self.steps[axis], 6)
        self.set(command)

    def set(self, command) -> None:
        """Hold ``(v_x, v_y, w_z)``, each clipped to its range."""
        self.wanted = tuple(min(hi, max(lo, float(v))) for v, (lo, hi) in zip(command, self.ranges))

    def stop(self) -> None:
        """Hold a zero command: the robot stands."""
        self.wanted = (0.0, 0.0, 0.0)

    def release(self) -> None:
        """Back to the task's commands."""
        self.wanted = None

    def describe(self) -> str:
        if self.wanted is None:
            return "the task's (random)"
        return ", ".join(f"{n} {v:+.2f} {u}" for n, v, u in zip(_NAMES, self.wanted, _UNITS))

    # -- the step loop's side ---------------------------------------------------------------------

    def sync(self, env_id: int) -> None:
        """Between steps: give env ``env_id`` the wanted command (and hand a previously followed env
        back to the task). Writes device tensors only when something changed."""
        wanted = self.wanted
        if (env_id, wanted) == self._given:
            return
        given_env, given = self._given
        if given is not None and (wanted is None or given_env != env_id):
            self.term.release_user_command([given_env])
        if wanted is not None:
            self.term.set_user_command(wanted, [env_id])
        self._given = (env_id, wanted)
