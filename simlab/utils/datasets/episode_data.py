"""One recorded episode: per-step tensors under (nested) keys, plus its seed and outcome."""

from __future__ import annotations

import torch


class EpisodeData:
    """Tensors recorded step by step under (nested) keys.

    As in Isaac Lab, a key holds a list of the steps' tensors while recording (appending copies no
    earlier step), and one tensor stacked along a new first (time) dimension after :meth:`pre_export`
    (which writing to a file runs) or when read from a file. Keys may be nested with ``"/"``
    (``"obs/policy/joint_pos"`` is ``data["obs"]["policy"]["joint_pos"]``). ``"actions"``, ``"states"``
    and ``"initial_state"`` are the keys replay reads.
    """

    def __init__(self) -> None:
        self._data: dict = {}
        self.next_action_index = 0
        self.next_state_index = 0
        self.seed: int | None = None
        self.env_id: str | int | None = None
        self.success: bool | None = None

    @property
    def data(self) -> dict:
        return self._data

    @data.setter
    def data(self, data: dict) -> None:
        self._data = data

    def is_empty(self) -> bool:
        return not self._data

    def add(self, key: str, value: torch.Tensor | dict) -> None:
        """Append one step of ``value`` under ``key`` (a dict value appends each of its entries)."""
        if isinstance(value, dict):
            for sub_key, sub_value in value.items():
                self.add(f"{key}/{sub_key}", sub_value)
            return
        if not isinstance(value, torch.Tensor):
            raise TypeError(f"EpisodeData.add('{key}', ...) needs a tensor or a dict of tensors, got {type(value)}.")
        *parents, leaf = key.split("/")
        node = self._data
        for name in parents:
            node = node.setdefault(name, {})
            if not isinstance(node, dict):
                raise ValueError(f"EpisodeData key '{key}': '{name}' already holds data, not a group of keys.")
        steps = node.setdefault(leaf, [])
        if not isinstance(steps, list):
            raise ValueError(f"EpisodeData key '{key}' holds exported (stacked) data; add before pre_export().")
        steps.append(value.clone())

    def pre_export(self) -> None:
        """Stack each key's recorded steps into one tensor (time first), ready to be written."""

        def stack(node: dict) -> None:
            for key, value in node.items():
                if isinstance(value, dict):
                    stack(value)
                elif isinstance(value, list):
                    node[key] = torch.stack(value)

        stack(self._data)

    def get_initial_state(self) -> torch.Tensor | dict | None:
        return self._data.get("initial_state")

    def get_action(self, action_index: int) -> torch.Tensor | None:
        actions = self._data.get("actions")
        if actions is None or action_index >= len(actions):
            return None
        return actions[action_index]

    def get_next_action(self) -> torch.Tensor | None:
        action = self.get_action(self.next_action_index)
        if action is not None:
            self.next_action_index += 1
        return action

    def get_state(self, state_index: int) -> dict | torch.Tensor | None:
        """Step ``state_index`` of every tensor under ``"states"`` (None past the end of any of them)."""
        if "states" not in self._data:
            return None

        def at(node: dict | list | torch.Tensor) -> dict | torch.Tensor | None:
            if not isinstance(node, dict):  # recorded steps, or their stacked tensor
                return node[state_index] if state_index < len(node) else None
            out = {}
            for key, value in node.items():
                out[key] = at(value)
                if out[key] is None:
                    return None
            return out

        return at(self._data["states"])

    def get_next_state(self) -> dict | torch.Tensor | None:
        state = self.get_state(self.next_state_index)
        if state is not None:
            self.next_state_index += 1
        return state
