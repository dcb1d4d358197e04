"""Bad input raises penumbra.PenumbraError (a ValueError) with the command line's one-line message,
a render setting named as its keyword argument rather than `--set`."""

import numpy as np
import pytest

import penumbra
from conftest import SCENE, SIZE, cli_error

SQUARE = np.array([[-1, 0, 1], [1, 0, 1], [1, 0, -1], [-1, 0, -1]], dtype=np.float32)
CAMERA = {"eye": [0, 16, 14], "target": [0, 0, -1], "fov_y_deg": 50}
LIGHT = {"center": [0, 10, 0], "edge_u": [4, 0, 0], "edge_v": [0, 0, 4]}


def test_an_unknown_scene_names_itself_as_on_the_command_line():
    with pytest.raises(penumbra.PenumbraError) as e:
        penumbra.Scene.load("no-such-scene")
    assert isinstance(e.value, ValueError)
    assert str(e.value) == cli_error("render", "--scene", "no-such-scene")
    assert str(e.value).startswith("no-such-scene: no such scene file or built-in scene")


def test_a_bad_render_setting_and_a_bad_parameter(renderer):
    with pytest.raises(penumbra.PenumbraError) as e:
        penumbra.Scene.load(SCENE, cull="sideways")
    cli = cli_error("render", "--scene", SCENE, "--set", "cull=sideways")
    assert str(e.value) == "cull='sideways'" + cli[len("--set cull=sideways"):]
    with pytest.raises(penumbra.PenumbraError) as e:
        renderer.render("adaptive:p_m=banana")
    assert str(e.value) == cli_error("render", "--scene", SCENE, "--set", f"resolution={SIZE}", "--method", "adaptive:p_m=banana")
    assert str(e.value) == "adaptive: parameter p_m = `banana` is not a number"


def test_a_bad_adapter_method_or_parameter_is_refused_as_on_the_command_line(scene, renderer):
    with pytest.raises(penumbra.GpuError) as e:
        penumbra.Renderer(scene, adapter="no-such-adapter")
    assert str(e.value) == cli_error("render", "--scene", SCENE, "--adapter", "no-such-adapter")
    assert str(e.value).startswith('adapter name "no-such-adapter": no adapter\'s name contains it (adapters seen: ')
    cli = cli_error("render", "--scene", SCENE, "--method", "nosuch")
    assert cli.startswith("unknown method `nosuch` (known: hard, pcf, pcss, ")
    # A refused request is refused again with its message: only accepted ones are remembered.
    for _ in range(2):
        with pytest.raises(penumbra.PenumbraError) as e:
            renderer.render("nosuch")
        assert str(e.value) == cli
        with pytest.raises(penumbra.PenumbraError) as e:
            renderer.render("hard", bogus=1)
        assert str(e.value) == cli_error("render", "--scene", SCENE, "--method", "hard", "--param", "bogus=1")
        assert str(e.value) == "method `hard` has no parameter `bogus` (its parameters: none)"
    v, _ = renderer.render("hard")
    assert v.shape == (SIZE, SIZE)


def test_meshes_from_arrays_are_checked_as_a_scene_file_is():
    ground = (SQUARE * 15, [0, 1, 2, 0, 2, 3])
    scene = penumbra.Scene.from_meshes([ground, (SQUARE * 2 + [0, 4, 0], [[0, 1, 2], [0, 2, 3]])], CAMERA, LIGHT, resolution=32, cull="none")
    assert (scene.width, scene.height, scene.triangles) == (32, 32, 4)
    # The same meshes, camera and light as scenes/analytic-square.toml: the same V, bit for bit.
    v, _ = penumbra.Renderer(scene).render("adaptive:preset=balanced")
    loaded, _ = penumbra.Renderer(penumbra.Scene.load(SCENE, resolution=32)).render("adaptive:preset=balanced")
    assert np.array_equal(v.view(np.uint32), loaded.view(np.uint32))
    assert np.nanmin(v) == 0.0 and np.nanmax(v) == 1.0 and 0.0 < np.nanmean(v) < 1.0
    with pytest.raises(penumbra.PenumbraError) as e:
        penumbra.Scene.from_meshes([(SQUARE, [0, 1, 7])], CAMERA, LIGHT)
    assert str(e.value) == "embedded scene: mesh 1: index 7 is out of range (4 positions)"
    with pytest.raises(penumbra.PenumbraError) as e:
        penumbra.Scene.from_meshes([ground, (SQUARE[:, :2], [0, 1, 2])], CAMERA, LIGHT)
    assert str(e.value) == "mesh 2 positions: expected an (N, 3) array, got shape [4, 2]"
    with pytest.raises(penumbra.PenumbraError, match=r"^embedded scene: light: give either edge_u and edge_v, or size and normal \(with optional u_axis\)$"):
        penumbra.Scene.from_meshes([ground], CAMERA, {"center": [0, 10, 0], "edge_u": [4, 0, 0]})


