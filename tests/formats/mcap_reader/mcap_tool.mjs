// Independent MCAP + ROS 2 CDR reader/writer for slamprep's export/import tests, built only on
// @mcap/core (the reference TypeScript MCAP library), @foxglove/rosmsg(2-serialization), and the
// pure JavaScript decompressors fzstd (zstd) and lz4js (LZ4 frames) for compressed chunks.
//
//   node mcap_tool.mjs read FILE OUT.jsonl   decode every message (indexed and streaming readers)
//   node mcap_tool.mjs write SPEC.json FILE   write a bag from a JSON description
import { readFile, writeFile, open } from "node:fs/promises";
import { McapIndexedReader, McapStreamReader, McapWriter } from "@mcap/core";
import { parse as parseMessageDefinition } from "@foxglove/rosmsg";
import { MessageReader, MessageWriter } from "@foxglove/rosmsg2-serialization";
import { decompress as unzstd } from "fzstd";
import lz4 from "lz4js";

// @mcap/core leaves decompression to the caller: one handler per chunk compression.
const decompressHandlers = {
  zstd: (data, size) => checkedSize(unzstd(data, new Uint8Array(Number(size))), size, "zstd"),
  lz4: (data, size) => checkedSize(lz4.decompress(data, Number(size)), size, "lz4"),
};
function checkedSize(bytes, size, what) {
  if (BigInt(bytes.byteLength) !== size)
    throw new Error(`${what} chunk: ${bytes.byteLength} bytes unpacked, ${size} announced`);
  return bytes;
}

// JSON has no BigInt, typed arrays, Infinity or NaN: encode them explicitly.
function jsonable(value) {
  if (typeof value === "bigint") return value.toString();
  if (typeof value === "number" && !Number.isFinite(value)) return String(value);
  if (ArrayBuffer.isView(value)) return Array.from(value, jsonable);
  if (value instanceof Map)
    return Object.fromEntries([...value].map(([k, v]) => [String(k), jsonable(v)]));
  if (Array.isArray(value)) return value.map(jsonable);
  if (value && typeof value === "object") {
    const out = {};
    for (const [k, v] of Object.entries(value)) out[k] = jsonable(v);
    return out;
  }
  return value;
}

function fileReadable(handle, size) {
  return {
    size: async () => BigInt(size),
    read: async (offset, length) => {
      const buffer = new Uint8Array(Number(length));
      const { bytesRead } = await handle.read(buffer, 0, Number(length), Number(offset));
      if (bytesRead !== Number(length)) throw new Error(`short read at ${offset}`);
      return buffer;
    },
  };
}

async function read(file, outFile) {
  const bytes = await readFile(file);
  // 1. Streaming reader over the whole file, CRCs validated.
  const stream = new McapStreamReader({ validateCrcs: true, decompressHandlers });
  stream.append(bytes);
  const streamMessages = [];
  const streamChannels = new Map();
  const streamSchemas = new Map();
  const metadata = [];
  let footer;
  for (let r; (r = stream.nextRecord()); ) {
    if (r.type === "Message") streamMessages.push(r);
    if (r.type === "Channel") streamChannels.set(r.id, r);
    if (r.type === "Schema") streamSchemas.set(r.id, r);
    if (r.type === "Footer") footer = r;
    if (r.type === "Metadata") metadata.push({ name: r.name, entries: r.metadata });
  }
  if (!stream.done()) throw new Error("stream reader did not reach the end of the file");

  // 2. Indexed reader (summary, chunk indexes, message indexes), CRCs validated. Files without
  // chunks have no message index: their messages are decoded from the stream reader.
  const handle = await open(file, "r");
  const reader = await McapIndexedReader.Initialize({ readable: fileReadable(handle, bytes.length),
    decompressHandlers });
  const indexed = [];
  if (reader.chunkIndexes.length > 0)
    for await (const m of reader.readMessages({ validateCrcs: true })) indexed.push(m);
  await handle.close();
  const source = reader.chunkIndexes.length > 0 ? indexed : streamMessages;
  const decoders = new Map();
  for (const [id, channel] of streamChannels) {
    const schema = streamSchemas.get(channel.schemaId);
    if (!schema || schema.encoding !== "ros2msg" || channel.messageEncoding !== "cdr")
      throw new Error(`channel ${channel.topic}: not ros2msg/cdr`);
    const text = new TextDecoder().decode(schema.data);
    decoders.set(id, new MessageReader(parseMessageDefinition(text, { ros2: true })));
  }
  const lines = [];
  let trailing = 0;
  let lastLogTime = -1n;
  let unordered = 0;
  for (const m of source) {
    const decoder = decoders.get(m.channelId);
    const msg = decoder.readMessage(m.data);
    if (decoder.lastReadHadTrailingBytes() || decoder.lastReadByteLength() !== m.data.byteLength)
      trailing++;
    if (m.logTime < lastLogTime) unordered++;
    lastLogTime = m.logTime;
    const channel = streamChannels.get(m.channelId);
    lines.push(JSON.stringify(jsonable({ topic: channel.topic, sequence: m.sequence,
      log_time: m.logTime, publish_time: m.publishTime, bytes: m.data.byteLength, msg })));
  }
  const channels = [...reader.channelsById.values()].map((c) => ({
    id: c.id, topic: c.topic, encoding: c.messageEncoding,
    schema: reader.schemasById.get(c.schemaId).name,
    metadata: Object.fromEntries(c.metadata) }));
  const summary = {
    profile: reader.header.profile, library: reader.header.library,
    statistics: reader.statistics, chunk_indexes: reader.chunkIndexes.length,
    chunk_compressions: [...new Set(reader.chunkIndexes.map((c) => c.compression))],
    metadata, metadata_indexes: reader.metadataIndexes.map((m) => m.name),
    summary_offsets: reader.summaryOffsetsByOpcode.size, channels,
    stream_messages: streamMessages.length, indexed_messages: indexed.length,
    trailing_bytes_messages: trailing, unordered_log_times: unordered,
    summary_crc: footer ? footer.summaryCrc : null, data_section_crc: reader.dataSectionCrc ?? null,
  };
  await writeFile(outFile, [JSON.stringify(jsonable(summary)), ...lines].join("\n") + "\n");
}

