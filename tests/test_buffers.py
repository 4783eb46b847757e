"""History buffers: CircularBuffer (frame history), DelayBuffer (latency), TimestampedBuffer (caching)."""

from __future__ import annotations

import pytest
import torch

from simlab.utils import CircularBuffer, DelayBuffer, TimestampedBuffer
from simlab.utils.buffers import reset_timestamps


def steps(batch: int, n: int, feature: tuple[int, ...] = (1,)):
    """Step ``k`` of every row holds the value ``k`` (so a delayed read tells its own age)."""
    for k in range(n):
        yield k, torch.full((batch, *feature), float(k))


# -- CircularBuffer --------------------------------------------------------------------------------


def test_circular_buffer_keeps_the_last_entries_oldest_first():
    buf = CircularBuffer(max_len=3, batch_size=2, device="cpu")
    assert buf.current_length.tolist() == [0, 0]
    for k, data in steps(2, 5):
        buf.append(data)
        assert buf.current_length.tolist() == [min(k + 1, 3)] * 2
    assert buf.buffer.shape == (2, 3, 1)
    assert buf.buffer[0, :, 0].tolist() == [2.0, 3.0, 4.0]
    # key = how many steps back, per row; clamped to the oldest entry held
    assert buf[torch.tensor([0, 2])][:, 0].tolist() == [4.0, 2.0]
    assert buf[torch.tensor([7, 1])][:, 0].tolist() == [2.0, 3.0]


def test_circular_buffer_fresh_rows_are_filled_with_their_first_entry():
    buf = CircularBuffer(max_len=4, batch_size=3, device="cpu")
    for _, data in steps(3, 2):
        buf.append(data)
    buf.reset([1])
    assert buf.current_length.tolist() == [2, 0, 2]
    assert torch.equal(buf.buffer[1], torch.zeros(4, 1))  # a reset row reads zero until written
    buf.append(torch.full((3, 1), 9.0))
    assert buf.buffer[1, :, 0].tolist() == [9.0] * 4  # no stale or zero history after a reset
    assert buf.buffer[0, :, 0].tolist() == [0.0, 0.0, 1.0, 9.0]  # rows not reset keep theirs
    assert buf[torch.tensor([3, 3, 3])][:, 0].tolist() == [0.0, 9.0, 0.0]


def test_circular_buffer_stacks_frames_along_a_data_dimension():
    buf = CircularBuffer(max_len=2, batch_size=2, device="cpu", stack_dim=-1)
    frames = [torch.randn(2, 4, 3) for _ in range(3)]
    for f in frames:
        buf.append(f)
    assert torch.equal(buf.stacked, torch.cat(frames[1:], dim=-1))  # oldest first
    assert torch.equal(buf.buffer, torch.stack(frames[1:], dim=1))
    with pytest.raises(NotImplementedError, match="stacked-output mode"):
        buf[torch.zeros(2, dtype=torch.long)]


def test_circular_buffer_errors():
    with pytest.raises(ValueError, match="at least 1"):
        CircularBuffer(0, 2, "cpu")
    with pytest.raises(ValueError, match="stack_dim must not be 0"):
        CircularBuffer(2, 2, "cpu", stack_dim=0)
    buf = CircularBuffer(2, 2, "cpu")
    with pytest.raises(RuntimeError, match="empty"):
        buf[torch.zeros(2, dtype=torch.long)]
    with pytest.raises(ValueError, match="batch size 2"):
        buf.append(torch.zeros(3, 1))
    with pytest.raises(RuntimeError, match="stack_dim"):
        buf.stacked  # noqa: B018
    with pytest.raises(IndexError, match="stack_dim=3"):
        CircularBuffer(2, 2, "cpu", stack_dim=3).append(torch.zeros(2, 5))


# -- DelayBuffer -----------------------------------------------------------------------------------


def test_delay_buffer_returns_the_input_of_lag_steps_ago():
    buf = DelayBuffer(history_length=4, batch_size=3, device="cpu")
    buf.set_time_lag(torch.tensor([0, 2, 4]))
    for k, data in steps(3, 10):
        out = buf.compute(data)
        expected = [max(k - lag, 0) for lag in (0, 2, 4)]  # before enough history: the oldest frame
        assert out[:, 0].tolist() == expected
        # a read without recording is relative to the newest recorded frame
        assert buf.compute(data + 100, update_history=False)[:, 0].tolist() == expected
    assert buf.min_time_lag == 0 and buf.max_time_lag == 4


