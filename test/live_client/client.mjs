// A Foxglove WebSocket protocol client that is not tethersim's code: Foxglove's own
// @foxglove/ws-protocol client over `ws`, and the ros2msg parser and CDR reader the Foxglove
// app decodes ROS 2 messages with (@foxglove/rosmsg, @foxglove/rosmsg2-serialization).
//
// usage: node client.mjs URL [--count] TOPIC [TOPIC ...]
//
// Connects to URL (retrying while nothing listens there yet), subscribes to each TOPIC (every
// topic for "*") once the server advertises it, and prints one JSON line per event to stdout
// until the server closes the connection (with --count only the close event, with the number
// of messages received per topic):
//   {"event": "serverInfo", "name", "capabilities"}
//   {"event": "advertise", "channels": [{topic, encoding, schemaName, schemaEncoding, schema}]}
//   {"event": "message", "topic", "logTime", "message"}  (logTime in ns as a string; the
//                                                        message decoded from its CDR bytes)
//   {"event": "time", "time"}                            (the server's first broadcast time, ns)
//   {"event": "close", "counts": {topic: messages received}}
import wsProtocol from "@foxglove/ws-protocol";
import rosmsg from "@foxglove/rosmsg";
import serialization from "@foxglove/rosmsg2-serialization";
import WebSocket from "ws";

const { FoxgloveClient } = wsProtocol;
const { parse } = rosmsg;
const { MessageReader } = serialization;

const [url, ...rest] = process.argv.slice(2);
const countOnly = rest[0] === "--count";
const topics = countOnly ? rest.slice(1) : rest;
if (!url || topics.length === 0) {
  console.error("usage: node client.mjs URL [--count] TOPIC [TOPIC ...]");
  process.exit(2);
}
const RETRY_MS = 100;
// The subprotocol the Foxglove SDK's server accepts (and today's Foxglove and Lichtblick offer):
// the same messages as the client's older "foxglove.websocket.v1", under a new name.
const SUBPROTOCOL = "foxglove.sdk.v1";

const counts = {};

function emit(event) {
  if (countOnly && event.event !== "close") return;
  process.stdout.write(
    JSON.stringify(event, (key, value) => {
      if (typeof value === "bigint") return value.toString();
      if (ArrayBuffer.isView(value)) return Array.from(value);
      return value;
    }) + "\n",
  );
}

function connect() {
  const ws = new WebSocket(url, [SUBPROTOCOL]);
  let opened = false;
  ws.on("open", () => {
    opened = true;
  });
  ws.on("error", (error) => {
    if (!opened) {
      setTimeout(connect, RETRY_MS);
    } else {
      console.error(`client: ${error.message}`);
    }
  });
  ws.on("close", () => {
    if (opened) {
      emit({ event: "close", counts });
    }
  });
  const client = new FoxgloveClient({ ws });
  const readers = new Map();
  let timeSeen = false;
  client.on("serverInfo", ({ name, capabilities }) => {
    emit({ event: "serverInfo", name, capabilities });
  });
  client.on("advertise", (channels) => {
    emit({
      event: "advertise",
      channels: channels.map((c) => ({
        topic: c.topic,
        encoding: c.encoding,
        schemaName: c.schemaName,
        schemaEncoding: c.schemaEncoding,
        schema: c.schema,
      })),
    });
    for (const channel of channels) {
      if (!topics.includes(channel.topic) && !topics.includes("*")) continue;
      const reader = new MessageReader(parse(channel.schema, { ros2: true }));
      readers.set(client.subscribe(channel.id), { topic: channel.topic, reader });
    }
  });
  client.on("time", ({ timestamp }) => {
    if (!timeSeen) {
      timeSeen = true;
      emit({ event: "time", time: timestamp });
    }
  });
  client.on("message", ({ subscriptionId, timestamp, data }) => {
    const { topic, reader } = readers.get(subscriptionId);
    counts[topic] = (counts[topic] ?? 0) + 1;
    emit({ event: "message", topic, logTime: timestamp, message: reader.readMessage(data) });
  });
}

connect();
