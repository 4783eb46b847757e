"""Walk to velocity commands while the hands track pose commands (Isaac Lab's ``locomanipulation/tracking``);
robots in ``config/``."""
