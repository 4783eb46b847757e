"""Files from elsewhere are data: load checkpoints and pickles without running code in them.

A pickle can call any function while it loads (``os.system`` included), so a checkpoint or a
statistics file someone else wrote is read the way PyTorch and Hugging Face read them: torch files
with ``torch.load(weights_only=True)`` (tensors, containers, numbers and the few numpy types real
checkpoints hold), other pickles through an unpickler that knows only harmless names. A file that
needs more is refused with one line; ``trust=True`` (the CLI's ``--trust_checkpoint``) loads a file
the user vouches for as its library would.
"""

from __future__ import annotations

import contextlib
import io
import os
import pickle
import re
import tempfile
import zipfile
from collections.abc import Callable, Iterator
from typing import Any

from simlab.utils.errors import CheckpointError, UntrustedFileError

__all__ = [
    "NUMPY_GLOBALS",
    "TRUST_HINT",
    "restricted_loads",
    "torch_load",
    "weights_only_copy",
]

TRUST_HINT = "pass --trust_checkpoint if you trust the file (loading it may run code)"

# numpy arrays and scalars as pickle stores them (numpy 1.x and 2.x module names)
NUMPY_GLOBALS = frozenset(
    f"{core}.{name}"
    for core in ("numpy.core.multiarray", "numpy._core.multiarray", "numpy.core.numeric", "numpy._core.numeric")
    for name in ("_reconstruct", "scalar", "_frombuffer")
) | {"numpy.ndarray", "numpy.dtype"}


def _torch_safe_globals() -> list[Any]:
    """numpy's array, scalar and dtype types: rl_games stores its best reward as a numpy scalar."""
    import numpy as np

    core = getattr(np, "_core", None) or np.core
    dtypes = [type(np.dtype(t)) for t in ("float16", "float32", "float64", "int32", "int64", "uint8", "bool")]
    return [core.multiarray.scalar, core.multiarray._reconstruct, np.ndarray, np.dtype, *dtypes]


def _first_reason(error: BaseException) -> str:
    """The one line of torch's weights-only refusal that names what the file needed."""
    text = str(error)
    match = re.search(r"GLOBAL ([\w.]+)", text)
    return f"it needs {match.group(1)}" if match else "it needs a Python object"


def torch_load(
    f: Any, map_location: Any = None, trust: bool = False, what: str | None = None, hint: str = TRUST_HINT
) -> Any:
    """``torch.load`` of weights only (``trust``: any pickle); a file that needs more raises
    :class:`UntrustedFileError` naming it, what it needed and ``hint`` (what the user can do)."""
    import torch

    if trust:
        return torch.load(f, map_location=map_location, weights_only=False)
    try:
        with torch.serialization.safe_globals(_torch_safe_globals()):
            return torch.load(f, map_location=map_location, weights_only=True)
    except pickle.UnpicklingError as e:
        if "GLOBAL" not in str(e):
            raise  # bytes that are no pickle torch reads (a corrupt file): the caller's error, not trust
        name = what or (f"'{os.fspath(f)}'" if isinstance(f, (str, os.PathLike)) else "the checkpoint")
        raise UntrustedFileError(
            f"Refused to load {name}: it holds more than weights ({_first_reason(e)}); {hint}."
        ) from None


def is_torchscript(path: str | os.PathLike) -> bool:
    """Whether ``path`` is a TorchScript archive (a zip that carries compiled code, which ``torch.jit.load``
    runs), not a ``torch.save`` file of weights. Reads the archive's names only."""
    if not zipfile.is_zipfile(path):
        return False
    with contextlib.suppress(zipfile.BadZipFile, OSError), zipfile.ZipFile(path) as archive:
        return any(n.endswith("/constants.pkl") or "/code/" in n for n in archive.namelist())
    return False


@contextlib.contextmanager
def weights_only_copy(path: str, trust: bool = False, kind: str = "torch") -> Iterator[str]:
    """A path for an RL library's own loader: rsl_rl, skrl and rl_games read checkpoints with
    ``torch.load(weights_only=False)`` (skrl on JAX with ``pickle.load``) and no way to ask otherwise.

    ``path`` is read as data (``kind`` "torch": :func:`torch_load`; "pickle": plain containers, bytes
    and numbers only) and written again to a temporary file, which the block gets: a pickle written
    from tensors, containers and numbers can only rebuild those, so the library's own load then runs
    unchanged and nothing in the process is patched. ``trust`` gives ``path`` itself. A file that
    holds more raises :class:`UntrustedFileError` before the block runs.
    """
    if trust:
        yield path
        return
    what = f"'{os.fspath(path)}'"
    with tempfile.TemporaryDirectory(prefix="simlab_checkpoint_") as folder:
        copy = os.path.join(folder, os.path.basename(path))  # the library may read the name (its epoch)
        if kind == "torch":
            import torch

            torch.save(torch_load(path, map_location="cpu", what=what), copy)
        elif kind == "pickle":
            with open(path, "rb") as f:
                data = restricted_loads(f.read(), lambda module, name: False, what)
            with open(copy, "wb") as f:
                pickle.dump(data, f, protocol=4)
        else:
            raise ValueError(f"kind must be 'torch' or 'pickle', not {kind!r}")
        yield copy


class _RestrictedUnpickler(pickle.Unpickler):
    def __init__(self, file: Any, allowed: Callable[[str, str], bool], what: str, hint: str):
        super().__init__(file)
        self._allowed, self._what, self._hint = allowed, what, hint

    def find_class(self, module: str, name: str) -> Any:
        if not self._allowed(module, name):
            raise UntrustedFileError(
                f"Refused to load {self._what}: it needs {module}.{name}, which is not plain data; {self._hint}."
            )
        return super().find_class(module, name)


def restricted_loads(data: bytes, allowed: Callable[[str, str], bool], what: str, hint: str = TRUST_HINT) -> Any:
    """Unpickle ``data`` when every global it names passes ``allowed(module, name)``; else
    :class:`UntrustedFileError` naming the first one that does not (nothing outside ``allowed`` runs)."""
    try:
        return _RestrictedUnpickler(io.BytesIO(data), allowed, what, hint).load()
    except UntrustedFileError:
        raise
    except Exception as e:  # noqa: BLE001 - corrupt bytes make pickle raise anything
        raise CheckpointError(f"Cannot read {what}: {type(e).__name__}: {e}".splitlines()[0]) from None
