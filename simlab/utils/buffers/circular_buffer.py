"""A fixed-length history of batched tensors, e.g. the last K observations of every env."""

from __future__ import annotations

from collections.abc import Sequence

import torch


class CircularBuffer:
    """The last ``max_len`` entries appended for each of ``batch_size`` rows.

    Appended data has shape ``(batch_size, ...)``. :attr:`buffer` gives ``(batch_size, max_len, ...)``
    oldest first; indexing with a per-row key gives entries newest first (``key = 0`` is the latest).
    The first append after a reset fills the whole history of the reset rows with that entry, so a
    fresh row never reads stale or zero data.

    With ``stack_dim`` set, storage is laid out so that :attr:`stacked` is the history concatenated
    along that dimension of the data (oldest first) as a free view, e.g. frame stacking along the
    channel dimension with ``stack_dim=-1``; key indexing is then unavailable.
    """

    def __init__(self, max_len: int, batch_size: int, device: str, stack_dim: int | None = None):
        if max_len < 1:
            raise ValueError(f"CircularBuffer max_len must be at least 1, got {max_len}.")
        if stack_dim == 0:
            raise ValueError("stack_dim must not be 0 (cannot stack along the batch dimension).")
        self._max_len = max_len
        self._batch_size = batch_size
        self._device = device
        self._rows = torch.arange(batch_size, device=device)
        self._num_pushes = torch.zeros(batch_size, dtype=torch.long, device=device)
        self._max_len_tensor = torch.full((batch_size,), max_len, dtype=torch.long, device=device)
        self._rows_need_fill = True  # some row was reset (or never written): next append backfills
        self._stack_dim_arg = stack_dim
        # position of the history axis in storage: 0 in the default layout, the data's stack_dim
        # (history inserted before it) in the stacked layout; known at the first append
        self._history_axis: int | None = None
        self._buffer: torch.Tensor | None = None

    # -- properties --------------------------------------------------------------------------------

    @property
    def batch_size(self) -> int:
        return self._batch_size

    @property
    def device(self) -> str:
        return self._device

    @property
    def max_length(self) -> int:
        return self._max_len

    @property
    def current_length(self) -> torch.Tensor:
        """Entries held per row since its last reset, at most :attr:`max_length`. Shape (batch_size,)."""
        return torch.minimum(self._num_pushes, self._max_len_tensor)

    @property
    def buffer(self) -> torch.Tensor:
        """The whole history, shape ``(batch_size, max_length, ...)``, oldest entry first."""
        if self._buffer is None:
            raise RuntimeError("The CircularBuffer is empty: append data before reading it.")
        if self._stacked_layout:
            return torch.movedim(self._buffer, self._history_axis, 1)
        return self._buffer.transpose(0, 1)

    @property
    def stacked(self) -> torch.Tensor:
        """The history concatenated along ``stack_dim`` of the data, oldest first (a view: do not modify)."""
        if self._stack_dim_arg is None:
            raise RuntimeError("stacked is only available for a CircularBuffer created with stack_dim set.")
        if self._buffer is None:
            raise RuntimeError("stacked is not available yet: call append() at least once.")
        axis, shape = self._history_axis, self._buffer.shape
        return self._buffer.reshape(*shape[:axis], shape[axis] * shape[axis + 1], *shape[axis + 2 :])

    @property
    def _stacked_layout(self) -> bool:
        return self._stack_dim_arg is not None

    # -- operations --------------------------------------------------------------------------------

    def reset(self, batch_ids: Sequence[int] | slice | torch.Tensor | None = None) -> None:
        """Forget the history of the given rows (all rows by default); their stored entries read as zero."""
        rows = slice(None) if batch_ids is None else batch_ids
        count = len(range(self._batch_size)[rows]) if isinstance(rows, slice) else len(rows)
        if count == 0:
            return
        self._num_pushes[rows] = 0
        self._rows_need_fill = True
        if self._buffer is not None:
            if self._stacked_layout:
                self._buffer[rows] = 0.0
            else:
                self._buffer[:, rows] = 0.0

    def append(self, data: torch.Tensor) -> None:
        """Add one entry per row; data has shape ``(batch_size, ...)``. The oldest entry drops out."""
        if data.shape[0] != self._batch_size:
            raise ValueError(f"CircularBuffer expects data with batch size {self._batch_size}, got {data.shape[0]}.")
        data = data.to(self._device)
        if self._buffer is None:
            self._allocate(data)
        axis = self._history_axis
        new_entry = data.unsqueeze(axis)
        # shift the history one step towards the old end and write the newest entry last
        older = self._buffer.narrow(axis, 1, self._max_len - 1).clone()
        self._buffer.narrow(axis, 0, self._max_len - 1).copy_(older)
        self._buffer.narrow(axis, self._max_len - 1, 1).copy_(new_entry)
        if self._rows_need_fill:
            # rows without history take the new entry in every slot (no host sync: torch.where)
            fresh = self._num_pushes == 0
            if self._stacked_layout:
                mask = fresh.view(-1, *([1] * (self._buffer.dim() - 1)))
            else:
                mask = fresh.view(1, -1, *([1] * (data.dim() - 1)))
            torch.where(mask, new_entry, self._buffer, out=self._buffer)
            self._rows_need_fill = False
        self._num_pushes += 1

    def __getitem__(self, key: torch.Tensor) -> torch.Tensor:
        """Entry ``key[i]`` steps back from the newest for every row ``i`` (clamped to the oldest held)."""
        if self._stacked_layout:
            raise NotImplementedError(
                "Indexing a CircularBuffer is not supported in stacked-output mode (stack_dim set); "
                "use .stacked or .buffer instead."
            )
        if len(key) != self._batch_size:
            raise ValueError(f"CircularBuffer key must have one entry per row ({self._batch_size}), got {len(key)}.")
        if self._buffer is None:
            raise RuntimeError("The CircularBuffer is empty: append data before indexing it.")
        # at most the oldest entry held (a row never written reads its zeroed slot)
        steps_back = torch.clamp(torch.minimum(key.to(self._device), self.current_length - 1), min=0)
        return self._buffer[(self._max_len - 1 - steps_back).long(), self._rows]

    def _allocate(self, data: torch.Tensor) -> None:
        if not self._stacked_layout:
            self._history_axis = 0
            self._buffer = torch.zeros((self._max_len, *data.shape), dtype=data.dtype, device=self._device)
            return
        ndim = data.dim()
        axis = self._stack_dim_arg + ndim if self._stack_dim_arg < 0 else self._stack_dim_arg
        if not 1 <= axis < ndim:
            raise IndexError(
                f"stack_dim={self._stack_dim_arg} does not name a non-batch dimension of data with {ndim} "
                f"dimensions; use one in [1, {ndim - 1}] or [-{ndim - 1}, -1]."
            )
        self._history_axis = axis
        self._buffer = torch.zeros(
            (*data.shape[:axis], self._max_len, *data.shape[axis:]), dtype=data.dtype, device=self._device
        )
