"""The folder tree is the architecture: imports point down the layers, the physics writes no files.

Layers, lowest first (a module may import its own layer and those below it, never above):

    foundation  errors, constants, _validate, _jit, files (atomic file writing)
    core        medium, materials, contact, radiation, images, approximations
    dynamics    the impact damper and its solvers
    field       the field evaluator, its kernels and grids
    levels      weighted levels, spectra, loudness, radiated energy
    sound       sound synthesis: impact trains rendered as calibrated pressure signals
    output      tables, plots, renders, WAV files (sinks only)
    sweep       design sweeps and the design table
    app         the application layer that both front-ends call
    scene       scene files: schema, validation, loading (a front-end)
    cli         the command line
"""

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

import acoustiviz

PKG = Path(acoustiviz.__file__).parent
LAYERS = [
    {"errors", "constants", "_validate", "_jit", "files"},
    {"core"},
    {"dynamics"},
    {"field"},
    {"levels"},
    {"sound"},
    {"output"},
    {"sweep"},
    {"app"},
    {"scene"},
    {"cli"},
]
RANK = {name: i for i, group in enumerate(LAYERS) for name in group}
#: Layers that compute physics: they never write files (the output layer does).
PHYSICS = {"core", "dynamics", "field", "levels", "sound"}
#: Layers that never import the output layer (its sinks come after the physics and the sweep's rows).
BELOW_OUTPUT = PHYSICS | {"sweep"}
#: Foundation modules that write files: a physics module never imports them (the sweep's journal does).
FILE_WRITERS = {"files"}
MAX_LINES = 600


def _modules():
    for path in sorted(PKG.rglob("*.py")):
        rel = path.relative_to(PKG)
        if rel.parts[0] == "assets":
            continue
        yield path, rel


def _top(rel: Path) -> str:
    return rel.parts[0].removesuffix(".py")


