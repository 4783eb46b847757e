"""Reading and writing configs: yaml (human-readable) and pickle (exact python objects).

Every file is written atomically (:func:`atomic_path`): a crash or a full disk leaves the old file
or none, never a torn one.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import pickle
import re
from collections.abc import Callable, Iterable, Iterator
from typing import Any

import yaml

from simlab.utils.dict import MISSING_STR, _value_to_plain, class_to_dict
from simlab.utils.errors import StorageError, UntrustedFileError, is_storage_error

__all__ = [
    "ConfigYamlDumper",
    "ConfigYamlLoader",
    "atomic_path",
    "atomic_torch_saves",
    "dump_pickle",
    "dump_yaml",
    "load_pickle",
    "load_yaml",
    "remove_stale_temp_files",
    "write_text",
]

TUPLE_TAG = "tag:yaml.org,2002:python/tuple"
"""PyYAML's tag for a tuple (``!!python/tuple``), the one Isaac Lab's dumped configs carry."""


class ConfigYamlDumper(yaml.SafeDumper):
    """PyYAML's safe dumper that writes tuples with the ``!!python/tuple`` tag, so a config's
    tuples come back as tuples (as in Isaac Lab's ``params/env.yaml``)."""


class ConfigYamlLoader(yaml.SafeLoader):
    """PyYAML's safe loader plus the ``!!python/tuple`` tag (and no other python tag): it reads
    Isaac Lab's and simlab's dumped configs without constructing arbitrary objects."""


ConfigYamlDumper.add_representer(tuple, lambda dumper, data: dumper.represent_sequence(TUPLE_TAG, data))
ConfigYamlLoader.add_constructor(TUPLE_TAG, lambda loader, node: tuple(loader.construct_sequence(node, deep=True)))


def _fsync_dir(folder: str) -> None:
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:  # e.g. Windows: directories cannot be opened
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


# the temporary files of atomic_path (and of simlab's video writer): .<name>.<pid>.tmp[<suffix>]
_TEMP_NAME = re.compile(r"^\..+\.(\d+)\.tmp")


def _process_exists(pid: int) -> bool:
    try:
        os.kill(pid, 0)  # signal 0: only asks whether the process exists
    except ProcessLookupError:
        return False
    except OSError:  # exists, but belongs to another user
        return True
    return True


def remove_stale_temp_files(folder: str | os.PathLike) -> list[str]:
    """Remove the temporary files in ``folder`` that a writer killed mid-write left (its process is gone);
    returns their paths. A writer that is still running keeps its file."""
    if os.name != "posix":  # os.kill(pid, 0) would end the process on Windows
        return []
    try:
        names = os.listdir(folder)
    except OSError:
        return []
    removed = []
    for name in names:
        match = _TEMP_NAME.match(name)
        if match is None or int(match.group(1)) == os.getpid() or _process_exists(int(match.group(1))):
            continue
        with contextlib.suppress(OSError):
            os.remove(os.path.join(folder, name))
            removed.append(os.path.join(folder, name))
    return removed


def _storage_problem(folder: str, error: BaseException) -> str | None:
    """Why a write into ``folder`` failed when the storage refused it (no permission, read-only, full),
    else None. torch reports a failed write as a ``RuntimeError`` without the cause: a small write
    into the folder, while the failed file is still there, tells whether the storage is the cause."""
    if is_storage_error(error):
        return getattr(error, "strerror", None) or str(error)
    if not isinstance(error, (OSError, RuntimeError)):
        return None
    probe = os.path.join(folder, f".probe.{os.getpid()}.tmp")
    try:
        with open(probe, "wb") as f:
            f.write(bytes(2**16))
            f.flush()
            os.fsync(f.fileno())
    except OSError as probe_error:
        return probe_error.strerror or str(probe_error)
    finally:
        with contextlib.suppress(OSError):
            os.remove(probe)
    return None


def _storage_error(path: str, reason: str) -> StorageError:
    kept = " (the file already there is unchanged)" if os.path.isfile(path) else ""
    return StorageError(f"Cannot write '{os.path.basename(path)}' into '{os.path.dirname(path)}': {reason}{kept}.")


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike, suffix: str = "", durable: bool = True) -> Iterator[str]:
    """Yield a temporary path next to ``path``; once the block has written it, it replaces ``path``.

    The temporary name starts with a dot (checkpoint patterns do not match it) and ends with
    ``suffix`` (for writers that insist on an extension, e.g. ``.zip``). ``durable`` flushes the
    file and its folder to disk before and after the rename, so a power cut leaves the old file or
    the new one. If the block fails, the temporary file is removed and ``path`` is untouched; a
    write the storage refused (no permission, read-only, full disk) raises :class:`StorageError`
    naming the folder. Temporary files of writers that were killed are removed here too.
    """
    path = os.path.abspath(os.fspath(path))
    folder, name = os.path.split(path)
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as error:
        raise _storage_error(path, error.strerror or str(error)) from error
    remove_stale_temp_files(folder)
    tmp = os.path.join(folder, f".{name}.{os.getpid()}.tmp{suffix}")
    try:
        yield tmp
        if not os.path.isfile(tmp):
            raise FileNotFoundError(f"atomic_path: nothing was written to '{tmp}' for '{path}'.")
        if durable:
            with open(tmp, "rb") as f:
                os.fsync(f.fileno())
        os.replace(tmp, path)
        if durable:
            _fsync_dir(folder)
    except Exception as error:
        reason = None if isinstance(error, StorageError) else _storage_problem(folder, error)
        if reason is None:
            raise
        raise _storage_error(path, reason) from error
    finally:
        with contextlib.suppress(OSError):  # no temporary file left behind, whatever stopped the block
            os.remove(tmp)


