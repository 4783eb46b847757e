"""Isaac Lab's controller helpers (``isaaclab.controllers.utils``): edits of URDF files that its
whole-body IK setups make before loading a robot.

``change_revolute_to_fixed`` and ``change_revolute_to_fixed_regex`` rewrite the URDF text as Isaac Lab's
do. ``convert_usd_to_urdf`` needs Isaac Sim's USD exporter and ``resolve_rmpflow_path`` its motion
generation extension: both raise, saying what to use, except for a path that needs no resolving.
"""

from __future__ import annotations

import logging
import re

from simlab.utils.errors import ConfigError

__all__ = ["change_revolute_to_fixed", "change_revolute_to_fixed_regex", "convert_usd_to_urdf", "resolve_rmpflow_path"]

logger = logging.getLogger(__name__)

_RMPFLOW_PREFIX = "rmpflow_ext:"
_REVOLUTE = re.compile(r'<joint name="([^"]+)" type="revolute">')


def _fix_joints(urdf_path: str, should_fix, verbose: bool) -> list[str]:
    """Make every revolute joint for which ``should_fix(name)`` holds a fixed joint; returns their names."""
    with open(urdf_path) as file:
        content = file.read()
    fixed = [name for name in _REVOLUTE.findall(content) if should_fix(name)]
    for name in fixed:
        content = content.replace(f'<joint name="{name}" type="revolute">', f'<joint name="{name}" type="fixed">')
        if verbose:
            logger.warning(f"Replacing {name} with fixed joint")
    with open(urdf_path, "w") as file:
        file.write(content)
    return fixed


def change_revolute_to_fixed(urdf_path: str, fixed_joints: list[str], verbose: bool = False) -> None:
    """Turn the revolute joints named in ``fixed_joints`` into fixed joints, in place."""
    fixed = _fix_joints(urdf_path, lambda name: name in fixed_joints, verbose)
    if verbose:
        for name in sorted(set(fixed_joints) - set(fixed)):
            logger.warning(f"Error: Could not find revolute joint named '{name}' in URDF file")


def change_revolute_to_fixed_regex(urdf_path: str, fixed_joints: list[str], verbose: bool = False) -> None:
    """Turn the revolute joints whose names match one of the regular expressions ``fixed_joints`` fixed."""
    _fix_joints(urdf_path, lambda name: any(re.match(pattern, name) for pattern in fixed_joints), verbose)


def convert_usd_to_urdf(usd_path: str, output_path: str, force_conversion: bool = True) -> tuple[str, str]:
    """Isaac Lab exports a USD robot to URDF with Isaac Sim; simlab reads no USD."""
    raise ConfigError(
        f"convert_usd_to_urdf('{usd_path}'): simlab reads no USD (Isaac Sim's URDF exporter converts it);"
        " give the robot's URDF file directly, or its MJCF (simlab/robots/assets)."
    )


def resolve_rmpflow_path(path: str) -> str:
    """``path`` itself; an ``rmpflow_ext:`` path names Isaac Sim's RMPflow extension, which simlab lacks."""
    if path.startswith(_RMPFLOW_PREFIX):
        raise ConfigError(
            f"'{path}' lies in Isaac Sim's motion-generation extension (RMPflow), which simlab does not have;"
            " use simlab.controllers.DifferentialIKController or OperationalSpaceController."
        )
    return path
