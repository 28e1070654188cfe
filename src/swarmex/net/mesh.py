"""Seed 003's exploration as OS processes on a brokerless ZeroMQ mesh (thesis ch. 2–3).

One process per robot plus one display process. Each binds its own PULL socket and sends
with one PUSH socket per peer, every send with a timeout: the thesis's nanomsg PIPELINE,
chosen there (§3.4) because a REQ-ROUTER sender blocks forever on a dead peer; a PUSH that
cannot deliver within ``send_timeout`` drops the message and counts it, so a killed robot
never stalls the others. Every frame is the wire format of :mod:`swarmex.net.wire`
(msgpack + CRC32); bad frames are dropped and counted.

The robots run the very :class:`~swarmex.missions.exploration.robot.ExplorerRobot` objects
the simulator drives, through the same calls (observe, housekeeping, on_message,
maybe_plan, next_step, moved). What the simulator owned — the truth, the lasers, the radio —
is split the way the real system splits it:

* **the truth and the laser** live in each robot process (the robot's own sensor reading
  the world file; the policy never sees it), and every step is checked against it;
* **the radio** is emulated: every radio frame carries the sender's cell, and the
  *receiver* drops it when the two are farther apart than the radio range (the disc model
  of the simulator, from true positions), or with the injected loss probability. Heartbeats
  (1 s) go to every node in the *air* — the run directory where each node publishes its
  PULL endpoint — so discovery works as the thesis's UDP heartbeats do: whoever is in range
  hears them; everything else goes to neighbour-table entries only. Multi-hop delivery is
  the robots' own ``SCAN`` flooding with de-duplication and, for the unicasts (``NEED_MAP``,
  ``MAP``, ``CHANGE_GOAL``), the simulator's AODV (:mod:`swarmex.net.routing`: its frames,
  and the ``NACK`` by which a receiver out of range refuses a unicast, the link-layer
  feedback the simulator gives at once);
* **the clock**: each robot ticks every ``0.1 × time_scale`` wall seconds (the thesis's
  100 ms movement period, scaled) on its own, asynchronously, as the thesis's processes did.

The display process (thesis §3.2: "the router, but it does not carry out the exploration")
joins the mesh: it heartbeats, relays floods, routes AODV unicasts, asks new neighbours for
their maps and keeps its own map of every scan it hears. Beside the radio there is a
**control link** that is not part of the robots' world — the experiment's harness: robots
say HELLO to the display, the display starts them together (GO), robots send STATUS
telemetry (position, moves, finished) and, after STOP, their REPORT (statistics and final
map). The display ends the run when every live robot has reported *finished* for a settling
time, writes the result record (the schema of ``swarmex explore``) and serves live monitor
events.

Faults: a robot that stops sending STATUS for ``dead_after`` seconds is dead to the display
(the others' neighbour tables time it out by themselves); ``inject_kill`` makes a robot exit
abruptly at a given tick; ``loss`` drops that share of radio frames at the receivers.

The jobs live in their own modules: :mod:`~swarmex.net.mesh_scenario` (the run directory's
scenario), :mod:`~swarmex.net.mesh_frames` (radio and control frames),
:mod:`~swarmex.net.mesh_node` (sockets and the emulated radio),
:mod:`~swarmex.net.mesh_robot` and :mod:`~swarmex.net.mesh_display` (the two kinds of
process), :mod:`~swarmex.net.mesh_record` (the result record). This module launches them.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import zmq

from swarmex.net.mesh_display import DisplayProcess
from swarmex.net.mesh_robot import RobotProcess
from swarmex.net.mesh_scenario import MeshOptions, write_scenario

if TYPE_CHECKING:  # imported where used: each process loads only what it needs
    from swarmex.missions.exploration.params import ExplorationParams
    from swarmex.worlds.metric import MetricGrid


#: what the fork server imports once, so each robot process starts in milliseconds instead
#: of re-importing numpy, scipy and numba (seconds each, on a busy machine)
PRELOAD = ["swarmex.net.mesh", "swarmex.missions.exploration.sim",
           "swarmex.missions.exploration.robot", "swarmex.missions.exploration.record",
           "swarmex.engine.record", "zmq"]


class DisplayDied(RuntimeError):
    """The display process ended, or hung, without writing the record (the launcher has
    nothing of the run: the robots report to the display only). One line, no traceback:
    :func:`swarmex.cli.shared.run_mesh` says it and exits with status
    :data:`EXIT_DISPLAY_DIED`."""


#: the launcher's exit status when the display died without a record (the robots, too,
#: leave with 3 when the display is gone)
EXIT_DISPLAY_DIED = 3


def _robot_entry(run_dir: str, rid: int, log_path: str) -> None:
    """A robot process's body (started by the fork server): output to its log file. A
    terminal's Ctrl-C, or a SIGTERM to the whole group (``timeout``, a service manager), is
    the display's to handle (it stops the robots and collects their reports), so a robot
    ignores both; without the display it leaves by itself, and the launcher kills leftovers."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    log = os.open(log_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
    os.dup2(log, 1)
    os.dup2(log, 2)
    code = main(["robot", run_dir, str(rid)])
    # a multiprocessing child ends with os._exit, which would kill ZeroMQ's I/O thread with
    # the REPORT still queued: terminating the context waits for each socket's linger
    zmq.Context.instance().term()
    sys.exit(code)


