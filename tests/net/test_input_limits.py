"""Bad values of the networked commands' options: exit status 2 and one line naming the
option and its range, before any socket, process or mission starts.

Each case was a reviewer's reproducer: a traceback (numpy's seed, msgpack's 64 bits,
ZeroMQ's int send timeout, a poll's milliseconds overflowed by a huge finite duration), a
mission run to its end with a malformed monitor URL, 300 robot processes forked, vehicle
limits checked only with ``--vehicle``, an emulator that never reached its ``--timeout``.
The programs' entry points are replaced by guards that fail the test if reached, so a
missing check fails here at once instead of starting what it should have refused.
"""

from __future__ import annotations

import subprocess
import sys
import threading
import time

import pytest

from swarmex.cli import main
from swarmex.errors import InputError

pytestmark = pytest.mark.timeout(60)


class Started(Exception):  # noqa: N818 (a signal from a guard, not an error)
    """A guarded program was reached: every check before it passed."""


@pytest.fixture
def guarded(monkeypatch: pytest.MonkeyPatch) -> None:
    """Nothing starts: the mesh launcher, the server, the agents, the viewer, the emulator."""
    import swarmex.net.agent
    import swarmex.net.events
    import swarmex.net.mesh
    import swarmex.net.server

    def started(*args: object, **kwargs: object) -> None:
        raise Started

    monkeypatch.setattr(swarmex.net.mesh, "run_processes", started)
    monkeypatch.setattr(swarmex.net.server, "TraversalServer", started)
    monkeypatch.setattr(swarmex.net.agent, "run_agents", started)
    monkeypatch.setattr(swarmex.net.events, "viewer_batches", started)
    try:
        import swarmex.net.uav_emulator
    except ImportError:  # the uav extra: its cases are skipped
        return
    monkeypatch.setattr(swarmex.net.uav_emulator.Emulator, "run", started)


SERVE = ["serve", "--grid", "4x4", "--agents", "1", "--port", "0"]
AGENT = ["agent", "--connect", "tcp://127.0.0.1:1"]
WATCH = ["watch", "--connect", "tcp://127.0.0.1:1"]
EXPLORE = ["explore", "--empty", "5x5", "--robots", "1", "--max-ticks", "5", "--processes"]
MESH = ["mesh", "--empty", "5x5", "--robots", "1", "--max-ticks", "5"]
EMULATOR = ["uav-emulator", "--listen", "udp:127.0.0.1:0"]

