"""fmcw.Scan from numpy arrays of shape (rows, cols), heads, validation, project_points, PCD round trip."""

import os
import resource

import numpy as np
import pytest

import fmcw
from scenes import room_scan


def test_scan_from_arrays_keeps_every_value():
    s = room_scan()
    intensity = np.linspace(0, 1, s["x"].size, dtype=np.float32).reshape(s["x"].shape)
    scan = fmcw.Scan(s["x"], s["y"], s["z"], s["v"], intensity=intensity, stamp=12.5)
    assert scan.shape == (48, 160) and scan.rows == 48 and scan.cols == 160
    assert scan.stamp == 12.5
    np.testing.assert_array_equal(scan.x, s["x"])
    np.testing.assert_array_equal(scan.v, s["v"])
    np.testing.assert_array_equal(scan.intensity, intensity)
    assert scan.valid.dtype == bool and scan.valid.all()
    assert scan.num_valid == 48 * 160
    # range defaults to the distance from the head origin (here the rig origin)
    expected = np.sqrt(s["x"].astype(np.float64) ** 2 + s["y"] ** 2 + s["z"] ** 2)
    np.testing.assert_allclose(scan.range, expected, rtol=1e-6)
    assert scan.time_offset is None
    assert len(scan.heads) == 1 and scan.heads[0].col_begin == 0 and scan.heads[0].col_end == 160


def test_nan_position_is_no_return_and_valid_is_derived():
    s = room_scan()
    x = s["x"].copy()
    x[3, 7] = np.nan
    scan = fmcw.Scan(x, s["y"], s["z"], s["v"])
    assert not scan.valid[3, 7]
    assert scan.num_valid == 48 * 160 - 1
    assert np.isnan(scan.range[3, 7])


def test_heads_with_mount_poses_set_beam_origins():
    s = room_scan()
    T = np.eye(4)
    T[:3, 3] = [1.0, 0.5, 2.0]
    heads = [fmcw.Head("left", 0, 80, stitched_to_next=True), fmcw.Head("right", 80, 160, T_rig_head=T)]
    scan = fmcw.Scan(s["x"], s["y"], s["z"], s["v"], heads=heads)
    assert [h.name for h in scan.heads] == ["left", "right"]
    np.testing.assert_array_equal(scan.heads[1].origin, [1.0, 0.5, 2.0])
    np.testing.assert_array_equal(scan.heads[1].T_rig_head, T)
    p = np.array([s["x"][0, 100], s["y"][0, 100], s["z"][0, 100]], dtype=np.float64)
    assert scan.range[0, 100] == pytest.approx(np.linalg.norm(p - [1.0, 0.5, 2.0]), rel=1e-6)


def test_bad_arrays_raise_value_error_naming_the_argument():
    s = room_scan()
    with pytest.raises(ValueError, match=r"'v' has shape \(48, 159\), expected \(48, 160\)"):
        fmcw.Scan(s["x"], s["y"], s["z"], s["v"][:, :159])
    with pytest.raises(ValueError, match="'x' must have shape \\(rows, cols\\), got 1 dimensions"):
        fmcw.Scan(s["x"].ravel(), s["y"], s["z"], s["v"])
    v = s["v"].copy()
    v[2, 5] = np.inf
    with pytest.raises(ValueError, match=r"valid pixel \(row 2, col 5\) holds a NaN or Inf"):
        fmcw.Scan(s["x"], s["y"], s["z"], v)
    with pytest.raises(ValueError, match="head"):
        fmcw.Scan(s["x"], s["y"], s["z"], s["v"], heads=[fmcw.Head("a", 0, 100)])
    with pytest.raises(ValueError, match="'T_rig_head' must be a 4x4 rigid transform"):
        fmcw.Head("a", 0, 10, T_rig_head=2 * np.eye(4))


def test_project_points_puts_column_k_at_azimuth_step_k():
    az = np.deg2rad(4.5 - np.arange(10))  # pixel centres of a 10 deg grid at 1 deg
    x, y = 10 * np.cos(az), 10 * np.sin(az)
    z = np.full(10, 10 * np.tan(np.deg2rad(0.5)))
    v = np.arange(10, dtype=np.float32)
    out = fmcw.project_points(x, y, z, v, fov_h=10, res_h=1, fov_v=4, res_v=1)
    scan = out["scan"]
    assert scan.shape == (4, 10)
    assert out["placed"] == 10 and out["collisions"] == 0 and out["outside_fov"] == 0
    np.testing.assert_array_equal(scan.v[1], v)
    np.testing.assert_array_equal(out["point_of_pixel"][1], np.arange(10))
    np.testing.assert_array_equal(out["pixel_of_point"], 10 + np.arange(10))
    # scan lines instead of elevation: row = line index
    out = fmcw.project_points(x, y, z, v, line_index=np.full(10, 2), fov_h=10, res_h=1)
    assert out["rows_by_line"] and out["scan"].shape == (3, 10)
    assert out["scan"].valid[2].all()


