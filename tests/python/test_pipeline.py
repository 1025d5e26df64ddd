"""fmcw.MotionPipeline on numpy scans whose ego and object velocities are known."""

import numpy as np
import pytest

import fmcw
from scenes import room_scan


def make_scan(**kwargs):
    s = room_scan(**kwargs)
    return fmcw.Scan(s["x"], s["y"], s["z"], s["v"]), s


def test_methods_are_the_cores():
    assert set(fmcw.MotionPipelineParams.methods()) == {"paper", "fast", "robust", "tracked"}
    assert fmcw.MotionPipelineParams.default_method() == "tracked"
    assert fmcw.MotionPipeline().params.method == "tracked"


@pytest.mark.parametrize("method", ["fast", "paper", "robust", "tracked"])
def test_ego_velocity_and_moving_object(method):
    scan, truth = make_scan()
    result = fmcw.MotionPipeline(method, seed=1).process(scan)
    assert result.ok, result.message
    assert result.status == "ok" and result.method == method
    np.testing.assert_allclose(result.ego_velocity, truth["ego"], atol=0.03)
    np.testing.assert_array_equal(result.ego["velocity"], result.ego_velocity)
    assert result.ego["valid"] and result.ego["points_used"] >= 1000  # paper: num_th^s = 1000
    assert result.labels.shape == scan.shape and result.labels.dtype == np.int32
    # Every pixel of the box face moves, and nothing else.
    np.testing.assert_array_equal(result.moving, truth["moving"])
    assert len(result.objects) == 1
    obj = result.objects[0]
    assert obj["pixels"] == truth["moving"].sum()
    assert obj["velocity"][0] == pytest.approx(truth["obj"][0], abs=0.1)
    np.testing.assert_array_equal(result.instances, np.where(truth["moving"], obj["id"], 0))
    assert obj["centroid"][0] == pytest.approx(15.0, abs=0.01)
    # Only the tracking method gives the object a track (born on this first frame), a box centre
    # and a yaw rate.
    assert (obj["track_id"] > 0) == (method == "tracked")
    assert obj["track_hits"] == (1 if method == "tracked" else 0)
    assert np.isfinite(obj["centre"]).all() == (method == "tracked")
    assert set(result.timing) == {"clustering_ms", "ego_ms", "objects_ms", "total_ms"}


def test_params_reach_the_method():
    scan, truth = make_scan()
    params = fmcw.MotionPipelineParams("fast")
    # A threshold larger than any Doppler step joins the box to the static world.
    params.segmentation.velocity_threshold_mps = 50.0
    result = fmcw.MotionPipeline(params).process(scan)
    assert result.ok and len(result.objects) == 0 and not result.moving.any()
    params.segmentation.velocity_threshold_mps = -1.0
    with pytest.raises(ValueError, match="velocity_threshold"):
        fmcw.MotionPipeline(params)


def test_the_lateral_pull_and_the_weak_direction_rule_are_settable():
    # tracked assumes a vehicle rig (no sideways slide at the origin); robust does not.
    assert fmcw.MotionPipelineParams("tracked").ego.lateral_velocity_sigma_mps == 0.1
    assert fmcw.MotionPipelineParams("robust").ego.lateral_velocity_sigma_mps == 0.0
    params = fmcw.MotionPipelineParams("tracked")
    params.ego.lateral_velocity_sigma_mps = -1.0
    with pytest.raises(ValueError, match="lateral_velocity_sigma_mps"):
        fmcw.MotionPipeline(params)
    params = fmcw.MotionPipelineParams("robust")
    params.max_weak_sigma_mps = 0.0
    with pytest.raises(ValueError, match="max_weak_sigma_mps"):
        fmcw.MotionPipeline(params)


def test_same_seed_same_result_any_thread_count():
    scan, _ = make_scan()
    one = fmcw.MotionPipeline("paper", seed=7, num_threads=1).process(scan)
    two = fmcw.MotionPipeline("paper", seed=7, num_threads=2).process(scan)
    np.testing.assert_array_equal(one.labels, two.labels)
    np.testing.assert_array_equal(one.ego_velocity, two.ego_velocity)


def test_scan_without_returns_is_a_status_not_an_exception():
    nan = np.full((4, 6), np.nan, dtype=np.float32)
    result = fmcw.MotionPipeline("fast").process(fmcw.Scan(nan, nan, nan, nan))
    assert not result.ok and result.status == "no_valid_points"
    assert (result.labels == -1).all()


def test_unknown_method_names_the_choices():
    with pytest.raises(ValueError, match="robust"):
        fmcw.MotionPipeline("fastest")
