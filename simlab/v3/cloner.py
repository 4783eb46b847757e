"""``isaaclab.cloner`` of Isaac Lab 3.0, the part a direct env's ``_setup_scene`` calls.

Isaac Lab 3.0 builds env 0 on its USD stage and copies it into every env: a direct env's
``_setup_scene`` calls ``grid_transforms``, ``clone_plan_from_env_0`` and ``replicate``. On simlab every
env is already a world of the one MuJoCo model the scene compiles, at the scene's grid of origins, so
there is nothing to copy: :func:`replicate` checks that the plan asks for what simlab's scene makes (env 0
at ``/World/envs/env_0`` copied to ``/World/envs/env_{}``, one copy per env) and refuses another layout
in one line. The plan's positions place the envs, as in 3.0 (whose scene reads its env origins from the
plan unless a terrain places the envs): they become the scene's env origins. :func:`grid_transforms`
gives the same grid as simlab's scene (Isaac Lab's terrain layout).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import torch

from simlab.terrains.terrain_importer import grid_origins
from simlab.utils.errors import ConfigError

__all__ = ["ClonePlan", "clone_plan_from_env_0", "filter_collisions", "grid_transforms", "replicate"]

SOURCE, DESTINATION = "/World/envs/env_0", "/World/envs/env_{}"


def grid_transforms(
    N: int, spacing: float = 1.0, up_axis: str = "z", device: Any = "cpu"
) -> tuple[torch.Tensor, torch.Tensor]:
    """``N`` env positions on a centred grid ``spacing`` apart (simlab's scene uses the same) and identity
    orientations (x, y, z, w)."""
    if up_axis.lower() != "z":
        raise ConfigError(f"grid_transforms(up_axis={up_axis!r}): simlab's worlds are z-up; use up_axis='z'.")
    positions = grid_origins(N, spacing, device)
    orientations = torch.zeros(N, 4, device=device)
    orientations[:, 3] = 1.0
    return positions, orientations


@dataclass
class ClonePlan:
    """What 3.0 code asks to clone: ``source`` (env 0) into ``destination`` (``{}`` the env id) ``num_clones`` times."""

    source: str
    destination: str
    num_clones: int
    positions: Any = None
    global_paths: tuple[str, ...] = ()


def clone_plan_from_env_0(
    source: str, destination: str, num_clones: int, *device_and_positions: Any, global_paths: Any = (), **_: Any
) -> ClonePlan:
    """The plan of copying env 0 into ``num_clones`` envs; 3.0 passes ``(device, positions)`` or ``(positions,)`` after
    ``num_clones`` (its versions differ), positions last."""
    positions = device_and_positions[-1] if device_and_positions else None
    if isinstance(positions, str):  # only a device was given
        positions = None
    return ClonePlan(source, destination, int(num_clones), positions, tuple(global_paths))


def replicate(plan: ClonePlan, stage: Any = None, **_: Any) -> None:
    """Check that ``plan`` is the layout simlab's scene made and place the envs at its positions (see the
    module); nothing is copied."""
    from simlab.sim import SimulationContext

    if (plan.source.rstrip("/"), plan.destination.rstrip("/")) != (SOURCE, DESTINATION):
        raise ConfigError(
            f"replicate: the plan copies '{plan.source}' into '{plan.destination}'; simlab's scene makes its envs at "
            f"'{DESTINATION}' from '{SOURCE}' (declare the assets under {{ENV_REGEX_NS}} and clone those paths)."
        )
    sim = SimulationContext.instance()
    if sim is not None and plan.num_clones != sim.num_envs:
        raise ConfigError(
            f"replicate: the plan makes {plan.num_clones} envs, the scene has {sim.num_envs} (scene.num_envs): "
            "clone scene.num_envs envs."
        )
    if plan.positions is None:
        return
    positions = torch.as_tensor(plan.positions, dtype=torch.float32)
    if tuple(positions.shape) != (plan.num_clones, 3):
        raise ConfigError(f"replicate: positions must be ({plan.num_clones}, 3), one per env.")
    if sim is not None and not sim.env_origins_from_terrain:  # a terrain's origins hold, as in 3.0
        positions = positions.to(sim.device)
        if sim.env_origins is None:
            sim.env_origins = positions.clone()
        else:  # in place: assets made before the plan read the same tensor
            sim.env_origins.copy_(positions)


def filter_collisions(*_: Any, **__: Any) -> None:
    """Nothing to filter: simlab's envs are separate MuJoCo worlds and never collide."""
