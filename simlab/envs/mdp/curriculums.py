"""Curriculum terms: ``func(env, env_ids, ...)`` run at resets; what they return is logged."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import torch

from simlab.managers.manager_base import ManagerTermBase

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv


def modify_reward_weight(
    env: ManagerBasedRLEnv, env_ids: torch.Tensor, term_name: str, weight: float, num_steps: int
) -> float:
    """Set the weight of reward term ``term_name`` to ``weight`` once ``num_steps`` env steps have passed."""
    term_cfg = env.reward_manager.get_term_cfg(term_name)
    if env.common_step_counter > num_steps and term_cfg.weight != weight:
        term_cfg.weight = weight
        env.reward_manager.set_term_cfg(term_name, term_cfg)
    return float(term_cfg.weight)


class modify_env_param(ManagerTermBase):  # noqa: N801 - Isaac Lab's name
    """Change any value reachable from the env by a dotted ``address`` (attributes, dict keys and
    list indices), e.g. ``"event_manager.cfg.reset_pole.params.position_range"``.

    ``modify_fn(env, env_ids, old_value, **modify_params)`` returns the new value, or
    ``modify_env_param.NO_CHANGE`` to leave it.
    """

    NO_CHANGE = object()

    def __init__(self, cfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        address = cfg.params.get("address")
        if not isinstance(address, str) or not address:
            raise ValueError("modify_env_param needs params['address'], a dotted path from the env")
        self._parts = address.split(".")
        self._get(env, self._parts)  # fail now if the address does not exist

    def _get(self, root: Any, parts: list[str]) -> Any:
        obj = root
        for i, part in enumerate(parts):
            try:
                if isinstance(obj, dict):
                    obj = obj[part]
                elif isinstance(obj, (list, tuple)) and part.isdigit():
                    obj = obj[int(part)]
                else:
                    obj = getattr(obj, part)
            except (AttributeError, KeyError, IndexError) as err:
                raise ValueError(f"modify_env_param: '{'.'.join(parts[: i + 1])}' does not exist ({err!r})") from err
        return obj

    def __call__(
        self,
        env: ManagerBasedRLEnv,
        env_ids: torch.Tensor,
        address: str,
        modify_fn: Callable,
        modify_params: dict | None = None,
    ) -> Any:
        parent = self._get(env, self._parts[:-1])
        old = self._get(parent, self._parts[-1:])
        new = modify_fn(env, env_ids, old, **(modify_params or {}))
        if new is self.NO_CHANGE:
            return None
        last = self._parts[-1]
        if isinstance(parent, dict):
            parent[last] = new
        elif isinstance(parent, list) and last.isdigit():
            parent[int(last)] = new
        else:
            setattr(parent, last, new)
        return new if isinstance(new, (int, float)) else None
