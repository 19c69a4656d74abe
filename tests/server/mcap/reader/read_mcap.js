// An independent reader of mbstream's MCAP export (tests/server/mcap/mcap_export_test.cc):
// @mcap/core reads FILE through its summary (schemas, channels, statistics, chunk indexes) and
// streams it whole, checking every CRC (chunks, data section, summary); a small CDR decoder
// reads /joint_states and /tf, and Foxglove's own decoder (@foxglove/rosmsg parsing each
// schema's ros2msg text, @foxglove/rosmsg2-serialization) must read every CDR message the
// same, and every joint value is compared, bit for bit, with the
// results directory's CSV files.
// With TCP_FRAME, each frame's /tf and /tf_static composed from the base to that frame must
// put it where tcp.csv says (to 1e-9 m): the transforms' direction and parents are right.
//   node read_mcap.js FILE.mcap RESULTS_DIR START_NS MODEL_FILE|- [TCP_FRAME]
// Prints one JSON object (what was read) and exits 0, or prints the first difference and
// exits 1.
"use strict";
const fs = require("fs");
const path = require("path");
const { McapIndexedReader, McapStreamReader } = require("@mcap/core");
const { crc32 } = require("@foxglove/crc");
const zstd = require("@foxglove/wasm-zstd");
const lz4 = require("@foxglove/wasm-lz4");
const { parse: parseMessageDefinition } = require("@foxglove/rosmsg");
const { MessageReader } = require("@foxglove/rosmsg2-serialization");

function fail(message) {
  console.log(`MISMATCH: ${message}`);
  process.exit(1);
}

// Plain CDR, little-endian, aligned from the end of the 4-byte encapsulation header.
class CdrReader {
  constructor(bytes) {
    if (bytes[0] !== 0 || bytes[1] !== 1) fail(`encapsulation ${bytes[0]} ${bytes[1]}: not CDR_LE`);
    this.view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    this.bytes = bytes;
    this.at = 4;
  }
  align(n) {
    this.at += (n - ((this.at - 4) % n)) % n;
  }
  int32() { this.align(4); const v = this.view.getInt32(this.at, true); this.at += 4; return v; }
  uint32() { this.align(4); const v = this.view.getUint32(this.at, true); this.at += 4; return v; }
  float64() { this.align(8); const v = this.view.getFloat64(this.at, true); this.at += 8; return v; }
  string() {
    const length = this.uint32();
    if (length === 0 || this.bytes[this.at + length - 1] !== 0) fail("a CDR string without its NUL");
    const text = Buffer.from(this.bytes.subarray(this.at, this.at + length - 1)).toString("utf8");
    this.at += length;
    return text;
  }
  float64s() { const n = this.uint32(); const out = []; for (let i = 0; i < n; i++) out.push(this.float64()); return out; }
  strings() { const n = this.uint32(); const out = []; for (let i = 0; i < n; i++) out.push(this.string()); return out; }
  header() { return { sec: this.int32(), nanosec: this.uint32(), frame_id: this.string() }; }
  end() { if (this.at !== this.bytes.length) fail(`CDR: ${this.bytes.length - this.at} bytes left over`); }
}

// The vector v rotated by the unit quaternion q = [x, y, z, w].
function rotate(q, v) {
  const [x, y, z, w] = q;
  const u = [x, y, z];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const t = cross(u, v).map((c) => 2 * c);
  const ut = cross(u, t);
  return [0, 1, 2].map((i) => v[i] + w * t[i] + ut[i]);
}

function readCsv(file) {
  if (!fs.existsSync(file)) return null;
  const lines = fs.readFileSync(file, "utf8").trim().split("\n");
  return { header: lines[0].split(","), rows: lines.slice(1).map((l) => l.split(",").map(Number)) };
}

function same(a, b) {
  return Object.is(a, b);  // bit for bit, -0 and NaN included
}

