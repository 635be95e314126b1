// End-to-end tests of `pim serve` in a real browser: Debian's chromium driven by playwright-core.
// Run from the repository: `cargo build --release -p pim-cli && (cd tests/browser && npm install
// && npm test)`. The binary is target/release/pim (PIM_BIN overrides), the browser
// /usr/bin/chromium (CHROMIUM overrides). Screenshots go to target/browser-screenshots/.
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import http from "node:http";
import { chromium } from "playwright-core";
import { startPim } from "./server.mjs";

const repo = path.resolve(import.meta.dirname, "../..");
const pimBin = process.env.PIM_BIN || path.join(repo, "target/release/pim");
const shots = path.join(repo, "target/browser-screenshots");
const CASE = "reconstruction_us.toml";
let dir, server, url, base, token, browser, page;
let timings = [];
let opened = {};

before(async () => {
  fs.mkdirSync(shots, { recursive: true });
  dir = fs.mkdtempSync(path.join(os.tmpdir(), "pim-serve-"));
  fs.cpSync(path.join(repo, "examples/cases"), dir, { recursive: true });
  fs.cpSync(path.join(repo, "examples/scene"), path.join(dir, "scene"), { recursive: true });
  let started;
  ({ server, url: started } = startPim(pimBin, dir));
  url = await started;
  base = url.replace(/\/\?.*$/, "");
  token = /token=([0-9a-f]+)/.exec(url)[1];
  browser = await chromium.launch({
    executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
    args: ["--no-sandbox"],
  });
  // The tests wait on the page with expressions, which the page's own policy (no eval) forbids:
  // their page bypasses it; "the page's headers" test opens one under the policy.
  page = await browser.newPage({ viewport: { width: 1400, height: 900 }, bypassCSP: true });
});

after(async () => {
  if (browser) await browser.close();
  if (server) server.kill();
  if (dir) fs.rmSync(dir, { recursive: true, force: true });
});

// A request as another site's page or a stray client would make it (Node sets any Host).
function raw(method, pathname, { host, cookie, body } = {}) {
  return new Promise((resolve, reject) => {
    const u = new URL(base);
    const req = http.request({
      host: u.hostname, port: u.port, method, path: pathname,
      headers: {
        host: host || u.host,
        ...(cookie ? { cookie } : {}),
        ...(body ? { "content-type": "application/json" } : {}),
      },
    }, (res) => {
      let data = "";
      res.on("data", (d) => (data += d));
      res.on("end", () => resolve({ status: res.statusCode, body: data }));
    });
    req.on("error", reject);
    if (body) req.write(JSON.stringify(body));
    req.end();
  });
}

// Nothing in flight: no case being opened, no answer, none waiting, no drag, no move of a rest.
const idle = () => page.waitForFunction(() => window.pim && !window.pim.opening && !window.pim.busy
  && !window.pim.pending && !window.pim.dragging && !window.pim.moves);
// The study's status line matches `re` (within `timeout` ms); else the failure says what the
// line said instead.
async function studySays(re, timeout = 60000) {
  try {
    await page.waitForFunction((src) => new RegExp(src).test(document.getElementById("study-status").textContent), re.source, { timeout });
  } catch (e) {
    const said = await page.textContent("#study-status");
    const report = await page.evaluate(() => JSON.stringify(window.pim.study && window.pim.study.report && { state: window.pim.study.report.state, done: window.pim.study.report.done, total: window.pim.study.report.total }));
    throw new Error(`the study's status never matched ${re}: it says "${said}" (report ${report}); ${e.message}`);
  }
}
const speeds = () => page.$$eval("#speeds tr[data-vehicle] td.contact", (tds) => tds.map((t) => +t.textContent));

// The example open with its text as the project has it (an earlier test saved a moved rest):
// the text, to put back at the end.
async function exampleAsCommitted() {
  // Chosen again: read from the folder (the path is already the case's: idle waits for the read).
  await page.selectOption("#cases", CASE);
  await idle();
  assert.equal(await page.evaluate(() => window.pim.path), CASE);
  const original = fs.readFileSync(path.join(repo, "examples/cases", CASE), "utf8");
  if ((await page.inputValue("#toml")) !== original) {
    await page.fill("#toml", original);
    await page.waitForFunction((t) => window.pim.text === t && window.pim.answer && !window.pim.busy, original, { timeout: 120000 });
    await idle();
  }
  // The whole scene in view, whatever an earlier test zoomed to.
  await page.click("#fit");
  return original;
}

test("opens the example and shows its reconstruction", async () => {
  await page.goto(url);
  await page.waitForSelector("#speeds td.contact");
  await idle();
  // `pim fit`'s contact speeds: 38.0950 mph (on the rounding edge of two decimals) and 27.196.
  const [sedan, suv] = await speeds();
  assert.ok(Math.abs(sedan - 38.095) < 0.006, `sedan ${sedan}`);
  assert.equal(suv, 27.2);
  opened = await page.evaluate(() => ({
    first_contentful_paint: performance.getEntriesByType("paint").find((p) => p.name === "first-contentful-paint")?.startTime,
    first_answer_drawn: performance.getEntriesByName("answer")[0]?.duration + performance.getEntriesByName("answer")[0]?.startTime,
  }));
  // The address drops nothing a reload needs: the token is now a cookie.
  const cookies = await page.context().cookies();
  assert.ok(cookies.some((c) => c.name === "pim_token" && c.httpOnly && c.sameSite === "Strict"));
  assert.equal(await page.locator(".given-rest circle.handle").count(), 2);
  assert.equal(await page.locator(".given-rest circle.rest-knob").count(), 2);
  // The geometry at contact: each CG and heading, the impact centre and the crush normal.
  assert.equal(await page.locator("rect.cg-handle").count(), 2);
  assert.equal(await page.locator("circle.heading-handle").count(), 2);
  assert.equal(await page.locator("path.centre-handle").count(), 1);
  assert.equal(await page.locator("circle.normal-handle").count(), 1);
  await page.screenshot({ path: path.join(shots, "01-opened.png") });
});

