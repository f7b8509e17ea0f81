"""Animated glTF and USD (--export out.glb/.gltf/.usd/.usda/.usdc), read back and compared with
the NPZ of the same run: one node/Xform per body, keys at the NPZ's t, translations x, rotations q;
meshes in the body frame; byte-identical reruns; the Khronos glTF validator; the bad-input lines."""
import json
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT

pygltflib = pytest.importorskip("pygltflib")
VALIDATOR = ROOT / ".tools" / "node_modules" / "gltf-validator"
F32 = dict(rtol=0, atol=2e-6)  # float32 round-off of values of order 1

TWO_KINDS = """
[[body]]
mesh = "sphere.obj"
scale = 0.2
position = [-0.5, -0.5, 0.0]

[[body]]
mesh = "t_handle.obj"
scale = 0.3
position = [0.4, -0.4, 0.0]
initial_angular_velocity = [0.0, 5.0, 1.0]
count = 2
"""


def run(argv, capsys):
    from rigid.cli import main

    code = main(["--headless", *map(str, argv)])
    err = capsys.readouterr().err
    return code, err


@pytest.fixture(scope="module")
def one_body(tmp_path_factory, ti_cpu):
    """The thrown sphere, 12 frames, every format from one run; then the GLB and USDA of a
    second run."""
    folder = tmp_path_factory.mktemp("one")
    names = ["a.npz", "a.glb", "a.gltf", "a.usda", "a.usdc"]
    from rigid.cli import main

    argv = ["--headless", "--frames", "12", "--scene", str(ROOT / "assets/scenes/thrown_sphere.toml")]
    assert main(argv + [arg for n in names for arg in ("--export", str(folder / n))]) == 0
    assert main(argv + ["--export", str(folder / "b.glb"), "--export", str(folder / "b.usda")]) == 0
    return folder


@pytest.fixture(scope="module")
def three_bodies(tmp_path_factory, ti_cpu):
    """A sphere and two T-handles ([[body]] tables), 10 frames: NPZ, GLB and USDA."""
    folder = tmp_path_factory.mktemp("three")
    scene = folder / "scene.toml"
    scene.write_text(TWO_KINDS)
    from rigid.cli import main

    assert main(["--headless", "--frames", "10", "--scene", str(scene), "--export", str(folder / "m.npz"),
                 "--export", str(folder / "m.glb"), "--export", str(folder / "m.usda")]) == 0
    return folder


def read_gltf(path):
    """(gltf, {node name: node}, accessor reader) of a .glb or .gltf file."""
    gltf = pygltflib.GLTF2.load(str(path))
    blob = gltf.binary_blob() if str(path).endswith(".glb") else gltf.decode_data_uri(gltf.buffers[0].uri)
    dtypes = {pygltflib.FLOAT: np.float32, pygltflib.UNSIGNED_INT: np.uint32}
    widths = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}

    def read(index):
        acc = gltf.accessors[index]
        view = gltf.bufferViews[acc.bufferView]
        data = np.frombuffer(blob, dtypes[acc.componentType], acc.count * widths[acc.type],
                             view.byteOffset + (acc.byteOffset or 0))
        return data.reshape(acc.count, -1) if widths[acc.type] > 1 else data

    return gltf, {n.name: n for n in gltf.nodes}, read


def body_keys(gltf, nodes, read, name):
    """(times, translations, rotations) of the animation's channels for the node ``name``."""
    anim, = gltf.animations
    index = gltf.nodes.index(nodes[name])
    out = {}
    for channel in anim.channels:
        if channel.target.node == index:
            sampler = anim.samplers[channel.sampler]
            assert sampler.interpolation == "LINEAR"
            out[channel.target.path] = (read(sampler.input), read(sampler.output))
    assert set(out) == {"translation", "rotation"}
    (t, x), (t2, q) = out["translation"], out["rotation"]
    assert np.array_equal(t, t2)
    return t, x, q


def check_against_npz(gltf_path, npz_path, names):
    d = np.load(npz_path)
    frames = len(d["t"])
    x, q = d["x"].reshape(frames, -1, 3), d["q"].reshape(frames, -1, 4)
    gltf, nodes, read = read_gltf(gltf_path)
    bodies = [n for n in gltf.nodes if n.name in names]
    assert [n.name for n in bodies] == names  # one node per body, in body order
    pairs = [(c.target.node, c.target.path) for c in gltf.animations[0].channels]
    assert len(pairs) == len(set(pairs)) == 2 * len(names)
    for b, name in enumerate(names):
        t, xs, qs = body_keys(gltf, nodes, read, name)
        np.testing.assert_array_equal(t, d["t"].astype(np.float32))  # key times are the NPZ's t
        np.testing.assert_allclose(xs, x[:, b], **F32)
        np.testing.assert_allclose(qs, q[:, b][:, [1, 2, 3, 0]], **F32)  # (w,x,y,z) -> (x,y,z,w)
        acc = gltf.accessors[gltf.animations[0].samplers[0].input]
        assert acc.min == [float(t[0])] and acc.max == [float(t[-1])]
        np.testing.assert_allclose(nodes[name].translation, x[0, b], **F32)  # at rest: frame 0
    return gltf, nodes, read, d


