"""scripts/benchmarks/amp_learn.py's own parts: the training budget (SIGTERM, then the checkpoint the
training saved is used), the TensorBoard trend and the PNG of the play video's frames. AMP training
and play themselves are tested in tests/test_humanoid_amp.py."""

from __future__ import annotations

import os
import sys

import imageio.v3 as iio
import numpy as np
from conftest import load_script

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _script():
    return load_script(os.path.join(REPO, "scripts", "benchmarks", "amp_learn.py"))


# a stand-in for `simlab train`: saves on SIGTERM and exits 143, as simlab does; SIGINT is ignored,
# as in a process started from a background shell job (the budget must still stop it)
INTERRUPTIBLE = """
import signal, sys, time
signal.signal(signal.SIGINT, signal.SIG_IGN)
def terminated(signum, frame):
    raise KeyboardInterrupt
signal.signal(signal.SIGTERM, terminated)
try:
    time.sleep(60)
except KeyboardInterrupt:
    open(sys.argv[1], "w").write("saved")
    sys.exit(143)
"""


def test_the_training_budget_interrupts_and_the_saved_run_counts(tmp_path):
    script = _script()
    saved = tmp_path / "saved"
    # 3 s: the stand-in must have its handler up before the signal, even on a loaded machine
    assert script.train([sys.executable, "-c", INTERRUPTIBLE, str(saved)], train_seconds=3.0)
    assert saved.read_text() == "saved"
    assert script.train([sys.executable, "-c", "pass"], train_seconds=None)  # finished on its own
    assert not script.train([sys.executable, "-c", "raise SystemExit(1)"], train_seconds=30)  # failed


def test_trend_reports_the_dip_and_the_rise():
    trend = _script().trend([0.6, 0.4, 0.2, 0.1, 0.3, 0.5, 0.7, 0.8, 0.9, 1.0])
    assert trend["first_fifth_mean"] == 0.5 and trend["last_fifth_mean"] == 0.95
    assert trend["min"] == 0.1 and trend["min_at_fraction"] == 3 / 9 and trend["last"] == 1.0
    assert trend["count"] == 10 and len(trend["points"]) == 10
    assert _script().trend([]) == {}


def test_frame_sheet_puts_six_frames_side_by_side(tmp_path):
    video = str(tmp_path / "play.mp4")
    frames = np.zeros((30, 64, 48, 3), dtype=np.uint8)
    frames[:, :, :, 0] = np.arange(30, dtype=np.uint8)[:, None, None] * 8  # red grows frame by frame
    iio.imwrite(video, frames, fps=30)
    sheet = iio.imread(_script().frame_sheet(video))
    assert sheet.shape == (64, 6 * 48, 3)
    reds = [int(sheet[:, i * 48 : (i + 1) * 48, 0].mean()) for i in range(6)]
    assert reds == sorted(reds) and reds[-1] - reds[0] > 150  # first to last frame, in order
