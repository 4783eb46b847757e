"""A one-line console progress bar (tqdm) with throughput and ETA for the training loops."""

from __future__ import annotations

from simlab.rl.utils import require

__all__ = ["ProgressBar"]


class ProgressBar:
    """``update(n, steps, seconds, **stats)`` per iteration; shows iterations, env steps/s, ETA and ``stats``."""

    def __init__(self, total: int, desc: str, initial: int = 0):
        tqdm = require("tqdm").tqdm
        self._bar = tqdm(total=total, initial=initial, desc=desc, unit="it", dynamic_ncols=True)
        self._steps = 0
        self._seconds = 0.0

    @property
    def seconds(self) -> float:
        """The training time counted so far (the sum of ``update``'s ``seconds``)."""
        return self._seconds

    def update(self, n: int = 1, steps: int = 0, seconds: float = 0.0, **stats: float) -> None:
        """``steps`` env steps taken in ``seconds`` of training (the library's own timing of the iteration:
        the bar is made after the first one, so its clock would count that one's steps in no time)."""
        self._steps += steps
        self._seconds += seconds
        fps = self._steps / self._seconds if self._seconds > 0 else 0.0
        post = {"steps/s": f"{fps:,.0f}"}
        post.update({k: f"{v:.3g}" for k, v in stats.items() if v is not None})
        self._bar.set_postfix(post, refresh=False)
        self._bar.update(n)

    def close(self) -> None:
        self._bar.close()
