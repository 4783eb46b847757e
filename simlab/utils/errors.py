"""The errors simlab raises on purpose: a wrong input or a state the user can act on.

Each subclasses the built-in error it stands for (``ValueError``, ``RuntimeError``, ...), so code that
catches those keeps working. The ``simlab`` command prints these as one line and exits with 2;
any other exception is a bug somewhere and keeps its traceback (see :func:`is_intended_error`).
"""

from __future__ import annotations

import errno
import os
import traceback

__all__ = [
    "CheckpointError",
    "ConfigError",
    "ConfigTypeError",
    "DeviceError",
    "MissingDependencyError",
    "SimlabError",
    "StorageError",
    "TrainingDivergedError",
    "UntrustedFileError",
    "describe",
    "is_intended_error",
    "is_storage_error",
]


class SimlabError(Exception):
    """Base of the errors simlab raises on purpose; the message says what was wrong and what to do."""


class ConfigError(SimlabError, ValueError):
    """A wrong setting: a flag, an override, a config field, a task id."""


class ConfigTypeError(ConfigError, TypeError):
    """A config field of the wrong type (a weight that is not a number, ...)."""


class DeviceError(SimlabError, RuntimeError):
    """A device that does not exist here, or a backend that is not installed for it."""


class CheckpointError(SimlabError, ValueError):
    """A checkpoint that is missing, unreadable, or of another library or task."""


class CheckpointNotFoundError(CheckpointError, FileNotFoundError):
    """No checkpoint where one was looked for."""


class UntrustedFileError(CheckpointError):
    """A checkpoint or statistics file that needs more than data to load (it could run code)."""


class MissingDependencyError(SimlabError, ImportError):
    """An optional library that the asked-for feature needs is not installed."""


class StorageError(SimlabError, OSError):
    """A file or folder that cannot be written: no permission, a read-only file system, a full disk."""


class TrainingDivergedError(SimlabError, RuntimeError):
    """The learner's loss or policy became non-finite (too high a learning rate, exploding rewards)."""


# errno values of a write the storage refused: the user frees space, or picks a folder they can write
STORAGE_ERRNOS = frozenset(
    getattr(errno, name) for name in ("EACCES", "EPERM", "EROFS", "ENOSPC", "EDQUOT", "EFBIG") if hasattr(errno, name)
)


def is_storage_error(error: BaseException) -> bool:
    """True for a write refused by the storage: no permission, a read-only file system, a full disk."""
    return isinstance(error, StorageError) or (isinstance(error, OSError) and error.errno in STORAGE_ERRNOS)


_SIMLAB_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep
# built-in errors that a ``raise`` statement in simlab's own code uses for bad input
_INPUT_ERRORS = (ValueError, TypeError, KeyError, IndexError, FileNotFoundError, NotImplementedError)


def is_intended_error(error: BaseException) -> bool:
    """True for errors simlab raises on purpose to report bad input.

    That is a :class:`SimlabError`, or a ``ValueError``-like built-in error raised by a ``raise``
    statement in simlab's own source (many checks of configs and terms predate the family), or a write
    the storage refused (:func:`is_storage_error`, a state the user fixes). Any other error raised inside
    a library, by a failed operation in simlab, or in the user's code is not.
    """
    if isinstance(error, SimlabError) or is_storage_error(error):
        return True
    if not isinstance(error, _INPUT_ERRORS) or error.__traceback__ is None:
        return False
    innermost = traceback.extract_tb(error.__traceback__)[-1]
    in_simlab = os.path.abspath(innermost.filename).startswith(_SIMLAB_ROOT)
    return in_simlab and (innermost.line or "").lstrip().startswith("raise ")


def describe(error: BaseException) -> str:
    """``"<type>: <first line of the message>"``, or the type alone for an error without a message
    (``MemoryError()``): for one-line reports of an error caught from a library."""
    first_line = next(iter(str(error).strip().splitlines()), "")
    return f"{type(error).__name__}: {first_line}" if first_line else type(error).__name__
