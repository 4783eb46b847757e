"""Isaac Lab's import path for the IO descriptors; they live in :mod:`simlab.managers.io_descriptors`,
the layer whose action terms describe themselves with them."""

import sys

from simlab.managers import io_descriptors

sys.modules[__name__] = io_descriptors  # one module under both names (what a test patches, every reader sees)
