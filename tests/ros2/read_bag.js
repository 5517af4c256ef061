// Reads a rosbag2 bag with MCAP storage written by asf (the ros2 source's `bag`) with
// libraries independent of asf: Foxglove's MCAP reader (@mcap/core), its ros2msg parser
// (@foxglove/rosmsg) on the schemas in the file, and its CDR deserializer
// (@foxglove/rosmsg2-serialization). Every message must decode without trailing bytes. Writes,
// in the format asf sim-robot writes what it decoded (tests/ros2/check_received.py reads
// both), the last /map (received/map.pgm, map.json), the last markers (received/markers.json),
// and sim_robot.json with the number of map -> odom transforms; prints the topics' counts.
// Usage: node read_bag.js BAG_FOLDER OUT_DIR
'use strict';
const fs = require('fs');
const path = require('path');
const { McapStreamReader } = require('@mcap/core');
const { parse } = require('@foxglove/rosmsg');
const { MessageReader } = require('@foxglove/rosmsg2-serialization');

const [bag, out] = process.argv.slice(2);
if (!bag || !out) throw new Error('usage: node read_bag.js BAG_FOLDER OUT_DIR');
const meta = fs.readFileSync(path.join(bag, 'metadata.yaml'), 'utf8');
if (!/storage_identifier: mcap/.test(meta)) throw new Error('metadata.yaml: not an MCAP bag');
const file = meta.match(/relative_file_paths:\n\s+- (\S+)/)[1];

const reader = new McapStreamReader();
reader.append(fs.readFileSync(path.join(bag, file)));
const schemas = new Map(), channels = new Map(), counts = {};
let lastMap = null, lastMarkers = null, mapToOdom = 0, maps = 0, sawFooter = false;
for (let rec; (rec = reader.nextRecord());) {
  if (rec.type === 'Schema') {
    if (rec.encoding !== 'ros2msg') throw new Error(`schema ${rec.name}: encoding ${rec.encoding}`);
    const text = new TextDecoder().decode(rec.data);
    schemas.set(rec.id, { name: rec.name, reader: new MessageReader(parse(text, { ros2: true })) });
  } else if (rec.type === 'Channel') {
    if (rec.messageEncoding !== 'cdr') throw new Error(`${rec.topic}: encoding ${rec.messageEncoding}`);
    channels.set(rec.id, { topic: rec.topic, schema: schemas.get(rec.schemaId) });
  } else if (rec.type === 'Message') {
    const ch = channels.get(rec.channelId);
    const msg = ch.schema.reader.readMessage(rec.data);
    if (ch.schema.reader.lastReadHadTrailingBytes())
      throw new Error(`${ch.topic}: message ${rec.sequence} has bytes its schema does not describe`);
    counts[ch.topic] = (counts[ch.topic] || 0) + 1;
    if (ch.schema.name === 'nav_msgs/msg/OccupancyGrid') { lastMap = msg; ++maps; }
    if (ch.schema.name === 'visualization_msgs/msg/MarkerArray') lastMarkers = msg.markers;
    if (ch.schema.name === 'tf2_msgs/msg/TFMessage')
      for (const t of msg.transforms)
        if (t.header.frame_id === 'map' && t.child_frame_id === 'odom') ++mapToOdom;
  } else if (rec.type === 'Footer') {
    sawFooter = true;
  }
}
if (!sawFooter) throw new Error('data.mcap ends without a Footer');

const yaw = (q) => Math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
const dir = path.join(out, 'received');
fs.mkdirSync(dir, { recursive: true });
if (lastMap) {
  const { width, height } = lastMap.info;
  const px = Buffer.from(Array.from(lastMap.data, (v) => (v < 0 ? 255 : v)));
  fs.writeFileSync(path.join(dir, 'map.pgm'), Buffer.concat([Buffer.from(`P5\n${width} ${height}\n255\n`), px]));
  fs.writeFileSync(path.join(dir, 'map.json'), JSON.stringify({
    width, height, resolution: lastMap.info.resolution,
    origin: [lastMap.info.origin.position.x, lastMap.info.origin.position.y],
    frame_id: lastMap.header.frame_id }));
}
fs.writeFileSync(path.join(dir, 'markers.json'), JSON.stringify((lastMarkers || []).map((m) => ({
  ns: m.ns, id: m.id, type: m.type, action: m.action, frame_id: m.header.frame_id,
  pose: [m.pose.position.x, m.pose.position.y, yaw(m.pose.orientation)],
  points: m.points.map((p) => [p.x, p.y, p.z]), text: m.text }))));
fs.writeFileSync(path.join(out, 'sim_robot.json'),
  JSON.stringify({ map_to_odom_received: mapToOdom, maps_received: maps }));
console.log(JSON.stringify({ topics: counts }));
