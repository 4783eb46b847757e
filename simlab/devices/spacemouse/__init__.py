"""SpaceMouse devices (Isaac Lab's ``isaaclab.devices.spacemouse``)."""

from .se3_spacemouse import Se3SpaceMouse, Se3SpaceMouseCfg

__all__ = ["Se3SpaceMouse", "Se3SpaceMouseCfg"]
