"""``acoustiviz run``: every output a scene file asks for, into one folder."""

from __future__ import annotations

from ..app.settings.run import RUN_OPTIONS
from ..app.settings.table import add_option


def add_parser(subparsers) -> None:
    """Register the ``run`` subcommand."""
    p = subparsers.add_parser(
        "run",
        help="produce every output a scene file asks for (default: the built-in scene)",
        description="Run a scene (TOML). Without SCENE, the built-in default scene: the paper's Table 1 "
        "damper striking a reflecting plane, listener at 0.7 m and 45 deg, with a small set of every "
        "kind of output. Writes DIR/summary.md listing each file and its key figures.",
    )
    for s in RUN_OPTIONS:
        add_option(p, s)
    p.set_defaults(func=run)


def run(args) -> int:
    """Load (or take the default) scene, validate it and the output folder, then run it."""
    import sys

    from .._validate import ParameterError
    from ..scene import default_scene, load_scene, schema_help

    if args.help_scene:
        print(schema_help())
        return 0
    if args.out is None:
        raise ParameterError("--out", "give an output folder, e.g. --out acoustiviz-out")
    from ..app.outputs import check_input_file, check_output_dir

    # --max-memory (checked by the command line) bounds the scene's work with grids.memory_limit_mb
    check_output_dir("--out", args.out)
    if args.scene is not None:
        check_input_file("SCENE", args.scene, "scene file")
    scene = load_scene(args.scene) if args.scene else default_scene()
    from ..app.pipeline import incomplete, run_scene

    def progress(msg):
        if not args.quiet:
            print(msg, file=sys.stderr, flush=True)

    products = run_scene(scene, args.out, force=args.replace, progress=progress,
                         stream=None if args.quiet else sys.stderr)
    for p in products:
        figs = ", ".join(f"{k}={v}" for k, v in p.figures.items())
        print(f"{p.path}" + (f"  ({figs})" if figs else ""))
    failures = incomplete(products)
    for line in failures:
        print(f"warning: incomplete: {line}", file=sys.stderr)
    return 1 if failures else 0
