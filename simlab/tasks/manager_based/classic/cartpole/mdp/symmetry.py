"""The cartpole's left-right symmetry, for rsl_rl's symmetry augmentation (``RslRlSymmetryCfg``).

Mirrored in the rail's middle, the cart's position and velocity and the pole's angle and angular
velocity all change sign, and so does the force that drives the cart: every observation and action
of the mirrored state is the negated one.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

if TYPE_CHECKING:
    from tensordict import TensorDict


def compute_symmetric_states(
    env, obs: TensorDict | None = None, actions: torch.Tensor | None = None
) -> tuple[TensorDict | None, torch.Tensor | None]:
    """The batch followed by its mirror image: ``2 * batch`` rows of observations (every group) and actions."""
    obs_aug = None if obs is None else torch.cat([obs, -obs])  # TensorDicts concatenate and negate per entry
    actions_aug = None if actions is None else torch.cat([actions, -actions])
    return obs_aug, actions_aug
