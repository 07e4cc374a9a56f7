"""The scene and solve options of the command line, generated from the one declaration
(``physics.options``): shared by ``solve`` and the subcommands that take a scene (``onset``)."""
from __future__ import annotations

from ..physics.options import OPTIONS, check_applies, check_needs

__all__ = ["add_scene_options", "add_solve_options", "scene_args", "scene_from_args"]


def add_scene_options(p, command: str | None = None):
    """The scene options of ``command`` (``solve``; None: a subcommand that takes the scene's
    common options, ``onset``), from the one declaration (``physics.options``): each left None
    when not given, so that an option the indenter does not take is refused and the scene's
    own defaults apply."""
    for o in OPTIONS:
        if (o.cli is True or (o.cli and o.cli == command)) and o.scenes != "solve":
            p.add_argument(o.flag, dest=o.name, type=o.cli_type, choices=o.choices, default=None,
                           metavar=o.symbol, help=o.cli_help())


def add_solve_options(p):
    """``solve``'s model, method, tol, grid points and period (``physics.options``; the model
    and method names from the solvers' registry)."""
    from ..api import METHODS, MODELS

    choices = {"model": MODELS, "method": tuple(METHODS)}
    for o in OPTIONS:
        if o.scenes == "solve":
            p.add_argument(o.flag, dest=o.name, type=o.kind, choices=choices.get(o.name),
                           default=o.default, help=o.cli_help())


def scene_args(args) -> dict:
    """The scene options the user gave (``physics.options``), refused where the indenter does not
    take them (one line naming the option as typed)."""
    given = {o.name: getattr(args, o.name) for o in OPTIONS
             if o.cli and o.scenes != "solve" and getattr(args, o.name, None) is not None}
    check_needs(given)
    check_applies(given, given.get("indenter", "line"))
    return given


def scene_from_args(args):
    """The scene of the scene options (``Scene`` for the line indenter, else ``Scene3D``): the
    options the user gave (``scene_args``), the scene's defaults for the others."""
    from ..physics.scene import Scene, Scene3D

    given = scene_args(args)
    indenter = given.pop("indenter", "line")
    return Scene(**given) if indenter == "line" else Scene3D(indenter=indenter, **given)
