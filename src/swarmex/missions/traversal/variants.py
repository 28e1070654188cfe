"""Variants of MADGTA beyond the seed (registered in POLICIES on import)."""
