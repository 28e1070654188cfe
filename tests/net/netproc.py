"""Subprocess helpers for the networked end-to-end tests: start, read, bound, and always kill.

Every process is started through :class:`Procs`, whose ``close()`` (called in the tests'
``finally``) kills whatever is still running, by its own pid only. Output lines are read on
threads so a test can wait for a line (the server prints the endpoint it bound to: tests use
``--port 0`` and read the port back, so parallel runs never collide on a port).
"""

from __future__ import annotations

import contextlib
import os
import queue
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


class Proc:
    def __init__(self, name: str, argv: list[str]) -> None:
        self.name = name
        env = dict(os.environ, PYTHONUNBUFFERED="1", COLUMNS="200")
        self.popen = subprocess.Popen(
            [sys.executable, "-m", "swarmex", *argv],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            cwd=REPO,
            env=env,
        )
        self.lines: list[str] = []
        self._q: queue.Queue[str] = queue.Queue()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.popen.stdout is not None
        for line in self.popen.stdout:
            self.lines.append(line.rstrip("\n"))
            self._q.put(line)

    def wait_line(self, pattern: str, timeout: float) -> re.Match:
        """The first output line matching ``pattern`` (earlier lines included)."""
        rx = re.compile(pattern)
        deadline = time.monotonic() + timeout
        seen = 0
        while True:
            for line in self.lines[seen:]:
                m = rx.search(line)
                if m:
                    return m
            seen = len(self.lines)
            left = deadline - time.monotonic()
            if left <= 0 or (self.popen.poll() is not None and self._q.empty()
                             and seen == len(self.lines) and not self._reader.is_alive()):
                raise AssertionError(
                    f"{self.name}: no line matching {pattern!r} within {timeout} s;"
                    f" output:\n" + "\n".join(self.lines[-40:])
                )
            with contextlib.suppress(queue.Empty):
                self._q.get(timeout=min(0.1, max(left, 0.01)))

    def wait(self, timeout: float) -> int:
        try:
            code = self.popen.wait(timeout)
        except subprocess.TimeoutExpired:
            raise AssertionError(
                f"{self.name} still running after {timeout} s; output:\n"
                + "\n".join(self.lines[-40:])
            ) from None
        self._reader.join(2)
        return code

    def kill(self) -> None:
        if self.popen.poll() is None:
            self.popen.send_signal(signal.SIGKILL)
            self.popen.wait(5)

    @property
    def output(self) -> str:
        return "\n".join(self.lines)


class Procs:
    """The processes of one test; ``close()`` kills the survivors."""

    def __init__(self) -> None:
        self.procs: list[Proc] = []

    def start(self, name: str, *argv: object) -> Proc:
        p = Proc(name, [str(a) for a in argv])
        self.procs.append(p)
        return p

    def close(self) -> None:
        for p in self.procs:
            p.kill()

    def __enter__(self) -> Procs:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def endpoint(server: Proc, timeout: float = 30.0) -> str:
    return server.wait_line(r"listening on (tcp://127\.0\.0\.1:\d+)", timeout)[1]