def test_metrics_refuse_a_v_of_another_shape(scene):
    ref = penumbra.reference(scene, samples=8)
    with pytest.raises(penumbra.PenumbraError, match=r"^metrics: V has shape \[32, 32\], the reference \(analytic-square\) is \(64, 64\)$"):
        penumbra.metrics(np.zeros((32, 32)), ref)
    with pytest.raises(penumbra.PenumbraError) as e:
        penumbra.reference(scene, samples=0)
    assert str(e.value) == "--samples must be in 1..=256, got 0"
    with pytest.raises(penumbra.PenumbraError) as e:
        penumbra.reference(scene, mode="sideways")
    assert str(e.value) == cli_error("compare", "--scene", SCENE, "--reference", "sideways", "--out", "unused-out")
    assert str(e.value).startswith("reference mode `sideways`: use `lattice`")


DISK_SCENE = """name = "disk-square"
[camera]
eye = [0.0, 16.0, 14.0]
target = [0.0, 0.0, -1.0]
fov_y_deg = 50.0
[light]
{light}
[render]
cull = "none"
[[mesh]]
builtin = "plane"
scale = [30.0, 1.0, 30.0]
[[mesh]]
builtin = "plane"
translate = [0.0, 4.0, 0.0]
scale = [4.0, 1.0, 4.0]
"""


def test_a_light_of_any_kind_from_a_dict_is_the_scene_files(tmp_path):
    disk = {"kind": "disk", "center": np.array([0.0, 10.0, 0.0]), "normal": [0, -1, 0], "radius": 2}
    meshes = [(SQUARE * 15, [0, 1, 2, 0, 2, 3]), (SQUARE * 2 + [0, 4, 0], [0, 1, 2, 0, 2, 3])]
    ours = penumbra.Scene.from_meshes(meshes, CAMERA, disk, resolution=32, cull="none")
    path = tmp_path / "disk.toml"
    path.write_text(DISK_SCENE.format(light='kind = "disk"\ncenter = [0.0, 10.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\nradius = 2.0'))
    theirs = penumbra.Scene.load(str(path), resolution=32)
    for method in ("hard", "adaptive:preset=balanced"):
        a, _ = penumbra.Renderer(ours).render(method)
        b, _ = penumbra.Renderer(theirs).render(method)
        assert np.array_equal(a.view(np.uint32), b.view(np.uint32)), method
        assert np.nanmin(a) == 0.0 and np.nanmax(a) == 1.0
    # A key of another kind: the scene file's message, with the scene's origin in front.
    stray = dict(disk, edge_u=[4, 0, 0])
    with pytest.raises(penumbra.PenumbraError) as e:
        penumbra.Scene.from_meshes(meshes, CAMERA, stray)
    path.write_text(DISK_SCENE.format(light='kind = "disk"\ncenter = [0.0, 10.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\nradius = 2.0\nedge_u = [4.0, 0.0, 0.0]'))
    cli = cli_error("render", "--scene", str(path))
    assert str(e.value).startswith("embedded scene: ") and cli.startswith(f"{path}: ")
    assert str(e.value)[len("embedded scene: "):] == cli[len(f"{path}: "):]


def test_read_exr_names_a_missing_file(tmp_path):
    missing = tmp_path / "visibility.exr"
    with pytest.raises(penumbra.PenumbraError) as e:
        penumbra.read_exr(missing)
    assert str(e.value) == f"{missing}: No such file or directory (os error 2)"
