# Isaac Lab's locomotion/velocity/config/digit task configs (release 2.x text), ported by the README's
# import mapping alone: no other line differs. tests/test_digit.py builds and steps them.