@contextlib.contextmanager
def atomic_torch_saves() -> Iterator[None]:
    """Within the block, every ``torch.save`` to a file path writes atomically (see :func:`atomic_path`).

    The RL libraries write their checkpoints with ``torch.save(obj, path)``; training runs inside
    this block, so a checkpoint on disk is always complete, even if the process dies mid-write.
    The patch is process-wide while the block runs, so it is made only with the torch release it
    was checked with (``simlab.utils.versions``); with another, saves are plain and a warning says so.
    """
    import torch

    from simlab.utils.versions import release_mismatch, warn_once

    mismatch = release_mismatch("torch")
    if mismatch is not None:
        warn_once(f"{mismatch}: checkpoints are written with torch's own torch.save, not atomically")
        yield
        return
    plain_save = torch.save

    def save(obj: Any, f: Any, *args: Any, **kwargs: Any) -> None:
        if not isinstance(f, (str, os.PathLike)):
            return plain_save(obj, f, *args, **kwargs)
        with atomic_path(f) as tmp:
            plain_save(obj, tmp, *args, **kwargs)

    torch.save = save
    try:
        yield
    finally:
        torch.save = plain_save


def write_text(filename: str | os.PathLike, text: str) -> None:
    """Write ``text`` to ``filename`` atomically (parent folders are created)."""
    with atomic_path(filename) as tmp, open(tmp, "w") as f:
        f.write(text)


def _to_yaml_ready(value: Any) -> Any:
    """Plain dicts/lists/scalars only: callables -> "module:qualname", MISSING -> "???"."""
    value = _value_to_plain(value)
    if value is dataclasses.MISSING:
        return MISSING_STR
    if isinstance(value, dict):
        return {str(k): _to_yaml_ready(v) for k, v in value.items()}
    if isinstance(value, tuple):
        return tuple(_to_yaml_ready(v) for v in value)
    if isinstance(value, list):
        return [_to_yaml_ready(v) for v in value]
    if hasattr(value, "tolist"):  # torch tensors
        return value.tolist()
    return value


def _prepare_path(filename: str | os.PathLike, ext: str) -> str:
    filename = os.fspath(filename)
    if not filename.endswith(ext) and not (ext == ".yaml" and filename.endswith(".yml")):
        filename += ext
    parent = os.path.dirname(filename)
    if parent:
        os.makedirs(parent, exist_ok=True)
    return filename


