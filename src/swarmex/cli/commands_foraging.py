"""Commands of the foraging surface (registered on import)."""