def _display_entry(run_dir: str, monitor_url: str | None, conn: Any) -> None:
    """The display process's body: its lines go back to the launcher through ``conn``."""
    node = DisplayProcess(Path(run_dir), monitor_url=monitor_url)
    try:
        code = node.run(conn.send)
    except Exception as exc:  # one line to the launcher, not a traceback on its terminal
        code = 1
        with contextlib.suppress(OSError):
            conn.send(f"swarmex mesh display: failed ({type(exc).__name__}: {exc!s:.80})")
    finally:
        node.close()
        node.view.close(1000)  # let the last event batch reach the viewers
        zmq.Context.instance().term()  # (see _robot_entry)
        with contextlib.suppress(OSError):  # the launcher may be gone (killed with its group)
            conn.send(None)
            conn.close()
    sys.exit(code)


def run_processes(grid: MetricGrid, params: ExplorationParams, options: MeshOptions,
                  json_path: Path | None = None, monitor_url: str | None = None,
                  say: Callable[[str], object] = print) -> dict[str, Any]:
    """``swarmex explore --processes``: a display and one OS process per robot; the record.

    Processes come from a multiprocessing *fork server* that has imported the mission code
    once (each child is still its own process with its own sockets, started from a clean
    single-threaded parent, so no lock or thread of the launcher leaks into it). Every child
    is killed (by its own pid) if it outlives the run; the run directory (the air) is
    removed at the end.
    """
    import multiprocessing

    from swarmex.missions.exploration.params import validate

    validate(params, grid)
    started = time.time()
    mp = multiprocessing.get_context("forkserver")
    mp.set_forkserver_preload(PRELOAD)
    run_dir = Path(tempfile.mkdtemp(prefix="swarmex-mesh-"))
    procs: list[Any] = []
    try:
        record_path = run_dir / "out.json"
        write_scenario(run_dir, grid, params, options, json_path or record_path)
        lines, child_end = mp.Pipe(duplex=False)
        display = mp.Process(target=_display_entry, args=(str(run_dir), monitor_url, child_end),
                             name="swarmex-display")
        # one robot, one computer: compiled kernels single-threaded. Set in the environment
        # the fork server starts with (asking numba at run time would start its thread pool,
        # whose lock a killed robot leaves behind)
        saved = os.environ.get("NUMBA_NUM_THREADS")
        os.environ["NUMBA_NUM_THREADS"] = "1"
        try:
            display.start()
        finally:
            if saved is None:
                os.environ.pop("NUMBA_NUM_THREADS", None)
            else:
                os.environ["NUMBA_NUM_THREADS"] = saved
        child_end.close()
        procs.append(display)
        for rid in range(params.robots):
            p = mp.Process(target=_robot_entry, name=f"swarmex-robot-{rid}",
                           args=(str(run_dir), rid, str(run_dir / f"robot-{rid}.log")))
            p.start()
            procs.append(p)
        deadline = time.monotonic() + options.timeout + 30
        try:
            _relay(lines, display, deadline, say)
        except KeyboardInterrupt:
            # Ctrl-C or SIGTERM: the display stops the robots and writes the record of what
            # was explored (as at a timeout); a second one leaves at once
            if display.pid is not None:
                with contextlib.suppress(ProcessLookupError):
                    os.kill(display.pid, signal.SIGTERM)
            # until the display's pipe ends: a group SIGTERM also ended the fork server, and
            # then is_alive() says False of a display still writing the record
            _relay(lines, None, time.monotonic() + max(3.0, 2 * options.dead_after) + 10,
                   say)
            display.join(5)
            raise
        display.join(max(1.0, deadline - time.monotonic()))
        path = json_path or record_path
        # written by this run (a --json file left by an earlier one is not this run's record)
        if not path.exists() or path.stat().st_mtime < started:
            # killed (SIGKILL, the OOM killer) or stuck: the robots' reports and the run's
            # state went with it, so there is nothing to save; the robots are killed below
            # at once instead of after their 10 s wait for the display's silence
            raise DisplayDied(
                "the display process was still running at the deadline"
                if display.exitcode is None else
                f"the display process ended (exit {display.exitcode}) without writing the"
                " record")
        for p in procs[1:]:
            p.join(10)
        import json

        return json.loads(path.read_text())
    finally:
        for p in procs:
            _kill(p)
        shutil.rmtree(run_dir, ignore_errors=True)


