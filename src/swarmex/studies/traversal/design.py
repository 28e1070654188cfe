"""Which runs ``swarmex reproduce traversal`` makes: seed 000's chapter-5 plan.

What is rerun (spec §4): Tables 5.1–5.2 (6×6 grid, 40×40 m, three identical agents from one
nest, the six symmetry groups of nests, ~108 runs each: the run count the tables' intervals
imply) and the series behind Figures 5.1–5.14 (10×10, 15×15 and 20×20 grids, 2–10 agents,
nests on the border or the diagonal, obstacle counts, mission duration, best fleet size).

Every run is one :class:`RunSpec` of a :class:`Config`: the thesis's agent parameters (3 m/s,
10 s jobs, 5 m altitude, 1.5 m/s up, 0.3 m/s down, clients 0.5 s apart) and node spacing
side/nodesOnEdge (spec §4.1 [derived]). A run's seed is a hash of its configuration and
repetition number, so results do not depend on scheduling or on the number of worker
processes, and a configuration shared by two figures (e.g. 20×20, 10 agents, nest 3 in
Figs. 5.5 and 5.11) is run once and reused. The thesis's Tables 5.1–5.2 are read from the
package (:func:`reference_rows`).

One run is :mod:`.runs` (executed by :mod:`swarmex.studies.runner`); the analysis, figures and
report are :mod:`.analysis`, :mod:`.figures` and :mod:`.report`;
:func:`swarmex.studies.traversal.reproduce` runs them all.
"""

from __future__ import annotations

import csv
import re
from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from typing import Any

from swarmex.experiments.runstore import stable_seed
from swarmex.studies import reference_file

# ---------------------------------------------------------------- thesis parameters (§5.1.2)
TRAVEL_SPEED = 3.0  # m/s (300 cm/s)
JOB_TIME = 10.0  # s per node
ALTITUDE = 5.0  # m
UP_SPEED = 1.5  # m/s
DOWN_SPEED = 0.3  # m/s
START_INTERVAL = 0.5  # s between clients
AGENT_PARAMS = {
    "travel_speed_m_s": TRAVEL_SPEED,
    "job_time_s": JOB_TIME,
    "altitude_m": ALTITUDE,
    "up_speed_m_s": UP_SPEED,
    "down_speed_m_s": DOWN_SPEED,
    "start_interval_s": START_INTERVAL,
    "algorithm": "madgta",
}

#: start jitters (s) of the sensitivity series: how uneven client starts change the tables
JITTERS = (30.0, 60.0)

PER_RUN_METRICS = ("total_time_all", "nodes_without_job_all")
PER_AGENT_METRICS = (
    "total_time",
    "travel_time",
    "job_time",
    "additional_time",
    "nodes_done",
    "nodes_traveled",
    "nodes_without_job",
)
#: thesis metric name → ours (metrics.py)
THESIS_METRIC = {
    "totalTimeAll": "total_time_all",
    "numNodesWoJAll": "nodes_without_job_all",
    "totalTime_i": "total_time",
    "travelTime_i": "travel_time",
    "jobTime_i": "job_time",
    "additionalTime_i": "additional_time",
    "numNodesDone_i": "nodes_done",
    "numNodesTraveled_i": "nodes_traveled",
    "numNodesWoJ_i": "nodes_without_job",
}


def thesis_node(k: int, size: int) -> int:
    """Thesis node id (1 = bottom-left, row-major upwards) → GridWorld vertex (row 0 on top)."""
    x, y_up = (k - 1) % size, (k - 1) // size
    return (size - 1 - y_up) * size + x


def diagonal_node(distance: int, size: int) -> int:
    """Thesis id of the node ``distance`` steps up the diagonal from corner node 1."""
    return 1 + distance * (size + 1)


