# Isaac Lab's navigation/config/anymal_c task config (release 2.x text), ported by the README's import
# mapping alone: no other line differs. tests/test_navigation.py builds and steps it.
