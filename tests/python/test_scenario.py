"""A scenario simulated from Python: frames and ground truth as arrays, and the pipeline's ego
velocity checked against the simulator's truth."""

import numpy as np
import pytest

import fmcw
from conftest import SOURCE_DIR, run_cli

STRAIGHT_ROAD = str(SOURCE_DIR / "scenarios" / "straight_road.yaml")


@pytest.fixture(scope="module")
def scenario():
    return fmcw.Scenario(STRAIGHT_ROAD, frames=3)


def test_scenario_metadata(scenario):
    assert len(scenario) == 3
    assert scenario.name == "straight_road"
    assert scenario.rate_hz == 10.0 and scenario.seed == 3
    assert "straight_road" in scenario.config_yaml
    assert len(fmcw.Scenario(STRAIGHT_ROAD, frames=2, seed=9)) == 2
    assert fmcw.Scenario(STRAIGHT_ROAD, frames=1, seed=9).seed == 9


def test_frame_arrays_and_truth(scenario):
    frame = scenario.frame(1)
    scan = frame.scan
    assert scan.shape == (150, 600)  # Table I rig: three 200 x 150 heads
    assert len(scan.heads) == 3
    truth = frame.truth
    assert truth["velocity"].shape == (150, 600, 3)
    assert truth["instance"].dtype == np.uint32 and truth["moving"].dtype == bool
    # Noise-free Doppler is within a few sigma of the measured one on valid pixels.
    valid = scan.valid
    assert np.abs(scan.v[valid] - truth["v"][valid]).max() < 0.031 * 7
    assert truth["moving"][valid].any()
    assert (truth["instance"][truth["moving"]] > 0).all()
    assert frame.ego["stamp"] == pytest.approx(0.1)
    assert frame.ego["T_world_rig"].shape == (4, 4)
    ids = {a["id"] for a in frame.actors}
    assert set(np.unique(truth["instance"][valid])) - {0} <= ids
    assert {a["class"] for a in frame.actors} >= {"car", "van"}


@pytest.mark.parametrize("method", ["robust", "fast"])
def test_pipeline_ego_velocity_matches_truth(scenario, method):
    frame = scenario.frame(2)
    truth = frame.ego["velocity"]
    assert truth[0] == pytest.approx(10.0, abs=1e-6)  # the scenario drives straight at 10 m/s
    result = fmcw.MotionPipeline(method).process(frame.scan)
    assert result.ok, result.message
    np.testing.assert_allclose(result.ego_velocity, truth, atol=0.01)
    assert len(result.objects) >= 1


def test_robust_method_follows_a_turning_ego():
    # Frame 40 of the turning scenario: the rig yaws at about -0.33 rad/s.
    frame = fmcw.Scenario(str(SOURCE_DIR / "scenarios" / "turn_and_straight_road.yaml")).frame(40)
    truth = frame.ego
    assert truth["angular_velocity"][2] < -0.3
    result = fmcw.MotionPipeline("robust").process(frame.scan)
    assert result.ok and result.ego["yaw_rate_estimated"]
    np.testing.assert_allclose(result.ego_velocity, truth["velocity"], atol=0.01)
    assert result.ego["angular_velocity"][2] == pytest.approx(truth["angular_velocity"][2], abs=0.01)


def test_frames_match_the_dataset_the_cli_writes(scenario, tmp_path):
    run_cli("simulate", STRAIGHT_ROAD, "-o", tmp_path / "ds", "--frames", 2)
    on_disk = fmcw.read_frame(str(tmp_path / "ds" / "frames" / "000001.pcd"))
    in_memory = scenario.frame(1)
    for field in ("x", "y", "z", "v", "range", "intensity"):
        np.testing.assert_array_equal(getattr(on_disk.scan, field), getattr(in_memory.scan, field), err_msg=field)
    np.testing.assert_array_equal(on_disk.truth["instance"], in_memory.truth["instance"])


def test_errors(scenario, tmp_path):
    with pytest.raises(IndexError, match="frame 3 of a scenario with 3 frames"):
        scenario.frame(3)
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: x\nframes: -2\n")
    with pytest.raises(ValueError, match="bad.yaml"):
        fmcw.Scenario(str(bad))


def test_imported_animation_moves_and_unplayed_clips_are_noted():
    crosswalk = fmcw.Scenario(str(SOURCE_DIR / "scenarios" / "crosswalk.yaml"), frames=20)
    # Actor 8 is a skinned walker with animate: false: its clips are noted, once.
    assert len(crosswalk.notices) == 1
    assert "walker_skinned.gltf" in crosswalk.notices[0] and "animate: false" in crosswalk.notices[0]
    assert fmcw.Scenario(STRAIGHT_ROAD, frames=1).notices == []
    frame = crosswalk.frame(15)
    instance = np.asarray(frame.truth["instance"])
    moving = np.asarray(frame.truth["moving"]).astype(bool)
    # The skinned walkers crossing (ids 2, 5, 6 walk from the start) have moving pixels; the statue none.
    for walker in (2, 5, 6):
        assert np.count_nonzero(moving & (instance == walker)) > 20, walker
    assert np.count_nonzero(instance == 8) > 20
    assert np.count_nonzero(moving & (instance == 8)) == 0



def test_boxes_and_classes_as_arrays():
    intersection = fmcw.Scenario(str(SOURCE_DIR / "scenarios" / "intersection.yaml"), frames=40)
    frame = intersection.frame(30)
    truth = frame.truth
    n = len(frame.actors)
    assert truth["boxes"].shape == (n, 7) and truth["box_velocity"].shape == (n, 3)
    assert truth["class"].dtype == np.uint16 and truth["class"].shape == (150, 600)
    assert list(truth["box_id"]) == [a["id"] for a in frame.actors]
    assert np.all((truth["visible_fraction"] >= 0) & (truth["visible_fraction"] <= 1))
    # The truck (id 4) drives straight along x: its box is 9 m long, heading 0, at its speed.
    truck = list(truth["box_id"]).index(4)
    assert truth["boxes"][truck, 3] == pytest.approx(9.0, abs=0.01)
    assert truth["boxes"][truck, 6] == pytest.approx(0.0, abs=1e-9)
    assert truth["box_velocity"][truck] == pytest.approx(frame.actors[truck]["velocity"], abs=1e-9)
    # Every pixel of an actor carries the actor's class: car 10, van 100, truck 18, pedestrian 30, ...
    instance = np.asarray(truth["instance"])
    assert set(np.unique(truth["class"][instance == 4])) == {18}
    assert {40, 48, 50, 70, 80} <= set(np.unique(truth["class"]).tolist())
