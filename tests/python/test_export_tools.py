"""`fmcw export` checked with other people's tools: Open3D loads the PLY, numpy reads the
SemanticKITTI .bin/.label by their documented layout, PCL's own programs read our PCD and
what they write reads back. Only the CLI is needed, not the Python module."""

import subprocess

import numpy as np
import pytest

from conftest import SOURCE_DIR, require_module, require_program, run_cli

# docs/FORMATS.md: SemanticKITTI codes per actor class name, (still, moving), for frames without
# the field `class`.
CLASS_CODES = {"car": (10, 252), "van": (10, 252), "truck": (18, 258), "bus": (13, 257), "cyclist": (31, 253),
               "pedestrian": (30, 254)}

# docs/FORMATS.md: SemanticKITTI's moving codes of the class ids of the field `class` (van 100 is
# its other-vehicle); other classes move as the generic 251, class 0 stays 0.
MOVING_CODES = {10: 252, 13: 257, 18: 258, 20: 259, 30: 254, 31: 253, 32: 255, 100: 259}


def kitti_semantic_of_class(class_id, moving):
    """The SemanticKITTI code of each point from its class id and moving flag."""
    class_id = class_id.astype(np.int64)
    still = np.where(class_id < 100, class_id, np.where(class_id == 100, 20, 99))
    lut = np.full(65536, 251)
    lut[0] = 0  # no class stays unlabeled
    for k, code in MOVING_CODES.items():
        lut[k] = code
    return np.where(moving, lut[class_id], still).astype(np.uint32)


def read_pcd_numpy(path):
    """This test's own PCD reader (ascii or binary, COUNT 1), independent of fmcw's."""
    header = {}
    with open(path, "rb") as f:
        while "DATA" not in header:
            line = f.readline()
            assert line, f"{path}: header ends before DATA"
            words = line.decode("ascii").split()
            if words and not words[0].startswith("#"):
                header[words[0]] = words[1:]
        body = f.read()
    names, types, sizes = header["FIELDS"], header["TYPE"], [int(s) for s in header["SIZE"]]
    assert all(c == "1" for c in header.get("COUNT", ["1"] * len(names)))
    dtype = np.dtype([(n, {"F": "<f", "U": "<u", "I": "<i"}[t] + str(s)) for n, t, s in zip(names, types, sizes)])
    n = int(header["POINTS"][0])
    if header["DATA"][0] == "binary":
        data = np.frombuffer(body, dtype=dtype, count=n)
        return {name: data[name] for name in names}, header
    table = np.array([line.split() for line in body.decode("ascii").splitlines() if line.strip()], dtype=object)
    assert table.shape == (n, len(names))
    return {name: table[:, k].astype(np.float64).astype(dtype[name]) for k, name in enumerate(names)}, header


def finite(cloud):
    return np.isfinite(cloud["x"]) & np.isfinite(cloud["y"]) & np.isfinite(cloud["z"])


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    out = tmp_path_factory.mktemp("ds")
    run_cli("simulate", SOURCE_DIR / "scenarios" / "straight_road.yaml", "-o", out, "--frames", 1, "--overwrite")
    return out


@pytest.fixture(scope="module")
def processed(dataset, tmp_path_factory):
    out = tmp_path_factory.mktemp("processed")
    run_cli("process", dataset, "-o", out, "--method", "robust")
    return out


def ply_header(path):
    with open(path, "rb") as f:
        lines = []
        while not lines or lines[-1] != "end_header":
            lines.append(f.readline().decode("ascii").strip())
    return lines


