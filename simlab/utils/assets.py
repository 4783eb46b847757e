"""Locating asset files. simlab ships its models inside the package, so only local paths exist.

Isaac Lab's Nucleus directory constants (``ISAACLAB_NUCLEUS_DIR`` and friends) name no server simlab
can read. A ``UsdFileCfg`` naming a Nucleus robot or prop that simlab ships spawns simlab's model of it
(``simlab.sim.spawners.from_files.usd_stand_ins``); Isaac Lab's pre-trained policies that simlab ships
one for read as TorchScript of it (``simlab.pretrained.isaaclab_policies``); reading any other path
under them is refused with an error saying to use an MJCF (or URDF) file instead.
"""

from __future__ import annotations

import functools
import io
import os
import shutil
from collections.abc import Callable

__all__ = [
    "ISAACLAB_NUCLEUS_DIR",
    "ISAAC_NUCLEUS_DIR",
    "NUCLEUS_ASSET_ROOT_DIR",
    "NVIDIA_NUCLEUS_DIR",
    "check_file_path",
    "check_usd_path_with_timeout",
    "read_file",
    "retrieve_file_path",
]

NUCLEUS_ASSET_ROOT_DIR = "nucleus://Assets/Isaac/5.1"
"""Stands for Isaac Lab's asset server root; simlab cannot read it (see the module docstring)."""

NVIDIA_NUCLEUS_DIR = f"{NUCLEUS_ASSET_ROOT_DIR}/NVIDIA"
ISAAC_NUCLEUS_DIR = f"{NUCLEUS_ASSET_ROOT_DIR}/Isaac"
ISAACLAB_NUCLEUS_DIR = f"{ISAAC_NUCLEUS_DIR}/IsaacLab"

# Remote locations Isaac Lab reads through omni.client; simlab has no client for them.
_REMOTE_PREFIXES = ("nucleus://", "omniverse://", "http://", "https://", "s3://")


def _nucleus_file(path: str | os.PathLike) -> Callable[[], bytes] | None:
    """The maker of a Nucleus file simlab makes itself (any Isaac Sim version's ``.../IsaacLab/<path>``):
    Isaac Lab's pre-trained policies that a shipped policy stands for."""
    if not str(path).startswith(_REMOTE_PREFIXES):
        return None
    from simlab.pretrained.isaaclab_policies import isaaclab_policy, torchscript_policy  # torch, when asked

    isaac_path = isaaclab_policy(str(path))
    return functools.partial(torchscript_policy, isaac_path) if isaac_path is not None else None


def refuse_remote_path(path: str) -> None:
    """Raise, naming what to use instead, if ``path`` is a Nucleus or other remote location."""
    if str(path).startswith(_REMOTE_PREFIXES):
        raise FileNotFoundError(
            f"'{path}' is an Omniverse Nucleus / remote asset (Isaac Lab's USD files); simlab reads local MJCF"
            " or URDF files only. Use the robot configs in simlab.robots (e.g. simlab.robots.CARTPOLE_CFG) or"
            " sim_utils.MjcfFileCfg(asset_path='path/to/robot.xml')."
        )


def _expand(path: str | os.PathLike) -> str:
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"Expected a file path (str or os.PathLike), got {type(path).__name__}: {path!r}.")
    return os.path.abspath(os.path.expandvars(os.path.expanduser(os.fspath(path))))


def check_file_path(path: str | os.PathLike) -> int:
    """0 if the file does not exist, 1 if it is a local file, 2 (Isaac Lab's code for a Nucleus file) for
    a Nucleus file simlab makes itself (a pre-trained policy of ``simlab.pretrained.isaaclab_policies``)."""
    if str(path).startswith(_REMOTE_PREFIXES):
        return 2 if _nucleus_file(path) is not None else 0
    return 1 if os.path.isfile(_expand(path)) else 0


def check_usd_path_with_timeout(usd_path: str, timeout: float = 300, log_interval: float = 30) -> bool:
    """Isaac Lab's check that a (Nucleus) USD file can be reached: whether a local file exists; a
    remote path raises, naming what to use instead (simlab has no Nucleus client and reads no USD)."""
    refuse_remote_path(usd_path)
    return os.path.isfile(_expand(usd_path))


def retrieve_file_path(path: str | os.PathLike, download_dir: str | None = None, force_download: bool = True) -> str:
    """The absolute path of a local file (absolute, relative or ``~`` paths).

    With ``download_dir`` the file is copied there (overwriting only if ``force_download``) and the
    copy's path is returned, as Isaac Lab does for remote files. Remote (Nucleus) paths raise.
    """
    refuse_remote_path(path)
    full = _expand(path)
    if not os.path.isfile(full):
        hint = " (it is a directory)" if os.path.isdir(full) else ""
        raise FileNotFoundError(f"Unable to find the file: '{path}' (resolved to '{full}'){hint}.")
    if download_dir is None:
        return full
    os.makedirs(_expand(download_dir), exist_ok=True)
    target = os.path.join(_expand(download_dir), os.path.basename(full))
    if os.path.abspath(target) != full and (force_download or not os.path.isfile(target)):
        shutil.copy2(full, target)
    return target


def read_file(path: str | os.PathLike) -> io.BytesIO:
    """The bytes of a local file or of a Nucleus file simlab makes itself; other remote paths raise."""
    make = _nucleus_file(path)
    if make is not None:
        return io.BytesIO(make())
    with open(retrieve_file_path(path), "rb") as f:
        return io.BytesIO(f.read())
