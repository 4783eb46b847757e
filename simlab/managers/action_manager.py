"""Actions: the policy's action vector, split among action terms that drive the scene's assets.

``process_action`` runs once per env step (scale, offset, clip); ``apply_action`` runs every physics
step (write joint targets), so a decimated env holds each action for ``decimation`` physics steps.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import torch

from simlab.utils.debug_vis import DebugVisHooks
from simlab.utils.env_mask import PerEnvState
from simlab.utils.errors import ConfigError

from .manager_base import ManagerBase, ManagerTermBase, cfg_items, format_table
from .manager_term_cfg import ActionTermCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv


class ActionTerm(ManagerTermBase, DebugVisHooks):
    """Turns its slice of the action vector into commands for one asset. A term that draws itself
    (Isaac Lab's navigation action draws its velocity arrows) overrides ``_set_debug_vis_impl`` and
    ``_debug_vis_callback``, as a command term does; ``debug_vis=True`` on another is refused."""

    def __init__(self, cfg: ActionTermCfg, env: ManagerBasedEnv):
        super().__init__(cfg, env)
        if cfg.debug_vis and not self.has_debug_vis_implementation:
            raise ConfigError(
                f"{type(cfg).__name__}.debug_vis=True is not supported by simlab: {type(self).__name__} draws no"
                " debug visualization. Set debug_vis=False (override: env.actions.<term>.debug_vis=false), or"
                " implement _set_debug_vis_impl and _debug_vis_callback in the term (simlab.markers)."
            )
        if cfg.asset_name not in env.scene:
            raise ValueError(f"asset_name '{cfg.asset_name}' is not in the scene; entities: {env.scene.keys()}")
        self._asset = env.scene[cfg.asset_name]
        self.set_debug_vis(cfg.debug_vis)

    def _debug_vis_simulation(self):
        return self._env.sim

    @property
    def action_dim(self) -> int:
        raise NotImplementedError

    @property
    def raw_actions(self) -> torch.Tensor:
        raise NotImplementedError

    @property
    def processed_actions(self) -> torch.Tensor:
        raise NotImplementedError

    def process_actions(self, actions: torch.Tensor) -> None:
        raise NotImplementedError

    def apply_actions(self) -> None:
        raise NotImplementedError

    @property
    def IO_descriptor(self):  # noqa: N802 - Isaac Lab's name
        """What this term's slice of the action means: its type, size, and the joints, scale, offset
        and clip of joint terms (read from the term where it has them)."""
        from .io_descriptors import GenericActionIODescriptor

        desc = GenericActionIODescriptor(
            full_path=f"{type(self).__module__}.{type(self).__qualname__}",
            description=" ".join((type(self).__doc__ or "").split()) or None,
            shape=(self.action_dim,),
            dtype=str(self.raw_actions.dtype),
            action_type=type(self).__name__,
        )
        desc.extras = {"asset_name": self.cfg.asset_name}
        for name in ("joint_names", "_scale", "_offset", "_clip"):
            value = getattr(self, name, None)
            if isinstance(value, torch.Tensor) and value.dim() > 1:
                value = value[0]  # per env: every env has the same
            if value is not None:
                desc.extras[name.lstrip("_")] = value
        return desc


class ActionManager(ManagerBase):
    """Splits the action among its terms, in declaration order."""

    def __init__(self, cfg: object, env: ManagerBasedEnv):
        self._terms: dict[str, ActionTerm] = {}
        super().__init__(cfg, env)
        self._state = PerEnvState(self.num_envs, self.device)
        self._action = self._state.zeros("action", (self.total_action_dim,))
        self._prev_action = self._state.zeros("prev_action", (self.total_action_dim,))

    def __str__(self) -> str:
        rows = [(i, name, term.action_dim) for i, (name, term) in enumerate(self._terms.items())]
        return format_table(
            f"Active Action Terms (shape: {self.total_action_dim})", ["Index", "Name", "Dimension"], rows
        )

    @property
    def total_action_dim(self) -> int:
        return sum(self.action_term_dim)

    @property
    def active_terms(self) -> list[str]:
        return list(self._terms)

    @property
    def action_term_dim(self) -> list[int]:
        return [term.action_dim for term in self._terms.values()]

    @property
    def action(self) -> torch.Tensor:
        """(num_envs, total_action_dim) the last action given to ``process_action``."""
        return self._action

    @property
    def prev_action(self) -> torch.Tensor:
        """The action before that."""
        return self._prev_action

    @property
    def has_debug_vis_implementation(self) -> bool:
        return any(term.has_debug_vis_implementation for term in self._terms.values())

    def set_debug_vis(self, debug_vis: bool) -> bool:
        """Show or hide the markers of every term that draws itself; False when none does."""
        drawn = [term.set_debug_vis(debug_vis) for term in self._terms.values()]
        return any(drawn)

    def get_term(self, name: str) -> ActionTerm:
        if name not in self._terms:
            raise KeyError(f"No action term '{name}'; action terms: {list(self._terms)}")
        return self._terms[name]

    def get_active_iterable_terms(self, env_idx: int) -> Sequence[tuple[str, Sequence[float]]]:
        out, idx = [], 0
        for name, term in self._terms.items():
            out.append((name, self._action[env_idx, idx : idx + term.action_dim].cpu().tolist()))
            idx += term.action_dim
        return out

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> dict[str, torch.Tensor]:
        mask = self._mask(env_ids)
        self._state.reset(mask)
        for term in self._terms.values():
            term.reset(mask)
        return {}

    def check_action(self, action) -> torch.Tensor:
        """The action as a float32 tensor on the env's device (detached), after checking its shape.

        Finite values are checked where the env step is run (``simlab.envs.utils.cuda_graph``).
        """
        if not isinstance(action, torch.Tensor):
            action = torch.as_tensor(np.asarray(action), dtype=torch.float32)
        expected = (self.num_envs, self.total_action_dim)
        if tuple(action.shape) != expected:
            raise ValueError(
                f"The action must have shape (num_envs, action_dim) = {expected}, got {tuple(action.shape)}"
                f" (action terms: {dict(zip(self.active_terms, self.action_term_dim))})"
            )
        return action.detach().to(device=self.device, dtype=torch.float32)

    def process_action(self, action: torch.Tensor) -> None:
        """Check the action, store it, and let each term process its slice."""
        action = self.check_action(action)
        self._prev_action[:] = self._action
        self._action[:] = action
        idx = 0
        for term in self._terms.values():
            term.process_actions(action[:, idx : idx + term.action_dim])
            idx += term.action_dim

    def apply_action(self) -> None:
        for term in self._terms.values():
            term.apply_actions()

    def _prepare_terms(self) -> None:
        for name, term_cfg in cfg_items(self.cfg):
            if not isinstance(term_cfg, ActionTermCfg):
                raise TypeError(f"ActionManager: term '{name}' must be an ActionTermCfg, got {type(term_cfg).__name__}")
            try:
                term_cfg.validate()
                self._terms[name] = term_cfg.class_type(term_cfg, self._env)
            except (ValueError, KeyError, TypeError) as err:
                raise self._term_error(name, str(err)) from err
