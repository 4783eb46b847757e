"""Episodes in an HDF5 file laid out as robomimic reads them: ``data/demo_<i>/<key>``."""

from __future__ import annotations

import json
import os
from collections.abc import Iterable

import numpy as np
import torch

from simlab.utils.datasets.dataset_file_handler_base import DatasetFileHandlerBase
from simlab.utils.datasets.episode_data import EpisodeData
from simlab.utils.errors import MissingDependencyError
from simlab.utils.memory import available_memory, format_bytes

try:
    import h5py
except ImportError as error:
    raise MissingDependencyError(
        'HDF5 datasets (simlab record / replay) need h5py: pip install "simlab[datasets]" (or bash scripts/setup.sh).'
    ) from error

# gzip, the filter these files use, shrinks data at most ~1030-fold: a dataset that declares more bytes
# than that times what the file stores for it cannot be there (unwritten rows would read as zeros)
MAX_COMPRESSION_RATIO = 1100


class HDF5DatasetFileHandler(DatasetFileHandlerBase):
    """Write :class:`EpisodeData` to, and read it from, an HDF5 file.

    Layout: group ``data`` with attributes ``total`` (steps over all episodes) and ``env_args``
    (JSON, ``{"env_name": ..., "type": 2}`` as robomimic expects); one group ``demo_<i>`` per
    episode with attributes ``num_samples``, ``seed``, ``success`` and one gzip dataset per key.
    """

    def __init__(self) -> None:
        self._file: h5py.File | None = None
        self._path = ""
        self._data_group: h5py.Group | None = None
        self._demo_count = 0
        self._env_args: dict = {}

    def open(self, file_path: str, mode: str = "r") -> None:
        if self._file is not None:
            raise RuntimeError("This HDF5DatasetFileHandler already has a file open: close() it first.")
        if not os.path.isfile(file_path):
            raise FileNotFoundError(f"Dataset file not found: '{file_path}'.")
        try:
            self._file = h5py.File(file_path, mode)
        except OSError as error:  # h5py's "file signature not found", a truncated file, ...
            raise ValueError(f"'{file_path}' is not a readable HDF5 file ({error}).") from None
        self._path = file_path
        data = self._file.get("data")
        if not isinstance(data, h5py.Group):
            self.close()
            raise ValueError(f"'{file_path}' is not an episode dataset: it has no 'data' group.")
        self._data_group = data
        self._demo_count = len(self._data_group)
        try:
            self._env_args = json.loads(self._data_group.attrs.get("env_args", "{}"))
            if not isinstance(self._env_args, dict):
                raise ValueError
        except (TypeError, ValueError):
            self.close()
            raise ValueError(
                f"'{file_path}' is not an episode dataset: its data/env_args is not a JSON object."
            ) from None

    def create(self, file_path: str, env_name: str | None = None) -> None:
        if self._file is not None:
            raise RuntimeError("This HDF5DatasetFileHandler already has a file open: close() it first.")
        if not file_path.endswith(".hdf5"):
            file_path += ".hdf5"
        directory = os.path.dirname(file_path)
        if directory:
            os.makedirs(directory, exist_ok=True)
        self._file = h5py.File(file_path, "w")
        self._path = file_path
        self._data_group = self._file.create_group("data")
        self._data_group.attrs["total"] = 0
        self._demo_count = 0
        self._env_args = {}
        self.add_env_args({"env_name": env_name if env_name is not None else "", "type": 2})

    def __del__(self) -> None:
        self.close()

    # -- metadata ----------------------------------------------------------------------------------

    def add_env_args(self, env_args: dict) -> None:
        """Merge ``env_args`` into the file's environment arguments."""
        self._require_open()
        self._env_args.update(env_args)
        self._data_group.attrs["env_args"] = json.dumps(self._env_args)

    def set_env_name(self, env_name: str) -> None:
        self.add_env_args({"env_name": env_name})

    def get_env_name(self) -> str | None:
        self._require_open()
        return self._env_args.get("env_name")

    def get_episode_names(self) -> Iterable[str]:
        self._require_open()
        return self._data_group.keys()

    def get_num_episodes(self) -> int:
        return self._demo_count

    @property
    def demo_count(self) -> int:
        return self._demo_count

    # -- episodes ----------------------------------------------------------------------------------

    def load_episode(self, episode_name: str, device: str) -> EpisodeData | None:
        self._require_open()
        if episode_name not in self._data_group:
            return None
        group = self._data_group[episode_name]
        where = f"'{self._path}' {episode_name}"
        if not isinstance(group, h5py.Group):
            raise ValueError(f"{where} is not an episode: a dataset where a group of datasets belongs.")
        self._check_sizes(group, where)

        def read(node: h5py.Group) -> dict:
            # np.array first: building a tensor from an h5py dataset element by element is slow
            return {
                key: read(item) if isinstance(item, h5py.Group) else torch.from_numpy(np.array(item)).to(device)
                for key, item in node.items()
            }

        episode = EpisodeData()
        try:
            episode.data = read(group)
        except OSError as error:  # HDF5 cannot read the bytes: a truncated or corrupt file
            raise ValueError(f"{where} cannot be read ({error}): the file is truncated or corrupt.") from None
        if "seed" in group.attrs:
            episode.seed = group.attrs["seed"].item()
        if "success" in group.attrs:
            episode.success = bool(group.attrs["success"])
        episode.env_id = self.get_env_name()
        return episode

    def _check_sizes(self, group: h5py.Group, where: str) -> None:
        """Refuse an episode whose datasets are not plain numbers, declare more bytes than the file holds
        for them, or would not fit in memory: checked on the declared shapes, before anything is read."""
        datasets: list[h5py.Dataset] = []
        group.visititems(lambda name, node: datasets.append(node) if isinstance(node, h5py.Dataset) else None)
        total = 0
        for dataset in datasets:
            if dataset.dtype.kind not in "biuf":
                raise ValueError(f"{where}: {dataset.name} holds {dataset.dtype}, not numbers.")
            declared = dataset.size * dataset.dtype.itemsize
            stored = dataset.id.get_storage_size()
            if declared > MAX_COMPRESSION_RATIO * stored + 2**16:
                raise ValueError(
                    f"{where}: {dataset.name} declares shape {dataset.shape} ({format_bytes(declared)}) but the "
                    f"file stores {format_bytes(stored)} for it: the file is corrupt or crafted."
                )
            total += declared
        free = available_memory()
        if free is not None and total > free:
            raise ValueError(
                f"{where} holds {format_bytes(total)} of data, more than the {format_bytes(free)} of memory available."
            )

    def write_episode(self, episode: EpisodeData) -> None:
        """Append ``episode`` as ``demo_<n>`` (an empty episode writes nothing)."""
        self._require_open()
        if episode.is_empty():
            return
        episode.pre_export()
        group = self._data_group.create_group(f"demo_{self._demo_count}")
        num_samples = len(episode.data["actions"]) if "actions" in episode.data else 0
        group.attrs["num_samples"] = num_samples
        if episode.seed is not None:
            group.attrs["seed"] = episode.seed
        if episode.success is not None:
            group.attrs["success"] = episode.success

        def write(parent: h5py.Group, key: str, value: dict | torch.Tensor) -> None:
            if isinstance(value, dict):
                child = parent.create_group(key)
                for sub_key, sub_value in value.items():
                    write(child, sub_key, sub_value)
            else:
                parent.create_dataset(key, data=value.detach().cpu().numpy(), compression="gzip")

        for key, value in episode.data.items():
            write(group, key, value)
        self._data_group.attrs["total"] += num_samples
        self._demo_count += 1

    def flush(self) -> None:
        self._require_open()
        self._file.flush()

    def close(self) -> None:
        if getattr(self, "_file", None) is not None:
            self._file.close()
            self._file = None
            self._data_group = None

    def _require_open(self) -> None:
        if self._file is None:
            raise RuntimeError("No dataset file is open: call create(path) or open(path) first.")