REFUSED = [
    # 1. numpy's generators take no negative seed
    (AGENT + ["--fault-seed", "-1"], "--fault-seed must be at least 0"),
    # 2. the seed travels in the mesh's scenario file as msgpack's 64-bit integer
    (EXPLORE + ["--seed", str(2**64)], f"--seed must be at most {2**64 - 1}"),
    (MESH + ["--seed", str(2**64)], f"--seed must be at most {2**64 - 1}"),
    # 3. ZeroMQ's send timeout is an int of milliseconds
    (EXPLORE + ["--send-timeout", "100000000000"], "--send-timeout must be in 1..60000 ms"),
    (EXPLORE + ["--send-timeout", "0"], "--send-timeout must be in 1..60000 ms"),
    (MESH + ["--send-timeout", "60001"], "--send-timeout must be in 1..60000 ms"),
    # 4. wall times: a poll's milliseconds overflowed
    (EXPLORE + ["--timeout", "1e308"], "--timeout must be > 0 and at most 1000000 s"),
    (EXPLORE + ["--time-scale", "1e9"], "--time-scale must be > 0 and at most 1000000"),
    (MESH + ["--timeout", "1e7"], "--timeout must be > 0 and at most 1000000 s"),
    (SERVE + ["--timeout", "1", "--heartbeat", "1e307", "--dead-after", "1e308"],
     "--heartbeat must be > 0 and at most 1000000 s"),
    (SERVE + ["--dead-after", "1e308"], "--dead-after must be > 0 and at most 1000000 s"),
    (SERVE + ["--timeout", "1e9"], "--timeout must be > 0 and at most 1000000 s"),
    (SERVE + ["--init-timeout", "1e9"], "--init-timeout must be > 0 and at most 1000000 s"),
    (SERVE + ["--spare-wait", "1e9"], "--spare-wait must be >= 0 and at most 1000000 s"),
    (SERVE + ["--time-scale", "1e9"], "--time-scale must be >= 0 and at most 1000000"),
    (AGENT + ["--server-timeout", "1e300"], "--server-timeout must be > 0 and at most"),
    (AGENT + ["--connect-timeout", "1e300"], "--connect-timeout must be > 0 and at most"),
    (AGENT + ["--timeout", "1e300"], "--timeout must be > 0 and at most 1000000 s"),
    (AGENT + ["--link-timeout", "1e300"], "--link-timeout must be > 0 and at most"),
    (WATCH + ["--timeout", "1e300"], "--timeout must be > 0 and at most 1000000 s"),
    # 5. the monitor URL, as serve and watch check it, before any process starts
    (EXPLORE + ["--monitor", "foo"], "--monitor: expected ws://HOST:PORT/ingest"),
    (MESH + ["--monitor", "foo"], "--monitor: expected ws://HOST:PORT/ingest"),
    # 7. the vehicle limits, with or without --vehicle (the messages --vehicle gives)
    (AGENT + ["--max-speed", "0"], "--max-speed must be > 0"),
    (AGENT + ["--arm-battery", "200"], "--arm-battery are percentages (0..100)"),
    (AGENT + ["--min-altitude", "200", "--max-altitude", "100"],
     "--min-altitude (200 m) is above --max-altitude (100 m)"),
    (AGENT + ["--link-timeout", "0"], "--link-timeout must be > 0"),
    (AGENT + ["--nest-radius", "-1"], "--nest-radius must be a number >= 0"),
    # 8. one OS process per robot: a cap, which the simulator does not have
    (["explore", "--empty", "5x5", "--robots", "300", "--processes"],
     "--robots must be at most 64 with one process per robot"),
    (["mesh", "--empty", "5x5", "--robots", "65"],
     "--robots must be at most 64 with one process per robot"),
]

EMULATOR_REFUSED = [
    # 4. and 6.: its wall times, and a clock it cannot keep pace with
    (EMULATOR + ["--timeout", "1e300"], "--timeout must be > 0 and at most 1000000 s"),
    (EMULATOR + ["--exit-when-idle", "1e300"], "--exit-when-idle must be > 0 and at most"),
    (EMULATOR + ["--timeout", "2", "--speedup", "1e12"], "--speedup must be > 0 and at most 1000"),
    (EMULATOR + ["--speedup", "1001"], "--speedup must be > 0 and at most 1000"),
]