# ---------------------------------------------------------------- plan
@dataclass(frozen=True)
class Config:
    """One simulation setting; repetitions cycle through ``nests`` (a symmetry group)."""

    size: int  # nodes on an edge
    side: float  # metres on an edge
    agents: int
    nests: tuple[int, ...]  # thesis node ids
    obstacles: int = 0
    jitter: float = 0.0  # each client starts up to this many seconds late (sensitivity only)

    @property
    def key(self) -> str:
        nests = "-".join(str(k) for k in self.nests)
        grid = f"{self.size}x{self.size}/{self.side:g}m"
        key = f"{grid}/{self.agents}a/nest{nests}/obs{self.obstacles}"
        return key + (f"/jit{self.jitter:g}" if self.jitter else "")

    @property
    def unit_length(self) -> float:
        # spacing = side / nodesOnEdge, not side / (nodesOnEdge - 1): spec §4.1 [derived]
        return self.side / self.size

    @property
    def cost(self) -> float:
        """Relative run time (measured: ~ nodes × (agents + 2)), for planning only."""
        return self.size * self.size * (self.agents + 2)

    def params(self) -> dict[str, Any]:
        return {
            "grid": [self.size, self.size],
            "side_m": self.side,
            "unit_length_m": self.unit_length,
            "agents": self.agents,
            "nests_thesis_ids": list(self.nests),
            "obstacles": self.obstacles,
            "start_jitter_s": self.jitter,
        }


@dataclass(frozen=True)
class RunSpec:
    config: Config
    rep: int

    @property
    def id(self) -> str:
        return f"{self.config.key}#{self.rep}"

    @property
    def seed(self) -> int:
        return stable_seed("traversal", self.config.key, self.rep)

    @property
    def nest(self) -> int:
        return self.config.nests[self.rep % len(self.config.nests)]


@dataclass(frozen=True)
class Group:
    """A row block of Tables 5.1–5.2: one symmetry class of nests on the 6×6 grid."""

    name: str
    label: str  # the CSV's / thesis's "nest in node …" text
    table: str  # "5.1" or "5.2"
    config: Config
    reps: int


@dataclass(frozen=True)
class Bar:
    label: str
    config: Config
    reps: int


@dataclass(frozen=True)
class Stated:
    """A number the thesis states in the text about a figure (spec §4.2)."""

    value: float
    text: str
    bar: str | None = None  # bar label it belongs to; None = all bars


@dataclass(frozen=True)
class FigureSpec:
    number: str  # "5.3"
    title: str
    xlabel: str
    metric: str  # per-run metric: total_time_all or max_total_time
    bars: tuple[Bar, ...]
    claim: str  # what the thesis says about the figure
    stated: tuple[Stated, ...] = ()
    choice: str = ""  # what we had to choose because the thesis does not say


@dataclass
class Plan:
    quick: bool
    groups: list[Group]
    figures: list[FigureSpec]
    #: the table groups rerun with uneven client starts (see :func:`execute`)
    sensitivity: list[Group] = field(default_factory=list)
    #: runs per table group / figure bar asked for (``--runs``); None: the plan's defaults.
    #: Kept so the report names the plan it was drawn from, and :func:`.report.rebuild`
    #: can draw it again
    reps: int | None = None

    def run_specs(self) -> list[RunSpec]:
        """Every run of the plan once, however many tables/figures use it."""
        reps: dict[Config, int] = {}
        for cfg, n in self._demands():
            reps[cfg] = max(reps.get(cfg, 0), n)
        return [RunSpec(cfg, r) for cfg, n in reps.items() for r in range(n)]

    def _demands(self) -> Iterable[tuple[Config, int]]:
        for g in (*self.groups, *self.sensitivity):
            yield g.config, g.reps
        for f in self.figures:
            for b in f.bars:
                yield b.config, b.reps

    def configs(self) -> dict[str, Config]:
        return {cfg.key: cfg for cfg, _ in self._demands()}


@dataclass(frozen=True)
class ReferenceRow:
    group: str
    metric: str
    min: float
    max: float
    median: float
    mean: float
    std: float
    ci_low: float
    ci_high: float


GROUP_NAMES = (
    "corners",
    "border, next to a corner",
    "border, middle",
    "inner diagonal",
    "other inner",
    "centre",
)


