"""Delay batched signals by a per-row number of steps (actuator or sensor latency)."""

from __future__ import annotations

from collections.abc import Sequence

import torch


class DelayBuffer:
    """Returns, for each row, the input from ``time_lags[row]`` recorded steps ago.

    Storage is ``history_length + 1`` frames per row, newest first, allocated at the first
    :meth:`compute`; recording shifts them one place (one concatenation and one copy back) and the
    per-row history counts stay on the device (no host sync, CUDA-graph safe). A lag of zero returns
    the current input; while a row has fewer recorded frames than its lag (after construction or
    :meth:`reset`), it gets its oldest frame, so no data from before a reset leaks.

    Lags are set with :meth:`set_time_lag`, or drawn by the buffer when ``hold_prob`` is given: a
    uniform lag in ``[min_lag, history_length]`` at construction and reset, and on each recorded
    frame every row keeps its lag with probability ``hold_prob`` (1.0: constant until reset; 0.0:
    redrawn every frame).
    """

    def __init__(
        self, history_length: int, batch_size: int, device: str, *, min_lag: int = 0, hold_prob: float | None = None
    ):
        self._history_length = max(0, history_length)
        if type(min_lag) is not int or not 0 <= min_lag <= self._history_length:
            raise ValueError(
                f"min_lag must be an integer in [0, history_length={self._history_length}], got {min_lag!r}."
            )
        if hold_prob is not None and not 0.0 <= hold_prob <= 1.0:
            raise ValueError(f"hold_prob must be in [0, 1] (or None for lags set by the caller), got {hold_prob}.")
        self._min_lag = min_lag
        self._hold_prob = hold_prob
        self._batch_size = batch_size
        self._device = device
        self._buffer: torch.Tensor | None = None
        """(batch_size, history_length + 1, frame size): each row's frames, newest first, flattened."""
        self._frame_shape: tuple[int, ...] = ()
        self._num_pushes = torch.zeros(batch_size, dtype=torch.long, device=device)
        self._rows = torch.arange(batch_size, device=device)
        self._time_lags = torch.zeros(batch_size, dtype=torch.int, device=device)
        if hold_prob is not None:
            self.reset()

    # -- properties --------------------------------------------------------------------------------

    @property
    def batch_size(self) -> int:
        return self._batch_size

    @property
    def device(self) -> str:
        return self._device

    @property
    def history_length(self) -> int:
        """Frames kept besides the newest: the largest lag allowed."""
        return self._history_length

    @property
    def num_pushes(self) -> torch.Tensor:
        """Frames recorded per row since its last reset, shape (batch_size,). Read only."""
        return self._num_pushes

    @property
    def min_time_lag(self) -> int:
        return int(self._time_lags.min().item())

    @property
    def max_time_lag(self) -> int:
        return int(self._time_lags.max().item())

    @property
    def time_lags(self) -> torch.Tensor:
        """The lag of every row, shape (batch_size,); may be written in place with values in ``[0, history_length]``."""
        return self._time_lags

    # -- operations --------------------------------------------------------------------------------

    def set_time_lag(
        self,
        time_lag: int | torch.Tensor,
        batch_ids: Sequence[int] | None = None,
        batch_mask: torch.Tensor | None = None,
    ) -> None:
        """Set the lag of the rows in ``batch_ids`` (all by default) or in ``batch_mask`` (which wins).

        ``time_lag`` is an int for all selected rows, or an integer tensor: one lag per selected row,
        or per row of the batch with ``batch_mask`` (not range-checked then, to avoid a host sync).
        Invalid lags raise before anything changes.
        """
        if isinstance(time_lag, torch.Tensor):
            if time_lag.dtype not in (torch.int, torch.long):
                raise TypeError(f"time_lag tensor must be torch.int or torch.long, got {time_lag.dtype}.")
            if batch_mask is not None:
                lags = time_lag.to(device=self._device, dtype=self._time_lags.dtype)
                torch.where(batch_mask, lags, self._time_lags, out=self._time_lags)
                return
            low = int(time_lag.min().item()) if time_lag.numel() else 0
            high = int(time_lag.max().item()) if time_lag.numel() else 0
        elif isinstance(time_lag, int) and not isinstance(time_lag, bool):
            low = high = time_lag
        else:
            raise TypeError(f"time_lag must be an int or an integer tensor, got {type(time_lag).__name__}.")
        if low < 0:
            raise ValueError(f"time lags cannot be negative, got {low}.")
        if high > self._history_length:
            raise ValueError(f"time lags cannot exceed history_length={self._history_length}, got {high}.")
        if batch_mask is not None:  # an int lag for the masked rows
            self._time_lags.masked_fill_(batch_mask.to(self._device), time_lag)
            return
        rows = slice(None) if batch_ids is None else batch_ids
        if isinstance(time_lag, torch.Tensor):
            self._time_lags[rows] = time_lag.to(device=self._device, dtype=self._time_lags.dtype)
        else:
            self._time_lags[rows] = time_lag

    def reset(self, batch_ids: Sequence[int] | None = None, batch_mask: torch.Tensor | None = None) -> None:
        """Forget the history of the given rows (all by default); drawn lags are redrawn, set lags kept."""
        rows = slice(None) if batch_ids is None else batch_ids
        if batch_mask is not None:
            self._num_pushes.masked_fill_(batch_mask.to(self._device), 0)
        else:
            self._num_pushes[rows] = 0
        if self._hold_prob is None:
            return
        if batch_mask is not None:
            # draw for every row and keep the masked ones: the selection stays on the device
            torch.where(batch_mask, self._draw_lags((self._batch_size,)), self._time_lags, out=self._time_lags)
        else:
            self._time_lags[rows] = self._draw_lags(self._time_lags[rows].shape)

    def compute(self, data: torch.Tensor | Sequence[torch.Tensor], *, update_history: bool = True) -> torch.Tensor:
        """The delayed data, shape (batch_size, ...), recording ``data`` as the newest frame first.

        ``data`` may also be a sequence of 2-D tensors ``(batch_size, n_i)``: the frame is their
        concatenation along dim 1, joined in the kernel that shifts the history (an actuator's
        position, velocity and effort targets, one kernel fewer than stacking them first).

        With ``update_history=False`` nothing is recorded: the result is relative to the newest
        recorded frame, and rows with no recorded frame get ``data`` itself. The result is a copy.
        """
        parts = (data,) if isinstance(data, torch.Tensor) else tuple(data)
        shape = data.shape if isinstance(data, torch.Tensor) else (parts[0].shape[0], sum(p.shape[1] for p in parts))
        if shape[0] != self._batch_size or any(p.shape[0] != self._batch_size for p in parts):
            raise ValueError(f"DelayBuffer expects data with batch size {self._batch_size}, got {shape[0]}.")
        if not isinstance(data, torch.Tensor) and any(p.dim() != 2 for p in parts):
            raise ValueError("DelayBuffer: data given as a sequence must be 2-D tensors (batch_size, n).")
        n, frames = self._batch_size, self._history_length + 1
        if self._buffer is None:
            if not update_history:
                return _joined(parts, self._device).reshape(shape).clone()
            self._frame_shape = tuple(shape[1:])
            size = 1
            for dim in self._frame_shape:
                size *= dim
            dtype = parts[0].dtype
            self._buffer = torch.zeros((n, frames, size), dtype=dtype, device=self._device)
        elif tuple(shape[1:]) != self._frame_shape:
            raise ValueError(f"DelayBuffer expects data of shape {self._frame_shape}, got {tuple(shape[1:])}.")
        flat = [p.to(device=self._device, dtype=self._buffer.dtype).reshape(n, -1) for p in parts]

        if not update_history:
            lag = torch.minimum(self._time_lags, (self._num_pushes - 1).clamp_min(0))
            delayed = self._buffer[self._rows, lag]
            has_history = (self._num_pushes > 0).view(n, 1)
            return torch.where(has_history, delayed, _joined(flat, self._device)).view(shape)

        if self._hold_prob is not None and self._hold_prob < 1.0:
            lags = self._draw_lags((n,))
            if self._hold_prob > 0.0:
                redraw = torch.rand(n, device=self._device) >= self._hold_prob
                lags = torch.where(redraw, lags, self._time_lags)
            self._time_lags.copy_(lags)

        # shift: the new frame first, then all but the oldest (kernels: cat, copy back, min, gather, count)
        history = self._buffer.view(n, -1)
        shifted = torch.cat([*flat, history[:, : history.shape[1] - self._buffer.shape[2]]], dim=1)
        history.copy_(shifted)
        lag = torch.minimum(self._time_lags, self._num_pushes)  # never older than the last reset
        delayed = shifted.view(self._buffer.shape)[self._rows, lag]  # advanced indexing: a copy
        self._num_pushes.add_(1)
        return delayed.view(shape)

    def _draw_lags(self, shape: torch.Size | tuple[int, ...]) -> torch.Tensor:
        return torch.randint(
            self._min_lag, self._history_length + 1, shape, dtype=self._time_lags.dtype, device=self._device
        )


def _joined(parts: Sequence[torch.Tensor], device) -> torch.Tensor:
    """One frame from its parts (a lone tensor as it is)."""
    if len(parts) == 1:
        return parts[0].to(device)
    return torch.cat([p.to(device) for p in parts], dim=1)