def test_open3d_loads_the_doppler_ply_with_every_point(dataset, tmp_path):
    o3d = require_module("open3d", "python3-open3d")
    run_cli("export", dataset, "-o", tmp_path, "--to", "ply", "--color", "doppler", "--doppler-scale", 5)
    cloud, header = read_pcd_numpy(dataset / "frames" / "000000.pcd")
    keep = finite(cloud)
    ply = o3d.io.read_point_cloud(str(tmp_path / "000000.ply"))
    points = np.asarray(ply.points)
    assert len(points) == keep.sum() > 10000
    np.testing.assert_array_equal(points, np.stack([cloud[a][keep] for a in "xyz"], axis=1).astype(np.float64))
    # Doppler colours: white at rest, red receding, blue approaching, full at 5 m/s.
    s = np.clip(cloud["v"][keep].astype(np.float64) / 5.0, -1, 1)
    fade = np.where(s >= 0, 1 - s, 1 + s)
    expected = np.stack([np.where(s >= 0, 1, fade), fade, np.where(s >= 0, fade, 1)], axis=1)
    np.testing.assert_allclose(np.asarray(ply.colors), expected, atol=0.6 / 255)
    # Every PCD field is a vertex property, then the colour.
    props = [line.split()[-1] for line in ply_header(tmp_path / "000000.ply") if line.startswith("property")]
    assert props == header["FIELDS"] + ["red", "green", "blue"]
    # Open3D reads our PCD directly too.
    pcd = o3d.io.read_point_cloud(str(dataset / "frames" / "000000.pcd"), remove_nan_points=True)
    assert len(pcd.points) == keep.sum()


def test_open3d_loads_label_coloured_plies(dataset, processed, tmp_path):
    o3d = require_module("open3d", "python3-open3d")
    run_cli("export", dataset, "-o", tmp_path / "truth", "--to", "ply", "--color", "label")
    run_cli("export", processed / "labels", "-o", tmp_path / "est", "--to", "ply", "--color", "label")
    truth_cloud, _ = read_pcd_numpy(dataset / "frames" / "000000.pcd")
    est_cloud, _ = read_pcd_numpy(processed / "labels" / "000000.pcd")
    truth_static = (truth_cloud["instance"] == 0) & (truth_cloud["moving"] == 0)
    for folder, cloud, static, moving in (("truth", truth_cloud, truth_static, truth_cloud["moving"] > 0),
                                          ("est", est_cloud, est_cloud["label"] == 0, est_cloud["label"] > 0)):
        ply = o3d.io.read_point_cloud(str(tmp_path / folder / "000000.ply"))
        colors = np.asarray(ply.colors)
        keep = finite(cloud)
        assert len(colors) == keep.sum()
        assert static[keep].any() and moving[keep].any()
        np.testing.assert_allclose(colors[static[keep]], 150 / 255, atol=1e-9)  # static world grey
        assert (colors[moving[keep]].max(axis=1) == 1.0).all()  # moving: a hue at full brightness


def read_kitti(folder, stem="000000"):
    scan = np.fromfile(folder / "velodyne" / f"{stem}.bin", dtype="<f4").reshape(-1, 4)
    label = np.fromfile(folder / "labels" / f"{stem}.label", dtype="<u4")
    assert len(label) == len(scan)
    return scan, label & 0xFFFF, label >> 16


def test_semantic_kitti_from_ground_truth(dataset, tmp_path):
    run_cli("export", dataset, "-o", tmp_path, "--to", "kitti")
    scan, semantic, instance = read_kitti(tmp_path)
    cloud, _ = read_pcd_numpy(dataset / "frames" / "000000.pcd")
    keep = finite(cloud)
    assert len(scan) == keep.sum()
    np.testing.assert_array_equal(scan[:, :3], np.stack([cloud[a][keep] for a in "xyz"], axis=1))
    np.testing.assert_array_equal(scan[:, 3], cloud["intensity"][keep])
    np.testing.assert_array_equal(instance, cloud["instance"][keep])
    # Each point's class (the field `class`), moving variants where the surface moves.
    moving = cloud["moving"][keep] > 0
    np.testing.assert_array_equal(semantic, kitti_semantic_of_class(cloud["class"][keep], moving))
    assert {252, 40} <= set(np.unique(semantic))  # moving cars and the road are there
    # (tests/python/test_export_labels.py: the intersection's classes, and frames without `class`.)


def test_semantic_kitti_from_the_estimate(processed, tmp_path):
    run_cli("export", processed / "labels", "-o", tmp_path, "--to", "kitti")
    scan, semantic, instance = read_kitti(tmp_path)
    cloud, _ = read_pcd_numpy(processed / "labels" / "000000.pcd")
    label = cloud["label"][finite(cloud)]
    assert len(scan) == len(label)
    np.testing.assert_array_equal(semantic, np.select([label > 0, label == 0], [251, 9], 0))
    np.testing.assert_array_equal(instance, np.maximum(label, 0))
    assert (label > 0).any()


