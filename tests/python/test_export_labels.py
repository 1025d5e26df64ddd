"""The exports a learning pipeline reads, checked on the intersection scene with numpy alone:
SemanticKITTI labels with the finer classes of the field `class`, OpenPCDet's custom-dataset
layout (points .npy, box labels, ImageSets, meta.json), PLY coloured by class, and the errors of
inputs that lack what an export needs. Only the CLI is needed, not the Python module."""

import csv
import json
import shutil

import numpy as np
import pytest

from conftest import SOURCE_DIR, run_cli
from test_export_tools import CLASS_CODES, finite, kitti_semantic_of_class, read_kitti, read_pcd_numpy

ROAD, SIDEWALK, BUILDING, VEGETATION, POLE = 40, 48, 50, 70, 80


@pytest.fixture(scope="module")
def intersection(tmp_path_factory):
    out = tmp_path_factory.mktemp("intersection")
    run_cli("simulate", SOURCE_DIR / "scenarios" / "intersection.yaml", "-o", out, "--frames", 20, "--overwrite")
    return out


def frame_ids(dataset):
    return sorted(p.stem for p in (dataset / "frames").glob("*.pcd"))


def objects_rows(dataset):
    with open(dataset / "objects.csv", newline="") as f:
        return list(csv.DictReader(f))


def drop_pcd_field(src, dst, name):
    """Writes the binary PCD src to dst without the field name: a frame as datasets wrote them
    before that field existed."""
    with open(src, "rb") as f:
        lines = []
        while not lines or not lines[-1].startswith(b"DATA"):
            lines.append(f.readline())
        body = f.read()
    header = {line.split()[0].decode(): [w.decode() for w in line.split()[1:]] for line in lines
              if line.split() and not line.startswith(b"#")}
    assert header["DATA"] == ["binary"]
    names = header["FIELDS"]
    dtype = np.dtype([(n, {"F": "<f", "U": "<u", "I": "<i"}[t] + s)
                      for n, t, s in zip(names, header["TYPE"], header["SIZE"])])
    data = np.frombuffer(body, dtype=dtype, count=int(header["POINTS"][0]))
    k = names.index(name)
    out = []
    for line in lines:
        words = line.split()
        if words and words[0].decode() in ("FIELDS", "SIZE", "TYPE", "COUNT"):
            del words[1 + k]
            line = b" ".join(words) + b"\n"
        out.append(line)
    kept = np.empty(len(data), dtype=[(n, dtype[n]) for n in names if n != name])
    for n in kept.dtype.names:
        kept[n] = data[n]
    dst.write_bytes(b"".join(out) + kept.tobytes())


@pytest.fixture(scope="module")
def old_dataset(intersection, tmp_path_factory):
    """The intersection dataset as written before classes and boxes: frames without `class`,
    objects.csv with its first 21 columns."""
    out = tmp_path_factory.mktemp("old")
    (out / "frames").mkdir()
    shutil.copy(intersection / "dataset.yaml", out)
    frames = sorted((intersection / "frames").glob("*.pcd"))[:2]
    for pcd in frames:
        drop_pcd_field(pcd, out / "frames" / pcd.name, "class")
    ego = (intersection / "ego.csv").read_text().splitlines(True)
    (out / "ego.csv").write_text("".join(ego[:1 + len(frames)]))
    objects = (intersection / "objects.csv").read_text().splitlines()
    (out / "objects.csv").write_text("".join(",".join(line.split(",")[:21]) + "\n" for line in objects
                                             if line.startswith("frame") or int(line.split(",")[0]) < len(frames)))
    return out


@pytest.fixture(scope="module")
def processed(intersection, tmp_path_factory):
    out = tmp_path_factory.mktemp("processed")
    run_cli("process", intersection / "frames" / "000005.pcd", "-o", out, "--method", "fast")
    return out


# --- SemanticKITTI -----------------------------------------------------------------------------

def test_semantic_kitti_labels_carry_the_classes_of_every_pixel(intersection, tmp_path):
    run_cli("export", intersection, "-o", tmp_path, "--to", "kitti")
    seen = set()
    for stem in frame_ids(intersection):
        scan, semantic, instance = read_kitti(tmp_path, stem)
        cloud, _ = read_pcd_numpy(intersection / "frames" / f"{stem}.pcd")
        keep = finite(cloud)
        assert len(scan) == keep.sum()
        np.testing.assert_array_equal(instance, cloud["instance"][keep])
        np.testing.assert_array_equal(semantic, kitti_semantic_of_class(cloud["class"][keep], cloud["moving"][keep] > 0),
                                      err_msg=stem)
        classes = set(np.unique(semantic).tolist())
        assert len(classes) >= 5, (stem, classes)
        assert {ROAD, BUILDING, VEGETATION, POLE} <= classes, (stem, classes)
        seen |= classes
    # The static world's classes, and actors still and moving: parked car 12 is 10, the
    # truck driving off 258, walking pedestrians 254.
    assert {ROAD, SIDEWALK, BUILDING, VEGETATION, POLE, 10, 258, 254} <= seen, seen
    assert 9 not in seen  # the coarse "static" is gone where classes are known


