"""Recording episodes: recorder terms hand the manager tensors at four points of the env's life
(before and after a step, before and after a reset); the manager keeps one ``EpisodeData`` per env
and exports finished episodes to a dataset file (HDF5 by default), as Isaac Lab's recorder manager.

Recording is host-side bookkeeping: it reads which envs reset, so an RL env with active recorder
terms steps eagerly (not as a CUDA graph).
"""

from __future__ import annotations

import enum
import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import torch

from simlab.utils import configclass
from simlab.utils.datasets import EpisodeData
from simlab.utils.datasets.dataset_file_handler_base import DatasetFileHandlerBase

from .manager_base import ManagerBase, ManagerTermBase, cfg_items, format_table
from .manager_term_cfg import RecorderTermCfg

if TYPE_CHECKING:
    from simlab.envs import ManagerBasedEnv


class DatasetExportMode(enum.IntEnum):
    """Which finished episodes are written, and where."""

    EXPORT_NONE = 0
    EXPORT_ALL = 1
    EXPORT_SUCCEEDED_FAILED_IN_SEPARATE_FILES = 2
    """Succeeded episodes to ``<dataset_filename>``, the others to ``<dataset_filename>_failed``."""
    EXPORT_SUCCEEDED_ONLY = 3


def _hdf5_handler() -> type:
    from simlab.utils.datasets.hdf5_dataset_file_handler import HDF5DatasetFileHandler

    return HDF5DatasetFileHandler


@configclass
class RecorderManagerBaseCfg:
    """Where and how episodes are exported; the recorder terms are the other fields."""

    dataset_file_handler_class_type: type | None = None
    """A ``DatasetFileHandlerBase`` subclass; None: ``HDF5DatasetFileHandler``."""
    dataset_export_dir_path: str = "/tmp/simlab/logs"
    dataset_filename: str = "dataset"
    """File name without its extension."""
    dataset_export_mode: DatasetExportMode = DatasetExportMode.EXPORT_ALL
    export_in_record_pre_reset: bool = True
    """Export an env's episode when it resets (False: only ``export_episodes()`` / close exports)."""
    export_in_close: bool = False
    """Export the episodes still in progress when the env closes."""


_SETTINGS = {f.name for f in RecorderManagerBaseCfg.__dataclass_fields__.values()}


class RecorderTerm(ManagerTermBase):
    """Records one ``(key, value)`` at some of the four points; a None key records nothing.

    ``value`` is a tensor (or nested dict of tensors) with one row per env: all envs for the step
    callbacks, the envs ``env_ids`` for the reset ones. Keys may nest with ``"/"`` (``"obs/policy"``).
    """

    def record_pre_reset(self, env_ids: Sequence[int] | None) -> tuple[str | None, Any]:
        """Before the envs ``env_ids`` reset (their episode is still complete)."""
        return None, None

    def record_post_reset(self, env_ids: Sequence[int] | None) -> tuple[str | None, Any]:
        """After the envs ``env_ids`` reset (their new episode's first state)."""
        return None, None

    def record_pre_step(self) -> tuple[str | None, Any]:
        """In ``step``, after the action manager has processed the action, before physics."""
        return None, None

    def record_post_step(self) -> tuple[str | None, Any]:
        """In ``step``, once every manager has run (before the finished envs reset)."""
        return None, None

    def record_post_physics_decimation_step(self) -> tuple[str | None, Any]:
        """After each of the step's ``decimation`` physics steps."""
        return None, None