def dump_yaml(filename: str | os.PathLike, data: Any, sort_keys: bool = False) -> None:
    """Write a dict or a configclass to ``filename`` (``.yaml`` is appended if missing).

    Parent directories are created. Callables and classes are written as ``"module:qualname"``,
    tuples as ``!!python/tuple`` sequences (Isaac Lab's files have them; :func:`load_yaml` reads them
    back as tuples), numpy/torch values as numbers or lists, ``MISSING`` as ``"???"``.
    """
    if dataclasses.is_dataclass(data) and not isinstance(data, type):
        data = class_to_dict(data)
    if not isinstance(data, dict):
        raise TypeError(f"dump_yaml expects a dict or a configclass instance, got {type(data).__name__}.")
    filename = _prepare_path(filename, ".yaml")
    with atomic_path(filename) as tmp, open(tmp, "w") as f:
        yaml.dump(_to_yaml_ready(data), f, Dumper=ConfigYamlDumper, default_flow_style=False, sort_keys=sort_keys)


def load_yaml(filename: str | os.PathLike) -> dict:
    """Read a yaml file into a dict (an empty file gives ``{}``); ``!!python/tuple`` gives a tuple."""
    filename = os.fspath(filename)
    if not os.path.isfile(filename):
        raise FileNotFoundError(f"yaml file not found: '{filename}'.")
    with open(filename) as f:
        data = yaml.load(f, Loader=ConfigYamlLoader)  # noqa: S506 - a safe loader plus the tuple tag
    return {} if data is None else data


def dump_pickle(filename: str | os.PathLike, data: Any) -> None:
    """Pickle ``data`` to ``filename`` (``.pkl`` is appended if missing; parent dirs are created)."""
    filename = _prepare_path(filename, ".pkl")
    with atomic_path(filename) as tmp, open(tmp, "wb") as f:
        pickle.dump(data, f)


_PLAIN_BUILTINS = frozenset({"set", "frozenset", "complex", "slice", "range", "bytearray"})


def _plain_globals(packages: tuple[str, ...], what: str) -> Callable[[str, str], bool]:
    """What :func:`dump_pickle` writes of configs and data: containers, numpy arrays and config classes
    (dataclasses) of ``packages``. A pickle may call a class it names (``__init__`` and
    ``__post_init__`` run), so a dataclass of any other module is refused, naming the module; no
    function, no other class, and no module outside ``packages`` is imported for the file's sake."""
    import importlib
    import sys

    from simlab.utils.trust import NUMPY_GLOBALS

    def allowed(module: str, name: str) -> bool:
        if (module == "builtins" and name in _PLAIN_BUILTINS) or f"{module}.{name}" in NUMPY_GLOBALS:
            return True
        if module == "collections" and name in ("OrderedDict", "deque"):
            return True
        inside = any(module == p or module.startswith(p + ".") for p in packages)
        if not inside and module not in sys.modules:
            return False
        obj = getattr(sys.modules.get(module) or importlib.import_module(module), name, None)
        if not (isinstance(obj, type) and dataclasses.is_dataclass(obj)):
            return False
        if not inside:
            raise UntrustedFileError(
                f"Refused to load {what}: it names {module}.{name}, a dataclass of '{module}', outside"
                f" {', '.join(packages)}; pass --allow_module {module.split('.')[0]} (load_pickle's"
                " allow_modules) to allow it."
            )
        return True

    return allowed


def load_pickle(filename: str | os.PathLike, trust: bool = False, allow_modules: Iterable[str] = ()) -> Any:
    """Load a pickle file of data (containers, numbers, numpy arrays, config dataclasses); one that names
    anything else (a function, another class: unpickling could run it) is refused unless ``trust``.

    Config dataclasses come from simlab, the packages the ``simlab`` command allows ``module:name`` values
    to name (the task's own package, ``--allow_module``) and ``allow_modules``.
    """
    from simlab.utils.string import allowed_callable_packages
    from simlab.utils.trust import restricted_loads

    filename = os.fspath(filename)
    if not os.path.isfile(filename):
        raise FileNotFoundError(f"pickle file not found: '{filename}'.")
    packages = tuple(sorted({"simlab", *allow_modules, *(allowed_callable_packages() or ())}))
    what = f"'{filename}'"
    with open(filename, "rb") as f:
        if trust:
            return pickle.load(f)
        return restricted_loads(f.read(), _plain_globals(packages, what), what, "pass trust=True if you trust the file")
