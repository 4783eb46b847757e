# Isaac Lab 3.0's isaaclab_tasks/core/locomotion/mdp grew two reward terms after the text ported in
# rewards.py; the ant config (isaaclab3_ant) uses them. Their torch text is not at hand, so:
# ``terminated_penalty`` is written here from its Warp version's documented behaviour ("emit 1 / step_dt on
# the terminating step so the manager's dt scaling cancels"), and ``survival_success_rate`` is 3.0's class
# from the cartpole mdp (isaaclab3_cartpole/mdp/rewards.py), which 3.0 moved here.

"""Reward terms Isaac Lab 3.0 added to the locomotion mdp later."""

from __future__ import annotations

import torch
from isaaclab3_cartpole.mdp.rewards import survival_success_rate  # noqa: F401


def terminated_penalty(env) -> torch.Tensor:
    """One-off penalty for terminating early, independent of the environment step size."""
    return env.termination_manager.terminated.float() / env.step_dt