async function main() {
  const [file, resultsDir, startText, modelFile, tcpFrame] = process.argv.slice(2);
  const startNs = BigInt(startText);
  await zstd.isLoaded;
  await lz4.isLoaded;
  const decompressHandlers = {
    zstd: (buffer, size) => zstd.decompress(buffer, Number(size)),
    lz4: (buffer, size) => lz4(buffer, Number(size)),
  };
  const bytes = fs.readFileSync(file);

  // 1. Streamed whole: chunk CRCs, the data section's CRC against DataEnd, every record.
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true, noMagicPrefix: false });
  stream.append(bytes);
  const counts = {};
  let record;
  let dataEndCrc = null;
  let dataEndOffset = null;
  while ((record = stream.nextRecord())) {
    counts[record.type] = (counts[record.type] || 0) + 1;
    if (record.type === "DataEnd") dataEndCrc = record.dataSectionCrc;
  }
  if (!stream.done()) fail("the stream reader did not reach the end of the file");
  // DataEnd is 13 bytes; the summary starts right after it (the footer says where).
  const summaryStart = Number(bytes.readBigUInt64LE(bytes.length - 8 - 29 + 9));
  dataEndOffset = summaryStart - 13;
  if (bytes[dataEndOffset] !== 0x0f) fail("no DataEnd record before the summary");
  const dataCrc = crc32(bytes.subarray(0, dataEndOffset));
  if (dataEndCrc !== dataCrc) fail(`data section CRC ${dataEndCrc}, recomputed ${dataCrc}`);

  // 2. Through the summary: schemas, channels, statistics, chunk indexes (summary CRC checked).
  const reader = await McapIndexedReader.Initialize({
    readable: {
      size: async () => BigInt(bytes.length),
      read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
    },
    decompressHandlers,
  });
  if (reader.header.profile !== "ros2") fail(`profile "${reader.header.profile}"`);
  const topics = {};
  for (const channel of reader.channelsById.values()) {
    const schema = reader.schemasById.get(channel.schemaId);
    topics[channel.topic] = { schema: schema.name, schemaEncoding: schema.encoding, messageEncoding: channel.messageEncoding };
  }
  if (reader.chunkIndexes.length === 0) fail("no chunk index");
  // Foxglove's decoders, built from the schemas' own text: a schema it cannot parse fails.
  const foxglove = new Map();
  for (const schema of reader.schemasById.values()) {
    if (schema.encoding !== "ros2msg") continue;
    const text = Buffer.from(schema.data).toString("utf8");
    foxglove.set(schema.id, new MessageReader(parseMessageDefinition(text, { ros2: true })));
  }
  const decodeAsFoxglove = (message) =>
    foxglove.get(reader.channelsById.get(message.channelId).schemaId).readMessage(message.data);
  const sameArray = (a, b) => a.length === b.length && Array.from(a).every((v, i) => same(v, b[i]));
  for (const index of reader.chunkIndexes) {
    if (index.compressedSize === 0n || index.messageIndexOffsets.size === 0) fail("an empty chunk index");
  }

  // 3. Every message in log-time order, CRCs validated, against the CSV files.
  const joints = readCsv(path.join(resultsDir, "joints.csv"));
  const velocities = readCsv(path.join(resultsDir, "velocities.csv"));
  const torques = readCsv(path.join(resultsDir, "torques.csv"));
  const tcp = readCsv(path.join(resultsDir, "tcp.csv"));
  const poses = new Map();  // child -> {parent, t, q}, /tf_static's and the latest /tf's
  let tcpErrorMax = tcpFrame ? 0 : null;
  // JointState carries the one-coordinate joints: joints.csv's columns that velocities.csv has
  // too. A free body's NAME.x .y .z .qw .qx .qy .qz are its /tf pose (a ROS floating base).
  const velocityColumns = new Set(velocities.header.slice(1));
  const names = joints.header.slice(1).filter((name) => velocityColumns.has(name));
  const columnOf = (csv) => new Map(csv.header.map((name, k) => [name, k]));
  const jointColumn = columnOf(joints), velocityColumn = columnOf(velocities);
  const torqueColumn = torques ? columnOf(torques) : null;
  // A free body has NAME.x .. NAME.qz; a ball joint (NAME.qw .. NAME.qz, no NAME.x) is not one.
  const freeBodies = joints.header.filter((name) => name.endsWith(".qz") && joints.header.includes(name.slice(0, -3) + ".x")).map((name) => name.slice(0, -3));
  let freeErrorMax = freeBodies.length ? 0 : null;
  const topicOf = (id) => reader.channelsById.get(id).topic;
  let frame = 0, tfFrame = 0, lastLogTime = -1n;
  const seen = {};
  let tfChildren = null, staticChildren = null, robotDescription = null, stats = null;
  for await (const message of reader.readMessages({ validateCrcs: true })) {
    const topic = topicOf(message.channelId);
    seen[topic] = (seen[topic] || 0) + 1;
    if (message.logTime < lastLogTime) fail("messages out of log-time order");
    lastLogTime = message.logTime;
    if (topic === "/joint_states") {
      const cdr = new CdrReader(message.data);
      const header = cdr.header();
      const stampNs = BigInt(header.sec) * 1000000000n + BigInt(header.nanosec);
      if (stampNs !== message.logTime) fail(`frame ${frame}: stamp ${stampNs} != log time ${message.logTime}`);
      const row = joints.rows[frame];
      if (!row) fail(`more JointState messages than rows of joints.csv (${joints.rows.length})`);
      const expectedNs = startNs + BigInt(Math.round(row[0] * 1e9));
      if (stampNs !== expectedNs) fail(`frame ${frame}: stamp ${stampNs}, t = ${row[0]} gives ${expectedNs}`);
      if (header.frame_id !== "") fail(`frame_id "${header.frame_id}"`);
      const msg = { name: cdr.strings(), position: cdr.float64s(), velocity: cdr.float64s(), effort: cdr.float64s() };
      cdr.end();
      const theirs = decodeAsFoxglove(message);
      if (theirs.header.stamp.sec !== header.sec || theirs.header.stamp.nanosec !== header.nanosec ||
          theirs.header.frame_id !== header.frame_id || !sameArray(theirs.name, msg.name) ||
          !sameArray(theirs.position, msg.position) || !sameArray(theirs.velocity, msg.velocity) ||
          !sameArray(theirs.effort, msg.effort)) {
        fail(`frame ${frame}: Foxglove's decoder reads the JointState otherwise: ${JSON.stringify(theirs)}`);
      }
      if (msg.name.join(",") !== names.join(",")) fail(`names ${msg.name} != ${names}`);
      for (let j = 0; j < names.length; j++) {
        const position = row[jointColumn.get(names[j])];
        if (!same(msg.position[j], position)) fail(`frame ${frame} position[${j}] ${msg.position[j]} != ${position}`);
        if (!same(msg.velocity[j], velocities.rows[frame][velocityColumn.get(names[j])])) fail(`frame ${frame} velocity[${j}]`);
        if (torques) {
          const effort = torques.rows[frame][torqueColumn.get(names[j])];
          if (!same(msg.effort[j], effort)) fail(`frame ${frame} effort[${j}] ${msg.effort[j]} != ${effort}`);
        }
      }
      if (!torques && msg.effort.length !== 0) fail("effort without torques.csv");
      if (torques && msg.effort.length !== names.length) fail("effort's length");
      frame++;
    } else if (topic === "/tf" || topic === "/tf_static") {
      const cdr = new CdrReader(message.data);
      const n = cdr.uint32();
      const children = [];
      const theirs = decodeAsFoxglove(message).transforms;
      if (theirs.length !== n) fail(`${topic}: Foxglove's decoder reads ${theirs.length} transforms`);
      for (let i = 0; i < n; i++) {
        const header = cdr.header();
        const child = cdr.string();
        const t = [cdr.float64(), cdr.float64(), cdr.float64()];
        const q = [cdr.float64(), cdr.float64(), cdr.float64(), cdr.float64()];
        const norm = Math.hypot(...q);
        if (Math.abs(norm - 1) > 1e-12) fail(`${topic}: ${child}'s quaternion has norm ${norm}`);
        if (!t.every(Number.isFinite)) fail(`${topic}: ${child}'s translation`);
        if (BigInt(header.sec) * 1000000000n + BigInt(header.nanosec) !== message.logTime) fail(`${topic} stamp`);
        const other = theirs[i];
        if (other.child_frame_id !== child || other.header.frame_id !== header.frame_id ||
            !sameArray([other.transform.translation.x, other.transform.translation.y, other.transform.translation.z], t) ||
            !sameArray([other.transform.rotation.x, other.transform.rotation.y, other.transform.rotation.z, other.transform.rotation.w], q)) {
          fail(`${topic}: Foxglove's decoder reads transform ${i} otherwise`);
        }
        children.push(`${header.frame_id}->${child}`);
        poses.set(child, { parent: header.frame_id, t, q });
      }
      cdr.end();
      if (topic === "/tf") {
        // A free body's /tf pose is its seven coordinates (the quaternion up to its sign).
        for (const body of freeBodies) {
          const pose = poses.get(body);
          if (!pose) fail(`/tf has no transform of the free body ${body}`);
          const row = joints.rows[tfFrame];
          const at = (suffix) => row[jointColumn.get(body + suffix)];
          const [x, y, z, w] = pose.q;
          const sign = Math.sign(w * at(".qw") + x * at(".qx") + y * at(".qy") + z * at(".qz")) || 1;
          const error = Math.max(Math.abs(pose.t[0] - at(".x")), Math.abs(pose.t[1] - at(".y")),
            Math.abs(pose.t[2] - at(".z")), Math.abs(sign * w - at(".qw")), Math.abs(sign * x - at(".qx")),
            Math.abs(sign * y - at(".qy")), Math.abs(sign * z - at(".qz")));
          freeErrorMax = Math.max(freeErrorMax, error);
          if (!(error < 1e-12)) fail(`frame ${tfFrame}: /tf's pose of ${body} is ${pose.t} ${pose.q}, joints.csv's differs by ${error}`);
        }
        if (tcpFrame) {
          // p_parent = R(q) p_child + t, from the TCP frame up to the root.
          let p = [0, 0, 0];
          for (let node = tcpFrame, hops = 0; poses.has(node); node = poses.get(node).parent, hops++) {
            if (hops > 1000) fail("a cycle in /tf");
            const { t, q } = poses.get(node);
            p = rotate(q, p).map((v, i) => v + t[i]);
          }
          const row = tcp.rows[tfFrame];
          const error = Math.hypot(p[0] - row[1], p[1] - row[2], p[2] - row[3]);
          tcpErrorMax = Math.max(tcpErrorMax, error);
          if (!(error < 1e-9)) fail(`frame ${tfFrame}: /tf puts ${tcpFrame} at ${p}, tcp.csv at ${row.slice(1)}`);
        }
        tfChildren = children;
        tfFrame++;
      } else staticChildren = children;
    } else if (topic === "/robot_description") {
      const cdr = new CdrReader(message.data);
      robotDescription = cdr.string();
      cdr.end();
      if (decodeAsFoxglove(message).data !== robotDescription) fail("/robot_description as Foxglove reads it");
    } else if (topic === "/mbstream/stats") {
      stats = JSON.parse(Buffer.from(message.data).toString("utf8"));
    } else if (topic === "/mbstream/probes") {
      JSON.parse(Buffer.from(message.data).toString("utf8"));
    }
  }
  if (frame !== joints.rows.length) fail(`${frame} JointState messages, ${joints.rows.length} rows in joints.csv`);
  if (tfFrame !== frame) fail(`${tfFrame} /tf messages for ${frame} frames`);
  // MODEL_FILE "-": the model's text is not at hand (a stored world's, includes written in).
  if (modelFile === "-" ? !robotDescription : robotDescription !== fs.readFileSync(modelFile, "utf8")) {
    fail("/robot_description differs from the model file");
  }
  const statsFile = JSON.parse(fs.readFileSync(path.join(resultsDir, "stats.json"), "utf8"));
  if (JSON.stringify(stats) !== JSON.stringify(statsFile)) fail("/mbstream/stats differs from stats.json");
  const statistics = reader.statistics;
  console.log(JSON.stringify({
    frames: frame,
    topics,
    messages: seen,
    statistics_messages: Number(statistics.messageCount),
    chunks: reader.chunkIndexes.length,
    compression: reader.chunkIndexes[0].compression,
    records: counts,
    tf: tfChildren,
    tf_static: staticChildren,
    has_effort: torques !== null,
    tcp_error_max_m: tcpErrorMax,
    foxglove_decoders: foxglove.size,
    names,
    free_bodies: freeBodies,
    free_pose_error_max: freeErrorMax,
  }));
}

main().catch((error) => {
  console.log(`ERROR: ${error.stack || error}`);
  process.exit(1);
});
