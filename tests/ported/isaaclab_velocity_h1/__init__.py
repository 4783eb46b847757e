# Isaac Lab's locomotion/velocity/config/h1 task configs (release 2.x text, before the Newton branch's
# MJWarp solver settings), ported by the README's import mapping alone: no other line differs.
# tests/test_humanoid_velocity.py builds and steps them.
