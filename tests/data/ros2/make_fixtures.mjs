// Writes the ROS 2 bag fixtures of tests/io/ros2_bag_test.cc with libraries that share no code
// with splam: @mcap/core (MCAP, chunks compressed by @bokuweb/zstd-wasm and lz4js),
// @foxglove/rosmsg2-serialization (CDR) and sql.js (SQLite, rosbag2's .db3 schema).
//   npm install && node make_fixtures.mjs
// The run they hold (the test checks splam's reading against these formulas):
//   scan i = 0..29 at t0 + 0.1 i on /scan, frame "laser": 9 beams from -2 rad by 0.5 rad, ranges
//     1 + 0.25 j + 0.01 i m, beam 4 +inf (no return), beam 7 NaN in scan 0; range 0.05-8 m;
//   odometry k = 0..30 at t0 - 0.05 + 0.1 k: pose (0.05 k, 0.02 k, yaw 0.01 k) on /odom
//     (nav_msgs/Odometry, odom -> base_link) or on /tf (odom -> base_link transforms);
//   /tf_static: base_link -> laser at (0.2, 0, 0.3), yaw 0.1;
//   /ground_truth (nav_msgs/Odometry, map -> base_link): pose (0.05 k + 0.01, 0.02 k, 0.01 k).
import fs from "node:fs";
import { McapWriter } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageWriter } from "@foxglove/rosmsg2-serialization";
import initSqlJs from "sql.js";
import lz4 from "lz4js";
import { init as zstdInit, compress as zstdCompress } from "@bokuweb/zstd-wasm";

const SEP = "\n================================================================================\n";
const TIME = "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec";
const HEADER = "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id";
const VECTOR3 = "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z";
const POINT = "MSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z";
const QUAT = "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w";
const DEFINITIONS = {
  "sensor_msgs/msg/LaserScan": [
    "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n" +
      "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n" +
      "float32[] ranges\nfloat32[] intensities",
    HEADER, TIME].join(SEP),
  "nav_msgs/msg/Odometry": [
    "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n" +
      "geometry_msgs/TwistWithCovariance twist",
    HEADER, TIME,
    "MSG: geometry_msgs/PoseWithCovariance\ngeometry_msgs/Pose pose\nfloat64[36] covariance",
    "MSG: geometry_msgs/Pose\ngeometry_msgs/Point position\ngeometry_msgs/Quaternion orientation",
    POINT, QUAT,
    "MSG: geometry_msgs/TwistWithCovariance\ngeometry_msgs/Twist twist\nfloat64[36] covariance",
    "MSG: geometry_msgs/Twist\ngeometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular",
    VECTOR3].join(SEP),
  "tf2_msgs/msg/TFMessage": [
    "geometry_msgs/TransformStamped[] transforms",
    "MSG: geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\n" +
      "geometry_msgs/Transform transform",
    HEADER, TIME,
    "MSG: geometry_msgs/Transform\ngeometry_msgs/Vector3 translation\n" +
      "geometry_msgs/Quaternion rotation",
    VECTOR3, QUAT].join(SEP),
};
const writers = Object.fromEntries(Object.entries(DEFINITIONS).map(
  ([type, text]) => [type, new MessageWriter(parse(text, { ros2: true }))]));

const T0_NS = 1700000000500000000n;  // t0 = 1700000000.5 s
const stampOf = (ns) => ({ sec: Number(ns / 1000000000n), nanosec: Number(ns % 1000000000n) });
const yawQuaternion = (yaw) => ({ x: 0, y: 0, z: Math.sin(yaw / 2), w: Math.cos(yaw / 2) });
const zeros36 = new Array(36).fill(0);

function odometry(ns, parent, x, y, yaw) {
  return {
    header: { stamp: stampOf(ns), frame_id: parent }, child_frame_id: "base_link",
    pose: { pose: { position: { x, y, z: 0 }, orientation: yawQuaternion(yaw) }, covariance: zeros36 },
    twist: { twist: { linear: { x: 0.5, y: 0, z: 0 }, angular: { x: 0, y: 0, z: 0.1 } },
             covariance: zeros36 },
  };
}
function transform(ns, parent, child, x, y, z, yaw) {
  return { header: { stamp: stampOf(ns), frame_id: parent }, child_frame_id: child,
           transform: { translation: { x, y, z }, rotation: yawQuaternion(yaw) } };
}

