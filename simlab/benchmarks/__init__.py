"""Benchmarks behind ``simlab bench``: they print figures; nothing here asserts a speed."""