class RecorderManager(ManagerBase):
    """Builds the recorder terms of a ``RecorderManagerBaseCfg`` and exports their episodes."""

    def __init__(self, cfg: object, env: ManagerBasedEnv):
        self._terms: dict[str, RecorderTerm] = {}
        self._episodes: dict[int, EpisodeData] = {}
        self._handler: DatasetFileHandlerBase | None = None
        self._failed_handler: DatasetFileHandlerBase | None = None
        self._succeeded_count: dict[int, int] = {}
        self._failed_count: dict[int, int] = {}
        self._env = env
        self.cfg = cfg
        if not cfg:  # None or an empty dict: no recording
            return
        super().__init__(cfg, env)
        if not self._terms:
            return
        if not isinstance(self.cfg, RecorderManagerBaseCfg):
            raise TypeError(
                "The recorders config must subclass RecorderManagerBaseCfg (it says where and how episodes are"
                f" exported), got {type(cfg).__name__}."
            )
        self._episodes = {env_id: EpisodeData() for env_id in range(env.num_envs)}
        mode = DatasetExportMode(self.cfg.dataset_export_mode)
        if mode != DatasetExportMode.EXPORT_NONE:
            path = os.path.join(self.cfg.dataset_export_dir_path, self.cfg.dataset_filename)
            self._handler = self._create_handler(path)
        if mode == DatasetExportMode.EXPORT_SUCCEEDED_FAILED_IN_SEPARATE_FILES:
            path = os.path.join(self.cfg.dataset_export_dir_path, f"{self.cfg.dataset_filename}_failed")
            self._failed_handler = self._create_handler(path)

    def __str__(self) -> str:
        rows = [(i, name) for i, name in enumerate(self._terms)]
        return f"<RecorderManager> contains {len(rows)} active terms.\n" + format_table(
            "Active Recorder Terms", ["Index", "Name"], rows
        )

    def __del__(self) -> None:
        self.close()

    # -- properties ------------------------------------------------------------------------------

    @property
    def active_terms(self) -> list[str]:
        return list(self._terms)

    @property
    def exported_successful_episode_count(self) -> int:
        return sum(self._succeeded_count.values())

    @property
    def exported_failed_episode_count(self) -> int:
        return sum(self._failed_count.values())

    def get_episode(self, env_id: int) -> EpisodeData:
        return self._episodes.get(env_id, EpisodeData())

    # -- recording -------------------------------------------------------------------------------

    def reset(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> dict[str, torch.Tensor]:
        if not self._terms:
            return {}
        ids = self._ids(env_ids)
        for term in self._terms.values():
            term.reset(env_ids=ids)
        for env_id in ids:
            self._episodes[env_id] = EpisodeData()
        return {}

    def add_to_episodes(self, key: str | None, value: Any, env_ids: Sequence[int] | torch.Tensor | None = None):
        """Append row ``i`` of ``value`` (a tensor or nested dict of tensors) to env ``env_ids[i]``'s episode."""
        if not self._terms or key is None:
            return
        ids = self._ids(env_ids)
        if isinstance(value, dict):
            for sub_key, sub_value in value.items():
                self.add_to_episodes(f"{key}/{sub_key}", sub_value, ids)
            return
        if value.shape[0] != len(ids):
            raise ValueError(f"Recorded '{key}' has {value.shape[0]} rows for {len(ids)} envs (one row per env).")
        for row, env_id in enumerate(ids):
            episode = self._episodes.setdefault(env_id, EpisodeData())
            episode.env_id = env_id
            episode.add(key, value[row])

    def set_success_to_episodes(self, env_ids: Sequence[int] | torch.Tensor | None, success_values: torch.Tensor):
        if not self._terms:
            return
        for row, env_id in enumerate(self._ids(env_ids)):
            self._episodes[env_id].success = bool(success_values[row].item())

    def record_pre_step(self) -> None:
        for term in self._terms.values():
            self.add_to_episodes(*term.record_pre_step())

    def record_post_step(self) -> None:
        for term in self._terms.values():
            self.add_to_episodes(*term.record_post_step())

    def record_post_physics_decimation_step(self) -> None:
        for term in self._terms.values():
            self.add_to_episodes(*term.record_post_physics_decimation_step())

    def record_pre_reset(self, env_ids: Sequence[int] | torch.Tensor | None, force_export_or_skip: bool | None = None):
        """Record, mark success (a termination term named ``success``) and, by default, export."""
        if not self._terms:
            return
        ids = self._ids(env_ids)
        for term in self._terms.values():
            key, value = term.record_pre_reset(ids)
            self.add_to_episodes(key, value, ids)
        success = torch.zeros(len(ids), dtype=torch.bool, device=self._env.device)
        terminations = getattr(self._env, "termination_manager", None)
        if terminations is not None and "success" in terminations.active_terms:
            success |= terminations.get_term("success")[ids]
        self.set_success_to_episodes(ids, success)
        if force_export_or_skip or (force_export_or_skip is None and self.cfg.export_in_record_pre_reset):
            self.export_episodes(ids)

    def record_post_reset(self, env_ids: Sequence[int] | torch.Tensor | None) -> None:
        if not self._terms:
            return
        ids = self._ids(env_ids)
        for term in self._terms.values():
            key, value = term.record_post_reset(ids)
            self.add_to_episodes(key, value, ids)

    # -- export ----------------------------------------------------------------------------------

    def get_ep_meta(self) -> dict:
        """The simulation settings written with the episodes."""
        cfg = self._env.cfg
        return {
            "sim_args": {
                "dt": cfg.sim.dt,
                "decimation": cfg.decimation,
                "render_interval": cfg.sim.render_interval,
                "num_envs": cfg.scene.num_envs,
            }
        }

    def export_episodes(self, env_ids: Sequence[int] | torch.Tensor | None = None) -> None:
        """Write the episodes of ``env_ids`` (all envs by default) by the export mode and clear them."""
        if not self._terms:
            return
        ids = self._ids(env_ids)
        finished = [i for i in ids if i in self._episodes and not self._episodes[i].is_empty()]
        if finished:
            for handler in (self._handler, self._failed_handler):
                if handler is not None and hasattr(handler, "add_env_args"):
                    handler.add_env_args(self.get_ep_meta())
        mode = DatasetExportMode(self.cfg.dataset_export_mode)
        written = False
        for env_id in finished:
            episode = self._episodes[env_id]
            episode.pre_export()
            succeeded = bool(episode.success)
            target = None
            if mode == DatasetExportMode.EXPORT_ALL or (mode == DatasetExportMode.EXPORT_SUCCEEDED_ONLY and succeeded):
                target = self._handler
            elif mode == DatasetExportMode.EXPORT_SUCCEEDED_FAILED_IN_SEPARATE_FILES:
                target = self._handler if succeeded else self._failed_handler
            if target is not None:
                target.write_episode(episode)
                written = True
            counts = self._succeeded_count if succeeded else self._failed_count
            counts[env_id] = counts.get(env_id, 0) + 1
        for env_id in ids:
            self._episodes[env_id] = EpisodeData()
        if written:
            for handler in (self._handler, self._failed_handler):
                if handler is not None:
                    handler.flush()

    def close(self) -> None:
        """Export what is still recorded if ``export_in_close``, then close the dataset files."""
        if self._terms and getattr(self.cfg, "export_in_close", False) and self._handler is not None:
            self.export_episodes()
        for handler in (self._handler, self._failed_handler):
            if handler is not None:
                handler.close()
        self._handler = self._failed_handler = None

    # -- helpers -----------------------------------------------------------------------------------

    def _create_handler(self, path: str) -> DatasetFileHandlerBase:
        handler_type = self.cfg.dataset_file_handler_class_type or _hdf5_handler()
        handler = handler_type()
        handler.create(path, env_name=getattr(self._env.cfg, "env_name", None))
        return handler

    def _ids(self, env_ids: Sequence[int] | torch.Tensor | None) -> list[int]:
        """Env ids as a list of ints (a bool mask gives the ids where it is set)."""
        if env_ids is None:
            return list(range(self._env.num_envs))
        if isinstance(env_ids, torch.Tensor):
            if env_ids.dtype == torch.bool:
                env_ids = env_ids.nonzero().flatten()
            return env_ids.tolist()
        if isinstance(env_ids, slice):
            return list(range(self._env.num_envs))[env_ids]
        return [int(i) for i in env_ids]

    def _prepare_terms(self) -> None:
        for name, term_cfg in cfg_items(self.cfg):
            if name in _SETTINGS:
                continue
            if not isinstance(term_cfg, RecorderTermCfg):
                raise TypeError(
                    f"RecorderManager: term '{name}' must be a RecorderTermCfg, got {type(term_cfg).__name__}"
                )
            term = term_cfg.class_type(term_cfg, self._env)
            if not isinstance(term, RecorderTerm):
                raise TypeError(f"RecorderManager: term '{name}' built a {type(term).__name__}, not a RecorderTerm.")
            self._terms[name] = term