// The message definitions this writer knows, written out here (not taken from slamprep).
const SEP = "=".repeat(80);
const HEADER = `${SEP}\nMSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n` +
  `${SEP}\nMSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n`;
const DEFINITIONS = {
  "sensor_msgs/msg/LaserScan": "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\n" +
    "float32 angle_increment\nfloat32 time_increment\nfloat32 scan_time\nfloat32 range_min\n" +
    "float32 range_max\nfloat32[] ranges\nfloat32[] intensities\n" + HEADER,
  "sensor_msgs/msg/JointState": "std_msgs/Header header\nstring[] name\nfloat64[] position\n" +
    "float64[] velocity\nfloat64[] effort\n" + HEADER,
  "nav_msgs/msg/Odometry": "std_msgs/Header header\nstring child_frame_id\n" +
    "geometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n" + HEADER +
    `${SEP}\nMSG: geometry_msgs/PoseWithCovariance\nPose pose\nfloat64[36] covariance\n` +
    `${SEP}\nMSG: geometry_msgs/Pose\nPoint position\nQuaternion orientation\n` +
    `${SEP}\nMSG: geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z\n` +
    `${SEP}\nMSG: geometry_msgs/Quaternion\nfloat64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n` +
    `${SEP}\nMSG: geometry_msgs/TwistWithCovariance\nTwist twist\nfloat64[36] covariance\n` +
    `${SEP}\nMSG: geometry_msgs/Twist\nVector3 linear\nVector3 angular\n` +
    `${SEP}\nMSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n`,
};

async function write(specFile, outFile) {
  const spec = JSON.parse(await readFile(specFile, "utf8"));
  const handle = await open(outFile, "w");
  let position = 0n;
  const writable = {
    write: async (buffer) => { await handle.write(buffer); position += BigInt(buffer.byteLength); },
    position: () => position,
  };
  const writer = new McapWriter({ writable, chunkSize: spec.chunk_size ?? 4096 });
  await writer.start({ profile: "ros2", library: "mcap_tool.mjs" });
  const channels = new Map();
  for (const { topic, type } of spec.channels) {
    const text = DEFINITIONS[type];
    if (!text) throw new Error(`unknown type ${type}`);
    const schemaId = await writer.registerSchema({ name: type, encoding: "ros2msg",
      data: new TextEncoder().encode(text) });
    const id = await writer.registerChannel({ topic, schemaId, messageEncoding: "cdr",
      metadata: new Map() });
    channels.set(topic, { id, serializer: new MessageWriter(parseMessageDefinition(text, { ros2: true })) });
  }
  const sequence = new Map();
  for (const m of spec.messages) {
    const ch = channels.get(m.topic);
    const seq = sequence.get(m.topic) ?? 0;
    sequence.set(m.topic, seq + 1);
    await writer.addMessage({ channelId: ch.id, sequence: seq, logTime: BigInt(m.log_time),
      publishTime: BigInt(m.log_time), data: ch.serializer.writeMessage(m.msg) });
  }
  await writer.end();
  await handle.close();
}

const [command, a, b] = process.argv.slice(2);
try {
  if (command === "read") await read(a, b);
  else if (command === "write") await write(a, b);
  else throw new Error("usage: mcap_tool.mjs read FILE OUT.jsonl | write SPEC.json FILE");
} catch (e) {
  console.error(`mcap_tool: ${e.stack ?? e}`);
  process.exit(1);
}
