// A case built in the page from an empty folder (a scene diagram and a survey's CSV only, no
// TOML typed): named and started, the diagram set behind the plan to scale, the survey
// imported, every section added from the forms and its values set there, the rests and a mark
// dropped on the survey's points, reconstructed and saved; `pim fit` of the saved file gives
// the page's document. Screenshots of each step in target/browser-screenshots (build-*.png).
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { chromium } from "playwright-core";
import { startPim } from "./server.mjs";

const repo = path.resolve(import.meta.dirname, "../..");
const pimBin = process.env.PIM_BIN || path.join(repo, "target/release/pim");
const shots = path.join(repo, "target/browser-screenshots");
let dir, server, url, browser, page;

// A survey in feet from a total station set up away from the scene: the impact area is point
// POI; the rests' CGs, a tyre mark and a hydrant.
const SURVEY = `point,x,y,code,description
1,980.00,2030.00,HYD,fire hydrant
POI,1000.00,2000.00,POI,gouge at the impact
R1,1011.90,2002.90,REST,sedan at rest (CG)
R2,1050.10,2079.70,REST,SUV at rest (CG)
M2,1032.60,2048.20,MARK,SUV tyre mark
`;

before(async () => {
  fs.mkdirSync(shots, { recursive: true });
  dir = fs.mkdtempSync(path.join(os.tmpdir(), "pim-build-"));
  fs.copyFileSync(path.join(repo, "examples/scene/intersection.png"), path.join(dir, "intersection.png"));
  fs.writeFileSync(path.join(dir, "survey.csv"), SURVEY);
  let started;
  ({ server, url: started } = startPim(pimBin, dir));
  url = await started;
  browser = await chromium.launch({ executablePath: process.env.CHROMIUM || "/usr/bin/chromium", args: ["--no-sandbox"] });
  page = await browser.newPage({ viewport: { width: 1400, height: 900 }, bypassCSP: true });
});

after(async () => {
  if (browser) await browser.close();
  if (server) server.kill();
  if (dir) fs.rmSync(dir, { recursive: true, force: true });
});

const t0 = Date.now();
const step = (what) => console.error(`${((Date.now() - t0) / 1000).toFixed(1)} s: ${what}`);

const idle = () => page.waitForFunction(() => window.pim && !window.pim.opening && !window.pim.busy
  && !window.pim.pending && !window.pim.dragging && !window.pim.moves, null, { timeout: 120000 });

// A form's field set as a user types it (the change event on leaving it).
async function setField(key, value) {
  const input = page.locator(`#forms input[data-key="${key}"]`);
  await input.evaluate((i) => { i.closest("details").open = true; });
  await input.fill(String(value));
  await input.dispatchEvent("change");
  await page.waitForFunction(([k, v]) => new RegExp(`${k.split(".").pop()} = ${v}\\b`).test(window.pim.text), [key, String(value)]);
  await idle();
}

// The screen centre of an element of the plan.
async function centreOf(selector) {
  const b = await page.locator(selector).first().boundingBox();
  return [b.x + b.width / 2, b.y + b.height / 2];
}

async function drag(from, to) {
  await page.mouse.move(...from);
  await page.mouse.down();
  await page.mouse.move(...to, { steps: 8 });
  await page.mouse.up();
}

