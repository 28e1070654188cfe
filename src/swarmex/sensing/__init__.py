"""What a robot's sensors give it, copied from the world's truth into its belief: discs with
line of sight (:mod:`.visibility`), lasers (:mod:`.laser`), occupancy grids
(:mod:`.occupancy`), frontiers (:mod:`.frontiers`), coverage rasters (:mod:`.coverage_raster`)
and teammates in view (:mod:`.teammates`). Traversal's adjacency sensing is its agent core's
own (``missions/traversal/agent.py``, ``AdjacencySensor``)."""
