"""Commands of the roadmap surface (registered on import)."""
