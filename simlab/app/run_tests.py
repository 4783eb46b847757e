"""Isaac Lab's ``run_tests()``: what a test file calls under ``if __name__ == "__main__"``."""

from __future__ import annotations

import inspect
import sys


def run_tests(argv: list[str] | None = None) -> None:
    """Run the calling file's tests with pytest (extra pytest arguments in ``argv``) and exit with its status."""
    import pytest

    caller = inspect.stack()[1].filename
    sys.exit(pytest.main([caller, *(argv or [])]))
