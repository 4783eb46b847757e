"""Stop a diverging learner at the first optimizer step that makes its weights non-finite.

Too high a learning rate (or exploding rewards) turns the weights into NaN / inf; the libraries then
fail later with an unrelated error (``normal expects all elements of std >= 0.0``) or, worse, keep
training on NaN actions. :func:`guard_optimizers` checks the weights after every optimizer step
(torch's step hooks); on the first bad step it puts back the weights and optimizer state from
before that step and raises :class:`TrainingDivergedError`, so the adapter can save them as the
last good checkpoint.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import torch

from simlab.utils.errors import TrainingDivergedError

__all__ = ["detached", "guard_optimizers", "non_finite"]


def detached(state: Any) -> Any:
    """A copy of a (nested) state dict whose tensors later optimizer steps do not change."""
    if isinstance(state, torch.Tensor):
        return state.detach().clone()
    if isinstance(state, dict):
        return {k: detached(v) for k, v in state.items()}
    if isinstance(state, (list, tuple)):
        return type(state)(detached(v) for v in state)
    return state


def non_finite(tensors: Iterable[torch.Tensor]) -> bool:
    """True if any floating-point tensor holds a NaN or an infinity (one device sync)."""
    checks = [t.isfinite().all() for t in tensors if isinstance(t, torch.Tensor) and t.is_floating_point()]
    return bool(checks) and not bool(torch.stack(checks).all())


def guard_optimizers(optimizers: Iterable[torch.optim.Optimizer], learning_rate_key: str) -> None:
    """After each step of each optimizer, check its parameters; restore and raise on NaN / inf.

    ``learning_rate_key`` is the override that sets the learning rate, named in the message.
    """
    for optimizer in optimizers:
        saved: dict[str, Any] = {}

        def before(opt: torch.optim.Optimizer, args: Any, kwargs: Any, saved: dict = saved) -> None:
            saved["params"] = [p.detach().clone() for g in opt.param_groups for p in g["params"]]
            saved["state"] = detached(opt.state_dict())

        def after(opt: torch.optim.Optimizer, args: Any, kwargs: Any, saved: dict = saved) -> None:
            params = [p for g in opt.param_groups for p in g["params"]]
            if not non_finite(params):
                return
            with torch.no_grad():
                for p, good in zip(params, saved["params"]):
                    p.copy_(good)
            opt.load_state_dict(saved["state"])
            rate = opt.param_groups[0].get("lr")
            raise TrainingDivergedError(
                f"Training diverged: an optimizer step made the weights non-finite (learning rate {rate:g}). "
                f"Lower the learning rate ({learning_rate_key}) or check the rewards and observations for huge values."
            )

        optimizer.register_step_pre_hook(before)
        optimizer.register_step_post_hook(after)
