"""Tasks whose policies Isaac Lab has deployed to real robots (Isaac Lab's ``manipulation/deploy``)."""
