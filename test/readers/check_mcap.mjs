// Reads an MCAP file tm-basecamp wrote with other projects' readers, and checks it against the recording it came
// from. @mcap/core reads it twice: from start to end with every CRC checked (McapStreamReader), and through its
// summary and chunk indexes as Foxglove opens a file (McapIndexedReader). @foxglove/omgidl-parser and
// @foxglove/omgidl-serialization decode every message of a channel with a schema from that schema alone.
//
//   node check_mcap.mjs FILE.mcap SAMPLES.tsv COMPRESSION [--sensor SPEC] [--expect VALUES.json] [SCHEMA_TYPE...]
//
// SAMPLES.tsv: the recording's samples, one a line, each topic's in the order received: topic, type name, receive ns, source
// ns, payload as hex (sqlite3 -separator $'\t' DB "SELECT topic, type_name, receive_ns, source_ns, hex(payload)
// FROM samples ORDER BY receive_ns, id"). COMPRESSION: what every chunk must say ("" for none). Each SCHEMA_TYPE
// must have a channel with an omgidl schema of that name. --sensor: the gateway's sensor every status must name. Prints what it checked; exit 1 on
// the first difference. With --expect, the first message of each topic VALUES.json names must decode to its
// members there, every member (64-bit integers as strings).
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader } from "@foxglove/omgidl-serialization";
import zstd from "@foxglove/wasm-zstd";
import lz4 from "@foxglove/wasm-lz4";
import { readFileSync } from "node:fs";
import { contentChecks } from "./known_content.mjs";

const [file, samplesFile, compression, ...rest] = process.argv.slice(2);
/// The value of `--flag VALUE` in rest, taken out of it; undefined when absent.
function option(flag) {
  const at = rest.indexOf(flag);
  return at < 0 ? undefined : rest.splice(at, 2)[1];
}
const expectFile = option("--expect");
const expectedValues = expectFile === undefined ? {} : JSON.parse(readFileSync(expectFile, "utf8"));
const sensor = option("--sensor");
const expectedSchemas = rest;
const knownContent = contentChecks({ sensor });

function fail(message) {
  console.error(`FAIL: ${file}: ${message}`);
  process.exit(1);
}

function hex(bytes) {
  return Buffer.from(bytes).toString("hex").toUpperCase();
}

await zstd.isLoaded;
await lz4.isLoaded;
const decompressHandlers = {
  zstd: (buffer, size) => zstd.decompress(buffer, Number(size)),
  lz4: (buffer, size) => lz4(buffer, Number(size)),
};

const expected = readFileSync(samplesFile, "utf8")
  .split("\n")
  .filter((line) => line.length > 0)
  .map((line) => {
    const [topic, typeName, receiveNs, sourceNs, payload] = line.split("\t");
    return { topic, typeName, logTime: BigInt(receiveNs), publishTime: BigInt(sourceNs), payload };
  });
if (expected.length === 0) fail(`${samplesFile} holds no samples`);

// Messages of one topic come in the order of their log time (when received; a backfilled one's, its source time,
// as the TSV gives it); across topics, samples received within the same
// microseconds may be in either order. Each reader's messages are compared topic by topic.
function messageChecker() {
  const next = new Map();
  let count = 0;
  return (message, channelsById) => {
    const channel = channelsById.get(message.channelId);
    if (!channel) fail(`message ${count} on unknown channel ${message.channelId}`);
    const ofTopic = byTopic.get(channel.topic) ?? [];
    const i = next.get(channel.topic) ?? 0;
    next.set(channel.topic, i + 1);
    ++count;
    const want = ofTopic[i];
    if (!want) fail(`${channel.topic}: message ${i} was not recorded (${ofTopic.length} were)`);
    const where = `${channel.topic} message ${i}`;
    if (message.logTime !== want.logTime) fail(`${where}: log time ${message.logTime}, expected ${want.logTime}`);
    if (message.publishTime !== want.publishTime) {
      fail(`${where}: publish time ${message.publishTime}, source time ${want.publishTime}`);
    }
    if (hex(message.data) !== want.payload) fail(`${where}: bytes differ from the recording`);
    return count;
  };
}
const byTopic = new Map();
for (const sample of expected) {
  if (!byTopic.has(sample.topic)) byTopic.set(sample.topic, []);
  byTopic.get(sample.topic).push(sample);
}

// 1. From start to end, as a streaming reader (and a file cut short by a crash) reads it, every CRC checked.
const bytes = readFileSync(file);
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(bytes);
const streamChannels = new Map();
const seen = {};
let streamed = 0;
const checkStreamed = messageChecker();
for (let record; (record = stream.nextRecord()); ) {
  seen[record.type] = (seen[record.type] ?? 0) + 1;
  if (record.type === "Channel") streamChannels.set(record.id, record);
  if (record.type === "Message") streamed = checkStreamed(record, streamChannels);
}
if (!stream.done()) fail("the stream reader did not reach the end magic");
if (streamed !== expected.length) fail(`${streamed} messages from start to end, the recording has ${expected.length}`);
for (const type of ["Header", "DataEnd", "Footer", "Statistics", "ChunkIndex", "MessageIndex", "SummaryOffset"]) {
  if (!seen[type]) fail(`no ${type} record`);
}
console.log(`ok: stream reader, CRCs checked: ${streamed} messages equal to the recording, records ${JSON.stringify(seen)}`);

