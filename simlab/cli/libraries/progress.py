"""A one-line console progress bar (tqdm) with throughput and ETA for the training loops."""

from __future__ import annotations

from simlab.rl.utils import require

__all__ = ["ProgressBar"]


class ProgressBar:
    """``update(n, steps, **stats)`` per iteration; shows iterations, env steps/s, ETA and ``stats``."""

    def __init__(self, total: int, desc: str, initial: int = 0):
        tqdm = require("tqdm").tqdm
        self._bar = tqdm(total=total, initial=initial, desc=desc, unit="it", dynamic_ncols=True)
        self._steps = 0

    def update(self, n: int = 1, steps: int = 0, elapsed: float | None = None, **stats: float) -> None:
        self._steps += steps
        rate = self._bar.format_dict.get("elapsed") or 0.0
        fps = self._steps / rate if rate > 0 else 0.0
        post = {"steps/s": f"{fps:,.0f}"}
        post.update({k: f"{v:.3g}" for k, v in stats.items() if v is not None})
        self._bar.set_postfix(post, refresh=False)
        self._bar.update(n)

    def close(self) -> None:
        self._bar.close()
