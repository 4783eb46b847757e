"""Recorded episodes and the files they are stored in (Isaac Lab's ``isaaclab.utils.datasets``).

:class:`HDF5DatasetFileHandler` needs ``h5py`` (the ``datasets`` extra: ``pip install simlab[datasets]``);
it is imported on first use so that :class:`EpisodeData` works without it.
"""

import importlib
from typing import Any

from simlab.utils.datasets.dataset_file_handler_base import DatasetFileHandlerBase
from simlab.utils.datasets.episode_data import EpisodeData

__all__ = ["DatasetFileHandlerBase", "EpisodeData", "HDF5DatasetFileHandler"]


def __getattr__(name: str) -> Any:
    if name == "HDF5DatasetFileHandler":
        module = importlib.import_module("simlab.utils.datasets.hdf5_dataset_file_handler")
        return module.HDF5DatasetFileHandler
    raise AttributeError(f"module 'simlab.utils.datasets' has no attribute '{name}'")
