# Isaac Lab's locomotion/velocity/config/cassie task configs (release 2.x text, before the Newton branch's
# MJWarp solver settings), ported by the README's import mapping alone: no other line differs.
# tests/test_cassie.py builds and steps them.