test("dragging car 2's rest 2 m changes the speeds, the TOML and the residuals", async () => {
  const before = await speeds();
  const text0 = await page.inputValue("#toml");
  const handle = page.locator('.given-rest circle.handle[data-vehicle="2"]');
  const box = await handle.boundingBox();
  // 2 m in the case's feet, in screen pixels: the view's width over the plan's width.
  const pxPerFt = await page.evaluate(() => document.getElementById("plan").clientWidth / window.pim.view.w);
  const dx = (2 / 0.3048) * pxPerFt;
  const x0 = box.x + box.width / 2, y0 = box.y + box.height / 2;
  await page.mouse.move(x0, y0);
  await page.mouse.down();
  for (let i = 1; i <= 10; i++) await page.mouse.move(x0 + (dx * i) / 10, y0);
  await page.mouse.up();
  await idle();
  const after = await speeds();
  const text1 = await page.inputValue("#toml");
  const rest = (t) => /\[scene\.vehicle2\]\nrest = \{ x = ([-0-9.]+), y = ([-0-9.]+)/.exec(t);
  const [, x0ft, y0ft] = rest(text0), [, x1ft, y1ft] = rest(text1);
  // SAE: to the right on the page is +y.
  assert.ok(Math.abs(+x1ft - +x0ft) < 0.3, `x ${x0ft} -> ${x1ft}`);
  assert.ok(Math.abs(+y1ft - +y0ft - 2 / 0.3048) < 0.3, `y ${y0ft} -> ${y1ft}`);
  assert.notDeepEqual(after, before, "the speeds at contact change");
  const chi = await page.evaluate(() => window.pim.answer.document.best.chi_square);
  assert.ok(chi > 0.5, `the moved rest costs chi-square ${chi}`);
  // Every other line of the file is kept.
  const a = text0.split("\n"), b = text1.split("\n");
  assert.equal(a.length, b.length);
  assert.equal(a.filter((l, i) => l !== b[i]).length, 1);
  await page.screenshot({ path: path.join(shots, "02-dragged.png") });
  timings = await page.evaluate(() => window.pim.timings);
});

test("a bad value marks the TOML and is not saved", async () => {
  const good = await page.inputValue("#toml");
  const onDisk = fs.readFileSync(path.join(dir, CASE), "utf8");
  await page.fill("#toml", good.replace("mass = 3400.0", "mass = -3400.0"));
  await page.waitForSelector("#error:not([hidden])");
  await idle();
  const message = await page.textContent("#error");
  assert.match(message, /mass/);
  assert.ok(await page.$("textarea.bad"));
  await page.click("#save");
  await page.waitForFunction(() => /not saved/.test(document.getElementById("status").textContent));
  assert.equal(fs.readFileSync(path.join(dir, CASE), "utf8"), onDisk);
  await page.screenshot({ path: path.join(shots, "03-bad-value.png") });
  await page.fill("#toml", good);
  await page.waitForSelector("#error", { state: "hidden" });
  await idle();
});

test("save writes the edit and nothing else; pim fit of the file gives the page's document", async () => {
  const original = fs.readFileSync(path.join(repo, "examples/cases", CASE), "utf8");
  await page.click("#save");
  await page.waitForFunction(() => /^saved/.test(document.getElementById("status").textContent));
  const saved = fs.readFileSync(path.join(dir, CASE), "utf8");
  assert.equal(saved, await page.inputValue("#toml"));
  const a = original.split("\n"), b = saved.split("\n");
  const changed = a.map((l, i) => [l, b[i]]).filter(([x, y]) => x !== y);
  assert.equal(changed.length, 1, JSON.stringify(changed));
  assert.match(changed[0][0], /^rest = \{ x = 50\.1, y = 79\.7, heading = 241\.0 \}/);
  // The comments are all there.
  for (const l of a.filter((l) => l.includes("#"))) assert.ok(b.includes(l), l);
  const page_doc = await page.evaluate(() => window.pim.answer.document);
  const cli = JSON.parse(execFileSync(pimBin, ["fit", path.join(dir, CASE), "--format", "json"], { encoding: "utf8" }));
  assert.deepEqual(page_doc, cli);
  // Reopened, the page shows the saved file.
  await page.reload();
  await page.waitForSelector("#speeds td.contact");
  await idle();
  assert.equal(await page.inputValue("#toml"), saved);
});

test("a file changed on disk while the page edits it: the page is told and loses nothing", async () => {
  const file = path.join(dir, CASE);
  await page.selectOption("#cases", CASE);
  await idle();
  // An edit in the page, not saved.
  const mine = (await page.inputValue("#toml")).replace("mass = 3400.0 ", "mass = 3450.0 ");
  await page.fill("#toml", mine);
  await page.waitForFunction((t) => window.pim.text === t, mine);
  await idle();
  // Another editor changes the friction and appends a line.
  const outside = fs.readFileSync(file, "utf8").replace("friction = 0.72", "friction = 0.65") + "# checked on site\n";
  fs.writeFileSync(file, outside);
  await page.click("#save");
  await page.waitForSelector("#conflict:not([hidden])");
  assert.match(await page.textContent("#conflict-message"), /changed on disk since it was opened/);
  assert.equal(fs.readFileSync(file, "utf8"), outside, "the outside edit was overwritten");
  assert.equal(await page.inputValue("#toml"), mine, "the page's edit was lost");
  await page.click("#conflict-compare-button");
  const marked = await page.$$eval("#conflict-disk .changed", (s) => s.map((x) => x.textContent.trim()));
  assert.ok(marked.includes("friction = 0.72                     # dry asphalt".replace("0.72", "0.65")), JSON.stringify(marked));
  assert.ok(marked.includes("# checked on site"), JSON.stringify(marked));
  await page.screenshot({ path: path.join(shots, "21-conflict.png") });
  // Saved over the file as it is now, knowingly.
  await page.click("#conflict-overwrite");
  await page.waitForFunction(() => /^saved/.test(document.getElementById("status").textContent));
  assert.equal(fs.readFileSync(file, "utf8"), mine);
  assert.ok(await page.isHidden("#conflict"));
  // Changed on disk again while the page holds no unsaved change: reloaded when the page is
  // looked at again.
  fs.writeFileSync(file, outside);
  await page.evaluate(() => window.dispatchEvent(new Event("focus")));
  await page.waitForFunction((t) => window.pim.text === t, outside);
  await idle();
  assert.equal(await page.inputValue("#toml"), outside);
  assert.match(await page.textContent("#status"), /changed on disk|solved/);
  // The example as the later tests expect it.
  fs.writeFileSync(file, fs.readFileSync(path.join(repo, "examples/cases", CASE), "utf8"));
  await page.evaluate(() => window.dispatchEvent(new Event("focus")));
  await page.waitForFunction(() => !/checked on site/.test(window.pim.text));
  await idle();
});

test("the page works under its own content policy, and an image's script never runs", async () => {
  fs.writeFileSync(path.join(dir, "evil.svg"), '<svg xmlns="http://www.w3.org/2000/svg"><script>window.parent.pwned = 1; document.title = "pwned";</script></svg>');
  const strict = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  const violations = [];
  strict.on("console", (m) => { if (/Content Security Policy/.test(m.text())) violations.push(m.text()); });
  await strict.goto(url);
  await strict.waitForSelector("#speeds td.contact", { timeout: 120000 });
  assert.deepEqual(violations, []);
  const res = await strict.goto(`${base}/api/image?path=evil.svg`);
  assert.match(res.headers()["content-security-policy"], /^sandbox;/);
  assert.equal(res.headers()["x-content-type-options"], "nosniff");
  assert.notEqual(await strict.title(), "pwned");
  await strict.close();
  fs.rmSync(path.join(dir, "evil.svg"));
});

test("an uncertainty study runs in the background, shows its intervals and can be cancelled", async () => {
  // A short study to its end: its document is the command's for the same draws and seed.
  await idle();
  await page.fill("#draws", "20");
  await page.click("#study-start");
  await studySays(/draws feasible/);
  const doc = await page.evaluate(() => window.pim.study.report.document);
  const cli = JSON.parse(execFileSync(pimBin, ["uncertainty", path.join(dir, CASE), "--draws", "20", "--format", "json"], { encoding: "utf8" }));
  assert.deepEqual(doc, cli);
  const cells = await page.$$eval("#speeds td.interval", (tds) => tds.map((t) => t.textContent));
  assert.equal(cells.length, 2);
  // The bands: each vehicle's run-out from each of the 20 draws, under the answer's paths.
  const bands = await page.evaluate(() => window.pim.study.report.bands);
  assert.equal(bands.length, 2 * doc.feasible_draws);
  assert.equal(await page.locator("polyline.band").count(), bands.length);
  for (const c of cells) {
    const [lo, hi] = c.split(" – ").map(Number);
    assert.ok(lo < hi, c);
  }
  // The intervals shown are the study's reported ones: the draws' widened to the profile's.
  for (const v of [1, 2]) {
    const name = `vehicle${v}.speed_at_contact`;
    const [lo, hi] = doc.intervals[name];
    const q = doc.quantities[name];
    const p = doc.profiles[name];
    assert.ok(lo <= q.p05 && hi >= q.p95, name);
    assert.ok(lo <= p.lower.speed && hi >= p.upper.speed, name);
  }
  await page.screenshot({ path: path.join(shots, "04-study.png") });
  // A long one, cancelled while it runs: the draws finished make the answer, and it says so.
  await page.fill("#draws", "5000");
  await page.click("#study-start");
  await page.waitForFunction(() => {
    const r = window.pim.study && window.pim.study.report;
    return r && r.total === 5000 && r.done >= 3;
  }, null, { timeout: 60000 });
  await page.click("#study-cancel");
  await studySays(/cancelled after/);
  const cancelled = await page.evaluate(() => window.pim.study.report.document.cancelled);
  assert.ok(cancelled.done >= 3 && cancelled.done < 5000, JSON.stringify(cancelled));
  assert.equal(cancelled.asked, 5000);
  assert.ok(await page.isHidden("#study-cancel"));
  await page.screenshot({ path: path.join(shots, "05-study-cancelled.png") });
});

test("the report opens from the page and the plan exports as SVG", async () => {
  // The report of the page's text is the one `pim report` writes of the saved file.
  const cookie = `pim_token=${token}`;
  const text = await page.inputValue("#toml");
  const r = await raw("POST", "/api/report", { cookie, body: { path: CASE, text } });
  assert.equal(r.status, 200);
  // Run where the page's path means the file (the report names it as given).
  const cli = execFileSync(pimBin, ["report", CASE], { cwd: dir, encoding: "utf8", maxBuffer: 1 << 26 });
  assert.equal(r.body, cli);
  const [popup] = await Promise.all([page.waitForEvent("popup"), page.click("#report")]);
  await popup.waitForFunction(() => document.title.length > 0, null, { timeout: 60000 });
  assert.equal(await popup.title(), /<title>([^<]*)<\/title>/.exec(cli)[1].replace(/&amp;/g, "&"));
  await popup.screenshot({ path: path.join(shots, "06-report.png") });
  await popup.close();
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#export")]);
  assert.equal(download.suggestedFilename(), "reconstruction_us.svg");
  const svg = fs.readFileSync(await download.path(), "utf8");
  assert.match(svg, /^<svg[^>]*viewBox=/);
  assert.ok(svg.includes("<style>") && (svg.match(/<polygon/g) || []).length >= 6, svg.slice(0, 300));
  fs.writeFileSync(path.join(shots, "07-exported.svg"), svg);
  // The plan for CAD: `pim fit --out`'s scene.dxf of the same text, byte for byte.
  const [dxf] = await Promise.all([page.waitForEvent("download"), page.click("#export-dxf")]);
  assert.equal(dxf.suggestedFilename(), "reconstruction_us.dxf");
  const out = fs.mkdtempSync(path.join(os.tmpdir(), "pim-dxf-"));
  fs.writeFileSync(path.join(out, "case.toml"), text);
  execFileSync(pimBin, ["fit", "case.toml", "--out", "o"], { cwd: out, encoding: "utf8" });
  assert.ok(fs.readFileSync(await dxf.path()).equals(fs.readFileSync(path.join(out, "o", "scene.dxf"))));
});

test("a switch of the display units redraws the speeds and the plan in them, the case unchanged", async () => {
  const mph = await speeds();
  const text = await page.inputValue("#toml");
  await page.selectOption("#units", "si");
  await page.waitForFunction(() => /m\/s/.test(document.querySelector("#speeds caption")?.textContent || ""));
  await idle();
  const si = await speeds();
  mph.forEach((v, i) => assert.ok(Math.abs(si[i] - v * 0.44704) < 0.006, `${si[i]} m/s against ${v} mph`));
  assert.equal(await page.inputValue("#toml"), text);
  assert.match(await page.textContent("#scale-note"), / m;/);
  await page.screenshot({ path: path.join(shots, "08-units-si.png") });
  await page.selectOption("#units", "");
  await page.waitForFunction(() => /mph/.test(document.querySelector("#speeds caption")?.textContent || ""));
  await idle();
  assert.deepEqual(await speeds(), mph);
});

// Screen coordinates of a pixel of the background image, through the image's own transform.
const onScreen = (u, v) => page.evaluate(([u, v]) => {
  const img = document.querySelector("image.background");
  const p = document.getElementById("plan").createSVGPoint(); p.x = u; p.y = v;
  const q = p.matrixTransform(img.getScreenCTM());
  return [q.x, q.y];
}, [u, v]);

// How many image pixels one screen pixel spans.
const imagePixelsPerScreenPixel = () => page.evaluate(() => {
  const m = document.querySelector("image.background").getScreenCTM();
  return 1 / Math.hypot(m.a, m.b);
});

async function clickPixels(a, b) {
  for (const [u, v] of [a, b]) {
    const [x, y] = await onScreen(u, v);
    await page.mouse.click(x, y);
  }
}

test("a photo made into a plan: four points clicked on it, the plan-view image written beside it and set as the background", async () => {
  const original = await exampleAsCommitted();
  // A photo of a 40 by 30 ft patch of road seen in perspective (its far edge 2.8 times
  // smaller), drawn by the browser's canvas: u = 600 + 28 (x - 20) / w, v = 760 - 60 y / w,
  // w = 1 + 0.06 y, for plan points (x right, y up).
  const cam = ([x, y]) => { const w = 1 + 0.06 * y; return [600 + 28 * (x - 20) / w, 760 - 60 * y / w]; };
  const png = await page.evaluate((camSrc) => {
    const cam = eval(camSrc);
    const c = document.createElement("canvas"); c.width = 1200; c.height = 800;
    const g = c.getContext("2d");
    g.fillStyle = "#c8dcf0"; g.fillRect(0, 0, 1200, 800);
    const quad = (pts, colour) => {
      g.fillStyle = colour; g.beginPath();
      pts.map(cam).forEach(([u, v], i) => (i ? g.lineTo(u, v) : g.moveTo(u, v)));
      g.closePath(); g.fill();
    };
    quad([[0, 0], [40, 0], [40, 30], [0, 30]], "#828282");
    quad([[25.5, 17.5], [26.5, 17.5], [26.5, 18.5], [25.5, 18.5]], "#1e1ee6");
    return c.toDataURL("image/png").split(",")[1];
  }, cam.toString());
  fs.writeFileSync(path.join(dir, "road_photo.png"), Buffer.from(png, "base64"));
  page.once("dialog", (d) => d.accept("road_photo.png"));
  await page.click("#photo-plan");
  await page.waitForFunction(() => { const i = document.getElementById("photo-img"); return i.complete && i.naturalWidth === 1200; });
  // Four corners of a 24 by 16 ft rectangle; the case is SAE, so each is typed as x (up the
  // plan) then y (to its right).
  const box = await page.locator("#photo-img").boundingBox();
  for (const p of [[8, 7], [32, 7], [32, 23], [8, 23]]) {
    const [u, v] = cam(p);
    page.once("dialog", (d) => d.accept(`${p[1]} ${p[0]}`));
    await page.mouse.click(box.x + (u * box.width) / 1200, box.y + (v * box.height) / 800);
  }
  assert.equal(await page.locator(".photo-point").count(), 4);
  assert.equal(await page.isDisabled("#photo-rectify"), false);
  await page.screenshot({ path: path.join(shots, "20-photo-points.png") });
  await page.click("#photo-rectify");
  await page.waitForFunction(() => /road_photo_plan\.png/.test(window.pim.text));
  await idle();
  assert.equal(await page.isHidden("#photo-pane"), true);
  const made = await page.evaluate(() => window.pim.photoResult);
  // Four points fix the perspective: each is met exactly.
  assert.ok(Math.max(...made.residuals) < 1e-6, JSON.stringify(made.residuals));
  assert.deepEqual(made.size, [2000, 1334]);
  assert.ok(fs.existsSync(path.join(dir, "road_photo_plan.png")));
  const text = await page.inputValue("#toml");
  const bg = /\[background\]\nimage = "road_photo_plan\.png"\npixels = \[\[0\.0, 0\.0\], \[2000\.0, 0\.0\]\]\ndistance = ([0-9.]+)\nat = \{ x = ([-0-9.]+), y = ([-0-9.]+) \}\nrotation = 0\.0\nlocked = true/.exec(text);
  assert.ok(bg, text.slice(-400));
  // The points' extent (8..32 by 7..23 ft) and half of it again: 48 ft wide, its top left
  // corner 31 ft up and 4 ft left (SAE: x = 31, y = -4).
  assert.deepEqual([+bg[1], +bg[2], +bg[3]], [48, 31, -4], bg[0]);
  assert.equal(await page.locator("#plan image.background").count(), 1);
  await page.screenshot({ path: path.join(shots, "21-photo-plan.png") });
  // A second time: the first image is kept, the new one takes a name of its own.
  page.once("dialog", (d) => d.accept("road_photo.png"));
  await page.click("#photo-plan");
  for (const p of [[8, 7], [32, 7], [32, 23], [8, 23]]) {
    const [u, v] = cam(p);
    page.once("dialog", (d) => d.accept(`${p[1]} ${p[0]}`));
    await page.mouse.click(box.x + (u * box.width) / 1200, box.y + (v * box.height) / 800);
  }
  await page.click("#photo-rectify");
  await page.waitForFunction(() => /road_photo_plan_2\.png/.test(window.pim.text));
  assert.ok(fs.existsSync(path.join(dir, "road_photo_plan.png")) && fs.existsSync(path.join(dir, "road_photo_plan_2.png")));
  await page.fill("#toml", original);
  await page.waitForFunction(() => !/road_photo_plan/.test(window.pim.text));
  await idle();
});

test("a background diagram set to scale by two points, and a distance measured on it", async () => {
  await page.selectOption("#cases", "scene/intersection_us.toml");
  await page.waitForSelector("image.background");
  await idle();
  // The road is 240 pixels wide, at 0.1 ft a pixel: 24 ft.
  await page.click("#measure");
  await clickPixels([480, 300], [720, 300]);
  const road = await page.evaluate(() => window.pim.measured.distance);
  // Each click within a screen pixel: the distance within two of them (0.1 ft an image pixel).
  const k0 = await imagePixelsPerScreenPixel();
  assert.ok(Math.abs(road - 24.0) <= 2 * k0 * 0.1, `the road measures ${road} ft (${k0} image pixels per screen pixel)`);
  await page.screenshot({ path: path.join(shots, "09-background.png") });
  // The scale bar's ends (600 pixels apart) given as 30 ft: the diagram halves.
  const before = await page.inputValue("#toml");
  page.once("dialog", (d) => d.accept("30"));
  await page.click("#set-scale");
  await clickPixels([1000, 1460], [1600, 1460]);
  await page.waitForFunction(() => /distance = 30\.0/.test(window.pim.text));
  await idle();
  const text = await page.inputValue("#toml");
  const px = /pixels = \[\[([-0-9.]+), ([-0-9.]+)\], \[([-0-9.]+), ([-0-9.]+)\]\]/.exec(text).slice(1).map(Number);
  // A click lands on a whole screen pixel: within one screen pixel's width of the image's.
  const k = await imagePixelsPerScreenPixel();
  [1000, 1460, 1600, 1460].forEach((want, i) => assert.ok(Math.abs(px[i] - want) <= k, `pixel ${px[i]} against ${want} (${k} per screen pixel)`));
  // Only the background's lines changed, every comment kept.
  const a = before.split("\n"), b = text.split("\n");
  assert.equal(a.length, b.length);
  assert.ok(a.every((l, i) => l === b[i] || l.startsWith("pixels") || l.startsWith("distance") || l.startsWith("at =")));
  await page.waitForFunction(() => document.querySelector("image.background"));
  await page.click("#measure");
  await clickPixels([480, 300], [720, 300]);
  const half = await page.evaluate(() => window.pim.measured.distance);
  const k1 = await imagePixelsPerScreenPixel();
  assert.ok(Math.abs(half - 12.0) <= 2 * k1 * 0.05 + 12.0 * (2 * k / 600), `the road now measures ${half} ft`);
  // The image is served only from inside the folder.
  const cookie = `pim_token=${token}`;
  assert.equal((await raw("GET", "/api/image?path=scene/intersection.png", { cookie })).status, 200);
  assert.equal((await raw("GET", "/api/image?path=../intersection.png", { cookie })).status, 403);
  assert.equal((await raw("GET", "/api/image?path=scene/intersection_us.toml", { cookie })).status, 403);
});

test("the background moved and turned by hand, then locked", async () => {
  await page.selectOption("#cases", "scene/intersection_us.toml");
  await page.waitForSelector("image.background");
  await idle();
  const original = await page.inputValue("#toml");
  const bg0 = await page.evaluate(() => ({ ...window.pim.answer.plan.background }));
  assert.equal(bg0.locked, true);
  assert.ok(await page.isChecked("#lock-image"));
  // Locked, it does not move.
  await page.click("#move-image");
  assert.match(await page.textContent("#status"), /locked/);
  await page.uncheck("#lock-image");
  await page.waitForFunction(() => /locked = false/.test(window.pim.text));
  await idle();
  await page.click("#move-image");
  // Dragged 60 screen pixels right and 30 up: its first scale point moves as far on the page.
  const box = await page.locator("#plan").boundingBox();
  const k = await page.evaluate(() => { const m = document.getElementById("plan").getScreenCTM(); return Math.hypot(m.a, m.b); });
  const [x0, y0] = [box.x + box.width * 0.6, box.y + box.height * 0.3];
  await page.mouse.move(x0, y0);
  await page.mouse.down();
  for (let i = 1; i <= 6; i++) await page.mouse.move(x0 + 10 * i, y0 - 5 * i);
  await page.mouse.up();
  await page.waitForFunction((at) => {
    const b = window.pim.answer.plan.background;
    return Math.abs(b.at[0] - at[0]) > 1e-6 && !window.pim.busy;
  }, bg0.at);
  await idle();
  const bg1 = await page.evaluate(() => ({ ...window.pim.answer.plan.background }));
  const tol = 1 / k + 0.001;
  assert.ok(Math.abs(bg1.at[0] - bg0.at[0] - 60 / k) <= tol && Math.abs(bg1.at[1] - bg0.at[1] - 30 / k) <= tol,
    `at ${JSON.stringify(bg0.at)} -> ${JSON.stringify(bg1.at)} (${k} px a ft)`);
  // Its knob turned 90 deg counter-clockwise about the first scale point.
  const knob = await page.locator("circle.rotate-image").boundingBox();
  const kx = knob.x + knob.width / 2, ky = knob.y + knob.height / 2;
  const c = await page.evaluate(([h, v]) => {
    const svg = document.getElementById("plan"), p = svg.createSVGPoint(); p.x = h; p.y = -v;
    const q = p.matrixTransform(svg.getScreenCTM()); return [q.x, q.y];
  }, bg1.at);
  const r = Math.hypot(kx - c[0], ky - c[1]);
  await page.mouse.move(kx, ky);
  await page.mouse.down();
  for (let i = 1; i <= 9; i++) {
    const t = (Math.PI / 2) * (i / 9);
    await page.mouse.move(c[0] + r * Math.cos(t), c[1] - r * Math.sin(t));
  }
  await page.mouse.up();
  await page.waitForFunction(() => Math.abs(window.pim.answer.plan.background.rotation) > 45 && !window.pim.busy);
  await idle();
  const bg2 = await page.evaluate(() => ({ ...window.pim.answer.plan.background }));
  assert.ok(Math.abs(bg2.rotation - 90) <= 1.0, `rotation ${bg2.rotation}`);
  await page.screenshot({ path: path.join(shots, "14-background-moved.png") });
  // Locked again: the file says so, and a drag pans the view instead.
  await page.click("#move-image");
  // The answer to the drag drawn first: a render resets the checkbox from the answer it draws.
  await idle();
  await page.check("#lock-image");
  await page.waitForFunction(() => /locked = true/.test(window.pim.text));
  await idle();
  const text = await page.inputValue("#toml");
  const a = original.split("\n"), b = text.split("\n");
  assert.equal(a.length, b.length);
  const changed = a.map((l, i) => [l, b[i]]).filter(([p, q]) => p !== q).map(([, q]) => q.split("=")[0].trim());
  assert.deepEqual(changed, ["at", "rotation"]);
  await page.mouse.move(x0, y0);
  await page.mouse.down();
  await page.mouse.move(x0 + 40, y0);
  await page.mouse.up();
  await idle();
  assert.equal(await page.inputValue("#toml"), text);
  await page.fill("#toml", original);
  await page.waitForFunction((t) => window.pim.text === t, original);
  await idle();
});

test("conflicting evidence: the pieces that disagree are marked, and one switched off gives the answer without it", async () => {
  // Chosen again: read from the folder (the path is already the case's: idle waits for the read).
  await page.selectOption("#cases", CASE);
  await idle();
  assert.equal(await page.evaluate(() => window.pim.path), CASE);
  const original = await page.inputValue("#toml");
  const edr = "vehicle2 EDR speed 0.5 s before contact";
  assert.equal(await page.locator("#evidence tr.piece").count(), 8);
  assert.equal(await page.locator("#evidence tr.disagrees").count(), 0);
  // The SUV's EDR read 8 mph high: the scene and the EDR disagree.
  const conflicting = original.replace("edr = [ { speed = 27.5,", "edr = [ { speed = 35.5,");
  assert.notEqual(conflicting, original);
  await page.fill("#toml", conflicting);
  await page.waitForSelector("#consistency-table", { timeout: 120000 });
  await idle();
  const row = `#evidence tr[data-name="${edr}"]`;
  // The pieces more than two standard deviations from the answer are marked (the EDR, or the
  // sedan's direction of travel that the fit leans on to meet it, as the rests lie).
  const pieces = await page.evaluate(() => window.pim.answer.pieces);
  const far = pieces.filter((p) => Math.abs(p.z) > 2).map((p) => p.name);
  const marked = await page.$$eval("#evidence tr.disagrees", (rs) => rs.map((r) => r.dataset.name));
  assert.deepEqual(marked, far);
  assert.ok(marked.length >= 1, JSON.stringify(pieces));
  const all = await page.evaluate(() => window.pim.answer.document);
  const withoutRow = all.consistency.rows.find((r) => r.left_out.length === 1 && r.left_out[0] === edr);
  assert.ok(withoutRow && withoutRow.consistent, JSON.stringify(all.consistency.rows));
  await page.screenshot({ path: path.join(shots, "10-conflict.png") });
  // Switched off: the answer is the case without the EDR's line, the file is not touched.
  const onDisk = fs.readFileSync(path.join(dir, CASE), "utf8");
  await page.locator(`${row} input`).uncheck();
  await page.waitForFunction((n) => window.pim.answer.pieces.some((p) => p.name === n && p.off), edr);
  await idle();
  const off = await page.evaluate(() => window.pim.answer.document);
  assert.ok(off.best.chi_square < all.best.chi_square, `${off.best.chi_square} against ${all.best.chi_square}`);
  assert.equal(await page.$("#consistency-table"), null, "the rest is consistent: no table");
  const without = path.join(dir, "without_edr.toml");
  fs.writeFileSync(without, conflicting.split("\n").filter((l) => !l.startsWith("edr = ")).join("\n"));
  const cli = JSON.parse(execFileSync(pimBin, ["fit", without, "--format", "json"], { encoding: "utf8" }));
  assert.deepEqual(off, cli);
  for (const k of [0, 1]) {
    const page_speed = off.best.vehicles[k].speed_at_contact;
    assert.ok(Math.abs(page_speed - withoutRow.speed_at_contact[k]) < 0.005, `${page_speed} against the table's row`);
  }
  assert.equal(await page.inputValue("#toml"), conflicting);
  assert.equal(fs.readFileSync(path.join(dir, CASE), "utf8"), onDisk);
  assert.equal(await page.textContent(`${row} td.z`), "off");
  // A mark switched off is drawn as off on the plan.
  await page.locator('#evidence tr[data-name="vehicle2 mark 1"] input').uncheck();
  await page.waitForSelector('g.evidence.off[data-piece="vehicle2 mark 1"]');
  await idle();
  await page.screenshot({ path: path.join(shots, "11-switched-off.png") });
  // Back to the case as it was, everything on.
  await page.locator('#evidence tr[data-name="vehicle2 mark 1"] input').check();
  await page.locator(`${row} input`).check();
  await page.fill("#toml", original);
  await page.waitForFunction(() => window.pim.off.length === 0 && !document.getElementById("consistency-table"), null, { timeout: 120000 });
  await idle();
  fs.rmSync(without);
});

test("a tyre mark placed by a click is written into the TOML where it was clicked", async () => {
  const original = await exampleAsCommitted();
  page.once("dialog", (d) => { assert.match(d.defaultValue(), /^2 /); d.accept("2 0.5"); });
  await page.click("#add-mark");
  // A point on car 2's path, a third of the way along: its screen position through the plan's
  // own transform.
  const [h, v, x, y, unitPx] = await page.evaluate(() => {
    const veh = window.pim.answer.plan.vehicles.find((w) => w.vehicle === 2);
    const [h, v] = veh.path[Math.floor(veh.path.length / 3)];
    const svg = document.getElementById("plan");
    const p = svg.createSVGPoint(); p.x = h; p.y = -v;
    const m = svg.getScreenCTM(), q = p.matrixTransform(m);
    return [h, v, q.x, q.y, Math.hypot(m.a, m.b)];
  });
  await page.mouse.click(x, y);
  await page.waitForFunction(() => window.pim.answer.pieces.some((p) => p.name === "vehicle2 mark 2"));
  await idle();
  const placed = await page.inputValue("#toml");
  const a = original.split("\n"), b = placed.split("\n");
  assert.equal(a.length, b.length);
  const changed = a.map((l, i) => [l, b[i]]).filter(([p, q]) => p !== q);
  assert.equal(changed.length, 1, JSON.stringify(changed));
  const m = /^marks = \[ \{ x = 32\.6, y = 48\.2, sigma = 0\.5 \}, \{ x = ([-0-9.]+), y = ([-0-9.]+), sigma = 0\.5 \} \]$/.exec(changed[0][1]);
  assert.ok(m, changed[0][1]);
  // SAE: the page's right is +y, up is +x; within a screen pixel (and the hundredth written).
  const tol = 1 / unitPx + 0.01;
  assert.ok(Math.abs(+m[1] - v) <= tol && Math.abs(+m[2] - h) <= tol, `mark (${m[1]}, ${m[2]}) against (${v}, ${h})`);
  const marks = await page.evaluate(() => window.pim.answer.plan.vehicles.find((w) => w.vehicle === 2).marks.length);
  assert.equal(marks, 2);
  await page.screenshot({ path: path.join(shots, "12-mark-placed.png") });
  // The new mark dragged 25 screen pixels right: its y (SAE: the page's right) follows.
  const mh = await page.locator('circle.mark-handle[data-vehicle="2"][data-mark="1"]').boundingBox();
  const [mx, my] = [mh.x + mh.width / 2, mh.y + mh.height / 2];
  await page.mouse.move(mx, my);
  await page.mouse.down();
  for (let i = 1; i <= 5; i++) await page.mouse.move(mx + 5 * i, my);
  await page.mouse.up();
  await idle();
  const dragged = await page.inputValue("#toml");
  const m2 = /^marks = \[ \{ x = 32\.6, y = 48\.2, sigma = 0\.5 \}, \{ x = ([-0-9.]+), y = ([-0-9.]+), sigma = 0\.5 \} \]$/m.exec(dragged);
  assert.ok(m2, dragged);
  assert.ok(Math.abs(+m2[1] - +m[1]) <= tol && Math.abs(+m2[2] - +m[2] - 25 / unitPx) <= tol, `dragged to (${m2[1]}, ${m2[2]})`);
  const text = dragged;
  // A cancelled prompt places nothing.
  page.once("dialog", (d) => d.dismiss());
  await page.click("#add-mark");
  await page.mouse.click(x + 40, y);
  await page.waitForFunction(() => /no mark placed/.test(document.getElementById("status").textContent));
  assert.equal(await page.inputValue("#toml"), text);
  // A mark left by the SUV's front right tyre: written with its wheel, and that tyre's path
  // drawn (the mark's residual is its distance from it).
  page.once("dialog", (d) => d.accept("2 0.5 fr"));
  await page.click("#add-mark");
  await page.mouse.click(x, y);
  await page.waitForFunction(() => window.pim.answer.pieces.some((p) => p.name === "vehicle2 mark 3"));
  await idle();
  assert.match(await page.inputValue("#toml"), /, \{ x = [-0-9.]+, y = [-0-9.]+, sigma = 0\.5, wheel = "front_right" \} \]$/m);
  assert.equal(await page.locator("g.v2 polyline.trace").count(), 1);
  assert.equal(await page.locator("g.v1 polyline.trace").count(), 0);
  await page.screenshot({ path: path.join(shots, "12b-tyre-mark.png") });
  await page.fill("#toml", original);
  await page.waitForFunction(() => !window.pim.answer.pieces.some((p) => p.name === "vehicle2 mark 2"));
  await idle();
});

