// The live view under navd --auth-tokens: the page and the WebSocket need a known token in the
// URL (HTTP 401 without), the viewer role watches but may not publish, the operator role may send
// a goal. Uses Foxglove's client for the WebSocket side.
// Usage: node access_test.mjs VIEW_PORT VIEWER_TOKEN OPERATOR_TOKEN
import protocol from "@foxglove/ws-protocol";
import WebSocket from "ws";

const { FoxgloveClient } = protocol;
const [port, viewerToken, operatorToken] = process.argv.slice(2);
const fail = (why) => {
  console.error("FAIL: " + why);
  process.exit(1);
};
setTimeout(() => fail("timed out after 60 s"), 60000).unref();
const base = `127.0.0.1:${port}`;

for (const [url, want] of [[`http://${base}/`, 401], [`http://${base}/?token=not-a-token-at-all`, 401],
                           [`http://${base}/?token=${viewerToken}`, 200]]) {
  const r = await fetch(url);
  console.log(`GET ${url.replace(/token=[^&]+/, "token=...")}: ${r.status}`);
  if (r.status !== want) fail(`expected HTTP ${want}`);
}
const refused = await new Promise((resolve) => {
  const ws = new WebSocket(`ws://${base}/`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  ws.on("unexpected-response", (req, res) => resolve(res.statusCode));
  ws.on("open", () => resolve("open"));
  ws.on("error", () => {});
});
console.log(`WebSocket without a token: ${refused}`);
if (refused !== 401) fail("a WebSocket without a token was not refused with 401");

// Connects with `token`; resolves with the server's capabilities and the statuses it sends after
// a /goal is published on a client channel.
function session(token, goal) {
  return new Promise((resolve) => {
    const client = new FoxgloveClient({ ws: new WebSocket(`ws://${base}/?token=${token}`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
    const statuses = [];
    let capabilities;
    client.on("serverInfo", (info) => { capabilities = info.capabilities; });
    client.on("status", (s) => statuses.push(s));
    client.on("advertise", () => {
      const channel = client.advertise({ topic: "/goal", encoding: "json", schemaName: "navd.Goal" });
      setTimeout(() => {
        client.sendMessage(channel, new TextEncoder().encode(JSON.stringify(goal)));
        setTimeout(() => { client.close(); resolve({ capabilities, statuses }); }, 1500);
      }, 200);
    });
  });
}
const viewer = await session(viewerToken, { x: 2, y: 3 });
console.log(`viewer: capabilities ${JSON.stringify(viewer.capabilities)}, statuses ${JSON.stringify(viewer.statuses.map((s) => s.message))}`);
if (viewer.capabilities.includes("clientPublish")) fail("a viewer was offered clientPublish");
if (!viewer.statuses.some((s) => s.level === 2 && /operator role/.test(s.message))) fail("a viewer's goal was not refused");
const operator = await session(operatorToken, { x: 2, y: 3 });
console.log(`operator: capabilities ${JSON.stringify(operator.capabilities)}, statuses ${JSON.stringify(operator.statuses.map((s) => s.message))}`);
if (!operator.statuses.some((s) => /^goal \d+ accepted$/.test(s.message))) fail("an operator's goal was not accepted");
const bad = await session(operatorToken, { x: "three" });
console.log(`malformed goal: ${JSON.stringify(bad.statuses.map((s) => s.message))}`);
if (!bad.statuses.some((s) => s.level === 2 && /goal: x is missing or not a number/.test(s.message))) fail("a malformed goal was not refused by name");
console.log("PASS");
process.exit(0);
