"""Agent-steps per second of the PettingZoo environments with a random legal policy, and
POGEMA 1.4's on its 32x32 grid with 16 agents beside swarmex foraging on a 32x32 grid with
16 agents (issue 13, item 5).

An *agent-step* is one agent's action taken by the environment: in a parallel step every
live agent acts (foraging: every robot moves every round; exploration and roadmap: the
agents that are not deciding get their no-op, which is still an action of the API), so a
parallel step of n agents counts n agent-steps, as POGEMA's own figures do. The random
policy samples uniformly among the actions its mask allows (one numpy call for the team when
the masks share a shape, as POGEMA's policy is one call); "env only" counts only the time
spent in reset and step. Each case (and POGEMA) first runs the same loop for ``--warmup``
seconds (default 1), not counted: compiled code is loaded and first-use imports happen once
per process, not per step.

POGEMA 1.4 pins gymnasium 0.28, which breaks PettingZoo 1.27 (it needs gymnasium >= 1.0), so
POGEMA runs in its own virtual environment, made by this script on first use under
``~/.cache/swarmex/bench-pogema`` (``pip install pogema==1.4.*``), in a subprocess of the
same run. ``--no-pogema`` skips it.

    python bench/bench_envs.py [--seconds 5] [--warmup 1] [--no-pogema] [--only TEXT]
"""

from __future__ import annotations

import importlib
import json
import os
import shutil
import subprocess
import sys
import time
import venv
from pathlib import Path
from typing import Any

import numpy as np

import _cli

REPO = Path(__file__).resolve().parents[1]

# (label, module, params): small and medium worlds per mission; foraging's 32x32/16 row is
# the one compared with POGEMA's 32x32/16 (the goal); its 256-round row ends each
# episode where POGEMA's do (max_episode_steps=256), so resets and the rounds before and
# during the communication phase weigh as much as in POGEMA's figure
CASES: list[tuple[str, str, dict[str, Any]]] = [
    ("foraging 32x32, 16 robots", "foraging_v0",
     {"grid": 32, "agents": 16, "algorithm": "sectors", "food_units": 10}),
    ("foraging 32x32, 16 robots, 256-round episodes", "foraging_v0",
     {"grid": 32, "agents": 16, "algorithm": "sectors", "food_units": 10, "max_rounds": 256}),
    ("foraging 64x64, 16 robots", "foraging_v0",
     {"grid": 64, "agents": 16, "algorithm": "sectors", "food_units": 10}),
    ("traversal 12x12, 4 agents", "traversal_v0", {"grid": "12x12", "agents": 4}),
    ("traversal 32x32, 8 agents", "traversal_v0", {"grid": "32x32", "agents": 8}),
    ("exploration 3x3 m at 10 cm, 2 robots", "exploration_v0",
     {"empty": "3x3", "cell": 0.1, "robots": 2, "laser_range": 1.0}),
    ("exploration 10x10 m at 10 cm, 4 robots", "exploration_v0",
     {"empty": "10x10", "cell": 0.1, "robots": 4}),
    ("roadmap fig8, 60 nodes, 2 agents", "roadmap_v0",
     {"env": str(REPO / "examples" / "roadmap_fig8.json"), "agents": 2, "nodes": 60,
      "step": 40.0, "sensor_range": "inf"}),
    ("roadmap fig8, 400 nodes, 8 agents", "roadmap_v0",
     {"env": str(REPO / "examples" / "roadmap_fig8.json"), "agents": 8, "nodes": 400,
      "step": 20.0, "sensor_range": "1eps"}),
]


def random_legal(obs: dict[str, Any], space: Any, rng: np.random.Generator) -> Any:
    mask = obs.get("action_mask") if isinstance(obs, dict) else None
    if mask is None:
        return space.sample()
    legal = np.flatnonzero(np.asarray(mask))
    return int(rng.choice(legal)) if legal.size else 0


def random_team(env: Any, obs: dict[str, Any], rng: np.random.Generator) -> dict[str, Any]:
    """Every live agent's random legal action. Where all agents have same-shaped masks the
    team is sampled with one numpy call, as POGEMA's policy is (the argmax of uniform noise
    on the legal entries is uniform among them; a row with none gives 0), so the figure is
    the environment's, not a per-agent Python sampler's; else agent by agent."""
    agents = env.agents
    masks = [o.get("action_mask") if isinstance(o, dict) else None
             for o in (obs[a] for a in agents)]  # fmt: skip
    if masks and all(m is not None for m in masks) and len({m.shape for m in masks}) == 1:
        legal = np.array(masks) > 0  # (np.stack: the same array, 3x the cost for 16 masks)
        choice = (rng.random(legal.shape) * legal).argmax(axis=1).tolist()
        return dict(zip(agents, choice, strict=True))
    return {a: random_legal(obs[a], env.action_space(a), rng) for a in agents}


def measure(
    module: str, params: dict[str, Any], seconds: float, warmup: float = 1.0
) -> tuple[float, float, int, int]:
    """(agent-steps/s, agent-steps/s counting only reset and step, agent-steps, episodes) of
    a random legal policy on the parallel env, after ``warmup`` seconds of the same loop
    (not counted: loading compiled code and first-use imports happen once per process)."""
    mod = importlib.import_module(f"swarmex.envs.{module}")
    env = mod.parallel_env(**params)
    rng = np.random.default_rng(0)
    if warmup > 0:
        start = time.perf_counter()
        obs, _ = env.reset(seed=10**6)
        while time.perf_counter() - start < warmup:
            if not env.agents:
                obs, _ = env.reset()
            obs, _, _, _, _ = env.step(random_team(env, obs, rng))
    agent_steps = episodes = 0
    in_env = 0.0
    clock = time.perf_counter
    start = clock()
    seed = 0
    while clock() - start < seconds:
        t0 = clock()
        obs, _ = env.reset(seed=seed)
        in_env += clock() - t0
        seed += 1
        episodes += 1
        while env.agents and clock() - start < seconds:
            actions = random_team(env, obs, rng)
            agent_steps += len(actions)
            t0 = clock()
            obs, _, _, _, _ = env.step(actions)
            in_env += clock() - t0
    env.close()
    return agent_steps / (clock() - start), agent_steps / in_env, agent_steps, episodes


