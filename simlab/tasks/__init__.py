"""The tasks, with Isaac Lab's layout (``manager_based/classic/cartpole``, ``direct/cartpole``, ...).

Importing this package imports every task package, whose ``__init__`` registers its Gymnasium ids
(``simlab/Cartpole-v0``, ...). Registration names the env and config classes by string, so no
simulation code is imported until ``gym.make``.
"""

from __future__ import annotations

import importlib
import pkgutil

# sub-packages that hold no task registrations
_SKIP = {"utils", "mdp", "agents"}


def _import_task_packages(package_name: str) -> None:
    package = importlib.import_module(package_name)
    for info in pkgutil.iter_modules(package.__path__):
        if info.ispkg and info.name not in _SKIP:
            _import_task_packages(f"{package_name}.{info.name}")


_import_task_packages(__name__)