def _refused(argv: list[str], says: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("swarmex: error: "), err
    assert says in err and "Traceback" not in err


@pytest.mark.usefixtures("guarded")
@pytest.mark.parametrize(("argv", "says"), REFUSED, ids=[f"{i}:{a[0]} {says.split()[0]}"
                                                          for i, (a, says) in
                                                          enumerate(REFUSED)])
def test_bad_network_option_is_one_line_and_exit_2(
    argv: list[str], says: str, capsys: pytest.CaptureFixture[str]
) -> None:
    _refused(argv, says, capsys)


@pytest.mark.usefixtures("guarded")
@pytest.mark.parametrize(("argv", "says"), EMULATOR_REFUSED,
                         ids=[" ".join(a[-2:]) for a, _ in EMULATOR_REFUSED])
def test_bad_emulator_option_is_one_line_and_exit_2(
    argv: list[str], says: str, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("pymavlink")
    _refused(argv, says, capsys)


@pytest.mark.usefixtures("guarded")
@pytest.mark.parametrize("argv", [
    EXPLORE + ["--seed", str(2**64 - 1), "--send-timeout", "60000", "--timeout", "1e6",
               "--time-scale", "1e6", "--monitor", "ws://127.0.0.1:9/ingest"],
    ["mesh", "--empty", "5x5", "--robots", "64", "--max-ticks", "5"],
    SERVE + ["--heartbeat", "1e5", "--dead-after", "1e6", "--timeout", "1e6",
             "--spare-wait", "1e6", "--time-scale", "1e6"],
    AGENT + ["--fault-seed", str(2**80), "--timeout", "1e6", "--link-timeout", "1e6"],
    WATCH + ["--timeout", "1e6"],
], ids=["explore", "mesh-64", "serve", "agent", "watch"])
def test_the_bounds_themselves_are_accepted(argv: list[str]) -> None:
    """The largest values allowed reach the program (the guard), not a refusal."""
    with pytest.raises(Started):
        main(argv)


def test_vehicle_flies_by_the_limits_checked_up_front(monkeypatch: pytest.MonkeyPatch) -> None:
    """The limits are checked once, without --vehicle too; with it, the vehicle gets them."""
    import swarmex.net.agent

    seen: list[tuple[str, object]] = []

    def opened(link: str, safety: object) -> None:
        seen.append((link, safety))
        raise Started

    monkeypatch.setattr(swarmex.net.agent, "open_vehicle", opened)
    with pytest.raises(Started):
        main(AGENT + ["--vehicle", "udp:127.0.0.1:14999", "--max-speed", "3"])
    ((link, safety),) = seen
    assert link == "udp:127.0.0.1:14999" and getattr(safety, "max_speed", None) == 3.0


def test_python_callers_get_input_errors_too() -> None:
    from swarmex.net.agent import Faults
    from swarmex.net.vehicle import Safety

    with pytest.raises(InputError, match="--fault-seed"):
        Faults(seed=-1)
    with pytest.raises(InputError, match="--link-timeout"):
        Safety(link_timeout=1e300)
    emulator = pytest.importorskip("swarmex.net.uav_emulator")
    with pytest.raises(InputError, match="--speedup"):
        emulator.EmulatorConfig(speedup=1e12)
    with pytest.raises(InputError, match="--timeout"):
        emulator.EmulatorConfig(timeout=1e308)


# ---------------------------------------------------------------- 6. the emulator's --timeout


def test_emulator_timeout_holds_while_its_clock_catches_up(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A clock that falls behind the wall (here: physics slowed to 5 ms a step at 1000x,
    100 times slower than the wall, as --speedup 1e12 was on any machine) used to catch up
    whole before --timeout was looked at again, each catch-up 100 times longer than the
    last: seconds past the timeout, then never (1e12 never exited)."""
    emulator = pytest.importorskip("swarmex.net.uav_emulator")
    step = emulator.Copter._step

    def slow(self: object, h: float) -> None:
        step(self, h)
        time.sleep(0.005)

    monkeypatch.setattr(emulator.Copter, "_step", slow)
    cfg = emulator.EmulatorConfig(speedup=1000.0, timeout=0.5)
    emu = emulator.Emulator("127.0.0.1", 0, cfg, lambda s: None)
    codes: list[int] = []
    thread = threading.Thread(target=lambda: codes.append(emu.run()), daemon=True)
    start = time.monotonic()
    thread.start()
    thread.join(5.0)
    assert not thread.is_alive(), "the emulator ran past its --timeout"
    assert codes == [0] and time.monotonic() - start < 1.5


def test_emulator_process_exits_at_its_timeout() -> None:
    """``swarmex uav-emulator --timeout 1 --speedup 1000`` as a process: exits 0 within a few
    seconds (the interpreter's start included), bounded by subprocess's own timeout. A smoke
    test of the command's path: at 1000x the emulator kept its timeout before the fix too;
    the in-process test above is the one that guards the catch-up's deadline."""
    pytest.importorskip("pymavlink")
    start = time.monotonic()
    done = subprocess.run(
        [sys.executable, "-m", "swarmex", *EMULATOR, "--timeout", "1", "--speedup", "1000"],
        capture_output=True, text=True, timeout=30,
    )
    elapsed = time.monotonic() - start
    assert done.returncode == 0, done.stderr
    assert "--timeout reached" in done.stdout and "Traceback" not in done.stderr
    assert elapsed < 10.0
