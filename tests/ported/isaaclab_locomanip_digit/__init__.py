# Isaac Lab's locomanipulation/tracking/config/digit task configs, ported by the README's import
# mapping alone: no other line differs. tests/test_digit_locomanip.py builds and steps them.