def test_delay_buffer_reset_never_leaks_the_previous_episode():
    buf = DelayBuffer(history_length=3, batch_size=2, device="cpu")
    buf.set_time_lag(3)
    for _, data in steps(2, 6):
        buf.compute(data)
    buf.reset([0])
    assert buf.num_pushes.tolist() == [0, 6]
    out = buf.compute(torch.full((2, 1), 50.0))
    assert out[:, 0].tolist() == [50.0, 3.0]  # row 0 starts over from its first new frame


def test_delay_buffer_mask_selects_the_same_rows_as_indices():
    by_ids = DelayBuffer(4, 6, "cpu")
    by_mask = DelayBuffer(4, 6, "cpu")
    mask = torch.tensor([False, True, False, True, False, False])
    by_ids.set_time_lag(torch.tensor([4, 1]), [1, 3])
    by_mask.set_time_lag(torch.tensor([9, 4, 9, 1, 9, 9]), batch_mask=mask)  # unmasked entries are ignored
    assert torch.equal(by_ids.time_lags, by_mask.time_lags)
    for _, data in steps(6, 5):
        by_ids.compute(data)
        by_mask.compute(data)
    by_ids.reset([1, 3])
    by_mask.reset(batch_mask=mask)
    assert torch.equal(by_ids.num_pushes, by_mask.num_pushes)
    for _, data in steps(6, 3):
        assert torch.equal(by_ids.compute(data), by_mask.compute(data))


def test_delay_buffer_draws_lags_when_asked():
    torch.manual_seed(0)
    held = DelayBuffer(5, 512, "cpu", min_lag=2, hold_prob=1.0)
    lags = held.time_lags.clone()
    assert lags.min() >= 2 and lags.max() <= 5 and len(lags.unique()) == 4  # uniform over 2..5
    for _, data in steps(512, 3):
        held.compute(data)
    assert torch.equal(held.time_lags, lags)  # hold_prob=1: constant until reset
    redrawn = DelayBuffer(5, 512, "cpu", min_lag=2, hold_prob=0.0)
    before = redrawn.time_lags.clone()
    redrawn.compute(torch.zeros(512, 1))
    assert (redrawn.time_lags != before).float().mean() > 0.5  # hold_prob=0: redrawn every frame


def test_delay_buffer_rejects_bad_lags_without_changing_anything():
    buf = DelayBuffer(3, 4, "cpu")
    buf.set_time_lag(torch.tensor([0, 1, 2, 3]))
    for bad in (4, -1, torch.tensor([1, 5])):
        with pytest.raises(ValueError, match="time lags"):
            buf.set_time_lag(bad, [0, 1] if isinstance(bad, torch.Tensor) else [0])
    with pytest.raises(TypeError, match="torch.int or torch.long"):
        buf.set_time_lag(torch.tensor([1.0]), [0])
    assert buf.time_lags.tolist() == [0, 1, 2, 3]
    with pytest.raises(ValueError, match="min_lag"):
        DelayBuffer(3, 4, "cpu", min_lag=4)
    with pytest.raises(ValueError, match="hold_prob"):
        DelayBuffer(3, 4, "cpu", hold_prob=1.5)


def test_delay_buffer_joins_a_frame_given_as_parts():
    """A frame given as 2-D parts (an actuator's position, velocity and effort targets) is their
    concatenation, joined in the kernel that shifts the history: the same lags as a joined frame."""
    parts, joined = DelayBuffer(3, 4, "cpu"), DelayBuffer(3, 4, "cpu")
    for buf in (parts, joined):
        buf.set_time_lag(torch.tensor([0, 1, 2, 3]))
    wide = torch.arange(4 * 5, dtype=torch.float32).view(4, 5)
    for k in range(6):
        a, b = wide[:, 1:3] + k, wide[:, 3:] * -k  # column views, as an actuator's targets are
        assert torch.equal(parts.compute((a, b)), joined.compute(torch.cat((a, b), dim=1)))
        assert torch.equal(
            parts.compute((a, b), update_history=False), joined.compute(torch.cat((a, b), 1), update_history=False)
        )
    with pytest.raises(ValueError, match="2-D"):
        parts.compute((torch.zeros(4, 2, 1), torch.zeros(4, 2)))


def test_delay_buffer_output_is_a_copy():
    buf = DelayBuffer(2, 2, "cpu")
    buf.set_time_lag(1)
    first = buf.compute(torch.ones(2, 1))
    first.fill_(999)
    assert buf.compute(torch.full((2, 1), 2.0))[:, 0].tolist() == [1.0, 1.0]


# -- TimestampedBuffer -----------------------------------------------------------------------------


def test_timestamped_buffer_and_reset():
    a, b = TimestampedBuffer(torch.zeros(2), 0.5), TimestampedBuffer()
    assert b.data is None and b.timestamp == -1.0
    reset_timestamps([a, None, b])
    assert a.timestamp == -1.0
