// Connects to tm-basecamp relay --foxglove-port with @foxglove/ws-protocol's client, as Foxglove does: one client
// that subscribes to every channel, and one that subscribes to nothing and must receive nothing. Every message is
// decoded with its channel's advertised omgidl schema (@foxglove/omgidl-parser, -serialization). A third client
// sends malformed requests, which must be answered with warnings while the others are served.
//
//   node check_foxglove.mjs URL SECONDS SENSOR OUT.tsv TOPIC...
//
// Waits for each TOPIC to be advertised, subscribes to every channel, collects messages for SECONDS, and writes
// each one to OUT.tsv (topic, receive ns, payload as hex) for the caller to compare with what the relay recorded.
// Exit 1 when a TOPIC was not advertised or sent nothing, a message does not decode, or the idle client got any.
import wsProtocol from "@foxglove/ws-protocol";
import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader } from "@foxglove/omgidl-serialization";
import { WebSocket } from "ws";
import { writeFileSync } from "node:fs";
import { contentChecks } from "./known_content.mjs";

const { FoxgloveClient } = wsProtocol; // a CommonJS module
const [url, seconds, sensor, outFile, ...topics] = process.argv.slice(2);
const knownContent = contentChecks({ sensor });

function fail(message) {
  console.error(`FAIL: ${url}: ${message}`);
  process.exit(1);
}

function connect() {
  const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
  client.on("error", (error) => fail(`connection: ${error.message ?? error}`));
  return client;
}

// A client that sends what no Foxglove would: the server must say so in status messages, and go on serving.
const rude = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const warnings = [];
rude.on("message", (data, isBinary) => {
  if (!isBinary) {
    const message = JSON.parse(data.toString());
    if (message.op === "status") warnings.push(message.message);
  }
});
rude.on("open", () => {
  rude.send("not JSON");
  rude.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: "one", channelId: 1 }] }));
  rude.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: 1, channelId: 99999 }] }));
  rude.send(JSON.stringify({ op: "unsubscribe", subscriptionIds: [null] }));
});

const idle = connect();
let idleMessages = 0;
idle.on("message", () => ++idleMessages);

const client = connect();
let serverName;
client.on("serverInfo", (info) => (serverName = info.name));
const channels = new Map(); // id -> channel, with its decoder
const bySubscription = new Map(); // subscription id -> channel
client.on("advertise", (advertised) => {
  for (const channel of advertised) {
    if (channel.encoding !== "cdr") fail(`${channel.topic}: encoding ${channel.encoding}`);
    let decoder;
    if (channel.schema !== "") {
      if (channel.schemaEncoding !== "omgidl") fail(`${channel.topic}: schema encoding ${channel.schemaEncoding}`);
      try {
        decoder = new MessageReader(channel.schemaName, parseIDL(channel.schema));
      } catch (error) {
        fail(`${channel.topic}: schema ${channel.schemaName} does not parse: ${error.message}`);
      }
    }
    channels.set(channel.id, { ...channel, decoder });
    bySubscription.set(client.subscribe(channel.id), channels.get(channel.id));
  }
});
const received = [];
const decodedByTopic = new Map();
client.on("message", ({ subscriptionId, timestamp, data }) => {
  const channel = bySubscription.get(subscriptionId);
  if (!channel) fail(`a message for subscription ${subscriptionId}, which this client never made`);
  const bytes = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
  received.push([channel.topic, timestamp.toString(), Buffer.from(bytes).toString("hex").toUpperCase()]);
  if (channel.decoder) {
    try {
      const value = channel.decoder.readMessage(bytes);
      if (!decodedByTopic.has(channel.topic)) decodedByTopic.set(channel.topic, { count: 0, first: value });
      const seen = decodedByTopic.get(channel.topic);
      const wrong = knownContent[channel.schemaName]?.(value, {}, seen.previous);
      if (wrong) fail(`${channel.topic}: message ${seen.count} decoded with ${channel.schemaName}: ${wrong}`);
      seen.previous = value;
      seen.count++;
    } catch (error) {
      fail(`${channel.topic}: a message does not decode with ${channel.schemaName}: ${error.message}`);
    }
  }
});

await new Promise((resolve) => setTimeout(resolve, Number(seconds) * 1000));
client.close();
idle.close();
rude.close();

if (serverName === undefined) fail("no serverInfo");
const advertised = new Set([...channels.values()].map((c) => c.topic));
for (const topic of topics) {
  if (!advertised.has(topic)) fail(`${topic} was never advertised; advertised: ${[...advertised].join(", ")}`);
  if (!received.some(([t]) => t === topic)) fail(`${topic}: no message in ${seconds} s`);
}
if (idleMessages !== 0) fail(`the client that subscribed to nothing got ${idleMessages} messages`);
if (warnings.length !== 4) fail(`${warnings.length} status warnings for 4 malformed requests: ${warnings.join("; ")}`);
writeFileSync(outFile, received.map((fields) => fields.join("\t")).join("\n") + "\n");
console.log(`ok: server '${serverName}', ${channels.size} channels advertised, ${received.length} messages received`);
for (const [topic, { count, first }] of decodedByTopic) {
  const shown = JSON.stringify(first, (key, v) => (typeof v === "bigint" ? v.toString() : v)).slice(0, 120);
  const schemaName = [...channels.values()].find((c) => c.topic === topic).schemaName;
  const checked = knownContent[schemaName] ? ", members checked" : "";
  console.log(`ok: ${topic}: ${count} messages decoded with ${schemaName}${checked}; the first: ${shown}`);
}
console.log("ok: the client that subscribed to nothing received nothing");
console.log(`ok: 4 malformed requests answered with status warnings: ${warnings.join("; ")}`);
process.exit(0);
