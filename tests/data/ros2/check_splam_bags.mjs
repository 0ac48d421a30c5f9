// Reads bags splam wrote (splam convert LOG x.mcap; splam convert LOG x.db3) with the same
// independent libraries: node check_splam_bags.mjs x.mcap x.db3
import fs from "node:fs";
import { McapStreamReader } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import initSqlJs from "sql.js";
import { init, decompress } from "@bokuweb/zstd-wasm";
await init();
const reader = new McapStreamReader({ decompressHandlers: { zstd: (d, size) => decompress(d) } });
reader.append(fs.readFileSync(process.argv[2]));
const schemas = {}, channels = {}, counts = {};
let record, first = {};
while ((record = reader.nextRecord())) {
  if (record.type === "Schema") schemas[record.id] = new MessageReader(parse(new TextDecoder().decode(record.data), { ros2: true }));
  if (record.type === "Channel") channels[record.id] = record;
  if (record.type === "Message") {
    const ch = channels[record.channelId];
    const msg = schemas[ch.schemaId].readMessage(record.data);
    counts[ch.topic] = (counts[ch.topic] ?? 0) + 1;
    if (!(ch.topic in first)) first[ch.topic] = msg;
  }
}
console.log("mcap:", counts);
console.log("first scan ranges:", Array.from(first["/scan"].ranges.slice(0, 4)), "stamp", first["/scan"].header.stamp);
console.log("first odom:", first["/odom"].pose.pose.position, first["/odom"].child_frame_id);
const SQL = await initSqlJs();
const db = new SQL.Database(fs.readFileSync(process.argv[3]));
console.log("db3:", db.exec("SELECT t.name, t.type, COUNT(*) FROM messages m JOIN topics t ON t.id = m.topic_id GROUP BY t.name")[0].values);
