"""The missions behind one contract: :mod:`.base` (Params, the parsers, Mission, Outcome,
StopRun), :mod:`.registry` (the four built-ins by module path, imported on first use, and the
``swarmex.missions`` entry-point group for third-party missions), and one package per seed
(:mod:`.traversal`, :mod:`.foraging`, :mod:`.exploration`, :mod:`.roadmap`)."""