// The run's messages as [topic, type, time (ns), message], in time order.
function messages(odometryOnTf, truth) {
  const out = [];
  out.push(["/tf_static", "tf2_msgs/msg/TFMessage", T0_NS - 100000000n,
            { transforms: [transform(T0_NS - 100000000n, "base_link", "laser", 0.2, 0, 0.3, 0.1)] }]);
  for (let k = 0; k <= 30; ++k) {
    const ns = T0_NS - 50000000n + 100000000n * BigInt(k);
    if (odometryOnTf) {
      out.push(["/tf", "tf2_msgs/msg/TFMessage", ns,
                { transforms: [transform(ns, "odom", "base_link", 0.05 * k, 0.02 * k, 0, 0.01 * k)] }]);
    } else {
      out.push(["/odom", "nav_msgs/msg/Odometry", ns, odometry(ns, "odom", 0.05 * k, 0.02 * k, 0.01 * k)]);
    }
    if (truth)
      out.push(["/ground_truth", "nav_msgs/msg/Odometry", ns,
                odometry(ns, "map", 0.05 * k + 0.01, 0.02 * k, 0.01 * k)]);
  }
  for (let i = 0; i < 30; ++i) {
    const ns = T0_NS + 100000000n * BigInt(i);
    const ranges = [];
    for (let j = 0; j < 9; ++j) ranges.push(1 + 0.25 * j + 0.01 * i);
    ranges[4] = Infinity;
    if (i === 0) ranges[7] = NaN;
    out.push(["/scan", "sensor_msgs/msg/LaserScan", ns, {
      header: { stamp: stampOf(ns), frame_id: "laser" }, angle_min: -2, angle_max: 2,
      angle_increment: 0.5, time_increment: 0, scan_time: 0.1, range_min: 0.05, range_max: 8,
      ranges: Float32Array.from(ranges), intensities: new Float32Array(0) }]);
  }
  out.sort((a, b) => (a[2] < b[2] ? -1 : a[2] > b[2] ? 1 : 0));
  return out;
}

async function writeMcap(path, list, compression) {
  const chunks = [];
  const writable = { position: () => BigInt(chunks.reduce((n, c) => n + c.length, 0)),
                     write: async (buffer) => { chunks.push(Buffer.from(buffer)); } };
  const compressChunk = compression === "zstd"
    ? (data) => ({ compression: "zstd", compressedData: zstdCompress(data, 10) })
    : compression === "lz4"
      ? (data) => ({ compression: "lz4", compressedData: lz4.compress(data) })
      : undefined;
  const writer = new McapWriter({ writable, useChunks: compression !== "none", chunkSize: 2048,
                                  compressChunk });
  await writer.start({ profile: "ros2", library: "splam fixtures (@mcap/core)" });
  const channels = {};
  let sequence = 0;
  for (const [topic, type, ns, message] of list) {
    if (!(topic in channels)) {
      const schemaId = await writer.registerSchema({ name: type, encoding: "ros2msg",
                                                     data: new TextEncoder().encode(DEFINITIONS[type]) });
      channels[topic] = await writer.registerChannel({ topic, schemaId, messageEncoding: "cdr",
                                                       metadata: new Map() });
    }
    await writer.addMessage({ channelId: channels[topic], sequence: sequence++, logTime: ns,
                              publishTime: ns, data: writers[type].writeMessage(message) });
  }
  await writer.end();
  fs.writeFileSync(path, Buffer.concat(chunks));
}

async function writeDb3(path, list) {
  const SQL = await initSqlJs();
  const db = new SQL.Database();
  db.run("CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);");
  db.run("INSERT INTO schema VALUES (3, 'humble');");
  db.run("CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, " +
         "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);");
  db.run("CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, " +
         "timestamp INTEGER NOT NULL, data BLOB NOT NULL);");
  db.run("CREATE INDEX timestamp_idx ON messages (timestamp ASC);");
  const ids = {};
  for (const [topic, type, ns, message] of list) {
    if (!(topic in ids)) {
      ids[topic] = Object.keys(ids).length + 1;
      db.run("INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')", [ids[topic], topic, type]);
    }
    db.run("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)",
           [ids[topic], ns.toString(), writers[type].writeMessage(message)]);
  }
  fs.writeFileSync(path, Buffer.from(db.export()));
}

await zstdInit();
await writeDb3("odom.db3", messages(false, true));
await writeMcap("tf_zstd.mcap", messages(true, false), "zstd");
await writeMcap("odom_lz4.mcap", messages(false, true), "lz4");
fs.mkdirSync("bag_dir", { recursive: true });
await writeMcap("bag_dir/bag_dir_0.mcap", messages(false, true), "none");
const list = messages(false, true);
fs.writeFileSync("bag_dir/metadata.yaml",
  "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: mcap\n" +
  "  relative_file_paths:\n    - bag_dir_0.mcap\n" +
  `  message_count: ${list.length}\n  compression_format: \"\"\n  compression_mode: \"\"\n`);
console.log("wrote odom.db3, tf_zstd.mcap, odom_lz4.mcap, bag_dir/");
