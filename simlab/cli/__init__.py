"""The ``simlab`` command: ``train``, ``play``, ``list``, ``random``, ``zero``, ``bench``."""
