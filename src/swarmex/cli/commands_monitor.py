"""``swarmex monitor``: placeholder replaced below."""
