// Load for the live view's benchmark (scripts/view-bench): N viewers of a view at PORT, each
// subscribed to every channel with Foxglove's client; the first of them stops reading its socket
// once subscribed (a viewer that never reads). Runs until killed; prints what each received.
// Usage: node viewers.mjs PORT N
import protocol from "@foxglove/ws-protocol";
import WebSocket from "ws";

const { FoxgloveClient } = protocol;
const [port, count] = process.argv.slice(2).map(Number);
const received = new Array(count).fill(0);
for (let i = 0; i < count; ++i) {
  const ws = new WebSocket(`ws://127.0.0.1:${port}/`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  client.on("advertise", (channels) => {
    for (const c of channels) client.subscribe(c.id);
    if (i === 0) setTimeout(() => ws._socket.pause(), 200); // never reads again
  });
  client.on("message", () => ++received[i]);
  client.on("error", (e) => console.error(`viewer ${i}: ${e}`));
}
const report = () => console.log(`viewers: messages received ${received.join(" ")}`);
process.on("SIGTERM", () => { report(); process.exit(0); });
process.on("SIGINT", () => { report(); process.exit(0); });
