"""Isaac Lab's spaces showcase: the direct cartpole (and camera cartpole) with each pair of Gymnasium
observation and action spaces (Box, Discrete, MultiDiscrete, Dict, Tuple) its DirectRLEnv accepts."""
