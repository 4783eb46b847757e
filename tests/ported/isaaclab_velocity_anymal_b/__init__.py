# Isaac Lab's locomotion/velocity/config/anymal_b task configs (release 2.x text, before the Newton
# branch's MJWarp solver settings), ported by the README's import mapping alone: no other line differs.
# tests/test_quadruped_zoo.py builds and steps them.
