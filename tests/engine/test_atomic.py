"""The atomic writer: whole files or none, and the mode a plain open() would give."""

from __future__ import annotations

import json
import os
import re
import stat
from pathlib import Path

import pytest

from swarmex.engine.atomic import atomic_open, atomic_path, write_atomic
from swarmex.engine.record import ResultRecord, write_record
from swarmex.errors import InputError


def _mode(path: Path) -> int:
    return stat.S_IMODE(path.stat().st_mode)


@pytest.fixture(params=[0o022, 0o027, 0o002])
def umask(request):
    old = os.umask(request.param)
    try:
        yield request.param
    finally:
        os.umask(old)


def _record() -> ResultRecord:
    return ResultRecord("foraging", "strips", {"grid": 8}, 0, {"kind": "grid"}, True, 1.0,
                        "step", {}, [])


def test_record_gets_the_mode_of_a_plain_open(tmp_path, umask):
    """``--json`` records used to be 0600 whatever the umask (mkstemp's mode survived the
    rename) while PNGs beside them were 0644."""
    plain_file = tmp_path / "plain.txt"
    plain_file.write_text("x")
    rec = write_record(_record(), tmp_path / "run.json")
    assert _mode(rec) == 0o666 & ~umask == _mode(plain_file)
    assert json.loads(rec.read_text())["mission"] == "foraging"


def test_every_entry_point_gets_the_same_mode(tmp_path, umask):
    want = 0o666 & ~umask
    assert _mode(write_atomic(tmp_path / "a.txt", "text")) == want
    assert _mode(write_atomic(tmp_path / "b.bin", b"\x00\x01")) == want
    with atomic_open(tmp_path / "c.json") as fh:
        json.dump({"a": 1}, fh)
    assert _mode(tmp_path / "c.json") == want
    with atomic_path(tmp_path / "d.bin") as tmp:
        tmp.write_bytes(b"data")
    assert _mode(tmp_path / "d.bin") == want
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b.bin", "c.json", "d.bin"]


def test_replaces_whole_and_creates_directories(tmp_path):
    path = tmp_path / "deep" / "er" / "out.txt"
    write_atomic(path, "first version, longer")
    write_atomic(path, "second", fsync=True)
    assert path.read_text() == "second"


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    path = tmp_path / "out.json"
    write_atomic(path, "old")
    with pytest.raises(RuntimeError), atomic_open(path) as fh:
        fh.write("half of the new")
        raise RuntimeError("killed mid-write")
    with pytest.raises(RuntimeError), atomic_path(path) as tmp:
        tmp.write_text("half")
        raise RuntimeError("killed mid-write")
    assert path.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.json"]


@pytest.mark.parametrize("errno_", [28, 27])  # ENOSPC (disk full), EFBIG (file-size limit)
def test_a_disk_that_fills_half_way_is_one_line_and_keeps_the_old_file(tmp_path, errno_):
    path = tmp_path / "out.json"
    write_atomic(path, "old")
    said = f"cannot write {re.escape(str(path))}: .*previous file.* unchanged"
    with pytest.raises(InputError, match=said), atomic_open(path) as fh:
        fh.write("half")
        raise OSError(errno_, os.strerror(errno_))
    with pytest.raises(InputError, match="cannot write"), atomic_path(path):
        raise OSError(errno_, os.strerror(errno_))
    assert path.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.json"]
    with pytest.raises(FileNotFoundError), atomic_open(path):  # not a write failure: as is
        raise FileNotFoundError(2, "No such file or directory")


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full on this system")
def test_the_cli_says_a_full_disk_in_one_line(capsys):
    from swarmex.cli import main

    assert main(["traverse", "--grid", "4x4", "--agents", "2", "--json", "/dev/full"]) == 2
    err = capsys.readouterr().err
    assert err == "swarmex: error: cannot write /dev/full: No space left on device\n"


def test_unwritable_place_is_an_input_error(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    with pytest.raises(InputError, match="cannot write"):
        write_record(_record(), blocker / "run.json")


def test_cli_json_record_and_png_share_a_mode(tmp_path):
    """The bug as a user met it: ``--json`` gave 0600 beside a 0644 ``--render`` PNG."""
    from swarmex.cli import main

    old = os.umask(0o022)
    try:
        argv = ["forage", "--grid", "16", "--agents", "4", "--algorithm", "strips",
                "--food-units", "2", "--seed", "1"]
        js, png = tmp_path / "run.json", tmp_path / "run.png"
        assert main([*argv, "--json", str(js), "--render", str(png)]) == 0
    finally:
        os.umask(old)
    assert _mode(js) == _mode(png) == 0o644


def test_a_folder_or_a_file_in_the_way_is_named(tmp_path):
    """``record.write("runs")`` with ``runs`` a folder raised IsADirectoryError (a
    traceback, after the whole write); a path below a file said only "File exists"."""
    import swarmex

    rec = swarmex.run("traversal", grid="3x3", agents=1, seed=0)
    (tmp_path / "runs").mkdir()
    with pytest.raises(InputError, match="runs: it is a folder"):
        rec.write(tmp_path / "runs")
    assert list((tmp_path / "runs").iterdir()) == [] and len(list(tmp_path.iterdir())) == 1
    (tmp_path / "f.json").write_text("{}", encoding="utf-8")
    with pytest.raises(InputError, match=r"f\.json is a file, not a folder"):
        rec.write(tmp_path / "f.json" / "sub" / "r.json")


def test_what_is_at_the_path_is_respected(tmp_path):
    """As root, ``--json /dev/null`` renamed a plain file over the device; a link became a
    plain file (its target untouched); a 0600 record came back 0644."""
    # a FIFO stands for /dev/null: written in place, still a FIFO afterwards
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    r = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        write_atomic(fifo, "through the pipe")
        assert os.read(r, 100) == b"through the pipe"
        with atomic_path(fifo) as same:
            assert same == fifo
    finally:
        os.close(r)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    # a link stays a link and its target gets the new content
    target, link = tmp_path / "real.json", tmp_path / "link.json"
    target.write_text("old")
    link.symlink_to(target)
    write_atomic(link, "new")
    assert link.is_symlink() and target.read_text() == "new"
    with atomic_path(link) as tmp:
        tmp.write_text("newer")
    assert link.is_symlink() and target.read_text() == "newer"
    # a private file stays private
    secret = tmp_path / "private.json"
    secret.write_text("{}")
    secret.chmod(0o600)
    with atomic_open(secret) as fh:
        fh.write("{}")
    assert _mode(secret) == 0o600


def test_the_cli_writes_a_record_into_a_special_file_without_replacing_it(tmp_path):
    """``--json /dev/null`` as a user types it; a FIFO stands in for the device, so that a
    regression cannot break the machine's /dev/null."""
    from swarmex.cli import main

    fifo = tmp_path / "null"
    os.mkfifo(fifo)
    r = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        assert main(["traverse", "--grid", "3x3", "--agents", "1", "--json", str(fifo)]) == 0
        assert json.loads(os.read(r, 1 << 16))["mission"] == "traversal"
    finally:
        os.close(r)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
