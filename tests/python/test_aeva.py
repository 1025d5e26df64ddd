"""Aeva Aeries II scans written by numpy in the documented little-endian layout, read by fmcw."""

import numpy as np
import pytest

import fmcw
from scenes import room_scan

RECORD_25 = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("reflectivity", "<f4"), ("velocity", "<f4"),
                      ("time_offset_ns", "<i4"), ("line_index", "u1")])
RECORD_29 = np.dtype(RECORD_25.descr + [("intensity", "<f4")])


def records(n, dtype, seed=0):
    rng = np.random.default_rng(seed)
    r = np.zeros(n, dtype=dtype)
    for name in ("x", "y", "z", "reflectivity", "velocity"):
        r[name] = rng.normal(0, 20, n)
    r["x"] = np.abs(r["x"]) + 1
    r["time_offset_ns"] = rng.integers(-(2 ** 31), 2 ** 31 - 1, n)
    r["line_index"] = rng.integers(0, 64, n)
    if "intensity" in dtype.names:
        r["intensity"] = rng.uniform(0, 1, n)
    return r


def test_record_sizes_are_the_documented_ones():
    assert RECORD_25.itemsize == 25 and RECORD_29.itemsize == 29


@pytest.mark.parametrize("dtype", [RECORD_25, RECORD_29])
def test_every_field_reads_back_bit_for_bit(tmp_path, dtype):
    r = records(101, dtype)
    path = tmp_path / "scan.bin"
    r.tofile(path)
    back = fmcw.read_aeva(str(path), str(dtype.itemsize))
    assert set(back) == set(dtype.names)
    for name in dtype.names:
        np.testing.assert_array_equal(back[name], r[name], err_msg=name)
    auto = fmcw.read_aeva(str(path))  # 101 records: only one layout fits the size
    np.testing.assert_array_equal(auto["x"], r["x"])


def test_scan_is_organized_by_line_and_azimuth(tmp_path):
    # Three points on line 5 at azimuth +59.9, 0.1 and -59.9 deg, and a farther point colliding
    # with the middle one.
    az = np.deg2rad([59.9, 0.1, -59.9, 0.1])
    rng = np.array([10.0, 12.0, 14.0, 30.0])
    r = np.zeros(4, dtype=RECORD_25)
    r["x"], r["y"], r["z"] = rng * np.cos(az), rng * np.sin(az), 0.5
    r["velocity"] = [1, 2, 3, 4]
    r["line_index"] = 5
    r["reflectivity"] = 0.25
    path = tmp_path / "1700000000000000000.bin"
    r.tofile(path)
    out = fmcw.read_aeva_scan(str(path))
    scan = out["scan"]
    assert scan.shape == (6, 600)  # lines 0..5; 120 deg at 0.2 deg
    assert scan.stamp == pytest.approx(1.7e9)
    assert out["placed"] == 3 and out["collisions"] == 1 and out["outside_fov"] == 0
    assert scan.v[5, 0] == 1 and scan.v[5, 299] == 2 and scan.v[5, 599] == 3
    assert scan.intensity[5, 0] == pytest.approx(0.25)  # reflectivity when there is no intensity
    np.testing.assert_array_equal(out["pixel_of_point"], [5 * 600, 5 * 600 + 299, 5 * 600 + 599, -1])
    assert scan.time_offset is not None
    assert fmcw.read_aeva_scan(str(path), negate_velocity=True)["scan"].v[5, 0] == -1


def test_pipeline_on_an_aeva_scan(tmp_path):
    s = room_scan(rows=48, cols=600, fov_h=120.0, fov_v=24.0)
    rows, cols = s["x"].shape
    r = np.zeros(rows * cols, dtype=RECORD_29)
    for name in ("x", "y", "z"):
        r[name] = s[name].ravel()
    r["velocity"] = s["v"].ravel()
    r["line_index"] = np.repeat(np.arange(rows), cols)
    order = np.random.default_rng(2).permutation(r.size)  # a sensor's order is not the image's
    r[order].tofile(tmp_path / "scan.bin")
    out = fmcw.read_aeva_scan(str(tmp_path / "scan.bin"), layout="29")
    assert out["placed"] == rows * cols and out["collisions"] == 0
    np.testing.assert_array_equal(out["scan"].v, s["v"])
    result = fmcw.MotionPipeline("fast").process(out["scan"])
    np.testing.assert_allclose(result.ego_velocity, s["ego"], atol=0.03)


def test_bad_files_name_the_problem(tmp_path):
    r = records(10, RECORD_25)
    path = tmp_path / "scan.bin"
    path.write_bytes(r.tobytes()[:-3])
    with pytest.raises(ValueError, match=r"size 247 bytes is not a multiple of the 25-byte Aeva record"):
        fmcw.read_aeva(str(path), "25")
    with pytest.raises(ValueError, match="neither 25-byte .* nor 29-byte"):
        fmcw.read_aeva(str(path))
    r["velocity"][4] = np.nan
    r.tofile(path)
    with pytest.raises(ValueError, match=r"record 4 \(byte 116\): field 'velocity' is nan"):
        fmcw.read_aeva(str(path))
    r = records(10, RECORD_25)
    r["line_index"][7] = 70
    r.tofile(path)
    with pytest.raises(ValueError, match=r"record 7: line_index 70 is out of range \[0, 64\)"):
        fmcw.read_aeva_scan(str(path), lines=64)
    (tmp_path / "empty.bin").write_bytes(b"")
    with pytest.raises(ValueError, match="empty Aeva file"):
        fmcw.read_aeva(str(tmp_path / "empty.bin"))
    both = np.zeros(29 * 25, dtype=RECORD_25)  # 725 * 25 bytes: a multiple of 29 too
    both.tofile(path)
    with pytest.raises(ValueError, match="fits both 25- and 29-byte"):
        fmcw.read_aeva(str(path))
    stamped = tmp_path / "1691936557946849180.bin"  # after the datasets' switch to 29 bytes
    both.tofile(stamped)
    assert "intensity" in fmcw.read_aeva(str(stamped))