POGEMA_CODE = """
import json, time, numpy as np
from pogema import pogema_v0, GridConfig
env = pogema_v0(grid_config=GridConfig(size=32, num_agents=16, density=0.3, seed=1,
                                        max_episode_steps=256))
rng = np.random.default_rng(0); steps = 0; episodes = 0
seconds, warmup = float(__import__('sys').argv[1]), float(__import__('sys').argv[2])
start = time.perf_counter(); env.reset(seed=10**6)
while time.perf_counter() - start < warmup:  # the same warm-up as swarmex's envs get
    obs, r, term, trunc, info = env.step(rng.integers(0, 5, 16).tolist())
    if all(term) or all(trunc):
        env.reset()
start = time.perf_counter()
while time.perf_counter() - start < seconds:
    obs, info = env.reset(seed=episodes); episodes += 1
    while time.perf_counter() - start < seconds:
        obs, r, term, trunc, info = env.step(rng.integers(0, 5, 16).tolist()); steps += 16
        if all(term) or all(trunc):
            break
print(json.dumps({"rate": steps / (time.perf_counter() - start), "steps": steps,
                  "episodes": episodes}))
"""


def _own_env() -> dict[str, str]:
    """This environment without ``PYTHONPATH``: the POGEMA venv's pip and Python must not see
    swarmex's source tree (``PYTHONPATH=src``, as the other scripts are run), or pip reports
    swarmex's NumPy 2 requirement as a conflict with POGEMA's NumPy 1."""
    return {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}


def pogema(seconds: float, warmup: float = 1.0) -> dict[str, Any] | None:
    home = Path.home() / ".cache" / "swarmex" / "bench-pogema"
    python = home / "bin" / "python"
    if not python.exists():
        print(f"making a virtual environment for POGEMA 1.4 in {home} ...", file=sys.stderr)
        venv.create(home, with_pip=True)
        got = subprocess.run([str(python), "-m", "pip", "install", "-q", "pogema==1.4.*"],
                             env=_own_env())
        if got.returncode:  # offline, say: no traceback, and no half-made venv kept for later
            shutil.rmtree(home, ignore_errors=True)
            print("POGEMA skipped: pip install pogema==1.4.* failed (see above); "
                  "--no-pogema leaves it out", file=sys.stderr)
            return None
    out = subprocess.run([str(python), "-c", POGEMA_CODE, str(seconds), str(warmup)],
                         capture_output=True, text=True, timeout=600, env=_own_env())
    if out.returncode:
        last = out.stderr.strip().splitlines()[-1:] or ["no message"]
        print(f"POGEMA skipped: its run failed: {last[0]}", file=sys.stderr)
        return None
    return json.loads(out.stdout)  # type: ignore[no-any-return]


def main() -> None:
    ap = _cli.Parser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=_cli.positive_float, default=5.0,
                    help="timing window per case")
    ap.add_argument("--warmup", type=_cli.nonneg_float, default=1.0,
                    help="seconds of the same loop before each timing window, not counted")
    ap.add_argument("--no-pogema", action="store_true",
                    help="leave POGEMA out; otherwise its first run makes a virtual environment"
                    " in ~/.cache/swarmex/bench-pogema and pip-installs pogema==1.4.* there")
    ap.add_argument("--only", default="", help="run only cases whose label contains this")
    args = ap.parse_args()
    if args.only and not any(args.only in label for label, _, _ in CASES):
        ap.error(f"--only {args.only!r} matches no case: "
                 + "; ".join(label for label, _, _ in CASES))
    rows = []
    for label, module, params in CASES:
        if args.only and args.only not in label:
            continue
        try:
            rate, env_rate, steps, eps = measure(module, params, args.seconds, args.warmup)
        except ModuleNotFoundError as exc:
            print(f"{label}: skipped ({exc})", file=sys.stderr)
            continue
        rows.append((label, rate, env_rate, steps, eps))
    ref = None if args.no_pogema else pogema(args.seconds, args.warmup)
    print(f"{'environment':48s} {'agent-steps/s':>14s} {'(env only)':>11s} {'agent-steps':>12s}"
          f" {'episodes':>9s}")
    for label, rate, env_rate, steps, eps in rows:
        print(f"{label:48s} {rate:14,.0f} {env_rate:11,.0f} {steps:12,d} {eps:9d}")
    if ref is not None:
        label = "POGEMA 1.4 32x32, 16 agents (density 0.3)"
        print(f"{label:48s} {ref['rate']:14,.0f} {'':11s} {ref['steps']:12,d}"
              f" {ref['episodes']:9d}")
        print()
        for row in rows:
            if row[0].startswith("foraging 32x32"):
                what = row[0].replace("foraging 32x32, 16 robots", "foraging 32x32/16")
                print(f"{what} vs POGEMA 32x32/16: ratio {row[1] / ref['rate']:.2f}"
                      + ("" if "256" in what else " (goal >= 1)"))


if __name__ == "__main__":
    _cli.run(main)