def _imports(path: Path):
    """Top-level acoustiviz subpackage names imported by ``path`` (relative and absolute imports)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    base = path.relative_to(PKG).parent.parts
    mods = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                up = base[: len(base) - (node.level - 1)]
                target = (*up, *(node.module.split(".") if node.module else ()))
                if not target:  # "from . import x" at the package root
                    target = tuple(a.name for a in node.names)
                    mods += list(target)
                    continue
                mods.append(target[0])
            elif node.module and node.module.split(".")[0] == "acoustiviz":
                parts = node.module.split(".")
                mods += [parts[1]] if len(parts) > 1 else [a.name for a in node.names]
        elif isinstance(node, ast.Import):
            mods += [a.name.split(".")[1] for a in node.names if a.name.startswith("acoustiviz.")]
    return mods


def _module_name(path: Path) -> str:
    parts = path.relative_to(PKG.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _module_graph() -> dict:
    """Every module of the package -> the package modules it imports (at the top or in a function).

    ``from X import name`` depends on ``X.name`` when that is a module, else on ``X`` (the package's
    ``__init__`` or the module itself).
    """
    paths = {_module_name(path): path for path, _ in _modules()}
    graph = {}
    for name, path in paths.items():
        pkg = name if path.name == "__init__.py" else name.rpartition(".")[0]
        deps = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = pkg.split(".")[: len(pkg.split(".")) - (node.level - 1)]
                    mod = ".".join([*base, *(node.module.split(".") if node.module else [])])
                else:
                    mod = node.module or ""
                deps |= {f"{mod}.{a.name}" if f"{mod}.{a.name}" in paths else mod for a in node.names}
            elif isinstance(node, ast.Import):
                deps |= {a.name for a in node.names}
        graph[name] = {d for d in deps if d in paths and d != name}
    return graph


def _cycles(graph: dict) -> list:
    """The strongly connected components of more than one module (Tarjan's algorithm, iterative)."""
    index, low, on, stack, found, counter = {}, {}, set(), [], [], [0]
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter[0]
        counter[0] += 1
        stack.append(root)
        on.add(root)
        while work:
            v, children = work[-1]
            w = next(children, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    found.append(sorted(comp))
    return found


#: Import cycles still being split elsewhere; an entry here is tolerated, not required.
KNOWN_CYCLES: list = []


def test_module_graph_is_acyclic():
    """No module imports, directly or through others, a module that imports it back."""
    cycles = [c for c in _cycles(_module_graph()) if c not in KNOWN_CYCLES]
    assert not cycles, "import cycles:\n" + "\n".join(" <-> ".join(c) for c in cycles)


def test_cycle_finder_finds_cycles():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a", "e"}, "e": {"d"}, "f": set()}
    assert sorted(_cycles(graph)) == [["a", "b", "c"], ["d", "e"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_every_module_belongs_to_a_layer():
    tops = {_top(rel) for _, rel in _modules() if rel.name != "__init__.py" or len(rel.parts) > 1}
    tops |= {_top(rel) for _, rel in _modules() if len(rel.parts) > 1}
    tops -= {"__init__", "__main__"}
    assert tops <= set(RANK), f"modules outside any layer: {sorted(tops - set(RANK))}"


@pytest.mark.slow
def test_imports_point_down_the_layers():
    bad = []
    for path, rel in _modules():
        top = _top(rel)
        if top not in RANK:
            continue  # reported by test_every_module_belongs_to_a_layer
        for mod in _imports(path):
            if mod in RANK and RANK[mod] > RANK[top]:
                bad.append(f"{rel} imports {mod}")
    assert not bad, "\n".join(bad)


def test_physics_and_sweeps_never_import_output():
    """Nothing under core, dynamics, field, levels, sound or sweep imports ``acoustiviz.output``: files are sinks."""
    bad = [f"{rel} imports output" for path, rel in _modules() if _top(rel) in BELOW_OUTPUT
           and "output" in _imports(path)]
    assert not bad, "physics and sweeps must not import the output layer:\n" + "\n".join(bad)


#: Packages whose functions evaluate pressures or levels, as dotted paths inside acoustiviz.
EVALUATORS = ("field", "levels", "core.radiation")
#: Functions of those packages the output layer may use: geometry that evaluates no pressure or level.
EVALUATOR_EXEMPT = {"fluid_box"}


def _evaluator_imports(tree, base: tuple) -> list:
    """``(line, what)`` for every evaluator a module of package ``base`` (e.g. ``("output", "render")``) imports.

    From :data:`EVALUATORS` a sink may import value types (capitalised names: ``SectionField``,
    ``BalloonData``, ``PlanarGrid``) and constants (``P_REF``), and the functions of
    :data:`EVALUATOR_EXEMPT`; any other name (a function such as ``section_field`` or
    ``sound_levels``, a submodule such as ``evaluate``, ``*``) or the package itself is reported.
    """
    def under(parts) -> bool:
        dotted = ".".join(parts)
        return any(dotted == e or dotted.startswith(e + ".") for e in EVALUATORS)

    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names
                      if a.name.split(".")[0] == "acoustiviz" and under(a.name.split(".")[1:])]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                target = (*base[: len(base) - (node.level - 1)], *(node.module.split(".") if node.module else ()))
            elif node.module and node.module.split(".")[0] == "acoustiviz":
                target = tuple(node.module.split(".")[1:])
            else:
                continue
            for a in node.names:
                value = a.name in EVALUATOR_EXEMPT or a.name[:1].isupper()
                if (under(target) and not value) or (not under(target) and under((*target, a.name))):
                    found.append((node.lineno, ".".join((*target, a.name))))
    return found


def test_output_imports_no_field_or_level_evaluator():
    """The output layer draws and writes values computed below it: no evaluator of field, levels or radiation."""
    bad = []
    for path, rel in _modules():
        if _top(rel) == "output":
            found = _evaluator_imports(ast.parse(path.read_text(encoding="utf-8")), rel.parent.parts)
            bad += [f"{rel}:{line} imports {what}" for line, what in found]
    assert not bad, "the output layer is sinks only; compute in the physics layer:\n" + "\n".join(bad)


def test_evaluator_import_finder_tells_value_types_from_evaluators():
    source = ("from ...field.sections import SectionField, section_field\n"   # 1: the evaluator
              "from ...field.grids import PlanarGrid, fluid_box\n"            # 2: a type and exempt geometry
              "from ...constants import P_REF\n"                              # 3: not a physics package
              "from ...field import evaluate\n"                               # 4: a submodule of evaluators
              "from ... import levels\n"                                      # 5: the package itself
              "def f():\n"
              "    from acoustiviz.levels.bands import BANDS, band_levels\n"  # 7: lazy, absolute
              "    import acoustiviz.core.radiation\n"                        # 8: a plain import
              "    from ...core.geometry import Geometry, geometry\n"         # 9: core, not radiation
              "    from ...core import radiation\n")                          # 10: the radiation module
    found = _evaluator_imports(ast.parse(source), ("output", "render"))
    assert sorted(found) == [(1, "field.sections.section_field"), (4, "field.evaluate"), (5, "levels"),
                             (7, "levels.bands.band_levels"), (8, "acoustiviz.core.radiation"),
                             (10, "core.radiation")]


def _public_definitions(path: Path) -> set:
    """Public names a module defines itself: top-level ``def``/``class`` and assigned names listed in ``__all__``.

    A name bound by an import (a re-export) is not a definition.
    """
    tree = ast.parse(path.read_text(encoding="utf-8"))
    exported, assigned, defined = set(), set(), set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            if not node.name.startswith("_"):
                defined.add(node.name)
            continue
        targets = node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(
            node, ast.AnnAssign) else []
        for target in targets:
            for name in ast.walk(target):
                if isinstance(name, ast.Name):
                    assigned.add(name.id)
                    if name.id == "__all__" and isinstance(node.value, (ast.List, ast.Tuple)):
                        exported |= {e.value for e in node.value.elts if isinstance(e, ast.Constant)}
    return defined | (exported & assigned)


#: The interface every ``acoustiviz <command>`` module implements: the same names by design.
SUBCOMMAND_INTERFACE = {"add_parser", "run", "settings_from_args"}

#: What every workflow's module ``app/JOB.py`` defines beside its settings ``app/settings/JOB.py`` (the layout
#: guide's "A workflow: settings, run, result, write"): its run function.
WORKFLOW_INTERFACE = {"run"}


def _is_workflow(rel: Path) -> bool:
    """True for ``app/JOB.py`` with settings of its own in ``app/settings/JOB.py``."""
    return len(rel.parts) == 2 and rel.parts[0] == "app" and (PKG / "app" / "settings" / rel.name).is_file()


def test_no_public_name_is_defined_twice():
    """Each public function, class or exported constant has one home; other modules import it from there."""
    homes: dict = {}
    for path, rel in _modules():
        for name in _public_definitions(path):
            if not (_top(rel) == "cli" and name in SUBCOMMAND_INTERFACE) \
                    and not (_is_workflow(rel) and name in WORKFLOW_INTERFACE):
                homes.setdefault(name, []).append(rel.as_posix())
    twice = {name: where for name, where in sorted(homes.items()) if len(where) > 1}
    assert not twice, "public names defined in more than one module:\n" + "\n".join(
        f"{name}: {', '.join(where)}" for name, where in twice.items())


def test_public_definition_finder_tells_definitions_from_re_exports(tmp_path):
    src = tmp_path / "mod.py"
    src.write_text("from x import A, B\nC = 1\n_D = 2\nE = 3\n__all__ = ['A', 'C']\n"
                   "def f():\n    pass\nclass G:\n    pass\ndef _h():\n    pass\n", encoding="utf-8")
    assert _public_definitions(src) == {"C", "f", "G"}


def _writes_files(tree) -> list:
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            f = node.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
            if name in {"write_text", "write_bytes", "savetxt", "savez", "save", "to_csv", "atomic_path",
                        "write_csv_atomic", "write_text_atomic", "write_bytes_atomic", "temporary_beside", "mkdir"}:
                found.append((node.lineno, name))
            if name == "open" and len(node.args) > 1 and isinstance(node.args[1], ast.Constant) \
                    and any(c in str(node.args[1].value) for c in "wax+"):
                found.append((node.lineno, "open"))
    return found


def test_physics_layers_write_no_files():
    """No physics module writes a file itself or imports the foundation's file writers."""
    bad = []
    for path, rel in _modules():
        if _top(rel) in PHYSICS:
            bad += [f"{rel}:{line} calls {name}" for line, name in _writes_files(ast.parse(path.read_text("utf-8")))]
            bad += [f"{rel} imports {mod}" for mod in _imports(path) if mod in FILE_WRITERS]
    assert not bad, "\n".join(bad)


def test_file_write_finder_sees_the_atomic_writers():
    """The calls and imports by which a physics module would write a file are all recognised."""
    calls = ["write_text_atomic(p, 't')", "write_bytes_atomic(p, b'')", "write_csv_atomic(p, [], [])",
             "files.atomic_path(p)", "temporary_beside(p)", "open(p, 'w')", "p.write_text('t')"]
    tree = ast.parse("\n".join(calls) + "\nopen(p)\nopen(p, 'rb')\n")
    assert [line for line, _ in _writes_files(tree)] == list(range(1, len(calls) + 1))
    # the sweep's journal is written through the foundation's writers: its import is seen
    assert FILE_WRITERS <= set(_imports(PKG / "sweep" / "store.py"))


def test_no_module_exceeds_the_size_limit():
    big = [f"{rel}: {n} lines" for path, rel in _modules()
           if (n := len(path.read_text(encoding="utf-8").splitlines())) > MAX_LINES]
    assert not big, "\n".join(big)


def test_no_private_scipy_imports():
    bad = [str(rel) for path, rel in _modules() if "scipy.integrate._ivp" in path.read_text(encoding="utf-8")]
    assert not bad, bad


def test_old_flat_module_paths_are_gone():
    """No import hook: ``acoustiviz.contact`` and the like are not importable (the real paths are)."""
    import importlib

    for old in ("contact", "images", "render", "plot", "pipeline"):
        with pytest.raises(ModuleNotFoundError):
            importlib.import_module(f"acoustiviz.{old}")
    assert importlib.import_module("acoustiviz.core.contact").__name__ == "acoustiviz.core.contact"
    assert not any(type(f).__module__.startswith("acoustiviz") for f in sys.meta_path)


def test_public_errors_carry_name_and_detail():
    from acoustiviz import ParameterError
    from acoustiviz.errors import ParameterError as Same

    assert ParameterError is Same
    err = ParameterError("radius", "must be > 0 m, got -1 m")
    assert (err.name, err.detail, str(err)) == ("radius", "must be > 0 m, got -1 m", "radius: must be > 0 m, got -1 m")
    import pickle

    back = pickle.loads(pickle.dumps(err))
    assert (back.name, back.detail) == (err.name, err.detail)


def test_import_is_light_and_side_effect_free():
    code = ("import sys, acoustiviz; heavy = [m for m in ('matplotlib', 'pyvista', 'soundfile', 'numba', "
            "'dask') if m in sys.modules]; print(heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def _geometry_name_comparisons(path: Path) -> list[str]:
    """``x == "room"``, ``x in ("free", "plane")`` and the like in one module: a registry name compared."""
    from acoustiviz.core.geometry import GEOMETRIES

    names = set(GEOMETRIES)
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if not isinstance(node, ast.Compare):
            continue
        consts = []
        for operand in (node.left, *node.comparators):
            if isinstance(operand, ast.Constant):
                consts.append(operand.value)
            elif isinstance(operand, (ast.Tuple, ast.List, ast.Set)):
                consts += [e.value for e in operand.elts if isinstance(e, ast.Constant)]
        hits = sorted({c for c in consts if isinstance(c, str) and c in names})
        if hits:
            found.append(f"{path.relative_to(PKG.parent)}:{node.lineno} compares {', '.join(hits)}")
    return found


def test_no_geometry_name_is_compared_outside_the_geometry_modules():
    """A geometry is a value: what it is comes from its class (enclosed, reflecting, ...), not its name."""
    home = {PKG / "core" / "geometry.py", PKG / "core" / "room_geometry.py"}
    found = [hit for path in sorted(PKG.rglob("*.py")) if path not in home for hit in _geometry_name_comparisons(path)]
    assert not found, "\n".join(found)


def _calls_outside(tree, func: str, allowed_roots=frozenset()) -> list:
    """``(line, where)`` of each call of ``func`` (a name or a method) in a module's ``tree``.

    ``where`` is the top-level definition holding the call (a function, class or assigned name), with the key
    of the top-level dict entry holding it (``"_OUT[wav]"``); ``"<module>"`` at the top level. Calls inside the
    definitions in ``allowed_roots`` (the one home of such calls) are left out.
    """
    found = []

    def name_of(node):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            return node.name
        targets = node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(
            node, ast.AnnAssign) else []
        return next((t.id for t in targets if isinstance(t, ast.Name)), "<module>")

    def calls(node):
        for sub in ast.walk(node):
            if isinstance(sub, ast.Call):
                f = sub.func
                if (f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")) == func:
                    yield sub

    for stmt in tree.body:
        root = name_of(stmt)
        if root in allowed_roots:
            continue
        value = getattr(stmt, "value", None)
        entries = list(zip(value.keys, value.values, strict=True)) if isinstance(value, ast.Dict) else []
        for call in calls(stmt):
            where = root
            for k, v in entries:
                if isinstance(k, ast.Constant) and any(c is call for c in ast.walk(v)):
                    where = f"{root}[{k.value}]"
            found.append((call.lineno, where, call))
    return found


#: Command-line modules still adding options by hand while their workflows are converted to jobs. It must be
#: empty: each file leaves it when its options come from records (``add_option``).
PENDING_OPTIONS = set()

#: Scene keys still spelled by hand in ``scene/schema.py`` while their workflows are converted (excitation,
#: sweep, render, WAV), by the definition holding them. It must be empty: each leaves it when its keys come
#: from records.
PENDING_KEYS = set()


def _is_version(call) -> bool:
    """The parser's own ``--version`` (not a setting)."""
    return bool(call.args) and isinstance(call.args[0], ast.Constant) and call.args[0].value == "--version"


def test_every_option_comes_from_a_record():
    """No ``add_argument(`` outside the settings table's ``add_option`` (the parser's ``--version`` aside)."""
    bad = []
    for path, rel in _modules():
        if rel.as_posix() in {"app/settings/table.py", *PENDING_OPTIONS}:
            continue
        bad += [f"{rel}:{line} ({where})" for line, where, call in _calls_outside(ast.parse(path.read_text("utf-8")),
                                                                                    "add_argument")
                if not _is_version(call)]
    assert not bad, "options added by hand (make a Setting record and use add_option):\n" + "\n".join(bad)


def test_every_scene_key_comes_from_a_record():
    """No ``Key(`` in ``scene/`` outside the generator that makes each key from its Setting record."""
    bad = []
    for path in sorted((PKG / "scene").glob("*.py")):
        for line, where, _ in _calls_outside(ast.parse(path.read_text("utf-8")), "Key", {"_key"}):
            if not (path.name == "schema.py" and (where in PENDING_KEYS or where.split("[")[0] in PENDING_KEYS)):
                bad.append(f"scene/{path.name}:{line} ({where})")
    assert not bad, "scene keys spelled by hand (make a Setting record):\n" + "\n".join(bad)


def test_hand_written_call_finder_finds_calls():
    source = ("import argparse\np = argparse.ArgumentParser()\np.add_argument('--version', action='version')\n"
              "def add_parser(sub):\n    sub.add_argument('--x', type=float)\n"
              "TABLE = {'a': Key('str', 'doc'), 'b': Key('int', 'doc'), 'c': _key(s)}\n"
              "def _key(s):\n    return Key(s.kind, s.doc)\n")
    tree = ast.parse(source)
    options = [(line, where) for line, where, call in _calls_outside(tree, "add_argument") if not _is_version(call)]
    assert options == [(5, "add_parser")]
    assert [(line, where) for line, where, _ in _calls_outside(tree, "Key", {"_key"})] == [(6, "TABLE[a]"),
                                                                                          (6, "TABLE[b]")]
    assert [where for _, where, _ in _calls_outside(tree, "Key")] == ["TABLE[a]", "TABLE[b]", "_key"]
#: Layers whose functions take the sphere's surroundings as ``geometry`` (a ``Geometry``), never ``config``.
GEOMETRY_NAMED = PHYSICS | {"sweep"}
#: Parameter names the surroundings once went by.
OLD_GEOMETRY_NAMES = {"config", "conf"}


def _old_geometry_parameters(source: str, where: str) -> list[str]:
    """Functions (and lambdas) of one module with a parameter named ``config`` or ``conf``."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            a = node.args
            params = [*a.posonlyargs, *a.args, *a.kwonlyargs, *(p for p in (a.vararg, a.kwarg) if p is not None)]
            name = getattr(node, "name", "<lambda>")
            found += [f"{where}:{node.lineno} {name}({p.arg})" for p in params if p.arg in OLD_GEOMETRY_NAMES]
    return found


def test_physics_and_sweep_functions_name_the_surroundings_geometry():
    """A ``Geometry`` is passed as ``geometry`` in the physics and sweep layers, never as ``config``."""
    found = [hit for path, rel in _modules() if _top(rel) in GEOMETRY_NAMED
             for hit in _old_geometry_parameters(path.read_text(encoding="utf-8"), rel.as_posix())]
    assert not found, "\n".join(found)


def test_old_geometry_parameter_finder_finds_each_kind_of_parameter():
    source = ("def f(geometry, config):\n    pass\n"
              "def g(*, conf=None):\n    pass\n"
              "class C:\n    async def h(self, /, config):\n        pass\n"
              "k = lambda conf: conf\n"
              "def fine(geometry, configuration_name, kind='plane'):\n    pass\n")
    assert _old_geometry_parameters(source, "m.py") == ["m.py:1 f(config)", "m.py:3 g(conf)", "m.py:6 h(config)",
                                                        "m.py:8 <lambda>(conf)"]


#: Parameters named ``config`` that hold a configuration kind's name (``"free"``, ``"plane"``, ...), never a
#: ``Geometry``: the name the command line (``--config``) and the sweep's ``config`` axis give it. ``design_map``
#: and ``check_listener`` cannot call it ``kind``: that is the excitation's kind beside it.
KIND_NAMED_CONFIG = {
    "app/impacts.py impact_setup(config)",  # the --config choice the setup's geometry is built from
    "app/impacts.py _impact_setup(config)",  # the same, with the names its errors use
    "app/impacts.py room_settings(config)",  # the --config given besides --room (refused unless "free")
    "app/forced_noise.py check_listener(config)",  # the cavity's kind (ForcedJob.config)
    "app/forced_noise.py design_map(config)",  # the cavity's kind; ``kind`` is the excitation's
}


def _config_parameters() -> list[str]:
    """``module function(param)`` of each ``config``/``conf`` parameter in ``acoustiviz/``."""
    found = []
    for path, rel in _modules():
        found += [re.sub(r":\d+ ", " ", hit)
                  for hit in _old_geometry_parameters(path.read_text(encoding="utf-8"), rel.as_posix())]
    return found


def test_functions_name_the_surroundings_geometry():
    """Every layer, the sinks too, passes a ``Geometry`` as ``geometry``; a ``config`` left is a kind's name."""
    found = _config_parameters()
    assert sorted(set(found) - KIND_NAMED_CONFIG) == []
    assert sorted(KIND_NAMED_CONFIG - set(found)) == [], "an exemption names no parameter any more: drop it"


def _configuration_fields(source: str, where: str) -> list[str]:
    """Classes of one module declaring a field ``configuration`` (an annotated name in the class body)."""
    return [f"{where}:{node.lineno} {node.name}.configuration" for node in ast.walk(ast.parse(source))
            if isinstance(node, ast.ClassDef)
            for item in node.body if isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name)
            and item.target.id == "configuration"]


def test_no_settings_or_setup_class_has_a_configuration_field():
    """Jobs, setups and results hold the surroundings as ``geometry``, as the physics names them."""
    found = [hit for path, rel in _modules()
             for hit in _configuration_fields(path.read_text(encoding="utf-8"), rel.as_posix())]
    assert not found, "\n".join(found)


def test_configuration_field_finder_finds_annotated_fields_only():
    source = ("class Job:\n    impact: object\n    configuration: object\n"
              "class Other:\n    configuration = 'plane'\n    def f(self, configuration):\n        pass\n"
              "class Setup(NamedTuple):\n    configuration: Geometry = None\n")
    assert _configuration_fields(source, "m.py") == ["m.py:1 Job.configuration", "m.py:8 Setup.configuration"]


#: Front ends: they build settings objects, whose ``names`` make the errors name what the user typed.
FRONT_ENDS = {"cli", "scene"}


def _user_terms_uses(source: str, where: str) -> list[str]:
    """Each import, call or mention of ``user_terms`` in one module's source."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom):
            found += [f"{where}:{node.lineno} import" for a in node.names if a.name == "user_terms"]
        elif isinstance(node, ast.Name) and node.id == "user_terms":
            found.append(f"{where}:{node.lineno} {node.id}")
        elif isinstance(node, ast.Attribute) and node.attr == "user_terms":
            found.append(f"{where}:{node.lineno} .{node.attr}")
    return sorted(found, key=lambda hit: int(hit.split(":")[1].split()[0]))


def test_front_ends_rename_no_errors_by_hand():
    """The command line and the scene loader hand names to the settings or the app helpers, never ``user_terms``."""
    found = [hit for path, rel in _modules() if _top(rel) in FRONT_ENDS
             for hit in _user_terms_uses(path.read_text(encoding="utf-8"), rel.as_posix())]
    assert not found, "user_terms in a front end (give the settings or the helper its names):\n" + "\n".join(found)


def test_user_terms_finder_finds_each_use():
    source = ("from acoustiviz.app.names import user_terms, IMPACT_OPTIONS\n"
              "def f(args):\n    with user_terms(IMPACT_OPTIONS):\n        pass\n"
              "def g():\n    from acoustiviz import errors\n    return errors.user_terms({})\n"
              "def fine(names):\n    return terms_of_use(names)\n")
    assert _user_terms_uses(source, "m.py") == ["m.py:1 import", "m.py:3 user_terms", "m.py:7 .user_terms"]