def test_glb_keys_are_the_npz_frames(one_body):
    check_against_npz(one_body / "a.glb", one_body / "a.npz", ["body"])
    check_against_npz(one_body / "a.gltf", one_body / "a.npz", ["body"])


def test_glb_and_usd_are_byte_identical_across_runs(one_body):
    assert (one_body / "a.glb").read_bytes() == (one_body / "b.glb").read_bytes()
    assert (one_body / "a.usda").read_bytes() == (one_body / "b.usda").read_bytes()


def test_many_bodies_one_node_each_and_the_static_box(three_bodies):
    names = ["sphere_0", "t_handle_1_0", "t_handle_1_1"]
    gltf, nodes, read, d = check_against_npz(three_bodies / "m.glb", three_bodies / "m.npz", names)
    scene = gltf.scenes[gltf.scene]
    assert [gltf.nodes[i].name for i in scene.nodes] == names + ["box"]
    assert [gltf.nodes[i].name for i in nodes["box"].children] == ["floor", "walls"]
    assert nodes["t_handle_1_0"].mesh == nodes["t_handle_1_1"].mesh != nodes["sphere_0"].mesh  # copies share
    floor = read(gltf.meshes[nodes["floor"].mesh].primitives[0].attributes.POSITION)
    np.testing.assert_array_equal(floor[:, 1], -1.0)
    for b, name in enumerate(names):  # vertex particles: the mesh is the body-frame particle set
        r0 = read(gltf.meshes[nodes[name].mesh].primitives[0].attributes.POSITION).astype(np.float64)
        m = d["mass"][b] / len(r0)
        inertia = m * (np.sum(r0 * r0) * np.eye(3) - r0.T @ r0)
        np.testing.assert_allclose(r0.mean(axis=0), 0.0, atol=1e-6)
        np.testing.assert_allclose(inertia, d["inertia_body"][b], rtol=1e-5, atol=1e-7)


def test_glb_meshes_are_the_models_body_frame_surfaces(sim_cache, tmp_path, capsys):
    from rigid.run.runner import run_frames

    sim = sim_cache(mesh=str(ROOT / "assets/t_handle.obj"), scale=0.5)
    assert run_frames(sim, 3, export_path=[tmp_path / "t.glb"]).status == "done"
    gltf, nodes, read = read_gltf(tmp_path / "t.glb")
    (name, vertices, faces), = sim.model.body_surfaces()
    primitive = gltf.meshes[nodes[name].mesh].primitives[0]
    assert primitive.mode == pygltflib.TRIANGLES
    np.testing.assert_array_equal(read(primitive.attributes.POSITION), vertices.astype(np.float32))
    np.testing.assert_array_equal(read(primitive.indices).reshape(-1, 3), faces)
    assert "wrote" in capsys.readouterr().err