test("a yaw mark traced by clicks along it is written into the TOML with its tyre", async () => {
  const original = await exampleAsCommitted();
  const chi = () => page.evaluate(() => window.pim.answer.document.best.chi_square);
  const before = await chi();
  // Three points of car 2's fitted path (a fifth, two fifths and three fifths along), through
  // the plan's own transform; then the last again to end the trace.
  const [points, unitPx] = await page.evaluate(() => {
    const veh = window.pim.answer.plan.vehicles.find((w) => w.vehicle === 2);
    const n = veh.path.length, svg = document.getElementById("plan"), m = svg.getScreenCTM();
    const pts = [n / 5, 2 * n / 5, 3 * n / 5].map((i) => {
      const [h, v] = veh.path[Math.floor(i)];
      const p = svg.createSVGPoint(); p.x = h; p.y = -v;
      const q = p.matrixTransform(m);
      return [q.x, q.y, h, v];
    });
    return [pts, Math.hypot(m.a, m.b)];
  });
  page.once("dialog", (d) => { assert.match(d.defaultValue(), /^2 [0-9.]+ fl$/); d.accept("2 0.5 cg"); });
  await page.click("#add-trace");
  for (const [x, y] of points) await page.mouse.click(x, y);
  assert.equal(await page.locator("polyline.click").count(), 1);
  const [lx, ly] = points[points.length - 1];
  await page.mouse.click(lx + 2, ly + 1);
  await page.waitForFunction(() => /^traces = /m.test(window.pim.text));
  await idle();
  const text = await page.inputValue("#toml");
  const added = text.split("\n").filter((l) => !original.split("\n").includes(l));
  assert.equal(added.length, 1, JSON.stringify(added));
  const m = /^traces = \[ \{ wheel = "cg", points = \[(.*)\], sigma = 0\.5 \} \]$/.exec(added[0]);
  assert.ok(m, added[0]);
  // Written in the file's frame (SAE: x is the page's up, y its right), within a pixel.
  const written = [...m[1].matchAll(/\[([-0-9.]+), ([-0-9.]+)\]/g)].map((c) => [+c[1], +c[2]]);
  assert.equal(written.length, 3);
  const tol = 1 / unitPx + 0.01;
  written.forEach(([x, y], i) => {
    const [, , h, v] = points[i];
    assert.ok(Math.abs(x - v) <= tol && Math.abs(y - h) <= tol, `point ${i}: (${x}, ${y}) against (${v}, ${h})`);
  });
  // Points of its own path, traced by the CG: the answer meets them.
  const after = await chi();
  assert.ok(Math.abs(after - before) < 0.05, `${after} against ${before}`);
  await page.screenshot({ path: path.join(shots, "12c-trace.png") });
  // A trace left unfinished (its tool switched off after two points) writes nothing.
  await page.click("#add-trace");
  await page.mouse.click(lx, ly);
  await page.mouse.click(lx + 1, ly);
  await page.click("#add-trace");
  assert.equal(await page.locator("polyline.click").count(), 0);
  assert.equal(await page.inputValue("#toml"), text);
  await page.fill("#toml", original);
  await page.waitForFunction(() => !/^traces = /m.test(window.pim.text));
  await idle();
});

