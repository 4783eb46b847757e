# Isaac Lab's direct/shadow_hand_over task (release 2.x text), ported by the README's import mapping
# alone: no other line differs. tests/test_shadow_hand_over.py builds and steps it.