def test_semantic_kitti_of_frames_without_class_keeps_the_coarse_mapping(old_dataset, tmp_path):
    run_cli("export", old_dataset, "-o", tmp_path, "--to", "kitti")
    names = {int(r["id"]): r["class"] for r in objects_rows(old_dataset)}
    for stem in frame_ids(old_dataset):
        _, semantic, instance = read_kitti(tmp_path, stem)
        cloud, _ = read_pcd_numpy(old_dataset / "frames" / f"{stem}.pcd")
        assert "class" not in cloud
        moving = cloud["moving"][finite(cloud)] > 0
        expected = np.where(moving, 251, 9).astype(np.uint32)
        for actor, name in names.items():
            here = instance == actor
            still, in_motion = CLASS_CODES.get(name, (99, 251))
            expected[here] = np.where(moving[here], in_motion, still)
        np.testing.assert_array_equal(semantic, expected)


# --- OpenPCDet ---------------------------------------------------------------------------------

def test_openpcdet_layout_numpy_reads(intersection, tmp_path):
    run_cli("export", intersection, "-o", tmp_path, "--to", "openpcdet")
    ids = frame_ids(intersection)
    assert (tmp_path / "ImageSets" / "train.txt").read_text().split("\n") == ids + [""]
    rows = objects_rows(intersection)
    meta = json.loads((tmp_path / "meta.json").read_text())
    first_seen = list(dict.fromkeys(r["class"] for r in rows))
    assert meta["classes"] == first_seen
    assert meta["point_features"] == ["x", "y", "z", "intensity", "v"]
    assert sorted(meta["frames"]) == ids
    boxes_total = 0
    for k, stem in enumerate(ids):
        # Points: an .npy numpy loads, float32 (N, 5) over the valid returns, rig frame.
        path = tmp_path / "points" / f"{stem}.npy"
        with open(path, "rb") as f:
            assert np.lib.format.read_magic(f) == (1, 0)
            np.lib.format.read_array_header_1_0(f)
            assert f.tell() % 64 == 0
        points = np.load(path)
        cloud, _ = read_pcd_numpy(intersection / "frames" / f"{stem}.pcd")
        keep = finite(cloud)
        assert points.dtype == np.float32 and points.shape == (keep.sum(), 5)
        np.testing.assert_array_equal(points, np.stack([cloud[c][keep] for c in ("x", "y", "z", "intensity", "v")], 1))
        # Labels: parsed as OpenPCDet's custom dataset does, one box per actor with pixels.
        lines = (tmp_path / "labels" / f"{stem}.txt").read_text().splitlines()
        assert all(len(line.strip().split(" ")) == 8 for line in lines)
        seen = [r for r in rows if int(r["frame"]) == k and int(r["pixels"]) > 0]
        assert len(lines) == len(seen)
        if seen:
            gt_boxes = np.array([line.strip().split(" ")[:-1] for line in lines], dtype=np.float32)
            gt_names = [line.strip().split(" ")[-1] for line in lines]
            assert gt_boxes.shape == (len(seen), 7)
            assert gt_names == [r["class"] for r in seen]
            columns = ["box_x_m", "box_y_m", "box_z_m", "box_length_m", "box_width_m", "box_height_m", "box_yaw_rad"]
            expected = np.array([[float(r[c]) for c in columns] for r in seen])
            np.testing.assert_allclose(gt_boxes, expected, rtol=1e-6, atol=1e-6)
        # meta.json: the rest of each box, in label line order.
        frame = meta["frames"][stem]
        assert frame["frame"] == k
        assert [b["actor_id"] for b in frame["boxes"]] == [int(r["id"]) for r in seen]
        for box, r in zip(frame["boxes"], seen):
            np.testing.assert_allclose(box["velocity_mps"], [float(r[c]) for c in ("box_vx_mps", "box_vy_mps", "box_vz_mps")],
                                       rtol=1e-12)
            assert box["visible_fraction"] == pytest.approx(float(r["visible_fraction"]), rel=1e-12)
            assert box["truncated"] == (r["truncated"] == "1")
            assert box["class"] == r["class"]
            assert box["pixels"] == int(r["pixels"])
        boxes_total += len(seen)
    assert boxes_total > 20
    moving = [b for f in meta["frames"].values() for b in f["boxes"] if np.linalg.norm(b["velocity_mps"]) > 1]
    assert moving  # the truck drives off, pedestrians walk


# --- PLY coloured by class ---------------------------------------------------------------------

