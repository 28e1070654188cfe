"""Write an animation — a list of RGB frames — to ``.gif`` or ``.mp4``, chosen by the suffix.

Every mission's ``--render`` goes through here so the formats behave the same everywhere:
the same suffix check and message, the same frame timing (the last frame is held so the final
state can be read), the same even-size padding for H.264, and the same one-line
:class:`~swarmex.errors.InputError` when the file cannot be written or the MP4 encoder is
missing. The missions only draw frames; they never talk to imageio or Pillow themselves.

GIFs are written with Pillow through imageio (adaptive palette per frame, which is fine for
the few flat colours of these drawings). The traversal animation keeps its own palette-GIF
writer because it shares one precomputed palette across hundreds of big frames for speed.
"""

from __future__ import annotations

import errno
import os
import secrets
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from swarmex.engine.atomic import write_atomic
from swarmex.errors import InputError, require

ANIMATION_SUFFIXES = (".gif", ".mp4")
RENDER_SUFFIXES = (".png", *ANIMATION_SUFFIXES)
HOLD_SECONDS = 2.0  # the final state stays on screen this long before the loop restarts


def check_suffix(
    path: Path, suffixes: Sequence[str] = RENDER_SUFFIXES, option: str = "--render"
) -> str:
    """The lower-case suffix of ``path``, or an InputError naming the allowed ones (and
    ``option``, what the caller called the path).

    Called before a run starts so a typo in ``--render`` costs nothing.
    """
    suffix = path.suffix.lower()
    if suffix not in suffixes:
        allowed = " or ".join(
            [", ".join(suffixes[:-1]), suffixes[-1]] if suffixes[:-1] else suffixes
        )
        raise InputError(f"{option} must end in {allowed}, got {path.name!r}")
    return suffix


def require_writer(path: Path) -> None:
    """Fail in one line naming the extra when writing ``path`` needs a missing one (.mp4:
    ``swarmex[video]``'s ffmpeg binary).

    Why a function of its own: the CLI calls it with its other output checks, before the
    run; checked only when writing, an MP4 asked for without the extra cost the whole run
    and then ended with exit 2 and no file."""
    if path.suffix.lower() == ".mp4":
        require("imageio_ffmpeg", "video", "an .mp4 animation")


def write_animation(path: str | Path, frames: Sequence[np.ndarray], fps: float) -> Path:
    """Write RGB uint8 ``frames`` (all the same shape) as a GIF or an MP4 by ``path``'s suffix.

    ``fps`` is the playback rate of the frames; the last one is then held for
    :data:`HOLD_SECONDS` in both formats.
    """
    path = Path(path)
    suffix = check_suffix(path, ANIMATION_SUFFIXES)
    if not frames:
        raise ValueError("an animation needs at least one frame")
    fps = max(float(fps), 0.5)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        if suffix == ".mp4":
            _write_mp4(path, frames, fps)
        else:
            _write_gif(path, frames, fps)
    except OSError as exc:  # imageio's ffmpeg error appends the command and its log
        reason = exc.strerror or str(exc).strip().splitlines()[0]
        raise InputError(f"cannot write {path}: {reason}") from None
    return path


def _write_gif(path: Path, frames: Sequence[np.ndarray], fps: float) -> None:
    import imageio.v2 as iio

    step = max(20, int(round(1000.0 / fps)))  # ms; browsers clamp shorter delays anyway
    durations = [step] * (len(frames) - 1) + [int(1000 * HOLD_SECONDS)]
    # encoded in memory, then written in one go: when imageio's writer fails to open the
    # file it retries from its finaliser, which printed a second traceback after our message
    data = iio.mimwrite("<bytes>", list(frames), format="GIF", duration=durations, loop=0)
    write_atomic(path, data)


def _write_mp4(path: Path, frames: Sequence[np.ndarray], fps: float) -> None:
    """RGB frames → H.264 MP4 with imageio's ffmpeg plugin (imageio-ffmpeg ships the binary).

    The last frame is held for :data:`HOLD_SECONDS` like the GIF's. Frames are padded with
    white to even sizes, which yuv420p requires (instead of imageio's default resize to
    multiples of 16, which would blur grids drawn one pixel per cell).
    """
    require_writer(path)  # the plugin's binary
    import imageio.v2 as iio

    h, w = frames[0].shape[:2]
    pad = ((0, h % 2), (0, w % 2), (0, 0))
    hold = [frames[-1]] * int(round(HOLD_SECONDS * fps))
    # ffmpeg picks the container by the suffix, so the temporary file keeps ".mp4"; it is
    # renamed over ``path`` only if ffmpeg wrote it (a short video whose output ffmpeg could
    # not open used to return as if written, leaving no file)
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.{secrets.token_hex(4)}{path.suffix}")
    try:
        _encode_mp4(iio, tmp, [*frames, *hold], pad, fps)
        if not tmp.is_file():
            raise OSError(errno.EIO, "the video encoder wrote no file")
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def _encode_mp4(iio: Any, path: Path, frames: list[np.ndarray],
                pad: tuple[tuple[int, int], ...], fps: float) -> None:
    writer = iio.get_writer(
        path,
        format="FFMPEG",
        mode="I",
        fps=fps,
        codec="libx264",
        pixelformat="yuv420p",
        macro_block_size=1,
        ffmpeg_log_level="error",
    )
    with writer:
        for f in frames:
            f = np.ascontiguousarray(f[..., :3], dtype=np.uint8)
            writer.append_data(np.pad(f, pad, constant_values=255) if any(pad[0] + pad[1]) else f)
