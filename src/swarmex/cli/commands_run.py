"""Commands of the run surface (registered on import)."""
