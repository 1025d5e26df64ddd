#!/usr/bin/env bash
# The controls of docs/RELIABILITY.md ("Data safety and limits"): cases 1, 2, 3, 6, 7 and 8 run
# against one fmcw binary, printing what each did. Not part of the test suite (the old binary
# crashes and allocates gigabytes); run it with an old and a new build side by side:
#   bash tests/reliability/controls.sh OLD/bin/fmcw /tmp/old; bash tests/reliability/controls.sh build/bin/fmcw /tmp/new
F=$(realpath "$1"); W=$2; A=$(cd "$(dirname "$0")/../.." && pwd)/assets
rm -rf "$W"; mkdir -p "$W"; cd "$W"; W=$(pwd)
cat > small.yaml <<Y
name: small
frames: 6
rate_hz: 10
seed: 5
rig:
  heads:
    - {name: front, mount: {x: 1.4, z: 1.6}, fov_deg: [60, 20], resolution_deg: [0.5, 0.5]}
measurement: {model: gaussian, range_sigma_m: 0.025, velocity_sigma_mps: 0.031}
ground: {z_m: 0, half_size_m: 200, reflectivity: 0.12}
ego:
  trajectory: {type: constant_velocity, pose: {x: 0}, velocity_mps: [8, 0, 0]}
static:
  - {mesh: $A/building_block.gltf, pose: {x: 40, y: 12}}
actors:
  - {id: 1, class: car, mesh: $A/car.gltf, trajectory: {type: waypoints, points: [[30, -10], [30, 40]], speed_mps: 6}}
Y
echo "== case 1: merge A B -o A --overwrite"
$F simulate small.yaml -o a --shard 0/2 >/dev/null 2>&1; $F simulate small.yaml -o b --shard 1/2 >/dev/null 2>&1
n0=$(ls a/frames | wc -l); $F merge a b -o a --overwrite 2>&1 | tail -1; echo "exit ${PIPESTATUS[0]}; a/frames before $n0 files, after $(ls a/frames 2>/dev/null | wc -l); a/dataset.yaml $(test -f a/dataset.yaml && echo present || echo GONE)"
echo "== case 2: two writers, different seeds"
sed 's/frames: 6/frames: 300/' small.yaml > long.yaml
$F simulate long.yaml -o d --overwrite --seed 1 --threads 1 > w1.log 2>&1 & p=$!; sleep 0.5
$F simulate long.yaml -o d --overwrite --seed 2 --threads 1 > w2.log 2>&1; e2=$?; wait $p; e1=$?
echo "first exit $e1, second exit $e2: $(tail -1 w2.log)"; grep -E "seed:|complete" d/dataset.yaml | head -3
echo "== case 3: a class named 'fork,lift'"
echo 'classes: {"fork,lift": 300}' > classes.yaml
sed "s|name: small|name: small\nclasses: $W/classes.yaml|; s|class: car|class: \"fork,lift\"|" small.yaml > c.yaml
$F simulate c.yaml -o c 2>&1 | tail -1; echo "simulate exit ${PIPESTATUS[0]}"
$F evaluate c -o ce --no-figures 2>&1 | tail -1; echo "evaluate exit ${PIPESTATUS[0]}"
echo "== case 6: --threads 100000"
$F simulate small.yaml -o t --threads 100000 2>&1 | tail -1; echo "exit ${PIPESTATUS[0]}"
echo "== case 7: ego pose x 1e39"
sed 's/pose: {x: 0}/pose: {x: 1e39}/' small.yaml > far.yaml
$F simulate far.yaml -o far 2>&1 | tail -1; echo "exit ${PIPESTATUS[0]}; far/ $(ls far/frames 2>/dev/null | wc -l) frames left"
echo "== case 8: repeat 100000 (memory capped at 3 GB, 120 s)"
sed 's|pose: {x: 40, y: 12}}|pose: {x: 40, y: 12}, repeat: {count: 100000, dx: 0.01}}|' small.yaml > rep.yaml
( ulimit -v 3000000; /usr/bin/time -f "peak %M KB, %e s" timeout 120 $F simulate rep.yaml -o rep 2>&1 | tail -3 );
