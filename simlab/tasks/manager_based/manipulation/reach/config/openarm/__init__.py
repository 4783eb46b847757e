"""OpenArm reach tasks: one arm (``unimanual``) and two arms (``bimanual``)."""