test("a rest measured by its tyres is placed by clicks and written as its tyre points", async () => {
  const original = await exampleAsCommitted();
  page.once("dialog", (d) => { assert.match(d.defaultValue(), /^2 [0-9.]+ fl rl$/); d.accept("2 0.3 fl rl"); });
  await page.click("#add-tyres");
  // The SUV's left tyres at its rest (SAE, ft: the page's right is y, up is x), on the screen
  // (once the tool is on: its status line may move the plan).
  const [points, unitPx] = await page.evaluate(() => {
    const svg = document.getElementById("plan"), m = svg.getScreenCTM();
    const pts = [[77.66, 45.94], [85.36, 50.21]].map(([h, v]) => {
      const p = svg.createSVGPoint(); p.x = h; p.y = -v;
      const q = p.matrixTransform(m);
      return [q.x, q.y, h, v];
    });
    return [pts, Math.hypot(m.a, m.b)];
  });
  for (const [x, y] of points) await page.mouse.click(x, y);
  const [lx, ly] = points[points.length - 1];
  await page.mouse.click(lx + 2, ly + 1);
  await page.waitForFunction(() => /^rest_tyres = \[/m.test(window.pim.text));
  await idle();
  const text = await page.inputValue("#toml");
  const scene = text.slice(text.indexOf("[scene.vehicle2]"));
  assert.ok(!/^rest = /m.test(scene) && !/^rest_sigma = /m.test(scene), scene);
  const written = [...scene.matchAll(/\{ wheel = "(\w+)", x = ([-0-9.]+), y = ([-0-9.]+), sigma = 0\.3 \}/g)];
  assert.deepEqual(written.map((w) => w[1]), ["front_left", "rear_left"]);
  // Written in the file's frame, within a pixel of where it was clicked.
  const tol = 1 / unitPx + 0.01;
  written.forEach((w, i) => {
    const [, , h, v] = points[i];
    assert.ok(Math.abs(+w[2] - v) <= tol && Math.abs(+w[3] - h) <= tol, `${w[0]} against (${v}, ${h})`);
  });
  assert.equal(await page.evaluate(() => window.pim.answer.document.status), "found");
  await page.screenshot({ path: path.join(shots, "12d-tyres.png") });
  await page.fill("#toml", original);
  await page.waitForFunction(() => !/^rest_tyres = /m.test(window.pim.text));
  await idle();
});

test("the motion played back: the frame at contact and at rest are the answer's, the braking starts a skid back", async () => {
  assert.equal(await page.isVisible("#playback"), true);
  const setTime = (t) => page.$eval("#time", (el, t) => { el.value = t; el.dispatchEvent(new Event("input")); }, t);
  const now = (v) => page.$eval(`g.motion g.v${v} polygon.outline.now`, (p) => p.getAttribute("points"));
  const drawn = (v, which) => page.evaluate(([v, which]) => {
    const veh = window.pim.answer.plan.vehicles.find((w) => w.vehicle === v);
    return veh[which].map(([h, u]) => `${h},${-u}`).join(" ");
  }, [v, which]);
  // No motion drawn until the slider is touched.
  assert.equal(await page.locator("g.motion").count(), 0);
  await setTime(0);
  assert.match(await page.textContent("#time-label"), /t = 0\.00 s \(contact\)/);
  for (const v of [1, 2]) assert.equal(await now(v), await drawn(v, "contact"), `vehicle ${v} at contact`);
  const m = await page.evaluate(() => window.pim.answer.plan.motion);
  await setTime(m.end);
  for (const v of [1, 2]) assert.equal(await now(v), await drawn(v, "rest"), `vehicle ${v} at rest`);
  // The sedan braked 42 ft up to contact: where its braking began its CG is 42 ft back.
  const sedan = m.vehicles.find((t) => t.vehicle === 1);
  assert.ok(sedan.braking);
  const back = Math.hypot(sedan.cg[0][0] - sedan.cg[sedan.times.indexOf(0)][0], sedan.cg[0][1] - sedan.cg[sedan.times.indexOf(0)][1]);
  assert.ok(Math.abs(back - 42.0) < 0.01, `${back} ft`);
  // The SUV, without a skid, approaches for a second at its contact velocity; the slider
  // starts at the earlier of the two.
  const suv = m.vehicles.find((t) => t.vehicle === 2);
  assert.ok(!suv.braking && Math.abs(suv.times[0] + 1) < 1e-9);
  assert.equal(m.start, Math.min(sedan.times[0], suv.times[0]));
  await setTime(1.0);
  await page.screenshot({ path: path.join(shots, "19-motion.png") });
  // Played at true time from the start: the time runs, and it stops at rest.
  await setTime(m.start);
  const t0 = Date.now();
  await page.click("#play");
  await page.waitForFunction(() => window.pim.playT > 0);
  assert.equal(await page.textContent("#play"), "Pause");
  await page.waitForFunction(() => !window.pim.playing, null, { timeout: 30000 });
  const took = (Date.now() - t0) / 1000;
  assert.ok(took >= (m.end - m.start) * 0.9, `played ${m.end - m.start} s in ${took} s`);
  for (const v of [1, 2]) assert.equal(await now(v), await drawn(v, "rest"));
  // The frame exported at a time, and the whole motion as an animated SVG whose key frames
  // at contact are the outlines at contact.
  await setTime(0.5);
  const [frame] = await Promise.all([page.waitForEvent("download"), page.click("#export")]);
  assert.equal(frame.suggestedFilename(), "reconstruction_us_t0.50s.svg");
  const [anim] = await Promise.all([page.waitForEvent("download"), page.click("#export-motion")]);
  assert.equal(anim.suggestedFilename(), "reconstruction_us_motion.svg");
  const svg = fs.readFileSync(await anim.path(), "utf8");
  fs.writeFileSync(path.join(shots, "19-motion.svg"), svg);
  const animations = [...svg.matchAll(/<animate attributeName="points" dur="([0-9.]+)s"[^>]*keyTimes="([^"]*)" values="([^"]*)"/g)];
  assert.equal(animations.length, 2, svg.slice(-600));
  animations.forEach((a, i) => {
    const v = m.vehicles[i];
    const keys = a[2].split(";").map(Number), values = a[3].split(";");
    assert.equal(keys.length, values.length);
    assert.ok(Math.abs(+a[1] - (m.end - m.start)) < 1e-9);
    const k = keys.findIndex((x) => Math.abs(x - (0 - m.start) / (m.end - m.start)) < 1e-5);
    assert.ok(k > 0, `a key frame at contact for vehicle ${v.vehicle}`);
    assert.equal(values[k], v.outlines[v.times.indexOf(0)].map(([h, u]) => `${h},${-u}`).join(" "));
  });
  // Back to the plan alone.
  await page.evaluate(() => { window.pim.playT = null; });
  await page.click("#fit");
  assert.equal(await page.locator("g.motion").count(), 0);
});

test("a friction zone is drawn on the plan under the run-outs, with its friction", async () => {
  await page.selectOption("#cases", "reconstruction_verge_us.toml");
  await idle();
  await page.click("#fit");
  // One zone, the grass verge east of the road's edge: `pim fit`'s speeds beside it.
  assert.equal(await page.locator("polygon.zone-area").count(), 1);
  assert.equal(await page.locator("text.zone-label").textContent(), "friction 0.45");
  const [sedan, suv] = await speeds();
  assert.ok(Math.abs(sedan - 38.10) < 0.006 && Math.abs(suv - 27.15) < 0.006, `${sedan} ${suv}`);
  // Its corners on the page: SAE y = 60 ft (east) is the page's x = 60.
  const xs = await page.$eval("polygon.zone-area", (p) => p.getAttribute("points").split(" ").map((c) => +c.split(",")[0]));
  assert.equal(Math.min(...xs), 60);
  // Drawn first: every vehicle's outline lies over it.
  const first = await page.$eval("#plan", (svg) => [...svg.querySelectorAll("polygon")][0].getAttribute("class"));
  assert.equal(first, "zone-area");
  await page.screenshot({ path: path.join(shots, "17-zone.png") });
});

test("a friction zone drawn by its corners is written into the TOML and the run-out runs on it", async () => {
  const original = await exampleAsCommitted();
  const before = await speeds();
  // A square 30 ft on a side about car 2's rest (SAE page: h is y, v is x), corner by corner
  // through the plan's own transform, then the first corner again to close it.
  const corners = await page.evaluate(() => {
    const veh = window.pim.answer.plan.vehicles.find((w) => w.vehicle === 2);
    const [h, v] = veh.given_rest.at;
    const svg = document.getElementById("plan"), m = svg.getScreenCTM();
    return [[-15, -15], [15, -15], [15, 15], [-15, 15]].map(([a, b]) => {
      const p = svg.createSVGPoint(); p.x = h + a; p.y = -(v + b);
      const q = p.matrixTransform(m);
      return [q.x, q.y, h + a, v + b];
    });
  });
  page.once("dialog", (d) => { assert.equal(d.defaultValue(), "0.45"); d.accept("0.3 wet grass"); });
  await page.click("#add-zone");
  for (const [x, y] of corners) await page.mouse.click(x, y);
  assert.equal(await page.locator("polyline.click").count(), 1);
  await page.mouse.click(corners[0][0] + 2, corners[0][1] + 1);
  await page.waitForFunction(() => window.pim.answer.plan.zones.length === 1);
  await idle();
  const text = await page.inputValue("#toml");
  assert.ok(text.startsWith(original), "the file as it was, the zone after it");
  const added = text.slice(original.length);
  const m = /^\n\[\[runout\.zones\]\]\nname = "wet grass"\nfriction = 0\.3\ncorners = \[(.*)\]\n$/.exec(added);
  assert.ok(m, added);
  // Written in the file's frame (SAE: x is the page's up, y its right), within a pixel.
  const written = [...m[1].matchAll(/\[([-0-9.]+), ([-0-9.]+)\]/g)].map((c) => [+c[1], +c[2]]);
  const unitPx = await page.evaluate(() => { const t = document.getElementById("plan").getScreenCTM(); return Math.hypot(t.a, t.b); });
  assert.equal(written.length, 4);
  written.forEach(([x, y], i) => {
    const [, , h, v] = corners[i];
    assert.ok(Math.abs(x - v) <= 1 / unitPx + 0.01 && Math.abs(y - h) <= 1 / unitPx + 0.01, `corner ${i}: (${x}, ${y}) against (${v}, ${h})`);
  });
  // The SUV's last 15 ft on 0.3 instead of the road's 0.72: a different answer.
  const after = await speeds();
  assert.notDeepEqual(after, before);
  assert.equal(await page.locator("text.zone-label").textContent(), "friction 0.3");
  await page.screenshot({ path: path.join(shots, "18-zone-placed.png") });
  await page.fill("#toml", original);
  await page.waitForFunction(() => window.pim.answer.plan.zones.length === 0);
  await idle();
});

test("a vehicle at contact dragged and turned by its handles: the case's position and heading follow", async () => {
  const original = await exampleAsCommitted();
  const screen = (h, v) => page.evaluate(([h, v]) => {
    const svg = document.getElementById("plan");
    const p = svg.createSVGPoint(); p.x = h; p.y = -v;
    const m = svg.getScreenCTM(), q = p.matrixTransform(m);
    return [q.x, q.y, Math.hypot(m.a, m.b)];
  }, [h, v]);
  const drag = async (from, to) => {
    await page.mouse.move(from[0], from[1]);
    await page.mouse.down();
    for (let i = 1; i <= 8; i++) await page.mouse.move(from[0] + ((to[0] - from[0]) * i) / 8, from[1] + ((to[1] - from[1]) * i) / 8);
    await page.mouse.up();
    await idle();
  };
  // The SUV's CG moved 3 ft right on the page (SAE: +y) and 2 ft down (-x).
  const cg0 = await page.evaluate(() => window.pim.answer.plan.vehicles.find((v) => v.vehicle === 2).cg);
  const [x0, y0, k] = await screen(cg0[0], cg0[1]);
  await drag([x0, y0], [x0 + 3 * k, y0 + 2 * k]);
  const moved = await page.inputValue("#toml");
  let a = original.split("\n"), b = moved.split("\n");
  let changed = a.map((l, i) => [l, b[i]]).filter(([p, q]) => p !== q);
  assert.equal(changed.length, 1, JSON.stringify(changed));
  const pos = /^position = \{ x = ([-0-9.]+), y = ([-0-9.]+) \}$/.exec(changed[0][1]);
  assert.ok(pos, changed[0][1]);
  // Within a screen pixel and the hundredth written: x 1.0 - 2, y 1.5 + 3.
  const tol = 1 / k + 0.01;
  assert.ok(Math.abs(+pos[1] - (1.0 - 2)) <= tol && Math.abs(+pos[2] - (1.5 + 3)) <= tol, changed[0][1]);
  const cg1 = await page.evaluate(() => window.pim.answer.plan.vehicles.find((v) => v.vehicle === 2).cg);
  assert.ok(Math.abs(cg1[0] - +pos[2]) < 1e-9 && Math.abs(cg1[1] - +pos[1]) < 1e-9, JSON.stringify(cg1));
  // Its heading knob turned 30 deg counter-clockwise about the CG on the page: 30 deg less,
  // clockwise from north.
  const veh = await page.evaluate(() => window.pim.answer.plan.vehicles.find((v) => v.vehicle === 2));
  const knob = await page.locator('circle.heading-handle[data-vehicle="2"]').boundingBox();
  const kx = knob.x + knob.width / 2, ky = knob.y + knob.height / 2;
  const [cx, cy] = await screen(veh.cg[0], veh.cg[1]);
  const r = Math.hypot(kx - cx, ky - cy), t = Math.atan2(-(ky - cy), kx - cx) + Math.PI / 6;
  await drag([kx, ky], [cx + r * Math.cos(t), cy - r * Math.sin(t)]);
  const turned = await page.inputValue("#toml");
  a = moved.split("\n"); b = turned.split("\n");
  changed = a.map((l, i) => [l, b[i]]).filter(([p, q]) => p !== q);
  assert.equal(changed.length, 1, JSON.stringify(changed));
  const heading = /^heading = ([-0-9.]+)$/.exec(changed[0][1]);
  assert.ok(heading, changed[0][1]);
  // The knob is about 60 screen pixels out: a pixel is under a degree.
  assert.ok(Math.abs(+heading[1] - 60.0) <= 1.0, changed[0][1]);
  const drawn = await page.evaluate(() => window.pim.answer.plan.vehicles.find((v) => v.vehicle === 2).heading);
  assert.ok(Math.abs(drawn - (90 - +heading[1])) < 1e-9, `${drawn}`);
  const chi = await page.evaluate(() => window.pim.answer.document.best && window.pim.answer.document.best.chi_square);
  assert.ok(chi !== undefined, "answered");
  await page.screenshot({ path: path.join(shots, "13-contact-moved.png") });
  // The page's document is the command's for the text as it stands.
  const file = path.join(dir, "contact_moved.toml");
  fs.writeFileSync(file, turned);
  const cli = JSON.parse(execFileSync(pimBin, ["fit", file, "--format", "json"], { encoding: "utf8" }));
  assert.deepEqual(await page.evaluate(() => window.pim.answer.document), cli);
  fs.rmSync(file);
  await page.fill("#toml", original);
  await page.waitForFunction((t) => window.pim.text === t, original);
  await idle();
});

test("a vehicle's rest turned by its knob: the rest's heading follows, nothing else", async () => {
  const original = await exampleAsCommitted();
  // The SUV's knob swung a quarter turn counter-clockwise on the page about its rest's CG.
  const [cg, knob] = await page.evaluate(() => {
    const svg = document.getElementById("plan"), m = svg.getScreenCTM();
    const at = (h, v) => { const p = svg.createSVGPoint(); p.x = h; p.y = -v; const q = p.matrixTransform(m); return [q.x, q.y]; };
    const gr = window.pim.answer.plan.vehicles.find((v) => v.vehicle === 2).given_rest;
    const k = document.querySelector('circle.rest-knob[data-vehicle="2"]');
    const b = k.getBoundingClientRect();
    return [at(gr.at[0], gr.at[1]), [b.x + b.width / 2, b.y + b.height / 2]];
  });
  const [sx, sy] = [knob[0] - cg[0], knob[1] - cg[1]];
  await page.mouse.move(knob[0], knob[1]);
  await page.mouse.down();
  for (let i = 1; i <= 12; i++) {
    // Screen y is down: a page turn of +a is (sx cos a + sy sin a, -sx sin a + sy cos a).
    const a = (Math.PI / 2) * (i / 12);
    await page.mouse.move(cg[0] + sx * Math.cos(a) + sy * Math.sin(a), cg[1] - sx * Math.sin(a) + sy * Math.cos(a));
  }
  await page.mouse.up();
  await idle();
  const turned = await page.inputValue("#toml");
  const a = original.split("\n"), b = turned.split("\n");
  const changed = a.map((l, i) => [l, b[i]]).filter(([p, q]) => p !== q);
  assert.equal(changed.length, 1, JSON.stringify(changed));
  // SAE headings are clockwise from x: 241 deg turned a quarter turn counter-clockwise is 151.
  const m = /^rest = \{ x = 50\.1, y = 79\.7, heading = ([0-9.]+) \}$/.exec(changed[0][1]);
  assert.ok(m && Math.abs(+m[1] - 151) < 1, changed[0][1]);
  await page.screenshot({ path: path.join(shots, "22-rest-turned.png") });
  await page.fill("#toml", original);
  await page.waitForFunction(() => /heading = 241\.0 \}/.test(window.pim.text));
  await idle();
});

