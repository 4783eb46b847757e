"""simlab: Isaac Lab's robot-learning API on MuJoCo (CPU, via mjbatch) and MuJoCo Warp (GPU)."""

__version__ = "0.1.0"
