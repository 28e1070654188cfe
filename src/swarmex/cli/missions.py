"""Mission commands generated from each mission's Params (issue 12).

Every option of ``swarmex traverse | forage | explore | roadmap`` is read off the mission's
Params declarations: flag, help, default, type. The command body only checks the output
paths, builds the Params (the mission's own parsers and checks), runs the mission through the
contract, and hands the outcome to the mission's printer and renderer. So the command line,
``swarmex.run``, scenario files and sweeps cannot drift apart: there is one list of options.

Typer reads a command's options from its function signature; the signature here is built
from the Params (``inspect.Signature``), which Typer honours like a hand-written one.
"""

from __future__ import annotations

import contextlib
import inspect
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, cast

import typer

from swarmex.cli.app import app, console, err_console, interrupted
from swarmex.cli.compiling import compile_notice
from swarmex.cli.outputs import RENDER_SUFFIXES, check_distinct, check_output
from swarmex.errors import InputError
from swarmex.missions.base import FrameCallback, Mission, OptionInfo, Outcome
from swarmex.viz.animation import require_writer


@dataclass(frozen=True)
class Extra:
    """A command-line-only option (not a mission parameter), e.g. ``--processes``."""

    name: str
    default: Any
    help: str
    annotation: Any
    flag: str | None = None  # default: --name-with-dashes


@dataclass
class Surface:
    """How the CLI shows one mission: its summary printer and renderer."""

    report: Callable[[Outcome, Any], None]
    # --render draws the run (swarmex.viz.render: the frames it keeps, the drawing)
    drawn: bool = True
    extras: Sequence[Extra] = ()
    # runs instead of the simulator when an extra asks for it (e.g. explore --processes)
    alternative: Callable[[Mission[Any, Any], Any, dict[str, Any], Path | None], bool] | None = (
        None
    )
    json_flag: str = "--json"
    render_help: str = "Draw the run (.png) or animate it (.gif, .mp4)."
    # (params, prepared world) -> whether this one-shot run is so small that its kernels
    # cost less interpreted than loading numba (swarmex._kernels.interpreted_while_cold)
    interpreted: Callable[[Any, Any], bool] | None = None
    # (params, prepared world, on_frame) -> the frame callback to run with instead, e.g. one
    # that also shows how far a long run is on a terminal; it may have ``close()``
    watch: Callable[[Any, Any, FrameCallback | None], FrameCallback | None] | None = None


Watch = Callable[[Any, Any, FrameCallback | None], FrameCallback | None]


def progress_bar(mission: Mission[Any, Any]) -> Watch:
    """A :attr:`Surface.watch` that shows a :class:`~swarmex.experiments.progress.
    FrameProgress` bar on a terminal, counting what ``mission.progress`` says (None: no
    bar)."""

    def watch(params: Any, world: Any, on_frame: FrameCallback | None) -> FrameCallback | None:
        from swarmex.experiments.progress import frame_progress

        return cast(FrameCallback | None,
                    frame_progress(mission, params, world, err_console, on_frame))

    return watch


def _annotation(info: OptionInfo) -> Any:
    kind = info.kind
    if kind is bool:
        return bool
    if info.default is None or info.required:
        return kind | None
    return kind


def plain_help(text: str) -> str:
    """``text`` as ``--help`` should print it. Typer renders option help as Rich markup
    when Rich is installed, so a literal ``[[agents]]`` (TOML's array of tables) came out as
    ``[]``: the Params' help is plain text, and the brackets are escaped here."""
    from typer.core import DEFAULT_MARKUP_MODE

    if DEFAULT_MARKUP_MODE != "rich":
        return text
    from rich.markup import escape

    return escape(text)


def _typer_option(info: OptionInfo) -> Any:
    flags = [info.flag if info.negation is None else f"{info.flag}/{info.negation}"]
    default: Any
    text = plain_help(info.help)
    if info.required:
        # checked by the Params, not by Typer: Typer names one missing option per try,
        # the Params every missing one in one line
        default, text = None, f"{text} (required)"
    elif isinstance(info.default, int | float | bool | str):
        default = info.default
    else:
        default = None  # tuples, paths, None: the Params default applies
    kw: dict[str, Any] = {"help": text, "show_default": default is not None}
    if info.metavar:
        kw["metavar"] = info.metavar
    return typer.Option(default, *flags, **kw)


COMMANDS: dict[str, Callable[..., Any]] = {}  # mission name -> its generated command
#: each mission command's command-line-only options (``explore``: processes, time_scale, …),
#: which a scenario file may set too
EXTRAS: dict[str, tuple[Extra, ...]] = {}


@contextlib.contextmanager
def interrupted_says_so() -> Iterator[None]:
    """Ctrl-C during a run: one line and status 130 (Typer turns a bare KeyboardInterrupt
    into a silent 130, so the user could not tell an interrupted run from a crash)."""
    try:
        yield
    except KeyboardInterrupt:
        interrupted("nothing written")


#: mission name -> its command's Surface, for the commands that run a mission from a record
#: (``swarmex rerun``, ``swarmex render``): the same small run keeps its kernels interpreted
#: there as it did when it was made, and a long one shows the same progress
SURFACES: dict[str, Surface] = {}


