"""The package as a notebook uses it: exception classes, typed signatures (stubs), docstrings, rows
into pandas, progress in a cell."""

import ast
import inspect
import io
import pathlib
import subprocess
import sys

import pandas
import pytest

import penumbra
from conftest import SCENE, SIZE, cli_error

STUB = pathlib.Path(penumbra.__file__).with_name("_penumbra.pyi")


def test_a_failing_gpu_is_a_runtime_error_and_bad_input_a_value_error():
    assert issubclass(penumbra.GpuError, RuntimeError) and not issubclass(penumbra.GpuError, ValueError)
    assert issubclass(penumbra.PenumbraError, ValueError) and not issubclass(penumbra.PenumbraError, RuntimeError)
    with pytest.raises(RuntimeError) as e:
        penumbra.Renderer(penumbra.Scene.load(SCENE, resolution=SIZE), adapter="no-such-adapter")
    assert type(e.value) is penumbra.GpuError
    with pytest.raises(ValueError) as e:
        penumbra.Scene.load("no-such-scene")
    assert type(e.value) is penumbra.PenumbraError


def test_a_render_setting_is_named_as_its_keyword():
    with pytest.raises(penumbra.PenumbraError) as e:
        penumbra.Scene.load(SCENE, cull="sideways")
    cli = cli_error("render", "--scene", SCENE, "--set", "cull=sideways")
    assert cli.startswith("--set cull=sideways: unknown variant `sideways`")
    assert str(e.value) == "cull='sideways'" + cli[len("--set cull=sideways"):]
    with pytest.raises(penumbra.PenumbraError) as e:
        penumbra.Scene.load(SCENE, resolution="abc")
    assert str(e.value) == "resolution='abc': invalid type: string \"abc\", expected u32"
    with pytest.raises(penumbra.PenumbraError) as e:
        penumbra.Scene.load(SCENE, widht=3)
    assert str(e.value).startswith("builtin:analytic-square: widht: unknown render setting (known: width, height, ")
    assert "--set" not in str(e.value)
    with pytest.raises(penumbra.PenumbraError) as e:
        penumbra.Scene.from_meshes([([[0, 0, 0], [1, 0, 0], [0, 0, 1]], [0, 1, 2])], {"eye": [0, 5, 5], "target": [0, 0, 0], "fov_y_deg": 50},
                                   {"center": [0, 4, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1]}, self_shadow=7)
    assert str(e.value).startswith("embedded scene: self_shadow=7: "), str(e.value)


def stub_docs():
    """(dotted name, docstring) of every stub entry that has one."""
    def walk(nodes, prefix=""):
        for n in nodes:
            if isinstance(n, (ast.FunctionDef, ast.ClassDef)):
                if ast.get_docstring(n):
                    yield prefix + n.name, ast.get_docstring(n), n
                if isinstance(n, ast.ClassDef):
                    yield from walk(n.body, prefix + n.name + ".")
    return list(walk(ast.parse(STUB.read_text()).body))


def runtime(name):
    obj = penumbra._penumbra
    for part in name.split("."):
        obj = inspect.getattr_static(obj, part) if inspect.isclass(obj) else getattr(obj, part)
    return obj.__func__ if isinstance(obj, staticmethod) else obj


def test_the_stubs_carry_the_extension_s_own_docstrings_and_parameters():
    docs = stub_docs()
    assert len(docs) >= 20
    for name, doc, node in docs:
        obj = runtime(name)
        assert inspect.cleandoc(obj.__doc__ or "") == doc, name
        if isinstance(node, ast.FunctionDef) and getattr(obj, "__text_signature__", None):
            stub_params = [a.arg for a in node.args.args + node.args.kwonlyargs]
            stub_params += [a.arg for a in (node.args.vararg, node.args.kwarg) if a]
            ours = [p for p in inspect.signature(obj).parameters if p not in ("self", "cls", "$self")]
            assert [p for p in stub_params if p != "self"] == ours, name
    # Every public function documents what it takes, returns and raises.
    for fn in (penumbra.Scene.load, penumbra.Renderer.render, penumbra.reference, penumbra.metrics, penumbra.compare):
        doc = inspect.getdoc(fn)
        assert all(h in doc for h in ("Args:", "Returns:", "Raises:")), fn
    assert "float32 of shape (height, width)" in inspect.getdoc(penumbra.Renderer.render)
    assert (pathlib.Path(penumbra.__file__).with_name("py.typed")).is_file()


def test_mypy_reads_the_types_of_render_scene_load_compare_and_metrics(tmp_path):
    probe = tmp_path / "probe.py"
    probe.write_text(
        "import penumbra\n"
        "scene = penumbra.Scene.load('analytic-square', resolution=64)\n"
        "v, record = penumbra.Renderer(scene).render('hard')\n"
        "reveal_type(v)\n"
        "reveal_type(penumbra.compare(scene, ['hard']))\n"
        "reveal_type(penumbra.metrics(v, penumbra.reference(scene)))\n"
        "penumbra.Scene.load(3)\n"
    )
    p = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental", str(probe)], capture_output=True, text=True)
    out = p.stdout
    assert p.returncode == 1, out
    v_type = next(line for line in out.splitlines() if "probe.py:4:" in line)
    assert 'Revealed type is "numpy.ndarray[' in v_type and "numpy.floating[" in v_type and "32Bit" in v_type, out
    assert 'Revealed type is "penumbra.Rows"' in out, out
    assert 'Revealed type is "dict[str, Any]"' in out or 'Revealed type is "builtins.dict[builtins.str, Any]"' in out, out
    assert 'Argument 1 to "load" of "Scene" has incompatible type "int"; expected "str"' in out, out
    assert out.count("error:") == 1, out


def test_compare_rows_go_straight_into_a_dataframe(scene):
    rows = penumbra.compare(scene, ["hard", "regular:n=3"], repeats=1, progress=False)
    assert isinstance(rows, penumbra.Rows) and isinstance(rows, list)
    frame = rows.to_frame()
    assert isinstance(frame, pandas.DataFrame)
    assert list(frame["label"]) == ["hard", "regular:n=3"]
    assert list(frame["maps"]) == [1, 9]
    assert frame["metrics.rmse"].tolist() == [r["metrics"]["rmse"] for r in rows]
    assert frame["metrics.rmse"].iloc[1] < frame["metrics.rmse"].iloc[0]


def test_progress_goes_to_a_callable_to_a_notebook_cell_or_nowhere(scene, monkeypatch):
    lines = []
    penumbra.compare(scene, "hard", repeats=1, progress=lines.append)
    assert len(lines) == 2 and lines[0].startswith("reference continuous 32x32 at 64x64") and lines[1].startswith("hard: 1 shadow maps, median "), lines
    # In a Jupyter kernel (ipykernel imported, stderr not a terminal) the lines go to the cell's stderr.
    cell = io.StringIO()
    monkeypatch.setitem(sys.modules, "ipykernel", sys.modules["io"])
    monkeypatch.setattr(sys, "stderr", cell)
    penumbra.reference(scene, samples=8)
    assert cell.getvalue().startswith("reference continuous 8x8 at 64x64"), cell.getvalue()
    monkeypatch.delitem(sys.modules, "ipykernel")
    quiet = io.StringIO()
    monkeypatch.setattr(sys, "stderr", quiet)
    penumbra.reference(scene, samples=8)
    assert quiet.getvalue() == ""
    with pytest.raises(penumbra.PenumbraError, match=r"^progress='yes': give None, True, False or a callable taking a line$"):
        penumbra.reference(scene, progress="yes")
