# Isaac Lab's locomotion/velocity/config/spot flat task config (release 2.x text), ported by the README's
# import mapping alone: no other line differs. tests/test_quadruped_zoo.py builds and steps it.
