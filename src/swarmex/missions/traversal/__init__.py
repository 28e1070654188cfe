"""Traversal mission (seed 000): MADGTA, its baselines and variants on any graph."""

from swarmex.missions.traversal import (
    followed,  # noqa: F401,E402  (registers madgta-f)
    madgta_h,  # noqa: F401,E402  (registers madgta-h)
    partition,  # noqa: F401,E402  (registers madgta-k)
    rollout,  # noqa: F401,E402  (registers madgta-r)
    teamplan,  # noqa: F401,E402  (registers madgta-p)
    variants,  # noqa: F401,E402  (registers madgta+)
)
from swarmex.missions.traversal.agent import TraversalAgent
from swarmex.missions.traversal.agents import AgentSpec, uniform_agents
from swarmex.missions.traversal.metrics import run_metrics, traversal_record
from swarmex.missions.traversal.policies import Madgta, Nearest, get_best_node, make_policy
from swarmex.missions.traversal.sim import TraversalRun, run_traversal

__all__ = [
    "AgentSpec",
    "Madgta",
    "Nearest",
    "TraversalAgent",
    "TraversalRun",
    "get_best_node",
    "make_policy",
    "run_metrics",
    "run_traversal",
    "traversal_record",
    "uniform_agents",
]
