"""Curriculum terms: ``func(env, env_ids, ...)`` run at resets; what they return is logged."""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import torch

from simlab.managers.manager_base import ManagerTermBase
from simlab.managers.scene_entity_cfg import SceneEntityCfg
from simlab.utils.env_mask import env_mask, takes_env_mask

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedRLEnv


@takes_env_mask
def modify_reward_weight(
    env: ManagerBasedRLEnv, env_ids: torch.Tensor, term_name: str, weight: float, num_steps: int
) -> torch.Tensor:
    """Set the weight of reward term ``term_name`` to ``weight`` at the first reset after ``num_steps``
    env steps (Isaac Lab's rule). The check and the change happen on the device, so a step replayed
    as a CUDA graph applies them too; returns the term's current weight."""
    due = env_ids.any() & (env._step_count > num_steps)
    return env.reward_manager.set_term_weight_where(term_name, due, weight)


_ROBOT = SceneEntityCfg("robot")


@takes_env_mask
def terrain_levels_vel(
    env: ManagerBasedRLEnv, env_ids: torch.Tensor, asset_cfg: SceneEntityCfg = _ROBOT
) -> torch.Tensor:
    """Isaac Lab's terrain curriculum: an env whose robot walked out of its tile (farther than half a
    tile from its origin) moves one row (difficulty level) up; one that walked less than half the
    distance its ``base_velocity`` command asked for over an episode moves one row down.
    Returns the mean terrain level."""
    asset = env.scene[asset_cfg.name]
    terrain = env.scene.terrain
    if terrain is None or terrain.terrain_origins is None:
        raise ValueError(
            "terrain_levels_vel needs a scene 'terrain' of TerrainImporterCfg with terrain_type='generator'"
        )
    command = env.command_manager.get_command("base_velocity")
    # computed for every env (fixed shapes), applied where the mask is set
    distance = torch.norm(asset.data.root_pos_w[:, :2] - env.scene.env_origins[:, :2], dim=1)
    move_up = distance > terrain.cfg.terrain_generator.size[0] / 2
    move_down = distance < torch.norm(command[:, :2], dim=1) * env.max_episode_length_s * 0.5
    move_down &= ~move_up
    terrain.update_env_origins(env_mask(env_ids, env.num_envs, env.device), move_up, move_down)
    return torch.mean(terrain.terrain_levels.float())


_INDEXED_PART = re.compile(r"^(\w+)\[(\d+)\]$")


def _split_address(address: str) -> list[str | int]:
    """``"a.b[2].c"`` (or ``"a.b.2.c"``) as ``["a", "b", 2, "c"]``."""
    parts: list[str | int] = []
    for part in address.split("."):
        indexed = _INDEXED_PART.match(part)
        if indexed:
            parts += [indexed.group(1), int(indexed.group(2))]
        else:
            parts.append(int(part) if part.isdigit() else part)
    return parts


def _child(obj: Any, part: str | int) -> Any:
    if isinstance(obj, dict):
        return obj[part]
    if isinstance(part, int):
        return obj[part]
    return getattr(obj, part)


def _set_child(obj: Any, part: str | int, value: Any) -> Any:
    """Set ``part`` of ``obj`` to ``value``; returns ``obj``, or a new tuple when ``obj`` is a tuple."""
    if isinstance(obj, tuple):
        items = list(obj)
        items[part] = value
        return tuple(items)
    if isinstance(obj, (dict, list)):
        obj[part] = value
    else:
        setattr(obj, part, value)
    return obj


class modify_env_param(ManagerTermBase):  # noqa: N801 - Isaac Lab's name
    """Change any value reachable from the env by a dotted ``address`` (attributes, dict keys and
    list or tuple indices, as ``name[2]`` or ``name.2``), e.g.
    ``"event_manager.cfg.reset_pole.params.position_range"``.

    ``modify_fn(env, env_ids, old_value, **modify_params)`` returns the new value, or
    ``modify_env_param.NO_CHANGE`` to leave it. A value inside a tuple is replaced by rebuilding
    the tuple in its parent.
    """

    NO_CHANGE = object()

    def __init__(self, cfg, env: ManagerBasedRLEnv):
        super().__init__(cfg, env)
        address = cfg.params.get("address")
        if not isinstance(address, str) or not address:
            raise ValueError(f"{type(self).__name__} needs params['address'], a dotted path from the env")
        self._address = self._full_address(address)
        self._parts = _split_address(self._address)
        self._path(env)  # fail now if the address does not exist

    def _full_address(self, address: str) -> str:
        return address

    def _path(self, root: Any) -> list[Any]:
        """The objects along the address: ``[root, child, ..., value]``."""
        objs = [root]
        for i, part in enumerate(self._parts):
            try:
                objs.append(_child(objs[-1], part))
            except (AttributeError, KeyError, IndexError, TypeError) as err:
                walked = ".".join(str(p) for p in self._parts[: i + 1])
                raise ValueError(
                    f"{type(self).__name__}: '{walked}' of address '{self._address}' does not exist ({err!r})"
                ) from err
        return objs

    def __call__(
        self,
        env: ManagerBasedRLEnv,
        env_ids: torch.Tensor,
        address: str,
        modify_fn: Callable,
        modify_params: dict | None = None,
    ) -> Any:
        objs = self._path(env)
        new = modify_fn(env, env_ids, objs[-1], **(modify_params or {}))
        if new is self.NO_CHANGE:
            return None
        # write back; a tuple cannot change in place, so its rebuilt copy goes into its own parent
        value = new
        for depth in range(len(self._parts) - 1, -1, -1):
            parent = objs[depth]
            updated = _set_child(parent, self._parts[depth], value)
            if updated is parent:
                break
            value = updated
        return new if isinstance(new, (int, float)) else None


class modify_term_cfg(modify_env_param):  # noqa: N801 - Isaac Lab's name
    """:class:`modify_env_param` with manager-config shorthand addresses.

    ``"rewards.alive.weight"`` means ``"reward_manager.cfg.alive.weight"``, ``"events.push.params.x"``
    means ``"event_manager.cfg.push.params.x"``, and likewise for observations, commands, actions,
    terminations and curriculum: the first ``"s."`` of the address becomes ``"_manager.cfg."``.
    """

    def _full_address(self, address: str) -> str:
        if "s." not in address:
            raise ValueError(
                f"modify_term_cfg address '{address}' must start with a manager's plural name, e.g."
                " 'rewards.<term>.weight' or 'events.<term>.params.<name>'."
            )
        return address.replace("s.", "_manager.cfg.", 1)
