"""Manipulation tasks, manager-based: reach and lift with the Franka arm."""
