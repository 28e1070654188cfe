"""The explicit registry: built-ins by name, third-party missions through entry points."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import pytest

import swarmex
from swarmex.engine.record import AgentRecord, ResultRecord
from swarmex.missions import registry
from swarmex.missions.base import Mission, Outcome, Params, integer, option


@dataclass(frozen=True)
class PatrolParams(Params):
    mission = "patrol"
    laps: int = option(2, help="Laps around the block.", parse=integer(lo=1))
    seed: int = option(0, help="Seed.", parse=integer())


class PatrolMission(Mission[PatrolParams, int]):
    name = "patrol"
    command = "patrol"
    summary = "Walk around the block."
    params_type = PatrolParams
    time_unit = "step"

    def prepare(self, params: PatrolParams) -> int:
        return 4

    def execute(
        self, params: PatrolParams, world: int, on_frame: Any = None, *, trace: bool = True
    ) -> Outcome:
        steps = world * params.laps
        rec = ResultRecord("patrol", "walk", {"laps": params.laps}, params.seed, {"kind": "grid"},
                           True, float(steps), "step", {"steps": steps}, [AgentRecord(1)])
        return Outcome(rec)


class FakeEntryPoint:
    name = "patrol"

    def load(self) -> type:
        return PatrolMission


@pytest.fixture
def with_plugin(monkeypatch):
    monkeypatch.setattr(registry, "entry_points", lambda group: [FakeEntryPoint()])
    registry._plugins.cache_clear()
    registry._get.cache_clear()
    yield
    registry._plugins.cache_clear()
    registry._get.cache_clear()


def test_a_plugin_mission_is_registered_and_runs(with_plugin):
    assert swarmex.missions() == ["exploration", "foraging", "patrol", "roadmap", "traversal"]
    rec = swarmex.run("patrol", laps=3)
    assert rec.makespan == 12 and rec.mission == "patrol"
    with pytest.raises(swarmex.InputError, match="did you mean 'laps'"):
        swarmex.run("patrol", lap=3)


def test_unknown_mission_names_the_nearest():
    with pytest.raises(swarmex.InputError, match="did you mean 'foraging'"):
        swarmex.run("foragin", grid=8)


def test_builtins_are_not_imported_until_asked():
    import subprocess
    import sys

    code = ("import sys, swarmex; swarmex.missions(); "
            "print(any(m.startswith('swarmex.missions.traversal') for m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