// 2. Through the summary, as Foxglove opens a file.
const reader = await McapIndexedReader.Initialize({
  readable: {
    size: async () => BigInt(bytes.length),
    read: async (offset, size) => bytes.subarray(Number(offset), Number(offset + size)),
  },
  decompressHandlers,
});
const stats = reader.statistics;
if (!stats) fail("no statistics in the summary");
if (stats.messageCount !== BigInt(expected.length)) {
  fail(`statistics say ${stats.messageCount} messages, the recording has ${expected.length}`);
}
// A channel for every recorded topic; a topic discovered but never heard from has one with no messages.
const channelTopics = new Set([...reader.channelsById.values()].map((c) => c.topic));
for (const topic of byTopic.keys()) {
  if (!channelTopics.has(topic)) fail(`no channel for the recorded topic ${topic}`);
}
if (stats.channelCount !== reader.channelsById.size) fail("statistics' channel count differs from the channels");
if (stats.chunkCount !== reader.chunkIndexes.length) fail("statistics' chunk count differs from the chunk indexes");
for (const index of reader.chunkIndexes) {
  if (index.compression !== compression) fail(`a chunk compressed '${index.compression}', expected '${compression}'`);
}
for (const channel of reader.channelsById.values()) {
  if (channel.messageEncoding !== "cdr") fail(`${channel.topic}: message encoding ${channel.messageEncoding}`);
  const count = expected.filter((s) => s.topic === channel.topic).length;
  if ((stats.channelMessageCounts.get(channel.id) ?? 0n) !== BigInt(count)) {
    fail(`${channel.topic}: statistics count ${stats.channelMessageCounts.get(channel.id)}, recorded ${count}`);
  }
}
let indexed = 0;
const checkIndexed = messageChecker();
for await (const message of reader.readMessages({ validateCrcs: true })) {
  indexed = checkIndexed(message, reader.channelsById);
}
if (indexed !== expected.length) fail(`${indexed} messages through the indexes, the recording has ${expected.length}`);
console.log(
  `ok: indexed reader: ${indexed} messages in ${reader.chunkIndexes.length} chunk(s) compressed '${compression}', ` +
    `${reader.channelsById.size} channels, ${reader.schemasById.size} schemas`,
);

/// A decoded value as JSON has it: BigInt as a string, typed arrays as arrays, in the schema's member order.
function plain(value) {
  if (typeof value === "bigint") return value.toString();
  if (ArrayBuffer.isView(value)) return Array.from(value, plain);
  if (Array.isArray(value)) return value.map(plain);
  if (value !== null && typeof value === "object") {
    return Object.fromEntries(Object.entries(value).map(([k, v]) => [k, plain(v)]));
  }
  return value;
}

// 3. Every message of a channel with a schema, decoded from the schema alone.
const schemaNames = new Set();
for (const channel of reader.channelsById.values()) {
  const schema = reader.schemasById.get(channel.schemaId);
  if (!schema) continue;
  if (schema.encoding !== "omgidl") fail(`${channel.topic}: schema encoding ${schema.encoding}`);
  schemaNames.add(schema.name);
  const definition = new TextDecoder().decode(schema.data);
  let decoder;
  try {
    decoder = new MessageReader(schema.name, parseIDL(definition));
  } catch (error) {
    fail(`${channel.topic}: schema ${schema.name} does not parse: ${error.message}\n${definition}`);
  }
  if (!byTopic.has(channel.topic)) continue;  // discovered, never heard from: its schema parsed is all
  let decoded = 0;
  let first;
  let previous;
  for await (const message of reader.readMessages({ topics: [channel.topic] })) {
    let value;
    try {
      value = decoder.readMessage(message.data);
    } catch (error) {
      fail(`${channel.topic}: message ${decoded} does not decode with ${schema.name}: ${error.message}`);
    }
    const wrong = knownContent[schema.name]?.(value, message, previous);
    if (wrong) fail(`${channel.topic}: message ${decoded} decoded with ${schema.name}: ${wrong}`);
    previous = value;
    first ??= value;
    ++decoded;
  }
  if (expectedValues[channel.topic] !== undefined) {
    const got = plain(first);
    const want = expectedValues[channel.topic];
    if (JSON.stringify(got) !== JSON.stringify(want)) {
      fail(`${channel.topic}: decoded ${JSON.stringify(got)}, published ${JSON.stringify(want)}`);
    }
    console.log(`ok: ${channel.topic}: every member of its first message as published`);
  }
  const shown = JSON.stringify(first, (key, v) => (typeof v === "bigint" ? v.toString() : v)).slice(0, 160);
  const checked = knownContent[schema.name] ? ", members checked" : "";
  console.log(`ok: ${channel.topic}: ${decoded} messages decoded with schema ${schema.name}${checked}; the first: ${shown}`);
}
for (const topic of Object.keys(expectedValues)) {
  if (!byTopic.has(topic)) fail(`--expect names ${topic}, which the recording does not have`);
}
for (const name of expectedSchemas) {
  if (!schemaNames.has(name)) fail(`no channel with an omgidl schema ${name}; schemas: ${[...schemaNames].join(", ")}`);
}
console.log(`ok: schemas ${[...schemaNames].join(", ")}`);
