"""Wrappers and configs that connect simlab environments to RL libraries (Isaac Lab's ``isaaclab_rl``).

One subpackage per library: :mod:`simlab.rl.rsl_rl`, :mod:`simlab.rl.skrl`, :mod:`simlab.rl.sb3`,
:mod:`simlab.rl.rl_games`. Each library is an optional dependency (``pip install "simlab[<extra>]"``);
importing a subpackage whose library is missing raises an ``ImportError`` with that command.
:mod:`simlab.rl.exporter` writes any policy network to TorchScript and ONNX. :mod:`simlab.rl.bc` is
behaviour cloning's policy, agent config and file (no library to install).
"""
