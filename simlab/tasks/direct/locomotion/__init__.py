"""The locomotion base of the direct ant and humanoid tasks."""
