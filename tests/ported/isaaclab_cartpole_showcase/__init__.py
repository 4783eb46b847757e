# Isaac Lab's direct/cartpole_showcase/cartpole task files (release 2.x text: the env imported from
# direct/cartpole/cartpole_env, efforts set with set_joint_effort_target), ported by the README's import
# mapping alone; the configs' docstrings (tables of the spaces) are left out, no code line differs.
# tests/test_cartpole_showcase.py builds and steps them beside simlab's own.
