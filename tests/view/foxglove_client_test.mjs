// Connects Foxglove's own client (@foxglove/ws-protocol) to a running navd's live view, lists the
// advertised channels, subscribes to the map and the pose, checks each message against the JSON
// Schema its channel advertised, and compares the pose with `navctl pose`.
// Usage: node foxglove_client_test.mjs VIEW_PORT NAVCTL NAVD_ADDRESS
import { execFileSync } from "node:child_process";
import Ajv from "ajv";
import protocol from "@foxglove/ws-protocol";
import WebSocket from "ws";

const { FoxgloveClient } = protocol;
const [viewPort, navctl, navdAddress] = process.argv.slice(2);
if (!navdAddress) {
  console.error("usage: foxglove_client_test.mjs VIEW_PORT NAVCTL NAVD_ADDRESS");
  process.exit(2);
}
const fail = (why) => {
  console.error("FAIL: " + why);
  process.exit(1);
};
setTimeout(() => fail("timed out after 60 s"), 60000).unref();

const EXPECTED = ["/map", "/map_building", "/costmap", "/pose", "/tf", "/path", "/path_ahead", "/scan", "/people",
                  "/moving_obstacles", "/status", "/mission"];
const ajv = new Ajv({ strict: false });
const channels = new Map();   // topic -> channel
const validators = new Map(); // channel id -> validate
const subscriptions = new Map(); // subscription id -> channel
const received = {};           // topic -> [messages]
const decoder = new TextDecoder();

const client = new FoxgloveClient({
  ws: new WebSocket(`ws://127.0.0.1:${viewPort}/`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]),
});
client.on("error", (e) => fail("client error: " + e));
client.on("serverInfo", (info) => console.log(`server '${info.name}', capabilities ${JSON.stringify(info.capabilities)}`));
const advertised = new Promise((resolve) => {
  client.on("advertise", (list) => {
    for (const c of list) {
      if (c.schemaEncoding !== "jsonschema" || c.encoding !== "json") fail(`${c.topic}: ${c.encoding}/${c.schemaEncoding}`);
      channels.set(c.topic, c);
      validators.set(c.id, ajv.compile(JSON.parse(c.schema)));
    }
    resolve();
  });
});
client.on("message", ({ subscriptionId, data }) => {
  const channel = subscriptions.get(subscriptionId);
  const message = JSON.parse(decoder.decode(new Uint8Array(data.buffer, data.byteOffset, data.byteLength)));
  const validate = validators.get(channel.id);
  if (!validate(message)) fail(`${channel.topic} does not match its schema: ${ajv.errorsText(validate.errors)}`);
  (received[channel.topic] ||= []).push(message);
});

await advertised;
console.log("channels: " + [...channels.keys()].join(" "));
for (const topic of EXPECTED) if (!channels.has(topic)) fail(`channel ${topic} is not advertised`);

for (const topic of ["/map", "/pose"]) {
  const c = channels.get(topic);
  subscriptions.set(client.subscribe(c.id), c);
}
const until = async (what, test, seconds = 20) => {
  const end = Date.now() + seconds * 1000;
  while (!test()) {
    if (Date.now() > end) fail("no " + what + " within " + seconds + " s");
    await new Promise((r) => setTimeout(r, 50));
  }
};
await until("map", () => received["/map"]);
await until("pose", () => received["/pose"]?.length >= 2);

// The map: a foxglove.Grid whose data holds every cell.
const map = received["/map"][0];
const cells = Buffer.from(map.data, "base64");
if (map.fields[0].name !== "occupancy" || map.cell_stride !== 1) fail("map layout: " + JSON.stringify(map.fields));
if (cells.length % map.row_stride !== 0 || cells.length / map.row_stride < 10) fail(`map data of ${cells.length} bytes`);
const occupied = cells.filter((v) => v === 100).length;
if (occupied === 0) fail("the map has no occupied cell");
console.log(`map ${map.column_count} x ${cells.length / map.row_stride} cells at ${map.cell_size.x} m, ${occupied} occupied`);

// The pose against navctl's, both from the same standing robot.
const out = execFileSync(navctl, ["--server", navdAddress, "pose"], { encoding: "utf8" });
const m = out.match(/pose \(([-\d.]+), ([-\d.]+), ([-\d.]+)\)/);
if (!m) fail("navctl pose said: " + out);
const pose = received["/pose"].at(-1).pose;
const yaw = 2 * Math.atan2(pose.orientation.z, pose.orientation.w);
const dx = pose.position.x - Number(m[1]), dy = pose.position.y - Number(m[2]);
const dyaw = Math.atan2(Math.sin(yaw - Number(m[3])), Math.cos(yaw - Number(m[3])));
console.log(`view pose (${pose.position.x.toFixed(3)}, ${pose.position.y.toFixed(3)}, ${yaw.toFixed(3)}); navctl ${m[0]}`);
if (Math.hypot(dx, dy) > 0.02 || Math.abs(dyaw) > 0.02) fail("the view's pose differs from navctl's");
const covariance = received["/pose"].at(-1).covariance;
if (!(covariance[0] > 0 && covariance[4] > 0)) fail("covariance " + JSON.stringify(covariance));

client.close();
console.log("PASS");
process.exit(0);