def _kill(proc: Any) -> None:
    """Kill a child that outlived the run, by its own pid. Asked directly, not through
    ``is_alive()``: once the fork server is gone (a SIGTERM to the group), that reports every
    child dead. A pid is killed only while it is still a fork-server child of this run's kind
    (its command line), never a process that reused the number."""
    if proc.is_alive():
        proc.kill()
        proc.join(5)
        return
    try:
        with open(f"/proc/{proc.pid}/cmdline", "rb") as f:
            mine = b"multiprocessing.forkserver" in f.read()
    except OSError:
        return
    if mine:
        with contextlib.suppress(ProcessLookupError):
            os.kill(proc.pid, signal.SIGKILL)


def _relay(lines: Any, display: Any, deadline: float, say: Callable[[str], object]) -> None:
    """Say the display's lines until it ends (or ``deadline``); ``display`` None: until its
    pipe ends, whatever ``is_alive()`` says."""
    while time.monotonic() < deadline:
        if lines.poll(0.5):
            try:
                line = lines.recv()
            except EOFError:
                return
            if line is None:
                return
            say(str(line))
        elif display is not None and not display.is_alive():
            return


def main(argv: list[str] | None = None) -> int:
    """``python -m swarmex.net.mesh robot RUN_DIR ID`` / ``display RUN_DIR [--monitor URL]``."""
    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) >= 2 and args[0] == "robot":
        import numba

        # (numba's config sets its attributes from the environment: invisible to mypy)
        if numba.config.NUMBA_NUM_THREADS > 1:  # type: ignore[attr-defined]
            numba.set_num_threads(1)  # one robot, one computer
        robot = RobotProcess(Path(args[1]), int(args[2]))
        try:
            return robot.run()
        finally:
            robot.close()
    if len(args) >= 2 and args[0] == "display":
        url = args[args.index("--monitor") + 1] if "--monitor" in args else None
        display = DisplayProcess(Path(args[1]), monitor_url=url)
        try:
            return display.run(lambda s: print(s, flush=True))
        finally:
            display.close()
            display.view.close(1000)
    print("usage: python -m swarmex.net.mesh robot RUN_DIR ID | display RUN_DIR", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main())
