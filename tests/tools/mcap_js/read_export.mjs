// Reads an `fmcw export --to mcap` file with Foxglove's own MCAP and ROS 2 libraries (not the
// project's reader): counts the messages per topic, decodes one PointCloud2 with the schema the
// file embeds, and checks its shape, its fields and one point against the frame's PCD file.
//   node read_export.mjs FILE.mcap FRAME.pcd FRAMES FRAME_INDEX
import { open } from "node:fs/promises";
import { readFileSync } from "node:fs";
import { McapIndexedReader } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import { decompress } from "fzstd";

const [mcapPath, pcdPath, framesArg, indexArg] = process.argv.slice(2);
const frames = Number(framesArg);
const frameIndex = Number(indexArg);
let failures = 0;
function check(ok, what) {
  console.log(`${ok ? "ok  " : "FAIL"} ${what}`);
  if (!ok) failures += 1;
}

// The PCD frame: header lines, then binary points (fields interleaved, little endian).
function readPcd(path) {
  const bytes = readFileSync(path);
  const end = bytes.indexOf("DATA binary\n") + "DATA binary\n".length;
  const header = {};
  for (const line of bytes.subarray(0, end).toString("latin1").split("\n")) {
    if (!line || line.startsWith("#")) continue;
    const [key, ...values] = line.split(" ");
    header[key] = values;
  }
  const fields = header.FIELDS;
  const sizes = header.SIZE.map(Number);
  const offsets = sizes.map((_, k) => sizes.slice(0, k).reduce((a, b) => a + b, 0));
  const step = sizes.reduce((a, b) => a + b, 0);
  const view = new DataView(bytes.buffer, bytes.byteOffset + end);
  return {
    fields,
    width: Number(header.WIDTH[0]),
    height: Number(header.HEIGHT[0]),
    float: (point, name) => view.getFloat32(point * step + offsets[fields.indexOf(name)], true),
  };
}

const handle = await open(mcapPath, "r");
const readable = {
  size: async () => BigInt((await handle.stat()).size),
  read: async (offset, length) => {
    const buf = Buffer.alloc(Number(length));
    await handle.read(buf, 0, Number(length), Number(offset));
    return new Uint8Array(buf.buffer, buf.byteOffset, buf.length);
  },
};
const reader = await McapIndexedReader.Initialize({
  readable,
  decompressHandlers: { zstd: (data, size) => decompress(data, new Uint8Array(Number(size))) },
});

// Messages per topic, counted by reading them all (and as the summary's statistics say).
const topicOf = new Map([...reader.channelsById.values()].map((c) => [c.id, c.topic]));
const counts = {};
const picked = {};  // the frame's message of each topic (the first of /tf_static)
for await (const m of reader.readMessages()) {
  const topic = topicOf.get(m.channelId);
  counts[topic] = (counts[topic] ?? 0) + 1;
  if (counts[topic] - 1 === (topic === "/tf_static" ? 0 : frameIndex)) picked[topic] = m;
}
const cloudMessage = picked["/points"];
console.log("messages per topic:", JSON.stringify(counts));
check(counts["/points"] === frames, `/points has ${counts["/points"]} messages, one per frame (${frames})`);
check(counts["/tf"] === frames, `/tf has ${counts["/tf"]} messages (world -> rig per frame)`);
check(counts["/markers/truth"] === frames, `/markers/truth has ${counts["/markers/truth"]} messages`);
check(counts["/tf_static"] === 1, `/tf_static has ${counts["/tf_static"]} message`);
const stats = reader.statistics;
const pointsChannel = [...reader.channelsById.values()].find((c) => c.topic === "/points");
check(Number(stats.channelMessageCounts.get(pointsChannel.id)) === frames, "the summary's statistics agree");
check(reader.chunkIndexes.length === frames, `${reader.chunkIndexes.length} chunk indexes, one per frame`);

