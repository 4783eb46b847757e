"""Motion clips of the AMP humanoid (Isaac Lab's ``.npz`` motion format), their loader and their generator."""

import os

MOTIONS_DIR = os.path.dirname(os.path.abspath(__file__))
