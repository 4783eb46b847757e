"""Locating asset files. simlab ships its models inside the package, so only local paths exist."""

from __future__ import annotations

import os
import shutil

__all__ = ["check_file_path", "retrieve_file_path"]


def _expand(path: str | os.PathLike) -> str:
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"Expected a file path (str or os.PathLike), got {type(path).__name__}: {path!r}.")
    return os.path.abspath(os.path.expandvars(os.path.expanduser(os.fspath(path))))


def check_file_path(path: str | os.PathLike) -> int:
    """0 if the file does not exist, 1 if it is a local file (Isaac Lab's 2, a Nucleus file, never occurs)."""
    return 1 if os.path.isfile(_expand(path)) else 0


def retrieve_file_path(path: str | os.PathLike, download_dir: str | None = None, force_download: bool = True) -> str:
    """The absolute path of a local file (absolute, relative or ``~`` paths).

    With ``download_dir`` the file is copied there (overwriting only if ``force_download``) and the
    copy's path is returned, as Isaac Lab does for remote files.
    """
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