// One PointCloud2, decoded through the ros2msg schema embedded in the file.
const schema = reader.schemasById.get(pointsChannel.schemaId);
check(schema.name === "sensor_msgs/msg/PointCloud2" && schema.encoding === "ros2msg", `schema ${schema.name} (${schema.encoding})`);
check(pointsChannel.messageEncoding === "cdr", `message encoding ${pointsChannel.messageEncoding}`);
const definitions = parse(new TextDecoder().decode(schema.data), { ros2: true });
const cloud = new MessageReader(definitions).readMessage(cloudMessage.data);
const pcd = readPcd(pcdPath);
check(cloud.width === pcd.width && cloud.height === pcd.height,
  `width x height ${cloud.width} x ${cloud.height}, the PCD's ${pcd.width} x ${pcd.height}`);
const names = cloud.fields.map((f) => f.name);
check(names.join(" ") === pcd.fields.join(" "), `fields [${names.join(" ")}] are the PCD's`);
check(cloud.header.frame_id === "rig", `frame_id ${cloud.header.frame_id}`);
const view = new DataView(cloud.data.buffer, cloud.data.byteOffset, cloud.data.byteLength);
const offset = Object.fromEntries(cloud.fields.map((f) => [f.name, f.offset]));
const value = (point, name) => view.getFloat32(point * cloud.point_step + offset[name], !cloud.is_bigendian);
// The middle row's first return, then compare x y z v bit for bit (float32 both sides).
let point = -1;
const row = Math.floor(cloud.height / 2);
for (let c = 0; c < cloud.width && point < 0; ++c) {
  if (Number.isFinite(value(row * cloud.width + c, "x"))) point = row * cloud.width + c;
}
check(point >= 0, `a return in row ${row} (point ${point})`);
for (const name of ["x", "y", "z", "v"]) {
  const a = value(point, name);
  const b = pcd.float(point, name);
  check(Object.is(a, b), `point ${point} ${name} = ${a}, the PCD has ${b}`);
}

// The transforms and the markers decode through their embedded schemas too, field for field.
function decode(topic) {
  const channel = [...reader.channelsById.values()].find((c) => c.topic === topic);
  const s = reader.schemasById.get(channel.schemaId);
  return new MessageReader(parse(new TextDecoder().decode(s.data), { ros2: true })).readMessage(picked[topic].data);
}
const tf = decode("/tf");
check(tf.transforms.length === 1 && tf.transforms[0].header.frame_id === "world" && tf.transforms[0].child_frame_id === "rig",
  `/tf: ${tf.transforms.map((t) => `${t.header.frame_id} -> ${t.child_frame_id}`).join(", ")}`);
const q = tf.transforms[0].transform.rotation;
check(Math.abs(Math.hypot(q.x, q.y, q.z, q.w) - 1) < 1e-9, "/tf: a unit quaternion");
const mounts = decode("/tf_static").transforms;
check(mounts.length >= 1 && mounts.every((t) => t.header.frame_id === "rig"),
  `/tf_static: rig -> ${mounts.map((t) => t.child_frame_id).join(", ")}`);
const markers = decode("/markers/truth").markers;
check(markers.length >= 1 && markers[0].action === 3, `/markers/truth: ${markers.length} markers, the first DELETEALL`);
const boxes = markers.filter((m) => m.ns === "truth_boxes");
const arrows = markers.filter((m) => m.ns === "truth_velocity");
check(boxes.every((m) => m.type === 1 && m.scale.x > 0 && m.header.frame_id === "rig") && boxes.length > 0,
  `${boxes.length} boxes (CUBE, in rig)`);
check(arrows.every((m) => m.type === 0 && m.points.length === 2) && arrows.length >= boxes.length,
  `${arrows.length} velocity arrows of two points each`);
check(markers.every((m) => m.text === "" && m.mesh_use_embedded_materials === false && m.uv_coordinates.length === 0),
  "every marker decodes to its last field");

await handle.close();
if (failures > 0) {
  console.log(`${failures} check(s) failed`);
  process.exit(1);
}
console.log("all checks passed");