def test_usd_time_samples_are_the_npz_frames(one_body, three_bodies):
    pytest.importorskip("pxr", reason="usd-core is not installed (pip install '.[usd]')")
    from pxr import Gf, Usd, UsdGeom

    for path, npz, names in ((one_body / "a.usda", one_body / "a.npz", ["body"]),
                             (one_body / "a.usdc", one_body / "a.npz", ["body"]),
                             (three_bodies / "m.usda", three_bodies / "m.npz", ["sphere_0", "t_handle_1_0", "t_handle_1_1"])):
        d = np.load(npz)
        frames = len(d["t"])
        x, q = d["x"].reshape(frames, -1, 3), d["q"].reshape(frames, -1, 4)
        stage = Usd.Stage.Open(str(path))
        assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y and UsdGeom.GetStageMetersPerUnit(stage) == 1
        assert stage.GetStartTimeCode() == 0 and stage.GetEndTimeCode() == frames - 1
        rate = stage.GetTimeCodesPerSecond()
        assert rate == 62.5  # 1 / (16 substeps × 1 ms)
        assert stage.GetPrimAtPath("/World/box/floor").IsA(UsdGeom.Mesh)
        for b, name in enumerate(names):
            xform = UsdGeom.Xformable(stage.GetPrimAtPath(f"/World/{name}"))
            mesh = UsdGeom.Mesh(stage.GetPrimAtPath(f"/World/{name}/{name}"))
            r0 = np.array(mesh.GetPointsAttr().Get(), np.float64)
            for k in (0, frames // 2, frames - 1):  # three time codes
                assert k / rate == pytest.approx(d["t"][k], rel=1e-6)
                translate, orient = (op.Get(k) for op in xform.GetOrderedXformOps())
                np.testing.assert_allclose(list(translate), x[k, b], **F32)
                np.testing.assert_allclose([orient.GetReal(), *orient.GetImaginary()], q[k, b], **F32)
                # pxr's own transform: body-frame vertex -> world is x + R(q) r0 (row vectors in Gf)
                matrix = np.array(xform.ComputeLocalToWorldTransform(k))
                w, v = q[k, b, 0], q[k, b, 1:]
                R = (w * w - v @ v) * np.eye(3) + 2 * np.outer(v, v) + 2 * w * np.array(
                    [[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
                np.testing.assert_allclose(r0 @ matrix[:3, :3] + matrix[3, :3], r0 @ R.T + x[k, b], atol=1e-5)
                assert isinstance(orient, Gf.Quatd)


def test_validator_finds_no_errors_or_warnings(one_body, three_bodies, tmp_path):
    node = shutil.which("node")
    if node is None or not VALIDATOR.is_dir():
        pytest.skip("the Khronos glTF validator is not installed (scripts/setup.sh installs it "
                    "into .tools/ with npm)")
    from rigid.run.export_gltf import gltf_bytes
    from rigid.run.export_motion import Motion

    cloud = tmp_path / "cloud.glb"  # a body with no triangles: a POINTS primitive
    rng = np.random.default_rng(0)
    q = rng.normal(size=(4, 1, 4))
    cloud.write_bytes(gltf_bytes(Motion(["cloud"], [rng.normal(size=(9, 3))], [np.zeros((0, 3), np.int32)],
                                        np.arange(4) * 0.016, rng.normal(size=(4, 1, 3)),
                                        q / np.linalg.norm(q, axis=-1, keepdims=True), 0.016, None), binary=True))
    files = [one_body / "a.glb", one_body / "a.gltf", three_bodies / "m.glb", cloud]
    script = ("const v = require(process.argv[1]); const fs = require('fs');"
              "Promise.all(process.argv.slice(2).map(f => v.validateBytes(new Uint8Array(fs.readFileSync(f)))))"
              ".then(r => console.log(JSON.stringify(r.map(x => x.issues))))"
              ".catch(e => { console.error(String(e)); process.exit(1); });")
    proc = subprocess.run([node, "-e", script, str(VALIDATOR), *map(str, files)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    for path, issues in zip(files, json.loads(proc.stdout)):
        assert (issues["numErrors"], issues["numWarnings"]) == (0, 0), (path.name, issues["messages"])


def test_blow_up_keeps_the_good_frames_in_every_format(tmp_path, ti_cpu, capsys):
    scene = tmp_path / "stiff.toml"
    scene.write_text("collision_stiffness = 1e7\n")
    code, err = run(["--frames", 300, "--scene", scene, "--export", tmp_path / "t.npz",
                     "--export", tmp_path / "t.glb"], capsys)
    assert code == 3 and "blow-up" in err
    d = np.load(tmp_path / "t.npz")
    assert 2 < len(d["t"]) < 301
    check_against_npz(tmp_path / "t.glb", tmp_path / "t.npz", ["body"])


def test_usd_without_usd_core_is_one_line_before_the_simulation(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "pxr", None)  # as if usd-core were not installed
    code, err = run(["--frames", 5, "--export", tmp_path / "t.npz", "--export", tmp_path / "t.usda"], capsys)
    assert code == 2
    assert err.strip() == (f"error: output {tmp_path / 't.usda'}: USD export needs the usd-core package; "
                           "install the usd extra: pip install -e '.[usd]' in this repository (or pip install usd-core)")
    assert not list(tmp_path.iterdir())  # nothing simulated, nothing written


def test_key_times_continue_through_a_window_reset():
    from rigid.run.export_motion import key_times

    t = np.array([0.0, 0.016, 0.032, 0.016, 0.032])  # 'r' in the window restarts the clock at 0
    np.testing.assert_allclose(key_times(t, 0.016), [0.0, 0.016, 0.032, 0.048, 0.064])
    same = np.array([0.0, 0.016, 0.032])
    assert np.array_equal(key_times(same, 0.016), same)
