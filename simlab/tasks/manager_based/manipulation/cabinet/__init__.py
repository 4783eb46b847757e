"""Open a cabinet's drawer (Isaac Lab's ``manipulation/cabinet``); robots in ``config/``."""
