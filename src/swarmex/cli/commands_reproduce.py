"""Commands of the reproduce surface (registered on import)."""