def test_scan_round_trips_through_pcd(tmp_path):
    s = room_scan()
    scan = fmcw.Scan(s["x"], s["y"], s["z"], s["v"])
    fmcw.write_frame(str(tmp_path / "f.pcd"), scan)
    back = fmcw.read_frame(str(tmp_path / "f.pcd"))
    assert back.truth is None and back.ego is None
    for field in ("x", "y", "z", "v", "range"):
        np.testing.assert_array_equal(getattr(back.scan, field), getattr(scan, field))
    with pytest.raises(ValueError, match="missing.pcd"):
        fmcw.read_frame(str(tmp_path / "missing.pcd"))


def test_errors_are_typed_by_whose_fault_they_are(tmp_path):
    # A file that is missing or malformed: fmcw.FileError, both a ValueError and an OSError.
    with pytest.raises(fmcw.FileError, match="missing.pcd") as error:
        fmcw.read_frame(str(tmp_path / "missing.pcd"))
    assert isinstance(error.value, ValueError) and isinstance(error.value, OSError)
    (tmp_path / "bad.pcd").write_text("VERSION 0.7\nFIELDS x y z v\n")
    with pytest.raises(OSError, match="bad.pcd: PCD header has no SIZE line"):
        fmcw.read_frame(str(tmp_path / "bad.pcd"))
    # A bad argument: fmcw.InputError, a ValueError and not an OSError.
    s = room_scan()
    with pytest.raises(fmcw.InputError, match="'v' has shape") as error:
        fmcw.Scan(s["x"], s["y"], s["z"], s["v"][:, :-1])
    assert isinstance(error.value, ValueError) and not isinstance(error.value, OSError)
    with pytest.raises(fmcw.InputError, match="velocity_threshold"):
        params = fmcw.MotionPipelineParams("fast")
        params.segmentation.velocity_threshold_mps = -1.0
        fmcw.MotionPipeline(params)


def test_a_stamp_must_be_a_finite_time():
    s = room_scan()
    for bad in (float("nan"), float("inf"), -float("inf")):
        with pytest.raises(ValueError, match="stamp_s is .*, expected a finite time"):
            fmcw.Scan(s["x"], s["y"], s["z"], s["v"], stamp=bad)
    scan = fmcw.Scan(s["x"], s["y"], s["z"], s["v"], stamp=3.5)
    with pytest.raises(ValueError, match="stamp_s is nan, expected a finite time"):
        scan.stamp = float("nan")
    assert scan.stamp == 3.5


def test_project_points_refuses_a_huge_grid_without_overflow():
    x, y, z, v = (np.ones(3, dtype=np.float32) for _ in range(4))
    # A resource limit, not a bad value: fmcw.LimitError, a RuntimeError.
    with pytest.raises(fmcw.LimitError) as error:
        fmcw.project_points(x, y, z, v, res_h=1e-9)
    assert isinstance(error.value, RuntimeError) and not isinstance(error.value, ValueError)
    assert "resolution_horizontal_deg 1e-09 over fov_horizontal_deg 120 gives 1.2e+11 columns" in str(error.value)
    with pytest.raises(fmcw.LimitError) as error:
        fmcw.project_points(x, y, z, v, res_h=1e-9, res_v=1e-9)
    assert "-2147483648" not in str(error.value)


def test_read_frame_refuses_what_is_not_a_regular_file(tmp_path):
    with pytest.raises(ValueError, match="/dev/zero: is not a regular file"):
        fmcw.read_frame("/dev/zero")
    with pytest.raises(ValueError, match="is a directory"):
        fmcw.read_frame(str(tmp_path))
    with pytest.raises(ValueError, match="/dev/zero: is not a regular file"):
        fmcw.read_aeva("/dev/zero")
    # A 2 GiB file without a newline: refused from its first line, not read whole.
    big = tmp_path / "big.pcd"
    big.write_bytes(b"VERSION")
    os.truncate(big, 1 << 31)
    with pytest.raises(ValueError, match="big.pcd:1: header line too long"):
        fmcw.read_frame(str(big))
    big.unlink()
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss < 200 * 1024