test("a case built in the page from a diagram and a survey, then reconstructed and saved", async () => {
  await page.goto(url);
  await page.waitForFunction(() => window.pim && Array.isArray(window.pim.cases));
  assert.deepEqual(await page.evaluate(() => window.pim.cases), []);
  await page.screenshot({ path: path.join(shots, "build-1-empty.png") });

  // New case: its name, US units, the SAE frame. Nothing is written yet.
  await page.click("#new-case");
  await page.fill("#new-name", "main_and_oak");
  await page.fill("#new-title", "Main and Oak, sedan into SUV");
  await page.selectOption("#new-units", "us");
  await page.selectOption("#new-convention", "sae");
  await page.click("#new-start");
  await page.waitForFunction(() => window.pim.path === "main_and_oak.toml" && window.pim.answer && window.pim.answer.sketch);
  await idle();
  assert.deepEqual(fs.readdirSync(dir).sort(), ["intersection.png", "survey.csv"]);

  // The diagram behind the plan, set to scale by its scale bar (600 pixels, 60 ft).
  page.once("dialog", (d) => d.accept("intersection.png"));
  await page.click("#background");
  await page.waitForSelector("image.background");
  await idle();
  page.once("dialog", (d) => d.accept("60"));
  await page.click("#set-scale");
  for (const [u, v] of [[1000, 1460], [1600, 1460]]) {
    const [x, y] = await page.evaluate(([u, v]) => {
      const img = document.querySelector("image.background");
      const p = document.getElementById("plan").createSVGPoint(); p.x = u; p.y = v;
      const q = p.matrixTransform(img.getScreenCTM());
      return [q.x, q.y];
    }, [u, v]);
    await page.mouse.click(x, y);
  }
  await page.waitForFunction(() => /distance = 60\.0/.test(window.pim.text));
  await idle();

  // The survey: its CSV, feet, the gouge made the origin.
  await page.click("#survey");
  await page.setInputFiles("#survey-file", path.join(dir, "survey.csv"));
  await page.selectOption("#survey-unit", "ft");
  await page.fill("#survey-origin", "POI");
  await page.click("#survey-import");
  await page.waitForFunction(() => document.querySelectorAll(".survey-point").length === 5);
  await idle();
  assert.match(await page.inputValue("#toml"), /\{ id = "R1", x = 11\.9, y = 2\.9, code = "REST", description = "sedan at rest \(CG\)" \}/);
  await page.click("#fit");
  await page.screenshot({ path: path.join(shots, "build-2-survey.png") });

  // Every section the forms offer, added in turn.
  for (;;) {
    const next = await page.$$eval("#add-section option", (o) => o.map((x) => x.value));
    if (!next.length) break;
    await page.selectOption("#add-section", next[0]);
    await page.click("#add-section-button");
    await page.waitForFunction((n) => window.pim.text.includes(`[${n}]`), next[0]);
    await idle();
    step(`[${next[0]}] added`);
  }
  await page.screenshot({ path: path.join(shots, "build-3-sections.png") });
  // A section removed from its form (asked first) is offered again by the menu.
  const whole = await page.evaluate(() => window.pim.text);
  await page.locator("#forms-box").evaluate((d) => { d.open = true; });
  page.once("dialog", (d) => d.accept());
  await page.click('#forms button.remove-section[data-section="sigma.initial"]');
  await page.waitForFunction(() => !window.pim.text.includes("[sigma.initial]"));
  await idle();
  assert.deepEqual(await page.$$eval("#add-section option", (o) => o.map((x) => x.value)), ["sigma.initial"]);
  await page.selectOption("#add-section", "sigma.initial");
  await page.click("#add-section-button");
  await page.waitForFunction(() => window.pim.text.includes("[sigma.initial]"));
  await idle();
  // Added back at the end of the file, with the values it had.
  const block = (t) => /\[sigma\.initial\]\n(?:[^[\n][^\n]*\n)*/.exec(t)[0];
  const again = await page.evaluate(() => window.pim.text);
  assert.equal(block(again), block(whole));
  assert.equal(again.length, whole.length);
  step("[sigma.initial] removed and added back");

  // The vehicles and the evidence as the brief gives them, typed into the forms.
  const fields = [
    ["vehicle1.mass", "3400.0"], ["vehicle1.yaw_inertia", "1900.0"], ["vehicle1.position.x", "-7.5"], ["vehicle1.position.y", "-1.0"],
    ["vehicle1.length", "16.0"], ["vehicle1.width", "6.0"], ["vehicle1.cg_to_front", "7.2"],
    ["vehicle2.mass", "3900.0"], ["vehicle2.position.x", "1.0"], ["vehicle2.position.y", "1.5"],
    ["vehicle2.length", "15.0"], ["vehicle2.width", "6.2"], ["vehicle2.cg_to_front", "6.8"],
    ["runout.vehicle1.braking", "0.3"], ["runout.vehicle2.braking", "0.2"],
    ["pre_impact.vehicle1.skid", "42.0"], ["pre_impact.vehicle2.edr.0.speed", "27.5"],
  ];
  for (const [k, v] of fields) { await setField(k, v); step(`${k} = ${v}`); }
  // Vehicle 2's yaw inertia is left to the estimate from its outline, offered in the form.
  const inertia = page.locator('#forms input[data-key="vehicle2.yaw_inertia"]');
  assert.equal(await inertia.inputValue(), "");
  assert.equal(await inertia.getAttribute("placeholder"), "estimated");
  assert.match(await inertia.getAttribute("title"), /^estimated as 2395 slug ft\^2 from mass 3900 lb, length 15\.00 and width 6\.20 ft/);

  // The rests placed on their survey points with the Rest tool: written at the points with
  // their headings, their ids kept.
  for (const [vehicle, point, heading] of [[1, "R1", 144], [2, "R2", 241]]) {
    await page.click("#fit");
    await idle();
    await page.click("#add-rest");
    page.once("dialog", (d) => d.accept(`${vehicle} ${heading} 1.0`));
    await page.mouse.click(...(await centreOf(`.survey-point[data-point="${point}"] rect`)));
    await page.waitForFunction((p) => window.pim.text.includes(`point = "${p}"`), point);
    await idle();
    step(`rest of vehicle ${vehicle} on ${point}`);
  }
  assert.equal(await page.evaluate(() => window.pim.answer.question), "reconstruction");
  // A tyre mark clicked on its survey point.
  await page.click("#add-mark");
  page.once("dialog", (d) => d.accept("2 0.5 cg"));
  await page.mouse.click(...(await centreOf('.survey-point[data-point="M2"] rect')));
  await page.waitForFunction(() => window.pim.text.includes('point = "M2"'));
  await idle();
  step("mark on M2");
  // The SUV's EDR table pasted as the crash data report prints it (km/h, newest last): its
  // rows kept in the case, the last carried to contact as its record, and drawn beside the
  // answer's speeds.
  await page.click("#edr");
  await page.selectOption("#edr-vehicle", "2");
  await page.selectOption("#edr-unit", "km/h");
  await page.fill("#edr-table", [
    "Time (sec)\tSpeed, Vehicle Indicated (km/h)\tAccelerator Pedal, % Full\tService Brake",
    "-2.0\t46\t15\tOff", "-1.5\t45\t0\tOff", "-1.0\t45\t0\tOff", "-0.5\t44\t0\tOff",
  ].join("\n"));
  await page.click("#edr-import");
  await page.waitForFunction(() => window.pim.text.includes("edr_history = ["));
  await idle();
  step("EDR table pasted");
  assert.match(await page.inputValue("#toml"), /edr = \[\n  \{ speed = 27\.34, time = 0\.5, deceleration = 0\.0, sigma = 1\.01 \},\n\]/);
  assert.equal(await page.isVisible("#speed-history svg"), true);
  // Four rows (open: brake off) and the answer's point at contact.
  assert.ok(await page.locator("#speed-history svg circle").count() >= 5);
  await page.locator("#speed-history-box").screenshot({ path: path.join(shots, "build-5-edr.png") });

  const text = await page.inputValue("#toml");
  assert.match(text, /rest = \{ x = 11\.9, y = 2\.9, heading = 144\.0, point = "R1" \}/);
  assert.match(text, /rest = \{ x = 50\.1, y = 79\.7, heading = 241\.0, point = "R2" \}/);
  assert.match(text, /\{ x = 32\.6, y = 48\.2, sigma = 0\.5, point = "M2" \}/);
  await page.click("#fit");
  await idle();
  await page.screenshot({ path: path.join(shots, "build-4-reconstructed.png") });

  // Saved: the file is created, and pim fit of it gives the page's document.
  await page.click("#save");
  await page.waitForFunction(() => /^saved/.test(document.getElementById("status").textContent));
  const saved = fs.readFileSync(path.join(dir, "main_and_oak.toml"), "utf8");
  assert.equal(saved, text);
  const pageDoc = await page.evaluate(() => window.pim.answer.document);
  const cli = JSON.parse(execFileSync(pimBin, ["fit", path.join(dir, "main_and_oak.toml"), "--format", "json"], { encoding: "utf8" }));
  assert.deepEqual(pageDoc, cli);
  assert.equal(cli.status, "found");
  // The case menu lists it; a second Save goes over the version saved.
  assert.deepEqual(await page.evaluate(() => window.pim.cases), ["main_and_oak.toml"]);
  await setField("vehicle1.mass", "3450.0");
  await page.click("#save");
  await page.waitForFunction(() => window.pim.text === window.pim.saved);
  assert.match(fs.readFileSync(path.join(dir, "main_and_oak.toml"), "utf8"), /mass = 3450\.0/);
});