test("a skid up to contact drawn behind the car and set by a click", async () => {
  const original = await exampleAsCommitted();
  await page.click("#fit");
  // The sedan's 42 ft skid is drawn behind its CG (the whole of it in the view).
  assert.equal(await page.locator("g.skid").count(), 1);
  assert.match(await page.textContent("g.skid text"), /skid 42\.0 ft/);
  const before = await page.evaluate(() => window.pim.answer.document.best.vehicles[0].speed_before_braking);
  // A click 30 ft behind the sedan's CG along its heading.
  const [x, y, k] = await page.evaluate(() => {
    const v = window.pim.answer.plan.vehicles.find((w) => w.vehicle === 1), t = (v.heading * Math.PI) / 180;
    const svg = document.getElementById("plan"), p = svg.createSVGPoint();
    p.x = v.cg[0] - 30 * Math.cos(t); p.y = -(v.cg[1] - 30 * Math.sin(t));
    const m = svg.getScreenCTM(), q = p.matrixTransform(m);
    return [q.x, q.y, Math.hypot(m.a, m.b)];
  });
  let offered = null;
  page.once("dialog", (d) => { offered = d.defaultValue(); d.accept(offered); });
  await page.click("#add-skid");
  await page.mouse.click(x, y);
  await page.waitForFunction(() => /skid = 3\d\.\d+ /.test(window.pim.text) || /skid = 29\.\d+ /.test(window.pim.text));
  await idle();
  const [vehicle, length] = offered.split(" ").map(Number);
  assert.equal(vehicle, 1);
  assert.ok(Math.abs(length - 30) <= 1 / k + 0.01, `offered ${offered}`);
  const text = await page.inputValue("#toml");
  const changed = original.split("\n").map((l, i) => [l, text.split("\n")[i]]).filter(([p, q]) => p !== q);
  assert.equal(changed.length, 1, JSON.stringify(changed));
  assert.match(changed[0][1], /^skid = [0-9.]+ +# ft of locked-wheel skid up to the impact$/);
  // A shorter skid: a lower speed before braking.
  const after = await page.evaluate(() => window.pim.answer.document.best.vehicles[0].speed_before_braking);
  assert.ok(after < before, `${after} against ${before}`);
  await page.fill("#toml", original);
  await page.waitForFunction((t) => window.pim.text === t, original);
  await idle();
});

test("a handle pressed and let go in place moves nothing; a tool's click on a handle is the tool's", async () => {
  const original = await exampleAsCommitted();
  const centre = async () => {
    const b = await page.locator('.given-rest circle.handle[data-vehicle="2"]').boundingBox();
    return [b.x + b.width / 2, b.y + b.height / 2];
  };
  const [x, y] = await centre();
  await page.mouse.move(x, y);
  await page.mouse.down();
  // The plan drawn again under the still pointer (the window resized: the view fitted anew),
  // and the browser's move at the same screen point that follows such a change.
  await page.setViewportSize({ width: 1300, height: 900 });
  await page.evaluate(([cx, cy]) => document.getElementById("plan").dispatchEvent(
    new PointerEvent("pointermove", { pointerId: 1, clientX: cx, clientY: cy, bubbles: true })), [x, y]);
  await page.mouse.up();
  await idle();
  assert.equal(await page.inputValue("#toml"), original);
  await page.setViewportSize({ width: 1400, height: 900 });
  await page.click("#fit");
  // The Mark tool's click lands on the rest's handle: a mark is placed there, the rest stays.
  const [hx, hy] = await centre();
  page.once("dialog", (d) => d.accept("2 0.5"));
  await page.click("#add-mark");
  await page.mouse.click(hx, hy);
  await page.waitForFunction(() => window.pim.answer.pieces.some((p) => p.name === "vehicle2 mark 2"));
  await idle();
  const placed = await page.inputValue("#toml");
  const changed = original.split("\n").map((l, i) => [l, placed.split("\n")[i]]).filter(([p, q]) => p !== q);
  assert.equal(changed.length, 1, JSON.stringify(changed));
  assert.match(changed[0][1], /^marks = \[ \{ x = 32\.6, y = 48\.2, sigma = 0\.5 \}, \{ x = [-0-9.]+, y = [-0-9.]+, sigma = 0\.5 \} \]$/);
  await page.fill("#toml", original);
  await page.waitForFunction(() => !window.pim.answer.pieces.some((p) => p.name === "vehicle2 mark 2"));
  await idle();
});

test("the forms: a field edited writes the TOML, a bad value marks its field and the plan's handle", async () => {
  const original = await exampleAsCommitted();
  const onDisk = fs.readFileSync(path.join(dir, CASE), "utf8");
  const openSection = (name) => page.evaluate((n) => {
    document.getElementById("forms-box").open = true;
    document.querySelector(`#forms details[data-section="${n}"]`).open = true;
  }, name);
  await openSection("vehicle1");
  const mass = page.locator('#forms input[data-key="vehicle1.mass"]');
  assert.equal(await mass.inputValue(), "3400.0");
  assert.equal(await mass.getAttribute("title"), "lb, with driver");
  const before = await speeds();
  await mass.fill("3600");
  await mass.press("Tab");
  await page.waitForFunction(() => /mass = 3600\.0 +# lb, with driver/.test(window.pim.text));
  await idle();
  const edited = await page.inputValue("#toml");
  const changed = original.split("\n").map((l, i) => [l, edited.split("\n")[i]]).filter(([p, q]) => p !== q);
  assert.equal(changed.length, 1, JSON.stringify(changed));
  assert.notDeepEqual(await speeds(), before);
  // The TOML edited by hand: the form follows.
  await page.fill("#toml", edited.replace("mass = 3600.0", "mass = 3650.0"));
  await page.waitForFunction(() => document.querySelector('#forms input[data-key="vehicle1.mass"]')?.value === "3650.0");
  await idle();
  // A bad value: its field marked, its section open, nothing saved.
  await mass.fill("-5");
  await mass.press("Tab");
  await page.waitForSelector('#forms input[data-key="vehicle1.mass"].bad-field');
  await idle();
  assert.match(await page.textContent("#error"), /vehicle1\.mass/);
  await page.click("#save");
  await page.waitForFunction(() => /not saved/.test(document.getElementById("status").textContent));
  assert.equal(fs.readFileSync(path.join(dir, CASE), "utf8"), onDisk);
  // A mark's bad sigma: the plan's handle of that mark is marked too.
  await page.fill("#toml", original);
  await page.waitForFunction((t) => window.pim.text === t && !window.pim.busy, original);
  await idle();
  await openSection("scene.vehicle2");
  const sigma = page.locator('#forms input[data-key="scene.vehicle2.marks.0.sigma"]');
  await sigma.fill("-1");
  await sigma.press("Tab");
  await page.waitForSelector('circle.mark-handle[data-vehicle="2"].bad-handle');
  await idle();
  await page.screenshot({ path: path.join(shots, "15-form-bad-value.png") });
  await page.fill("#toml", original);
  await page.waitForFunction((t) => window.pim.text === t, original);
  await idle();
  assert.equal(await page.$(".bad-field, .bad-handle"), null);
});

test("the pose at contact's priors edited in their form: the pose is fitted with them", async () => {
  await page.selectOption("#cases", "reconstruction_pose_us.toml");
  await idle();
  const original = await page.inputValue("#toml");
  const row = () => page.evaluate(() => window.pim.answer.document.best.contact_pose
    .find((r) => r.name === "vehicle2.impact_point.x"));
  const before = await row();
  assert.ok(Math.abs(before.prior_sigma - 0.8 * 0.3048) < 1e-9, JSON.stringify(before));
  assert.match(await page.textContent("#table"), /pose at contact/);
  await page.evaluate(() => {
    document.getElementById("forms-box").open = true;
    document.querySelector('#forms details[data-section="contact_sigma"]').open = true;
  });
  const field = page.locator('#forms input[data-key="contact_sigma.vehicle2.impact_point.x"]');
  assert.equal(await field.inputValue(), "0.8");
  await field.fill("0.3");
  await field.press("Tab");
  await page.waitForFunction(() => /impact_point = \{ x = 0\.3 \}/.test(window.pim.text));
  await idle();
  const after = await row();
  assert.ok(Math.abs(after.prior_sigma - 0.3 * 0.3048) < 1e-9, JSON.stringify(after));
  assert.ok(after.sigma < before.sigma, `${after.sigma} ${before.sigma}`);
  const edited = await page.inputValue("#toml");
  const changed = original.split("\n").map((l, i) => [l, edited.split("\n")[i]]).filter(([p, q]) => p !== q);
  assert.equal(changed.length, 1, JSON.stringify(changed));
  await page.screenshot({ path: path.join(shots, "19-pose-prior-form.png") });
  await page.fill("#toml", original);
  await page.waitForFunction((t) => window.pim.text === t, original);
  await idle();
});

test("a batch of the folder in the background: pim batch's records, a row opening its case", async () => {
  // Chosen again: read from the folder (the path is already the case's: idle waits for the read).
  await page.selectOption("#cases", CASE);
  await idle();
  assert.equal(await page.evaluate(() => window.pim.path), CASE);
  await page.click("#batch-start");
  await page.waitForFunction(() => /case files, \d+ records/.test(document.getElementById("batch-status").textContent), null, { timeout: 300000 });
  const doc = await page.evaluate(() => window.pim.batch.report.document);
  const files = fs.readdirSync(dir).filter((f) => f.endsWith(".toml")).sort();
  assert.equal(doc.files, files.length);
  assert.equal(await page.locator("#batch-table tr[data-file]").count(), files.length);
  // The command's records of the same folder, each file named as the page names it.
  const out = execFileSync(pimBin, ["batch", ".", "--format", "json"], { cwd: dir, encoding: "utf8" }).replaceAll("./", "");
  const cli = out.trim().split("\n").map((l) => JSON.parse(l));
  assert.deepEqual(doc.records, cli);
  await page.screenshot({ path: path.join(shots, "16-batch.png") });
  // A row opens its case.
  await page.click('#batch-table tr[data-file="runout_scene.toml"]');
  await page.waitForFunction(() => window.pim.path === "runout_scene.toml");
  await idle();
  // Chosen again: read from the folder (the path is already the case's: idle waits for the read).
  await page.selectOption("#cases", CASE);
  await idle();
  assert.equal(await page.evaluate(() => window.pim.path), CASE);
});

test("the API answers every example case with the command's document", async () => {
  const cookie = `pim_token=${token}`;
  for (const name of ["reconstruction_us.toml", "reconstruction_damage_us.toml", "ricsac7_fit.toml", "oblique_sae_us.toml"]) {
    const text = fs.readFileSync(path.join(repo, "examples/cases", name), "utf8");
    const r = await raw("POST", "/api/answer", { cookie, body: { path: name, text } });
    assert.equal(r.status, 200, r.body);
    const cli = JSON.parse(execFileSync(pimBin, ["fit", path.join(repo, "examples/cases", name), "--format", "json"], { encoding: "utf8" }));
    assert.deepEqual(JSON.parse(r.body).document, cli, name);
  }
  // A case that gives its coefficients is solved as `pim solve` solves it, its run-outs drawn.
  const text = fs.readFileSync(path.join(repo, "examples/cases/runout_spin.toml"), "utf8");
  const r = await raw("POST", "/api/answer", { cookie, body: { path: "runout_spin.toml", text } });
  assert.equal(r.status, 200, r.body);
  const a = JSON.parse(r.body);
  assert.equal(a.question, "solve");
  assert.equal(a.plan.vehicles.length, 2);
  const cli = JSON.parse(execFileSync(pimBin, ["solve", path.join(repo, "examples/cases/runout_spin.toml"), "--format", "json"], { encoding: "utf8" }));
  assert.deepEqual(a.document, cli);
});

test("foreign hosts, missing tokens and paths outside the folder are refused", async () => {
  const cookie = `pim_token=${token}`;
  assert.equal((await raw("GET", "/api/cases", { cookie })).status, 200);
  assert.equal((await raw("GET", "/api/cases", { cookie, host: "evil.example" })).status, 403);
  assert.equal((await raw("GET", "/api/cases", { cookie, host: `evil.example:${new URL(base).port}` })).status, 403);
  assert.equal((await raw("GET", "/api/cases")).status, 403);
  assert.equal((await raw("GET", "/api/cases", { cookie: "pim_token=0000" })).status, 403);
  assert.equal((await raw("GET", "/")).status, 403);
  for (const p of ["../outside.toml", "/etc/outside.toml", "sub/../../outside.toml", "notes.txt"]) {
    const r = await raw("POST", "/api/save", { cookie, body: { path: p, text: "title = \"x\"" } });
    assert.equal(r.status, 403, `${p}: ${r.body}`);
    const g = await raw("GET", `/api/case?path=${encodeURIComponent(p)}`, { cookie });
    assert.equal(g.status, 403, p);
  }
  assert.ok(!fs.existsSync(path.join(path.dirname(dir), "outside.toml")));
  const big = await raw("POST", "/api/answer", { cookie, body: { path: CASE, text: "#".repeat(2 << 20) } });
  assert.equal(big.status, 413);
});

test("the server's answer times while dragging (performance marks)", async () => {
  const t = timings;
  fs.writeFileSync(path.join(shots, "timings.json"), JSON.stringify({ opened, answers: t }, null, 1));
  console.log(`first paint ${opened.first_contentful_paint} ms, first answer drawn ${opened.first_answer_drawn} ms after navigation`);
  const median = (xs) => xs.sort((a, b) => a - b)[xs.length >> 1];
  const live = t.filter((x) => x.live).map((x) => x.server), whole = t.filter((x) => !x.live).map((x) => x.server);
  console.log(`live answers while dragging: ${live.length}, server ms median ${median(live)}; whole answers: ${whole.length}, median ${median(whole)}`);
  // The drag was followed live, and ended with a whole answer.
  assert.ok(live.length >= 1 && whole.length >= 2);
  assert.equal(t[t.length - 1].live, false);
});
