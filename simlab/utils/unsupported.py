"""Refusing a config setting that simlab cannot honour, instead of accepting and ignoring it.

Isaac Lab configs carry settings that mean something in Omniverse / PhysX and nothing in MuJoCo. A
value equal to the default is accepted silently (a config that leaves it alone still loads); any
other value stops with a :class:`~simlab.utils.errors.ConfigError` that says why and what to use.
"""

from __future__ import annotations

from typing import Any

from simlab.utils.errors import ConfigError


def refuse_unless_default(owner: str, field: str, value: Any, default: Any, why: str, instead: str) -> None:
    """Raise ``ConfigError`` when ``owner.field`` is set to anything but ``default``.

    ``why`` says what simlab lacks for it, ``instead`` what to set or use.
    """
    if value != default:
        raise ConfigError(f"{owner}.{field}={value!r} is not supported by simlab: {why}. {instead}")
