# Isaac Lab's direct/anymal_c task (release 2.x text, before the warp-array and physics-preset changes),
# ported by the README's import mapping alone: no other line differs. tests/test_anymal_c_direct.py
# builds and steps it.