PLY_TYPES = {"float": "<f4", "double": "<f8", "uchar": "u1", "ushort": "<u2", "uint": "<u4", "char": "i1",
             "short": "<i2", "int": "<i4"}


def read_ply_numpy(path):
    """This test's own reader of binary little-endian PLY vertices."""
    with open(path, "rb") as f:
        header = []
        while not header or header[-1] != "end_header":
            header.append(f.readline().decode("ascii").strip())
        body = f.read()
    assert header[1] == "format binary_little_endian 1.0"
    n = int(next(line.split()[2] for line in header if line.startswith("element vertex")))
    dtype = np.dtype([(line.split()[2], PLY_TYPES[line.split()[1]]) for line in header if line.startswith("property")])
    assert len(body) == n * dtype.itemsize
    return np.frombuffer(body, dtype=dtype, count=n)


def test_ply_coloured_by_class(intersection, tmp_path):
    run_cli("export", intersection / "frames" / "000005.pcd", "-o", tmp_path, "--to", "ply", "--color", "class")
    ply = read_ply_numpy(tmp_path / "000005.ply")
    cloud, _ = read_pcd_numpy(intersection / "frames" / "000005.pcd")
    np.testing.assert_array_equal(ply["class"], cloud["class"][finite(cloud)])
    rgb = np.stack([ply["red"], ply["green"], ply["blue"]], 1)
    colour_of = {}
    for c in np.unique(ply["class"]):
        colours = np.unique(rgb[ply["class"] == c], axis=0)
        assert len(colours) == 1, f"class {c} has {len(colours)} colours"  # the same class, the same colour
        colour_of[int(c)] = tuple(colours[0])
    assert len(colour_of) >= 5
    assert len(set(colour_of.values())) == len(colour_of), colour_of  # different classes, different colours
    # docs/FORMATS.md: SemanticKITTI's palette, e.g. road magenta, vegetation green.
    assert colour_of[ROAD] == (255, 0, 255) and colour_of[VEGETATION] == (0, 175, 0)


# --- What an export needs and does not find ----------------------------------------------------

def expect_one_error(args, output, *parts):
    proc = run_cli(*args, expect_ok=False)
    assert proc.returncode == 3, proc.stderr  # the input's fault: a file missing or without what is needed
    errors = [line for line in proc.stderr.splitlines() if line.startswith("fmcw: error: ")]
    assert len(errors) == 1, proc.stderr
    for part in parts:
        assert str(part) in errors[0], errors[0]
    assert not output.exists(), "a failed export left files behind"


def test_openpcdet_of_a_cloud_without_truth(intersection, processed, tmp_path):
    lone = processed / "labels" / "000005.pcd"
    expect_one_error(["export", lone, "-o", tmp_path / "a", "--to", "openpcdet"], tmp_path / "a", lone,
                     "not a dataset folder")
    expect_one_error(["export", processed / "labels", "-o", tmp_path / "b", "--to", "openpcdet"], tmp_path / "b",
                     processed / "labels" / "dataset.yaml", "missing")
    frame = intersection / "frames" / "000000.pcd"  # a dataset's frame alone: no boxes either
    expect_one_error(["export", frame, "-o", tmp_path / "c", "--to", "openpcdet"], tmp_path / "c", frame,
                     "not a dataset folder")


def test_openpcdet_of_a_dataset_written_before_boxes(old_dataset, tmp_path):
    expect_one_error(["export", old_dataset, "-o", tmp_path / "out", "--to", "openpcdet"], tmp_path / "out",
                     old_dataset / "objects.csv", "no box columns")


def test_colour_by_class_of_a_cloud_without_class(old_dataset, processed, tmp_path):
    lone = processed / "labels" / "000005.pcd"
    expect_one_error(["export", lone, "-o", tmp_path / "a", "--to", "ply", "--color", "class"], tmp_path / "a", lone,
                     "no field 'class'")
    expect_one_error(["export", old_dataset, "-o", tmp_path / "b", "--to", "ply", "--color", "class"], tmp_path / "b",
                     old_dataset / "frames" / "000000.pcd", "no field 'class'")


def test_a_frame_that_fails_midway_takes_back_what_the_export_wrote(intersection, processed, tmp_path):
    mixed = tmp_path / "mixed"
    mixed.mkdir()
    shutil.copy(intersection / "frames" / "000000.pcd", mixed / "a.pcd")
    shutil.copy(processed / "labels" / "000005.pcd", mixed / "b.pcd")  # no `class`
    out = tmp_path / "out"
    out.mkdir()
    (out / "mine.txt").write_text("kept")
    expect_one_error(["export", mixed, "-o", out / "ply", "--to", "ply", "--color", "class"], out / "ply",
                     mixed / "b.pcd", "no field 'class'")
    assert sorted(p.name for p in out.iterdir()) == ["mine.txt"]
