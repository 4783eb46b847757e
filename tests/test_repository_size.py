"""The repository stays small: every clone, wheel and GPU run carries its tracked files (issue 38 point 6
set the limit at 15 MB with the shipped policies included)."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
LIMIT_BYTES = 15_000_000


def test_the_tracked_files_stay_under_15_mb():
    listed = subprocess.run(["git", "ls-files", "-z"], cwd=REPO, capture_output=True, check=True).stdout
    paths = [REPO / os.fsdecode(name) for name in listed.split(b"\0") if name]
    # a file deleted but not yet committed is listed and absent: it no longer counts
    sizes = {path: path.stat().st_size for path in paths if path.is_file()}
    total = sum(sizes.values())
    largest = sorted(sizes, key=sizes.get, reverse=True)[:5]
    assert total <= LIMIT_BYTES, f"tracked files hold {total / 1e6:.2f} MB (limit 15 MB); largest: " + ", ".join(
        f"{p.relative_to(REPO)} ({sizes[p] / 1e3:.0f} kB)" for p in largest
    )
