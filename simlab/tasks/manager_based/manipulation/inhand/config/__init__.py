"""Robot configs of the in-hand task."""
