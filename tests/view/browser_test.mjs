// Opens navd's live view page in Debian's chromium (playwright-core, headless) while navsim and
// navd run: checks that the robot is drawn where navd's pose says, clicks a goal on the map and
// sees `navctl status` report it, sees the robot move between two screenshots, clicks cancel and
// sees the goal end; then opens navsim's ground-truth page and finds the robot there too.
// Usage: node browser_test.mjs NAVD_VIEW_PORT NAVSIM_VIEW_PORT NAVCTL NAVD_ADDRESS SCREENSHOT_DIR
import { execFileSync } from "node:child_process";
import { chromium } from "playwright-core";

const [viewPort, simViewPort, navctl, navdAddress, shots] = process.argv.slice(2);
if (!shots) {
  console.error("usage: browser_test.mjs NAVD_VIEW_PORT NAVSIM_VIEW_PORT NAVCTL NAVD_ADDRESS SCREENSHOT_DIR");
  process.exit(2);
}
let browser;
const fail = async (why) => {
  console.error("FAIL: " + why);
  if (browser) await browser.close().catch(() => {});
  process.exit(1);
};
setTimeout(() => fail("timed out after 150 s"), 150000).unref();
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const navctlSays = (...args) => execFileSync(navctl, ["--server", navdAddress, ...args], { encoding: "utf8" });
const navctlPose = () => {
  const m = navctlSays("pose").match(/pose \(([-\d.]+), ([-\d.]+), ([-\d.]+)\)/);
  return { x: Number(m[1]), y: Number(m[2]) };
};
async function until(what, test, seconds = 30) {
  const end = Date.now() + seconds * 1000;
  for (;;) {
    const value = await test();
    if (value) return value;
    if (Date.now() > end) await fail("no " + what + " within " + seconds + " s");
    await sleep(100);
  }
}

browser = await chromium.launch({
  executablePath: "/usr/bin/chromium",
  headless: true,
  args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking"],
});
const page = await browser.newPage({ viewport: { width: 1100, height: 760 } });
page.on("pageerror", (e) => fail("page error: " + e.message));
await page.goto(`http://127.0.0.1:${viewPort}/`);
await until("map and pose on the page", () =>
  page.evaluate(() => !!(navdView.state.latest["/map"] && navdView.state.latest["/pose"] && navdView.state.latest["/costmap"])));

// Robot pixels (the page's robot colour, #2ecc71) around a point of the canvas.
const robotPixelsAt = (x, y) =>
  page.evaluate(([x, y]) => {
    const canvas = document.getElementById("canvas");
    const [sx, sy] = navdView.worldToScreen(x, y);
    const d = canvas.getContext("2d").getImageData(Math.round(sx) - 3, Math.round(sy) - 3, 7, 7).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4) if (Math.abs(d[i] - 46) < 12 && Math.abs(d[i + 1] - 204) < 12 && Math.abs(d[i + 2] - 113) < 12) ++n;
    return n;
  }, [x, y]);
// Standing, the robot must be drawn at navctl's pose. Moving, at the pose the page last received,
// and navctl's pose, asked between two looks at the page's, must lie within 0.3 m of the way the
// page's went meanwhile (the view's 10 Hz feed and the page's frames lag a little; navctl takes a
// while to start on a loaded machine, during which the robot drives on).
const pagePose = () => page.evaluate(() => navdView.state.latest["/pose"].pose.position);
function distanceToSegment(p, a, b) {
  const dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
  const t = len2 > 0 ? Math.max(0, Math.min(1, ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2)) : 0;
  return Math.hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}
async function robotDrawnAtNavdPose(label, moving = false) {
  await sleep(300); // a frame or two after the newest pose
  const before = moving ? await pagePose() : null;
  const p = navctlPose();
  let at = p;
  if (moving) {
    const drawn = await pagePose();
    const apart = distanceToSegment(p, before, drawn);
    if (apart > 0.3) await fail(`${label}: the page's pose is ${apart.toFixed(2)} m from navctl's`);
    at = { x: drawn.x, y: drawn.y };
  }
  const n = await robotPixelsAt(at.x, at.y);
  console.log(`${label}: navctl pose (${p.x.toFixed(2)}, ${p.y.toFixed(2)}), ${n} of 49 robot pixels at (${at.x.toFixed(2)}, ${at.y.toFixed(2)})`);
  if (n < 10) await fail(`${label}: the robot is not drawn at navd's pose`);
  return p;
}
const start = await robotDrawnAtNavdPose("standing");