def mission_command(mission: Mission[Any, Any], surface: Surface) -> Callable[..., Any]:
    """Register ``swarmex <mission.command>`` on the app and return its function."""
    options = mission.params_type.options()
    SURFACES[mission.name] = surface
    extras = {e.name: e for e in surface.extras}

    def command(**kwargs: Any) -> Any:
        json_path: Path | None = kwargs.pop("json_path")
        render: Path | None = kwargs.pop("render")
        drawn = surface.drawn and render is not None
        if drawn:
            from swarmex.viz.render import draw, frame_recorder
        extra_values = {name: kwargs.pop(name) for name in extras}
        check_output(json_path, surface.json_flag)
        check_output(render, "--render", RENDER_SUFFIXES)
        check_distinct((json_path, surface.json_flag), (render, "--render"))
        if render is not None:
            require_writer(render)  # a missing extra costs one line now, not the run
        params = mission.params({k: v for k, v in kwargs.items() if v is not None})
        for name, why in params.ignored().items():
            err_console.print(f"note: {options[name].flag} is ignored: {why}",
                              markup=False, highlight=False, soft_wrap=True)
        if surface.alternative is not None:
            with interrupted_says_so():
                if surface.alternative(
                    mission, params, {**extra_values, "render": render}, json_path
                ):
                    return None
        with compile_notice(err_console), interrupted_says_so():
            recorder = frame_recorder(mission.name, str(render)) if drawn else None
            # the watch wraps the recorder; the render below reads the recorder itself
            outcome = mission.run(params, recorder, interpreted=surface.interpreted,
                                  watch=surface.watch)
        surface.report(outcome, params)
        if json_path is not None:
            from swarmex.engine.record import write_record

            write_record(outcome.record, json_path)
            console.print(f"wrote {json_path}")
        if drawn:
            draw(mission.name, outcome, str(render), recorder)
            console.print(f"wrote {render}")
        return None

    sig: list[inspect.Parameter] = []
    for info in options.values():
        sig.append(
            inspect.Parameter(
                info.name,
                inspect.Parameter.KEYWORD_ONLY,
                default=_typer_option(info),
                annotation=_annotation(info),
            )
        )
    for e in surface.extras:
        sig.append(
            inspect.Parameter(
                e.name,
                inspect.Parameter.KEYWORD_ONLY,
                default=typer.Option(
                    e.default, e.flag or "--" + e.name.replace("_", "-"),
                    help=plain_help(e.help),
                ),
                annotation=e.annotation,
            )
        )
    for name, flag, helptext in (
        ("json_path", surface.json_flag, "Write the result record here."),
        ("render", "--render", surface.render_help),
    ):
        sig.append(
            inspect.Parameter(
                name,
                inspect.Parameter.KEYWORD_ONLY,
                default=typer.Option(None, flag, help=helptext, show_default=False),
                annotation=Path | None,
            )
        )
    command.__signature__ = inspect.Signature(sig)  # type: ignore[attr-defined]
    command.__doc__ = mission.summary
    command.__name__ = mission.command
    app.command(name=mission.command, help=mission.summary)(command)
    COMMANDS[mission.name] = command
    EXTRAS[mission.name] = tuple(surface.extras)
    return command


def invoke(mission: str, values: dict[str, Any], overrides: Sequence[str] = ()) -> Any:
    """Run mission ``mission``'s command with ``values`` (Python values, e.g. from a
    scenario file; ``json``/``render`` as paths) and then the command-line ``overrides``
    (``["--seed", "3"]``), which win. Values go to the mission's own parsers unchanged, so a
    file's ``grid = [6, 5]`` means what ``grid=(6, 5)`` means in Python."""
    command = COMMANDS[mission]
    sig = inspect.signature(command)
    kwargs: dict[str, Any] = {}
    for name, param in sig.parameters.items():
        default = getattr(param.default, "default", None)
        kwargs[name] = None if default is ... else default
    by_flag: dict[str, tuple[str, Any]] = {}
    for name, param in sig.parameters.items():
        decls = getattr(param.default, "param_decls", None) or ()
        for decl in decls:
            for i, flag in enumerate(decl.split("/")):
                by_flag[flag] = (name, param.annotation if i == 0 else "negation")
    for key, given in values.items():
        name = {"json": "json_path"}.get(key, key)
        if name not in kwargs:
            raise InputError(f"swarmex {command.__name__} has no option --{key}")
        kwargs[name] = given
    args = list(overrides)
    while args:
        flag = args.pop(0)
        value: Any
        flag, _, inline = flag.partition("=")
        if flag not in by_flag:
            raise InputError(f"swarmex {command.__name__} has no option {flag}")
        name, kind = by_flag[flag]
        if kind == "negation":
            value = False
        elif kind is bool:
            value = True
        else:
            if not inline and not args:
                raise InputError(f"{flag} needs a value")
            value = inline or args.pop(0)
            if kind in (Path, Path | None):
                value = Path(value)
            elif kind in (float, float | None, int, int | None) and name not in values:
                value = _number(value, flag, int if kind in (int, int | None) else float)
        kwargs[name] = value
    return command(**kwargs)


def _number(text: str, flag: str, kind: type) -> Any:
    try:
        return kind(text)
    except ValueError:
        what = "an integer" if kind is int else "a number"
        raise InputError(f"{flag}: expected {what}, got {text!r}") from None


__all__ = ["Extra", "Surface", "mission_command", "progress_bar"]