def reference_rows() -> list[ReferenceRow]:
    """Tables 5.1–5.2 as shipped in the package (copied from ../shared/reference)."""
    with reference_file("traversal_tables_5_1_5_2.csv").open(encoding="utf-8") as fh:
        return [
            ReferenceRow(
                r["nest_nodes"],
                r["metric"],
                float(r["min"]),
                float(r["max"]),
                float(r["median"]),
                float(r["mean"]),
                float(r["std"]),
                float(r["ci_low"]),
                float(r["ci_high"]),
            )
            for r in csv.DictReader(fh)
        ]


def table_groups(reps: int) -> list[Group]:
    labels: list[str] = []
    for row in reference_rows():
        if row.group not in labels:
            labels.append(row.group)
    groups = []
    for i, label in enumerate(labels):
        nests = tuple(sorted(int(k) for k in re.findall(r"\d+", label)))
        groups.append(
            Group(
                GROUP_NAMES[i] if i < len(GROUP_NAMES) else label,
                label,
                "5.1" if i < 3 else "5.2",
                Config(6, 40.0, 3, nests),
                reps,
            )
        )
    return groups


def _pick(items: list, quick: bool) -> list:
    """The quick plan keeps the first, a middle and the last bar of each series."""
    if not quick or len(items) <= 3:
        return items
    return [items[0], items[len(items) // 2], items[-1]]


def build_plan(quick: bool = False, reps: int | None = None) -> Plan:
    """Tables and figures; ``quick`` keeps 3 bars per figure and a handful of runs each.

    Choices the thesis leaves open (stated in the report): nests for the agent-count series
    (node 3, as stated for Fig. 5.11), the "middle" nests (the diagonal from node 1, as
    stated for Fig. 5.2), and the obstacle counts of Fig. 5.10.
    """
    table_reps = reps or (6 if quick else 108)
    fig_reps = reps or (3 if quick else 108)
    big_reps = reps or (2 if quick else 108)  # 20×20 with many agents: the costliest runs

    def bars(items: list[tuple[str, Config]]) -> tuple[Bar, ...]:
        chosen = _pick(items, quick)
        return tuple(
            Bar(lab, cfg, big_reps if cfg.size >= 20 and cfg.agents >= 5 else fig_reps)
            for lab, cfg in chosen
        )

    agents_range = list(range(2, 11))
    figures = [
        FigureSpec(
            "5.3",
            "10×10 nodes, 40×40 m, 5 agents, nest on the border",
            "nest node (thesis numbering)",
            "total_time_all",
            bars([(str(k), Config(10, 40.0, 5, (k,))) for k in range(1, 6)]),
            'The nest-location effect is "not that clear" any more.',
            choice="border nodes 1–5 (the border up to its middle, as in Fig. 5.5)",
        ),
        FigureSpec(
            "5.4",
            "10×10 nodes, 40×40 m, 5 agents, nest in the middle",
            "nest node (diagonal from node 1)",
            "total_time_all",
            bars(
                [
                    (str(diagonal_node(d, 10)), Config(10, 40.0, 5, (diagonal_node(d, 10),)))
                    for d in range(1, 5)
                ]
            ),
            'The nest-location effect is "not that clear" any more.',
            choice="diagonal nodes at distance 1–4 from node 1 (as Fig. 5.2 does on 6×6)",
        ),
        FigureSpec(
            "5.5",
            "20×20 nodes, 80×80 m, 10 agents, nest on the border",
            "nest node (thesis numbering)",
            "total_time_all",
            bars([(str(k), Config(20, 80.0, 10, (k,))) for k in range(1, 11)]),
            "No correlation with the nest location; all values about 4750 s.",
            (Stated(4750.0, "≈4750 s for every nest"),),
            choice="border nodes 1–10 as stated",
        ),
        FigureSpec(
            "5.6",
            "20×20 nodes, 80×80 m, 10 agents, nest in the middle",
            "nest node (diagonal from node 1)",
            "total_time_all",
            bars(
                [
                    (str(diagonal_node(d, 20)), Config(20, 80.0, 10, (diagonal_node(d, 20),)))
                    for d in range(1, 10)
                ]
            ),
            "No correlation with the nest location; all values about 4750 s.",
            (Stated(4750.0, "≈4750 s for every nest"),),
            choice="diagonal nodes at distance 1–9 from node 1",
        ),
        FigureSpec(
            "5.7",
            "10×10 nodes, 40×40 m, 1 nest, 2–10 agents",
            "agents",
            "total_time_all",
            bars([(str(m), Config(10, 40.0, m, (3,))) for m in agents_range]),
            'totalTimeAll "goes up rapidly" with more agents (more conflicts).',
            choice="nest node 3 (the nest the thesis states for Fig. 5.11)",
        ),
        FigureSpec(
            "5.8",
            "15×15 nodes, 40×40 m, 1 nest, 2–10 agents",
            "agents",
            "total_time_all",
            bars([(str(m), Config(15, 40.0, m, (3,))) for m in agents_range]),
            "Same rising trend as Fig. 5.7.",
            choice="nest node 3",
        ),
        FigureSpec(
            "5.9",
            "15×15 nodes, 80×80 m, 1 nest, 2–10 agents",
            "agents",
            "total_time_all",
            bars([(str(m), Config(15, 80.0, m, (3,))) for m in agents_range]),
            "Same rising trend; the best number of agents for totalTimeAll is < 5.",
            choice="nest node 3",
        ),
        FigureSpec(
            "5.10",
            "20×20 nodes, 80×80 m, 10 agents, nest node 1, random obstacles",
            "obstacles",
            "total_time_all",
            bars([(str(k), Config(20, 80.0, 10, (1,), k)) for k in (0, 20, 40, 60, 80)]),
            "totalTimeAll decreases as obstacles increase (fewer jobs); long whiskers.",
            choice=(
                "0, 20, 40, 60, 80 obstacles (0–20 % of the cells; the thesis gives no "
                "counts), placed uniformly at random per run, never on the nest, redrawn "
                "until the free cells are connected; nest node 1"
            ),
        ),
        FigureSpec(
            "5.11",
            "20×20 nodes, 80×80 m, nest node 3, 2–10 agents",
            "agents",
            "total_time_all",
            bars([(str(m), Config(20, 80.0, m, (3,))) for m in agents_range]),
            "totalTimeAll ≈4580 s with the fewest agents, rising to ≈4760 s with 10.",
            (Stated(4580.0, "≈4580 s (fewest agents)", "2"), Stated(4760.0, "≈4760 s", "10")),
        ),
        FigureSpec(
            "5.12",
            "20×20 nodes, 80×80 m, nest node 3, 2–10 agents: mission duration",
            "agents",
            "max_total_time",
            bars([(str(m), Config(20, 80.0, m, (3,))) for m in agents_range]),
            'max totalTime_i: 2 agents ≈2300 s, 3 agents 1500 s, 10 agents "up to 450 s".',
            (
                Stated(2300.0, "≈2300 s", "2"),
                Stated(1500.0, "1500 s", "3"),
                Stated(450.0, "450 s", "10"),
            ),
        ),
    ]
    if quick:  # 5.12's fleet-size analysis needs 2, 3 and 10 agents at least
        for i, f in enumerate(figures):
            if f.number in ("5.11", "5.12"):
                keep = [
                    Bar(str(m), Config(20, 80.0, m, (3,)), big_reps if m >= 5 else fig_reps)
                    for m in (2, 3, 10)
                ]
                figures[i] = FigureSpec(
                    f.number,
                    f.title,
                    f.xlabel,
                    f.metric,
                    tuple(keep),
                    f.claim,
                    f.stated,
                    f.choice,
                )
    groups = table_groups(table_reps)
    jitters = (60.0,) if quick else JITTERS
    sensitivity = [
        Group(g.name, g.label, g.table, replace(g.config, jitter=j), 3 if quick else g.reps)
        for j in jitters
        for g in (groups[:1] if quick else groups)
    ]
    return Plan(quick, groups, figures, sensitivity, reps)
