"""The interface every episode-dataset file format implements."""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Iterable

from simlab.utils.datasets.episode_data import EpisodeData


class DatasetFileHandlerBase(ABC):
    """Create or open a dataset file, write episodes to it and load them back."""

    @abstractmethod
    def open(self, file_path: str, mode: str = "r") -> None:
        """Open an existing dataset file."""

    @abstractmethod
    def create(self, file_path: str, env_name: str | None = None) -> None:
        """Create a new dataset file (replacing one at that path)."""

    @abstractmethod
    def get_env_name(self) -> str | None:
        """The name of the environment the episodes were recorded in."""

    @abstractmethod
    def get_episode_names(self) -> Iterable[str]:
        """The names of the stored episodes."""

    @abstractmethod
    def get_num_episodes(self) -> int:
        """How many episodes the file holds."""

    @abstractmethod
    def write_episode(self, episode: EpisodeData) -> None:
        """Append one episode."""

    @abstractmethod
    def load_episode(self, episode_name: str, device: str) -> EpisodeData | None:
        """The episode called ``episode_name`` with its tensors on ``device`` (None if there is none)."""

    @abstractmethod
    def flush(self) -> None:
        """Write buffered data to disk."""

    @abstractmethod
    def close(self) -> None:
        """Close the file."""
