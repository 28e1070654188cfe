"""Train one shared PPO policy for every robot of ``foraging_v0`` and compare it with the seed.

Stable-Baselines3's PPO learns through SuperSuit (``pettingzoo_env_to_vec_env_v1`` +
``concat_vec_envs_v1``): each robot of each environment copy is one entry of the vector env, so
the robots share one policy (parameter sharing) and one timestep is one robot's move (a round
of n robots is n timesteps). The learned policy is evaluated during training, and at the end it
is compared with the seed's own rules (``foraging_v0.baseline_policy`` for a few patterns) and
with a random legal policy, all on the same evaluation seeds (the seed draws the food cell),
the same grid, team, food units, transport and round cap.

Metrics per episode: the rounds until the k-th unit is home (the record's makespan; an
episode that hits the round cap counts as the cap) and the units delivered within the cap.
Reported as mean ± 95 % confidence interval (Student t) over the evaluation seeds.

Action mask: SB3's PPO samples without a mask, so the environments run with
``invalid_action="project"`` (the documented opt-in: a move off the grid becomes *stay*); the
mask is still part of the observation. sb3-contrib's MaskablePPO is not used.

Outputs in ``--out``: ``train_foraging.png`` (learning curve, baselines and random as
horizontal bands) and ``train_foraging.json`` (the numbers).

    PYTHONPATH=src python examples/train_foraging.py --out docs/img   # defaults: ~8 min, 1 core
    PYTHONPATH=src python examples/train_foraging.py --timesteps 200000 --out /tmp/quick

Needs the ``rl`` extra: ``pip install 'swarmex[rl]'``.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

RL_MODULES = ("torch", "stable_baselines3", "supersuit", "pettingzoo", "gymnasium")
EVAL_SEED0 = 1_000_000  # evaluation seeds: EVAL_SEED0 + i; training draws seeds below it
MODES = 7  # len(foraging_v0.MODES)


def require_rl() -> None:
    """Exit with one line naming the extra when a learning library is missing."""
    from swarmex.errors import InputError, require

    try:
        for module in RL_MODULES:
            require(module, "rl", "examples/train_foraging.py")
    except InputError as e:
        print(f"error: {e}", file=sys.stderr)
        raise SystemExit(2) from None


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "--timesteps",
        type=int,
        default=2_500_000,
        help="PPO timesteps (robot moves; a round is n of them)",
    )
    ap.add_argument("--grid", type=int, default=8, help="grid side g")
    ap.add_argument("--agents", type=int, default=4, help="robots n")
    ap.add_argument("--food-units", type=int, default=3, help="units k at the food")
    ap.add_argument(
        "--transport",
        default="end-to-end",
        help="transport of every policy (end-to-end | relay-food | relay-path)",
    )
    ap.add_argument(
        "--max-rounds", type=int, default=None, help="round cap of every episode (default 8·g²)"
    )
    ap.add_argument(
        "--world-pattern",
        default="sectors",
        help="the pattern of the world the learned and random policies act in: it fixes "
        "the pattern neighbours an informed robot must tell before it transports",
    )
    ap.add_argument(
        "--baselines",
        default="sectors,strips,spiral",
        help="comma-separated patterns played by baseline_policy",
    )
    ap.add_argument("--seed", type=int, default=0, help="training seed")
    ap.add_argument("--envs", type=int, default=4, help="environment copies in the vector env")
    ap.add_argument("--eval-episodes", type=int, default=30, help="evaluation seeds")
    ap.add_argument(
        "--eval-every",
        type=int,
        default=None,
        help="timesteps between evaluations (default timesteps/10)",
    )
    ap.add_argument("--out", type=Path, default=Path("train_foraging_out"), help="output dir")
    args = ap.parse_args(argv)
    if args.max_rounds is None:
        args.max_rounds = 8 * args.grid * args.grid
    if args.eval_every is None:
        args.eval_every = max(1, args.timesteps // 10)
    for name in ("timesteps", "eval_episodes", "eval_every", "envs"):
        if getattr(args, name) < 1:
            ap.error(f"--{name.replace('_', '-')} must be at least 1")
    return args


# ---------------------------------------------------------------------- the learner's view


def make_flat_env(params: dict[str, Any]) -> Any:
    """``foraging_v0`` with one flat float32 observation per robot (what an MLP wants)."""
    from gymnasium import spaces
    from pettingzoo.utils.wrappers import BaseParallelWrapper

    from swarmex.envs import foraging_v0

    class FlatForaging(BaseParallelWrapper):
        """Per robot: its cell and the nest and food relative to it (scaled by g), load,
        informed, phase (one-hot), neighbours still to tell, the robots it senses (relative,
        with a seen flag), the action mask, round/cap and its own index (one-hot, so the
        shared policy may tell the robots apart). Resets without a seed draw the next mission
        seed from a generator seeded by the last explicit seed (copies of the env seeded
        seed + i draw different streams; all below EVAL_SEED0)."""

        def __init__(self, env: Any) -> None:
            super().__init__(env)
            base = env.unwrapped
            self.g, self.n, self.cap = base.g, len(base.possible_agents), base.max_rounds
            size = 2 + 2 + 2 + 2 + MODES + self.n + 3 * self.n + 5 + 1 + self.n
            box = spaces.Box(-1.0, 1.0, (size,), np.float32)
            self._spaces = dict.fromkeys(base.possible_agents, box)
            self._rng = np.random.default_rng(base.params.seed)
            self._ids = np.eye(self.n, dtype=np.float32)

        def observation_space(self, agent: str) -> Any:
            return self._spaces[agent]

        def flat(self, agent: str, o: dict[str, np.ndarray]) -> np.ndarray:
            g, i = self.g, int(agent.rsplit("_", 1)[1])
            pos = o["position"].astype(np.float32)
            informed = float(o["informed"][0])
            food = (o["food"] - pos) / g if informed else np.zeros(2, np.float32)
            mode = np.zeros(MODES, np.float32)
            mode[int(o["mode"][0])] = 1
            team = o["team_positions"]
            seen = (team[:, 0] >= 0).astype(np.float32)
            rel = (team - pos) / 2.0 * seen[:, None]  # SENSING = 2
            return np.concatenate(
                [
                    pos / max(1, g - 1),
                    (o["nest"] - pos) / g,
                    o["carrying"],
                    [informed],
                    food,
                    mode,
                    o["to_tell"],
                    rel.ravel(),
                    seen,
                    o["action_mask"],
                    o["round"] / self.cap,
                    self._ids[i],
                ]
            ).astype(np.float32)

        def reset(self, seed: int | None = None, options: Any = None) -> Any:
            if seed is not None:
                self._rng = np.random.default_rng(seed)
            else:
                seed = int(self._rng.integers(EVAL_SEED0))
            obs, infos = self.env.reset(seed=seed, options=options)
            return {a: self.flat(a, o) for a, o in obs.items()}, infos

        def step(self, actions: Any) -> Any:
            obs, rewards, terms, truncs, infos = self.env.step(actions)
            for a, cut in truncs.items():
                if cut:  # SB3 bootstraps a truncated episode's value
                    infos[a]["TimeLimit.truncated"] = True
            return {a: self.flat(a, o) for a, o in obs.items()}, rewards, terms, truncs, infos

    return FlatForaging(foraging_v0.parallel_env(**params))


# ---------------------------------------------------------------------- evaluation


def episode_metrics(env: Any) -> tuple[float, int]:
    record = env.unwrapped.record()
    delivered = sum(int(a.metrics["drops"]) for a in record.agents)
    return float(record.makespan), delivered


def play(env: Any, seeds: list[int], act: Any) -> dict[str, list[float]]:
    """Run one episode per seed; ``act(obs, seed)`` gives the parallel actions."""
    rounds, delivered, food = [], [], []
    for s in seeds:
        obs, infos = env.reset(seed=s)
        while env.agents:
            obs, _, _, _, infos = env.step(act(obs, infos))
        r, d = episode_metrics(env)
        rounds.append(r)
        delivered.append(d)
        food.append(list(env.unwrapped.record().params["food"]))
    return {"rounds": rounds, "delivered": delivered, "food": food}


def summary(values: list[float]) -> dict[str, float]:
    from scipy import stats

    x = np.asarray(values, dtype=float)
    mean = float(x.mean())
    if len(x) < 2:
        return {"mean": mean, "ci95": float("nan")}
    half = float(stats.t.ppf(0.975, len(x) - 1) * x.std(ddof=1) / math.sqrt(len(x)))
    return {"mean": mean, "ci95": half}


def learned_actor(model: Any, env: Any, deterministic: bool) -> Any:
    import torch

    agents = env.possible_agents

    def act(obs: dict[str, np.ndarray], infos: Any) -> dict[str, int]:
        batch = np.stack([obs[a] for a in agents])
        actions, _ = model.predict(batch, deterministic=deterministic)
        return {a: int(v) for a, v in zip(agents, actions, strict=True)}

    def run(seeds: list[int]) -> dict[str, list[float]]:
        with torch.random.fork_rng():  # sampled evaluation leaves training's RNG alone
            torch.manual_seed(seeds[0])
            return play(env, seeds, act)

    return run


def random_actor(seed: int) -> Any:
    rng = np.random.default_rng(seed)

    def act(obs: dict[str, dict[str, np.ndarray]], infos: Any) -> dict[str, int]:
        return {a: int(rng.choice(np.flatnonzero(o["action_mask"]))) for a, o in obs.items()}

    return act


# ---------------------------------------------------------------------- figure


def plot(
    path: Path,
    curve: list[dict[str, Any]],
    refs: dict[str, dict[str, Any]],
    title: str,
    cap: int,
    units: int,
) -> None:
    """Two panels (rounds, delivered units) against training timesteps; the reference
    policies as horizontal lines with their 95 % CI as bands (clipped to what is possible)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, NullFormatter, ScalarFormatter

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    x = np.array([c["timesteps"] for c in curve], dtype=float)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    panels = (
        ("rounds", "rounds to deliver all units (capped)", (1, cap)),
        ("delivered", "units delivered within the cap", (0, units)),
    )
    for ax, (key, label, (lo, hi)) in zip(axes, panels, strict=True):
        for j, (name, ref) in enumerate(refs.items()):
            m, h = ref[key]["mean"], ref[key]["ci95"]
            style = "--" if name == "random" else ":"
            c = "0.4" if name == "random" else colours[(j + 1) % len(colours)]
            ax.axhline(m, color=c, ls=style, lw=1.2, label=f"{name} ({m:.1f})")
            ax.axhspan(max(lo, m - h), min(hi, m + h), color=c, alpha=0.12, lw=0)
        y = np.array([c[key]["mean"] for c in curve])
        h = np.array([c[key]["ci95"] for c in curve])
        ax.plot(x, y, "o-", color=colours[0], lw=1.8, ms=4, label="PPO, shared policy")
        ax.fill_between(
            x, np.maximum(lo, y - h), np.minimum(hi, y + h), color=colours[0], alpha=0.2, lw=0
        )
        if key == "rounds":  # baselines and learner differ by an order of magnitude
            ax.set_yscale("log")
            ax.set_yticks([t for t in (10, 20, 50, 100, 200, 500, 1000, 2000, 5000) if t <= hi])
            ax.yaxis.set_major_formatter(ScalarFormatter())
            ax.yaxis.set_minor_formatter(NullFormatter())
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v / 1e6:g}M" if v else "0"))
        ax.set_xlabel("training timesteps (robot moves)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="best")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


# ---------------------------------------------------------------------- main


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    require_rl()
    import supersuit as ss
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.utils import set_random_seed

    from swarmex.envs import foraging_v0
    from swarmex.errors import InputError

    torch.set_num_threads(1)
    set_random_seed(args.seed)
    started = time.perf_counter()
    world = dict(
        grid=args.grid,
        agents=args.agents,
        food_units=args.food_units,
        transport=args.transport,
        max_rounds=args.max_rounds,
    )
    learn_params = dict(
        world, algorithm=args.world_pattern, invalid_action="project", seed=args.seed
    )
    baselines = [p.strip() for p in args.baselines.split(",") if p.strip()]
    try:
        train_env = make_flat_env(learn_params)
        eval_env = make_flat_env(learn_params)
        for pattern in baselines:  # now, not after minutes of training
            foraging_v0.parallel_env(**world, algorithm=pattern, seed=args.seed).close()
    except InputError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    seeds = [EVAL_SEED0 + i for i in range(args.eval_episodes)]

    vec = ss.pettingzoo_env_to_vec_env_v1(train_env)
    vec = ss.concat_vec_envs_v1(vec, args.envs, num_cpus=0, base_class="stable_baselines3")
    vec.venv.reset(seed=args.seed)  # seeds each copy's stream (SB3's env.seed is not wired)
    n_envs = vec.num_envs  # copies × robots
    n_steps = max(32, 4096 // n_envs)
    model = PPO(
        "MlpPolicy",
        vec,
        n_steps=n_steps,
        batch_size=512,
        n_epochs=5,
        learning_rate=3e-4,
        gamma=0.99,
        gae_lambda=0.95,
        ent_coef=0.01,
        clip_range=0.2,
        verbose=0,
        device="cpu",
        policy_kwargs=dict(net_arch=[128, 128]),
    )

    curve: list[dict[str, Any]] = []
    sampled = learned_actor(model, eval_env, deterministic=False)

    def evaluate(t: int) -> None:
        res = sampled(seeds)
        point = {
            "timesteps": t,
            "rounds": summary(res["rounds"]),
            "delivered": summary(res["delivered"]),
        }
        curve.append(point)
        print(
            f"[{time.perf_counter() - started:6.0f} s] timesteps {t:>8,}: rounds "
            f"{point['rounds']['mean']:7.1f} ± {point['rounds']['ci95']:5.1f}, delivered "
            f"{point['delivered']['mean']:4.2f} / {args.food_units}",
            flush=True,
        )

    class Every(BaseCallback):
        def __init__(self) -> None:
            super().__init__()
            self.next = args.eval_every

        def _on_step(self) -> bool:
            return True

        def _on_rollout_start(self) -> None:  # after the previous rollout's update
            if self.num_timesteps >= self.next:
                evaluate(self.num_timesteps)
                while self.next <= self.num_timesteps:
                    self.next += args.eval_every

    evaluate(0)
    model.learn(total_timesteps=args.timesteps, callback=Every())
    trained = time.perf_counter() - started
    if curve[-1]["timesteps"] != model.num_timesteps:  # the trained model's last point
        evaluate(model.num_timesteps)
    vec.close()

    # the final comparison, every policy on the same seeds
    results: dict[str, dict[str, list[float]]] = {}
    results["PPO (sampled)"] = sampled(seeds)
    results["PPO (greedy)"] = learned_actor(model, eval_env, deterministic=True)(seeds)
    for pattern in baselines:  # each was checked before training
        env = foraging_v0.parallel_env(**world, algorithm=pattern, seed=args.seed)
        results[pattern] = play(env, seeds, foraging_v0.baseline_policy(env))
    plain = foraging_v0.parallel_env(**learn_params)
    results["random"] = play(plain, seeds, random_actor(args.seed))
    foods = {name: r.pop("food") for name, r in results.items()}
    assert all(f == foods["random"] for f in foods.values()), "food cells differ between runs"

    table = {
        name: {
            "rounds": summary(r["rounds"]),
            "delivered": summary(r["delivered"]),
            "complete": sum(d >= args.food_units for d in r["delivered"]),
            "per_episode_rounds": r["rounds"],
            "per_episode_delivered": r["delivered"],
        }
        for name, r in results.items()
    }
    wall = time.perf_counter() - started
    args.out.mkdir(parents=True, exist_ok=True)
    refs = {k: v for k, v in table.items() if not k.startswith("PPO")}
    title = (
        f"foraging_v0: {args.grid}×{args.grid} grid, {args.agents} robots, "
        f"{args.food_units} units, {args.transport}, cap {args.max_rounds} rounds; "
        f"{len(seeds)} evaluation seeds, mean ± 95 % CI"
    )
    plot(args.out / "train_foraging.png", curve, refs, title, args.max_rounds, args.food_units)
    command = "examples/train_foraging.py " + " ".join(sys.argv[1:] if argv is None else argv)
    out = {
        "command": command.strip(),
        "config": {k: (str(v) if isinstance(v, Path) else v) for k, v in vars(args).items()},
        "ppo": {
            "n_envs": n_envs,
            "n_steps": n_steps,
            "batch_size": 512,
            "n_epochs": 5,
            "learning_rate": 3e-4,
            "ent_coef": 0.01,
            "net_arch": [128, 128],
            "action_mask": "invalid_action='project' (off-grid move -> stay)",
        },
        "eval_seeds": [seeds[0], seeds[-1]],
        "foods": foods["random"],
        "train_seconds": round(trained, 1),
        "wall_seconds": round(wall, 1),
        "torch": torch.__version__,
        "curve": curve,
        "final": table,
    }
    (args.out / "train_foraging.json").write_text(json.dumps(out, indent=1) + "\n")

    width = max(len(k) for k in table)
    print(
        f"\n{'policy':<{width}}  rounds (mean ± 95 % CI)  delivered / {args.food_units}  complete"
    )
    for name, row in table.items():
        r, d = row["rounds"], row["delivered"]
        print(
            f"{name:<{width}}  {r['mean']:8.1f} ± {r['ci95']:6.1f}       "
            f"{d['mean']:5.2f} ± {d['ci95']:4.2f}   {row['complete']}/{len(seeds)}"
        )
    print(
        f"\nwrote {args.out / 'train_foraging.png'} and {args.out / 'train_foraging.json'} "
        f"({wall:.0f} s, training {trained:.0f} s)"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