// A goal 4-8 m away in free space (a cell the costmap gives no cost at all), far enough that the
// robot is still on its way when cancel is clicked.
const goal = await page.evaluate(([rx, ry]) => {
  const g = navdView.state.latest["/costmap"];
  const bytes = Uint8Array.from(atob(g.data), (c) => c.charCodeAt(0));
  const rows = bytes.length / g.row_stride;
  let best = null;
  for (let row = 0; row < rows; row += 2) {
    for (let col = 0; col < g.column_count; col += 2) {
      if (bytes[row * g.row_stride + col] !== 0) continue;
      const x = g.pose.position.x + (col + 0.5) * g.cell_size.x, y = g.pose.position.y + (row + 0.5) * g.cell_size.y;
      const d = Math.hypot(x - rx, y - ry);
      if (d > 4 && d < 8 && (!best || Math.abs(d - 6) < Math.abs(best.d - 6))) best = { x, y, d };
    }
  }
  return best;
}, [start.x, start.y]);
if (!goal) await fail("no free cell 4-8 m from the robot");
const canvasBox = await page.locator("#canvas").boundingBox();
const [gx, gy] = await page.evaluate(([x, y]) => navdView.worldToScreen(x, y), [goal.x, goal.y]);
await page.mouse.click(canvasBox.x + gx, canvasBox.y + gy);
const status = await until("navctl status reporting the clicked goal", () => {
  const s = navctlSays("status");
  return /goal active/.test(s) ? s : null;
});
console.log(`clicked (${goal.x.toFixed(2)}, ${goal.y.toFixed(2)}); navctl status: ${status.trim()}`);
const sentGoal = await page.evaluate(() => navdView.state.latest["/mission"]);

await page.screenshot({ path: `${shots}/view-1.png` });
const first = await robotDrawnAtNavdPose("screenshot 1", true);
await sleep(2000);
await page.screenshot({ path: `${shots}/view-2.png` });
const second = await robotDrawnAtNavdPose("screenshot 2", true);
const moved = Math.hypot(second.x - first.x, second.y - first.y);
console.log(`the robot moved ${moved.toFixed(2)} m between the screenshots`);
if (moved < 0.1) await fail("the robot did not move between the screenshots");
const mission = await until("the mission on the page", () =>
  page.evaluate(() => (navdView.state.latest["/mission"]?.active ? navdView.state.latest["/mission"] : null)));
if (Math.hypot(mission.goal.x - goal.x, mission.goal.y - goal.y) > 0.05) await fail("the mission's goal is not the click");

await page.click("#cancel");
await until("the goal cancelled", () => /idle/.test(navctlSays("status")));
const result = await until("the page showing the mission ended", () =>
  page.evaluate((id) => {
    const m = navdView.state.latest["/mission"];
    return m && !m.active && m.goal_id === id ? m.last_result?.outcome : null;
  }, mission.goal_id));
console.log(`after cancel: navctl status '${navctlSays("status").trim()}', page result ${result}`);
if (result !== "canceled") await fail("the page shows " + result + " after cancel");

// navsim's view: the true robot near where navd believes it is.
const truth = await browser.newPage({ viewport: { width: 1100, height: 760 } });
truth.on("pageerror", (e) => fail("truth page error: " + e.message));
await truth.goto(`http://127.0.0.1:${simViewPort}/`);
const robots = await until("the true robot on navsim's page", () =>
  truth.evaluate(() => navdView.state.latest["/truth/robots"]?.discs?.length ? navdView.state.latest["/truth/robots"].discs : null));
const now = navctlPose();
const off = Math.hypot(robots[0].x - now.x, robots[0].y - now.y);
console.log(`navsim's truth ${robots[0].id} at (${robots[0].x.toFixed(2)}, ${robots[0].y.toFixed(2)}), ${off.toFixed(2)} m from navd's pose`);
if (off > 0.5) await fail("navsim's truth and navd's pose are far apart");
await truth.screenshot({ path: `${shots}/truth.png` });
await browser.close();
console.log("PASS (screenshots in " + shots + ")", sentGoal ? "" : "");
process.exit(0);
