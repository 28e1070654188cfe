"""Distances and paths: distance fields, shortest-path steps, roadmaps."""

from swarmex.planning.distance import distance_field, distance_fields, steps_towards

__all__ = ["distance_field", "distance_fields", "steps_towards"]