def pcl(program, *args):
    path = require_program(program, "pcl-tools")
    proc = subprocess.run([path, *map(str, args)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"{program} failed:\n{proc.stdout}\n{proc.stderr}"
    return proc


@pytest.mark.parametrize("source", ["dataset", "processed"])
def test_pcl_reads_our_pcd_and_we_read_what_pcl_writes(source, dataset, processed, tmp_path):
    original = dataset / "frames" / "000000.pcd" if source == "dataset" else processed / "labels" / "000000.pcd"
    ours, header = read_pcd_numpy(original)
    # PCL rewrites our binary PCD as ASCII, then that ASCII as binary again.
    pcl("pcl_convert_pcd_ascii_binary", original, tmp_path / "ascii.pcd", 0)
    pcl("pcl_convert_pcd_ascii_binary", tmp_path / "ascii.pcd", tmp_path / "binary.pcd", 1)
    ascii_cloud, ascii_header = read_pcd_numpy(tmp_path / "ascii.pcd")
    assert ascii_header["DATA"] == ["ascii"]
    assert ascii_header["FIELDS"] == header["FIELDS"]
    assert (ascii_header["WIDTH"], ascii_header["HEIGHT"]) == (header["WIDTH"], header["HEIGHT"])
    for name in header["FIELDS"]:
        # PCL prints floats with 7 significant digits: a relative error up to 5e-7.
        np.testing.assert_allclose(ascii_cloud[name], ours[name], rtol=6e-7, atol=1e-30, equal_nan=True,
                                   err_msg=name)
    # fmcw reads both of PCL's files: exported again as PCD, every value survives.
    for name in ("ascii", "binary"):
        run_cli("export", tmp_path / f"{name}.pcd", "-o", tmp_path / f"back_{name}", "--to", "pcd")
        back, _ = read_pcd_numpy(tmp_path / f"back_{name}" / f"{name}.pcd")
        for field in header["FIELDS"]:
            np.testing.assert_array_equal(back[field], ascii_cloud[field], err_msg=f"{name}: {field}")
    # and its motion methods run on PCL's binary file (PCL drops comment lines, so the head
    # layout is lost: one head at the origin is assumed).
    if source == "dataset":
        run_cli("process", tmp_path / "binary.pcd", "-o", tmp_path / "proc", "--method", "fast")


def test_pcl_converts_our_pcd_to_ply_for_open3d(dataset, tmp_path):
    o3d = require_module("open3d", "python3-open3d")
    original = dataset / "frames" / "000000.pcd"
    pcl("pcl_pcd2ply", original, tmp_path / "pcl.ply")
    ours, _ = read_pcd_numpy(original)
    ply = o3d.io.read_point_cloud(str(tmp_path / "pcl.ply"), remove_nan_points=True)
    assert len(ply.points) == finite(ours).sum()


def test_aeva_scan_exports_to_a_pcd_pcl_reads(tmp_path):
    record = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("reflectivity", "<f4"), ("velocity", "<f4"),
                       ("time_offset_ns", "<i4"), ("line_index", "u1")])
    r = np.zeros(200, dtype=record)
    az = np.deg2rad(np.linspace(-50, 50, 100))
    r["x"] = np.tile(20 * np.cos(az), 2)
    r["y"] = np.tile(20 * np.sin(az), 2)
    r["z"] = np.repeat([0.5, -0.5], 100)
    r["velocity"] = -5 * r["x"] / 20
    r["line_index"] = np.repeat([0, 1], 100)
    r.tofile(tmp_path / "scan.bin")
    run_cli("export", tmp_path / "scan.bin", "--format", "aeva", "-o", tmp_path / "out", "--to", "pcd")
    pcl("pcl_convert_pcd_ascii_binary", tmp_path / "out" / "scan.pcd", tmp_path / "ascii.pcd", 0)
    cloud, header = read_pcd_numpy(tmp_path / "ascii.pcd")
    assert header["HEIGHT"] == ["2"] and header["WIDTH"] == ["600"]
    assert finite(cloud).sum() == 200
