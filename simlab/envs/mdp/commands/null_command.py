"""A command term that generates nothing (for tasks without commands)."""

from __future__ import annotations

from simlab.managers.command_manager import CommandTerm


class NullCommand(CommandTerm):
    def __str__(self) -> str:
        return "NullCommand: no command"

    @property
    def command(self):
        raise RuntimeError("NullCommand generates no command; the task's observations/rewards should not ask for one")

    def reset(self, env_ids=None) -> dict[str, float]:
        return {}

    def compute(self, dt: float) -> None:
        pass
