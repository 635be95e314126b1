// pim serve: the scene editor. The server answers in pim's own documents; this page draws
// them, lets the rest positions be dragged and the TOML edited, and saves the case back.
"use strict";

const NS = "http://www.w3.org/2000/svg";
const $ = (id) => document.getElementById(id);
const state = {
  path: null, text: "", saved: "", answer: null, busy: false, pending: false,
  view: null, dragging: null, timings: [], study: null, units: "",
  images: [], sizes: {}, tool: null, clicks: [], measured: null,
  off: [], // pieces of evidence switched off (by name): the answer is the case without them
  photo: null, photoResult: null, // the photo being made into a plan, and the last made
  playT: null, playing: false, // the time slider's time from contact (null: not shown), s
};
window.pim = state; // for the tests and the curious

function el(name, attrs, parent) {
  const e = document.createElementNS(NS, name);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  if (parent) parent.appendChild(e);
  return e;
}
// Page coordinates (right, up) to the SVG's (right, down).
const pts = (list) => list.map(([h, v]) => `${h},${-v}`).join(" ");

function status(msg) {
  $("status").textContent = msg;
  $("status").classList.toggle("dirty", state.text !== state.saved);
}

async function api(method, url, body) {
  const res = await fetch(url, {
    method, headers: body ? { "content-type": "application/json" } : {},
    body: body ? JSON.stringify(body) : undefined,
  });
  const data = await res.json().catch(() => ({ error: `${res.status} ${res.statusText}` }));
  if (!res.ok) throw Object.assign(new Error(data.error || res.statusText), { status: res.status, data });
  return { data, res };
}

// The folder's case files in the case menu (`current` chosen in it); the folder's answer.
async function listCases(current) {
  const { data } = await api("GET", "/api/cases");
  state.images = data.images || [];
  state.cases = data.cases;
  const sel = $("cases");
  sel.innerHTML = "";
  for (const c of data.cases) {
    const o = document.createElement("option");
    o.value = o.textContent = c;
    sel.appendChild(o);
  }
  if (current) sel.value = current;
  return data;
}

async function loadCases() {
  const data = await listCases();
  const first = data.initial || (data.cases.includes("reconstruction_us.toml")
    ? "reconstruction_us.toml" : data.cases[0]);
  const wanted = new URLSearchParams(location.search).get("case") || first;
  if (wanted) { $("cases").value = wanted; await openCase(wanted); }
}

// `state.opening` while the case is read and its first answer asked for.
async function openCase(path) {
  state.opening = (state.opening || 0) + 1;
  try {
    const { data } = await api("GET", `/api/case?path=${encodeURIComponent(path)}`);
    state.path = path; state.text = state.saved = data.text; state.version = data.version; state.view = null;
    state.fresh = false;
    state.conflict = null; $("conflict").hidden = true;
    state.study = null; state.measured = null; state.off = [];
    $("study-status").textContent = ""; $("study-progress").hidden = true; $("study-cancel").hidden = true;
    $("toml").value = data.text;
    await solve();
  } finally {
    state.opening -= 1;
  }
}

// Solves the current text; a request made while one runs waits for it (the newest wins, a
// whole answer over a live one). `live`: while dragging, the server follows its last answer
// (a few refinement steps) instead of searching; the whole search runs on release.
async function solve(live = false) {
  if (state.busy) { state.pending = state.pending === "full" || !live ? "full" : "live"; return; }
  state.busy = true;
  status(live ? "following…" : "solving…");
  const t0 = performance.now();
  try {
    const { data, res } = await api("POST", "/api/answer", { path: state.path, text: state.text, live, units: state.units, off: state.off });
    state.answer = data;
    data.path = state.path;
    const server = /dur=([0-9.]+)/.exec(res.headers.get("server-timing") || "");
    state.timings.push({ live, server: server ? +server[1] : null, page: performance.now() - t0 });
    performance.measure(live ? "live answer" : "answer", { start: t0, end: performance.now() });
    $("error").hidden = true;
    $("toml").classList.remove("bad");
    render();
    await refreshForms(null);
    status(`${live ? "followed" : "solved"} in ${server ? server[1] : "?"} ms`);
  } catch (e) {
    $("error").hidden = false;
    $("error").textContent = e.message;
    $("toml").classList.add("bad");
    status("not solved");
    // A case being built: the plan of what its text gives so far (background, survey).
    if (e.data && e.data.sketch && (!state.answer || state.answer.sketch || state.answer.path !== state.path)) {
      state.answer = { sketch: true, path: state.path, plan: e.data.sketch, table: "" };
      render();
    }
    await refreshForms(e.message);
  } finally {
    state.busy = false;
    if (state.pending) { const live = state.pending === "live"; state.pending = false; solve(live); }
  }
}

// The key pim's message names (`file:line:col: vehicle1.mass: ...`), if any.
function keyOf(message) {
  const m = /:\d+:\d+: ([A-Za-z0-9_.]+)/.exec(message || "");
  return m ? m[1] : null;
}

// The forms: one per section the file writes, a field per value (the comment after it as its
// help); an edit is written into the text by the server and solved. An error of the answer
// marks the field it names (its section opened) and the plan's handle of that piece.
async function refreshForms(error) {
  const box = $("forms");
  if (state.formText !== state.text) {
    state.formText = state.text;
    let sections = [];
    try {
      ({ data: { sections } } = await api("POST", "/api/form", { path: state.path, text: state.text }));
    } catch (e) { /* not TOML: the TOML's own mark says why */ }
    const open = new Set([...box.querySelectorAll("details[open]")].map((d) => d.dataset.section));
    box.innerHTML = "";
    for (const sec of sections) {
      const d = document.createElement("details");
      d.dataset.section = sec.name;
      d.open = open.has(sec.name);
      const sum = document.createElement("summary");
      sum.textContent = sec.name ? `[${sec.name}]` : "(top of the file)";
      if (sec.name && sec.name !== "units") {
        const rm = document.createElement("button");
        rm.type = "button";
        rm.className = "remove-section";
        rm.textContent = "remove";
        rm.title = `remove [${sec.name}] from the case (the TOML; Save writes it)`;
        rm.dataset.section = sec.name;
        rm.addEventListener("click", (e) => { e.preventDefault(); e.stopPropagation(); removeSection(sec.name); });
        sum.appendChild(rm);
      }
      d.appendChild(sum);
      const t = document.createElement("table");
      for (const f of sec.fields) {
        const r = t.insertRow();
        r.insertCell().textContent = f.label;
        const input = document.createElement("input");
        input.dataset.key = f.key;
        if (f.kind === "bool") { input.type = "checkbox"; input.checked = f.value === "true"; }
        else { input.type = "text"; input.value = f.value; input.readOnly = f.kind === "list"; }
        if (f.comment) input.title = f.comment;
        if (f.optional && !f.value) input.placeholder = "estimated";
        input.setAttribute("aria-label", f.key);
        input.addEventListener("change", () => setField(f.key, f.kind === "bool" ? input.checked : input.value));
        r.insertCell().appendChild(input);
        const help = r.insertCell();
        help.className = "help";
        help.textContent = f.comment || "";
      }
      d.appendChild(t);
      box.appendChild(d);
    }
  }
  await refreshSections();
  for (const b of document.querySelectorAll(".bad-field")) b.classList.remove("bad-field");
  for (const b of document.querySelectorAll(".bad-handle")) b.classList.remove("bad-handle");
  const key = keyOf(error);
  if (!key) return;
  // The field the message names, or every field under the table or array it names.
  const inputs = [...box.querySelectorAll("input[data-key]")];
  const exact = inputs.filter((i) => i.dataset.key === key);
  for (const input of exact.length ? exact : inputs.filter((i) => i.dataset.key.startsWith(`${key}.`))) {
    input.classList.add("bad-field");
    input.closest("details").open = true;
    $("forms-box").open = true;
  }
  // The plan's handle of the piece the message names.
  const m = /^scene\.vehicle(\d)\.(rest|marks(?:\.(\d+))?)/.exec(key) || /^vehicle(\d)\.(position|heading|impact_point)/.exec(key);
  if (m) {
    const sel = m[2].startsWith("rest") ? `.given-rest circle.handle[data-vehicle="${m[1]}"]`
      : m[2].startsWith("marks") ? `circle.mark-handle[data-vehicle="${m[1]}"]${m[3] != null ? `[data-mark="${m[3]}"]` : ""}`
      : `rect.cg-handle[data-vehicle="${m[1]}"]`;
    for (const h of document.querySelectorAll(sel)) h.classList.add("bad-handle");
  }
}

async function setField(key, value) {
  try {
    const { data } = await api("POST", "/api/set", { path: state.path, text: state.text, key, value });
    state.text = data.text;
    $("toml").value = data.text;
    await solve();
  } catch (e) {
    $("error").hidden = false;
    $("error").textContent = e.message;
    await refreshForms(e.message);
  }
}

function speedsTable(a) {
  const t = $("speeds");
  t.innerHTML = "";
  const best = a.document && a.document.best;
  const u = a.plan.speed_metres || 1;
  if (a.question !== "reconstruction" || !best) {
    t.innerHTML = "<tr><td>no reconstruction of the speeds: see what pim fit prints</td></tr>";
    return;
  }
  const head = t.insertRow();
  for (const h of ["vehicle", "before braking", "at contact", "at separation"]) {
    const th = document.createElement("th"); th.textContent = h; head.appendChild(th);
  }
  for (const v of best.vehicles) {
    const r = t.insertRow();
    r.className = `v${v.vehicle}`;
    r.dataset.vehicle = v.vehicle;
    const cells = [String(v.vehicle),
      v.speed_before_braking == null ? "-" : (v.speed_before_braking / u).toFixed(2),
      (v.speed_at_contact / u).toFixed(2), (v.speed_at_separation / u).toFixed(2)];
    cells.forEach((c, i) => { const td = r.insertCell(); td.textContent = c; if (i === 2) td.className = "contact"; });
  }
  const cap = t.createCaption(); cap.textContent = `speeds, ${a.plan.speed_label}`;
  intervals(a);
}

// The study's 90 % intervals of the speeds at contact (the draws' widened to the profile's, as
// the study reports them) beside the speeds, for the text they were drawn from.
function intervals(a) {
  const st = state.study;
  const q = st && st.text === state.text && st.off === state.off.join("\n")
    && st.report.document && st.report.document.intervals;
  if (!q || a.question !== "reconstruction") return;
  const u = a.plan.speed_metres || 1;
  const rows = $("speeds").rows;
  const th = document.createElement("th"); th.textContent = "90 % at contact"; rows[0].appendChild(th);
  for (let i = 1; i < rows.length; i++) {
    const s = q[`vehicle${rows[i].dataset.vehicle}.speed_at_contact`];
    const td = rows[i].insertCell();
    td.className = "interval";
    td.textContent = s ? `${(s[0] / u).toFixed(2)} – ${(s[1] / u).toFixed(2)}` : "-";
  }
}

// The uncertainty study runs on the server; the page polls its progress and can cancel it.
async function startStudy() {
  const draws = Math.round(+$("draws").value);
  const text = state.text;
  try {
    const off = state.off.slice();
    const { data } = await api("POST", "/api/study", { path: state.path, text, draws, off, units: state.units });
    state.study = { id: data.id, text, off: off.join("\n"), units: state.units, report: { state: "running", done: 0, total: draws } };
    $("study-cancel").hidden = false;
    $("study-progress").hidden = false;
    $("study-start").disabled = true;
    studyShown();
    pollStudy(data.id);
  } catch (e) {
    $("study-status").textContent = e.message;
  }
}

async function pollStudy(id) {
  while (state.study && state.study.id === id) {
    const { data } = await api("GET", `/api/study?id=${id}`);
    if (!state.study || state.study.id !== id) return;
    state.study.report = data;
    studyShown();
    if (data.state !== "running") {
      $("study-cancel").hidden = true;
      $("study-start").disabled = false;
      render();
      return;
    }
    await new Promise((r) => setTimeout(r, 200));
  }
}

function studyShown() {
  const r = state.study.report, p = $("study-progress");
  p.max = Math.max(r.total, 1); p.value = r.done;
  const d = r.document;
  $("study-status").textContent =
    r.state === "running" ? `${r.done} of ${r.total} draws`
    : r.state === "failed" ? `study failed: ${r.error}`
    : r.state === "cancelled" ? `cancelled after ${d.cancelled.done} of ${d.cancelled.asked} draws; intervals from them (${d.feasible_draws} feasible)`
    : `${d.feasible_draws} of ${d.draws} draws feasible (seed ${d.seed})`;
}

// A batch of the case files in the current case's folder (pim batch's records), in the
// background with its progress and cancel; its best record per file in a table, a row opening
// its case.
async function startBatch() {
  const folder = state.path.includes("/") ? state.path.slice(0, state.path.lastIndexOf("/") + 1) : "";
  const paths = (state.cases || []).filter((c) => c.startsWith(folder) && !c.slice(folder.length).includes("/"));
  try {
    const { data } = await api("POST", "/api/batch", { paths });
    state.batch = { id: data.id, report: { state: "running", done: 0, total: paths.length } };
    $("batch-cancel").hidden = false; $("batch-progress").hidden = false; $("batch-start").disabled = true;
    $("batch-table").innerHTML = "";
    while (state.batch && state.batch.id === data.id) {
      const { data: r } = await api("GET", `/api/study?id=${data.id}`);
      state.batch.report = r;
      const p = $("batch-progress"); p.max = Math.max(r.total, 1); p.value = r.done;
      $("batch-status").textContent = r.state === "running" ? `${r.done} of ${r.total} case files` : "";
      if (r.state !== "running") break;
      await new Promise((res) => setTimeout(res, 200));
    }
  } catch (e) {
    $("batch-status").textContent = e.message;
  }
  $("batch-cancel").hidden = true; $("batch-start").disabled = false;
  const r = state.batch && state.batch.report;
  if (r && r.document) batchTable(r.document);
}

function batchTable(doc) {
  const t = $("batch-table");
  t.innerHTML = "";
  const u = (state.answer && state.answer.plan.speed_metres) || 1, label = (state.answer && state.answer.plan.speed_label) || "m/s";
  const head = t.insertRow();
  for (const h of ["case", "answer", "chi² / cost", `contact ${label}`]) {
    const th = document.createElement("th"); th.textContent = h; head.appendChild(th);
  }
  const files = [...new Set(doc.records.map((r) => r.file))];
  for (const f of files) {
    const recs = doc.records.filter((r) => r.file === f);
    const best = recs.find((r) => r.best) || recs[0];
    const row = t.insertRow();
    row.dataset.file = f;
    // A fit's record carries its branch's fields flat; a scene case's, its reconstruction.
    const rec = best.reconstruction;
    const speeds = rec ? rec.vehicles.map((v) => (v.speed_at_contact / u).toFixed(2)).join(" / ")
      : best.vehicles ? best.vehicles.map((v) => (v.speed_initial / u).toFixed(2)).join(" / ") : "-";
    const cells = [f, rec ? rec.status : best.outcome,
      rec && rec.chi_square != null ? rec.chi_square.toFixed(3) : best.cost != null ? best.cost.toPrecision(4) : "-", speeds];
    for (const c of cells) row.insertCell().textContent = c;
    if (best.error) row.title = best.error;
    row.addEventListener("click", () => { $("cases").value = f; openCase(f); });
  }
  const d = doc.cancelled;
  $("batch-status").textContent = d ? `cancelled after ${d.done} of ${d.asked} case files` : `${doc.files} case files, ${doc.records.length} records`;
}

async function cancelBatch() {
  if (state.batch) await api("POST", "/api/study/cancel", { id: state.batch.id });
}

async function cancelStudy() {
  if (!state.study) return;
  await api("POST", "/api/study/cancel", { id: state.study.id });
}

function summary(a) {
  const d = a.document, best = d && d.best;
  const s = $("summary");
  if (a.question === "reconstruction" && best) {
    s.textContent = (a.live ? "live (refined from the last answer; the whole search when you let go): " : "") + `chi-square ${best.chi_square.toFixed(3)} with ${best.degrees_of_freedom} dof, ` +
      `p = ${best.p_value.toFixed(4)}; e ${best.e.toFixed(3)}, mu ${best.mu.toFixed(3)}` +
      (d.status !== "found" ? ` — ${d.status}: ${d.reason || ""}` : "");
  } else if (a.question === "reconstruction") {
    s.textContent = `${d.status}: ${d.reason || ""}`;
  } else if (a.question === "solve") {
    s.textContent = "solved from its coefficients (pim solve): both run-outs from its separation";
  } else {
    s.textContent = "an impact fit (no scene evidence to reconstruct from)";
  }
  $("table").textContent = a.table;
}

// A piece of evidence disagrees with the answer when one of its residuals lies more than two
// standard deviations from it.
const DISAGREES = 2;

// The pieces of evidence, each with a switch: off, the answer is the case without it (the file
// keeps it). Beside each its residual farthest from the answer, in standard deviations.
function evidence(a) {
  const t = $("evidence");
  t.innerHTML = "";
  $("evidence-box").hidden = !a.pieces || a.pieces.length === 0;
  for (const p of a.pieces || []) {
    const r = t.insertRow();
    r.className = "piece";
    r.dataset.name = p.name;
    if (p.off) r.classList.add("off");
    if (p.z != null && Math.abs(p.z) > DISAGREES) r.classList.add("disagrees");
    const box = document.createElement("input");
    box.type = "checkbox"; box.checked = !p.off;
    box.setAttribute("aria-label", `use ${p.name}`);
    box.addEventListener("change", () => switchPiece(p.name, box.checked));
    r.insertCell().appendChild(box);
    r.insertCell().textContent = p.name;
    const z = r.insertCell();
    z.className = "z";
    z.textContent = p.off ? "off" : p.z == null ? "-" : `${p.z.toFixed(2)} σ`;
  }
  consistency(a);
}

function switchPiece(name, on) {
  state.off = on ? state.off.filter((n) => n !== name) : [...state.off, name];
  solve();
}

// The consistency table of a refused or poorly fitting answer: the reconstruction with each
// piece (or pair) left out; a row's button switches those pieces off.
function consistency(a) {
  const box = $("consistency");
  box.innerHTML = "";
  const c = a.document && a.document.consistency;
  if (!c) return;
  const u = a.plan.speed_metres || 1;
  const p = document.createElement("p");
  p.textContent = c.summary;
  box.appendChild(p);
  const t = document.createElement("table");
  t.id = "consistency-table";
  const head = t.insertRow();
  for (const h of ["left out", "chi²", "p", `v1 ${a.plan.speed_label}`, `v2 ${a.plan.speed_label}`, ""]) {
    const th = document.createElement("th"); th.textContent = h; head.appendChild(th);
  }
  for (const row of [c.all, ...c.rows]) {
    const r = t.insertRow();
    if (row.consistent) r.classList.add("consistent");
    const speed = (v) => (v == null ? "-" : (v / u).toFixed(2));
    const cells = [row.left_out.length ? row.left_out.join(" + ") : "nothing",
      row.chi_square == null ? row.status : row.chi_square.toFixed(2),
      row.p_value == null ? "-" : row.p_value.toFixed(3),
      speed(row.speed_at_contact[0]), speed(row.speed_at_contact[1])];
    for (const c of cells) r.insertCell().textContent = c;
    const td = r.insertCell();
    if (row.left_out.length) {
      const b = document.createElement("button");
      b.textContent = "off";
      b.title = `the answer without ${row.left_out.join(" and ")}`;
      b.addEventListener("click", () => { state.off = row.left_out.slice(); solve(); });
      td.appendChild(b);
    }
  }
  box.appendChild(t);
}

// How the plan shows a piece of evidence (found by what it is: kind, vehicle, index):
// switched off, disagreeing (with its residual), or neither.
function pieceLook(kind, vehicle, index) {
  const p = ((state.answer && state.answer.pieces) || []).find(
    (x) => x.id.kind === kind && x.id.vehicle === vehicle && (x.id.index ?? null) === (index ?? null));
  if (!p) return { cls: "" };
  if (p.off) return { cls: " off" };
  if (p.z != null && Math.abs(p.z) > DISAGREES) return { cls: " disagrees", z: p.z };
  return { cls: "", z: p.z };
}

function bounds(plan) {
  const all = [];
  for (const v of plan.vehicles) {
    all.push(...v.contact, ...v.rest, ...v.path);
    if (v.given_rest) all.push(...v.given_rest.outline);
    for (const m of v.marks) all.push([m[0], m[1]]);
    if (v.skid && v.cg) {
      const t = (v.heading * Math.PI) / 180;
      all.push([v.cg[0] - v.skid * Math.cos(t), v.cg[1] - v.skid * Math.sin(t)]);
    }
  }
  for (const s of plan.survey || []) all.push(s.at);
  if (plan.impact) all.push(plan.impact.centre);
  const b = plan.background, size = b && state.sizes[b.image];
  if (size) {
    // The image's corners on the page.
    const r = (b.rotation * Math.PI) / 180, [u1, v1] = b.pixels[0];
    for (const [u, v] of [[0, 0], [size[0], 0], [0, size[1]], [size[0], size[1]]]) {
      const du = (u - u1) * b.per_pixel, dv = (v - v1) * b.per_pixel;
      all.push([b.at[0] + Math.cos(r) * du + Math.sin(r) * dv, b.at[1] + Math.sin(r) * du - Math.cos(r) * dv]);
    }
  }
  if (!all.length) return { x: -10, y: -10, w: 20, h: 20 };
  const hs = all.map((p) => p[0]), vs = all.map((p) => -p[1]);
  const x0 = Math.min(...hs), x1 = Math.max(...hs), y0 = Math.min(...vs), y1 = Math.max(...vs);
  const pad = 0.08 * Math.max(x1 - x0, y1 - y0, 5);
  return { x: x0 - pad, y: y0 - pad, w: x1 - x0 + 2 * pad, h: y1 - y0 + 2 * pad };
}

function fitView() {
  if (!state.answer) return;
  const svg = $("plan"), b = bounds(state.answer.plan);
  const aspect = svg.clientWidth / Math.max(svg.clientHeight, 1);
  let { x, y, w, h } = b;
  if (w / h < aspect) { const w2 = h * aspect; x -= (w2 - w) / 2; w = w2; } else { const h2 = w / aspect; y -= (h2 - h) / 2; h = h2; }
  state.view = { x, y, w, h };
  render();
}

function pxPerUnit() {
  return $("plan").clientWidth / state.view.w;
}

function grid(g) {
  const v = state.view;
  const target = 80 / pxPerUnit(); // about 80 px between lines
  const p10 = 10 ** Math.floor(Math.log10(target));
  const step = [1, 2, 5, 10].map((k) => k * p10).find((s) => s >= target);
  for (let x = Math.ceil(v.x / step) * step; x <= v.x + v.w; x += step)
    el("line", { x1: x, y1: v.y, x2: x, y2: v.y + v.h, class: Math.abs(x) < step / 2 ? "axis" : "grid" }, g);
  for (let y = Math.ceil(v.y / step) * step; y <= v.y + v.h; y += step)
    el("line", { x1: v.x, y1: y, x2: v.x + v.w, y2: y, class: Math.abs(y) < step / 2 ? "axis" : "grid" }, g);
  const a = state.answer.plan;
  const along = a.frame === "sae" ? "x up, y to the right (SAE)" : "x to the right, y up";
  $("scale-note").textContent = `grid ${+step.toPrecision(3)} ${a.length_label}; ${along}`;
}

function render() {
  const a = state.answer;
  if (!a) return;
  if (a.sketch) {
    for (const id of ["speeds", "evidence", "consistency", "summary"]) $(id).innerHTML = "";
    $("summary").textContent = "not yet a case that answers: add its sections (Forms), place what the scene gives";
  } else {
    speedsTable(a);
    summary(a);
    evidence(a);
  }
  if (typeof speedHistory === "function") speedHistory(a);
  const bg = a.plan.background;
  $("lock-image").disabled = !bg;
  // The checkbox follows the answer only when the answer's lock changes: a render of an answer
  // that has not yet seen a click must not undo it.
  const locked = !!(bg && bg.locked);
  if (locked !== state.lockedDrawn) { $("lock-image").checked = locked; state.lockedDrawn = locked; }
  if (!state.view) { fitView(); return; }
  const svg = $("plan");
  const v = state.view;
  svg.setAttribute("viewBox", `${v.x} ${v.y} ${v.w} ${v.h}`);
  svg.innerHTML = "";
  drawBackground(svg);
  drawZones(svg, a.plan.zones || []);
  grid(el("g", {}, svg));
  drawSurvey(svg);
  drawClicks(svg);
  drawBands(svg);
  const r = 7 / pxPerUnit();
  for (const veh of a.plan.vehicles) {
    const g = el("g", { class: `v${veh.vehicle}`, "data-vehicle": veh.vehicle }, svg);
    for (const o of veh.every) el("polygon", { points: pts(o), class: "outline every" }, g);
    el("polyline", { points: pts(veh.path), class: "path" }, g);
    for (const t of veh.traces || []) el("polyline", { points: pts(t), class: "trace" }, g);
    el("polygon", { points: pts(veh.contact), class: "outline contact" }, g);
    if (veh.damage && veh.damage.length) el("polygon", { points: pts(veh.damage), class: "crush" }, g);
    el("polygon", { points: pts(veh.rest), class: "outline rest" }, g);
    veh.marks.forEach((m, i) => {
      const look = pieceLook("mark", veh.vehicle, i);
      const mg = el("g", { class: `evidence${look.cls}`, "data-piece": `vehicle${veh.vehicle} mark ${i + 1}` }, g);
      el("circle", { cx: m[0], cy: -m[1], r: m[2], class: "sigma" }, mg);
      el("path", { d: `M${m[0] - r} ${-m[1]}h${2 * r}M${m[0]} ${-m[1] - r}v${2 * r}`, class: "mark" }, mg);
      if (look.z != null) zLabel(mg, m[0] + r, m[1] + r, look.z);
      const mh = el("circle", { cx: m[0], cy: -m[1], r: r * 0.6, class: "handle mark-handle", "data-vehicle": veh.vehicle, "data-mark": i }, mg);
      const d = state.dragging;
      if (d && d.vehicle === veh.vehicle && d.mark === i) {
        Object.assign(d, { group: mg, base: [m[0], m[1]] });
        mh.classList.add("dragging");
        follow(d);
      }
      mh.addEventListener("pointerdown", (e) => startDrag(e, { vehicle: veh.vehicle, mark: i }, [m[0], m[1]], mg, mh));
    });
    if (veh.given_rest) {
      const gr = veh.given_rest;
      const look = pieceLook("rest", veh.vehicle);
      const moved = el("g", { class: `given-rest evidence${look.cls}`, "data-piece": `vehicle${veh.vehicle} rest` }, g);
      if (look.z != null) zLabel(moved, gr.at[0] + r, gr.at[1] + r, look.z);
      el("polygon", { points: pts(gr.outline), class: "outline given" }, moved);
      for (const t of gr.tyres || []) el("rect", { x: t[0] - r / 2, y: -t[1] - r / 2, width: r, height: r, class: "tyre" }, moved);
      // The one-sigma ellipse: its deviations along the page's axes.
      el("ellipse", { cx: gr.at[0], cy: -gr.at[1], rx: gr.sigma[0], ry: gr.sigma[1], class: "sigma" }, moved);
      const h = el("circle", { cx: gr.at[0], cy: -gr.at[1], r, class: "handle", "data-vehicle": veh.vehicle }, moved);
      const d = state.dragging;
      if (d && d.vehicle === veh.vehicle && d.mark == null) {
        Object.assign(d, { group: moved, base: gr.at });
        h.classList.add("dragging");
        follow(d);
      }
      h.addEventListener("pointerdown", (e) => startDrag(e, { vehicle: veh.vehicle }, gr.at, moved, h));
      if (gr.heading != null) restKnob(moved, veh.vehicle, gr);
    }
  }
  if (a.question === "reconstruction") drawContactHandles(svg, a);
  drawMotion(svg, a);
}

// The motion at the slider's time (none until the slider or Play is touched): each vehicle's
// outline there, filled, and the path its CG has travelled, over the plan.
function drawMotion(svg, a) {
  const m = a.plan.motion, bar = $("playback");
  bar.hidden = !m;
  if (!m) return;
  const slider = $("time");
  if (+slider.min !== m.start || +slider.max !== m.end) {
    Object.assign(slider, { min: m.start, max: m.end, step: "any" });
    if (state.playT == null) slider.value = m.end;
  }
  if (state.playT == null) { $("time-label").textContent = "time: drag, or Play"; return; }
  const t = Math.min(Math.max(state.playT, m.start), m.end);
  slider.value = t;
  const phase = t < 0 ? "before contact" : t === 0 ? "contact" : "run-out";
  $("time-label").textContent = `t = ${t.toFixed(2)} s (${phase})`;
  const g = el("g", { class: "motion" }, svg);
  for (const tr of m.vehicles) {
    const vg = el("g", { class: `v${tr.vehicle}`, "data-vehicle": tr.vehicle }, g);
    const { outline, travelled } = trackAt(tr, t);
    el("polyline", { points: pts(travelled), class: "path travelled" }, vg);
    el("polygon", { points: pts(outline), class: "outline now" }, vg);
  }
}

// A track at time `t`: its outline (linear between the samples, held before the first and
// after the last) and its CG's path up to then.
function trackAt(tr, t) {
  const n = tr.times.length;
  let k = 0;
  while (k + 1 < n && tr.times[k + 1] <= t) k++;
  if (t <= tr.times[0] || k + 1 >= n) {
    const i = t <= tr.times[0] ? 0 : n - 1;
    return { outline: tr.outlines[i], travelled: tr.cg.slice(0, i + 1) };
  }
  const w = (t - tr.times[k]) / (tr.times[k + 1] - tr.times[k]);
  const mix = (p, q) => p.map((x, j) => x + w * (q[j] - x));
  const outline = tr.outlines[k].map((p, j) => mix(p, tr.outlines[k + 1][j]));
  return { outline, travelled: [...tr.cg.slice(0, k + 1), mix(tr.cg[k], tr.cg[k + 1])] };
}

// Play from the slider's time (from the start once at the end) at the chosen pace; Pause stops.
function togglePlay() {
  const m = state.answer && state.answer.plan.motion;
  if (!m) return;
  if (state.playing) { state.playing = false; $("play").textContent = "Play"; return; }
  if (state.playT == null || state.playT >= m.end) state.playT = m.start;
  state.playing = true;
  $("play").textContent = "Pause";
  let last = performance.now();
  const step = (now) => {
    if (!state.playing) return;
    const motion = state.answer && state.answer.plan.motion;
    if (!motion) { state.playing = false; return; }
    state.playT += ((now - last) / 1000) * +$("pace").value;
    last = now;
    if (state.playT >= motion.end) { state.playT = motion.end; state.playing = false; $("play").textContent = "Play"; }
    render();
    if (state.playing) requestAnimationFrame(step);
  };
  requestAnimationFrame(step);
}

// The motion as an animated SVG (SMIL): the plan as it stands under both vehicles' outlines,
// each moving through its samples at true time, and the time shown; it plays on a loop.
function exportMotion() {
  const m = state.answer && state.answer.plan.motion;
  if (!m) return;
  const saved = state.playT;
  state.playT = null;
  render();
  const svg = standalonePlan();
  state.playT = saved;
  render();
  const span = m.end - m.start;
  const key = (t) => ((t - m.start) / span).toFixed(5);
  for (const tr of m.vehicles) {
    const g = el("g", { class: `v${tr.vehicle}` }, svg);
    const times = [m.start, ...tr.times, m.end];
    const outlines = [tr.outlines[0], ...tr.outlines, tr.outlines[tr.outlines.length - 1]];
    const poly = el("polygon", { points: pts(outlines[0]), class: "outline now" }, g);
    el("animate", {
      attributeName: "points", dur: `${span}s`, repeatCount: "indefinite", calcMode: "linear",
      keyTimes: times.map(key).join(";"),
      values: outlines.map((o) => o.map(([h, v]) => `${h},${-v}`).join(" ")).join(";"),
    }, poly);
  }
  download(svg, "_motion");
}

// The ground's friction zones under everything else: each polygon shaded, its friction in the
// middle of its corners.
function drawZones(svg, zones) {
  const g = el("g", { class: "zones" }, svg);
  for (const z of zones) {
    const zg = el("g", { class: "zone" }, g);
    el("polygon", { points: pts(z.corners), class: "zone-area" }, zg);
    const mid = z.corners.reduce((m, c) => [m[0] + c[0] / z.corners.length, m[1] + c[1] / z.corners.length], [0, 0]);
    const t = el("text", { x: mid[0], y: -mid[1], class: "zone-label", style: `font-size: ${12 / pxPerUnit()}px` }, zg);
    t.textContent = `friction ${+z.friction.toFixed(2)}`;
  }
}

// The study's bands: each vehicle's CG path from the velocities at separation of the study's
// first draws (for the text, evidence and units the study was drawn with), under the answer.
function drawBands(svg) {
  const st = state.study;
  const r = st && st.report;
  if (!r || !r.bands || st.text !== state.text || st.off !== state.off.join("\n") || st.units !== state.units) return;
  const g = el("g", { class: "bands" }, svg);
  for (const b of r.bands) el("polyline", { points: pts(b.path), class: `band v${b.vehicle}` }, g);
}

// A residual beside a piece of evidence on the plan, in standard deviations.
function zLabel(g, h, v, z) {
  const far = Math.abs(z) > DISAGREES;
  const t = el("text", { x: h, y: -v, class: far ? "z-label" : "z-label near", style: `font-size: ${(far ? 13 : 11) / pxPerUnit()}px` }, g);
  t.textContent = `${z.toFixed(1)} σ`;
}

// The geometry at contact: each vehicle's CG (a square) and heading (a knob ahead of the
// nose), the impact centre (a diamond) and the crush surface's normal (a knob on a line from
// the centre). Dragging one edits the case text in its own form (POST /api/contact) and
// answers live; the whole answer comes on release.
function drawContactHandles(svg, a) {
  const px = pxPerUnit(), r = 6 / px;
  drawSkids(svg, a);
  const g = el("g", { class: "contact-handles" }, svg);
  for (const veh of a.plan.vehicles) {
    if (!veh.cg) continue;
    const vg = el("g", { class: `v${veh.vehicle}` }, g);
    const reach = Math.max(...veh.contact.map(([h, v]) => Math.hypot(h - veh.cg[0], v - veh.cg[1]))) + 16 / px;
    const t = (veh.heading * Math.PI) / 180;
    const knob = [veh.cg[0] + reach * Math.cos(t), veh.cg[1] + reach * Math.sin(t)];
    el("line", { x1: veh.cg[0], y1: -veh.cg[1], x2: knob[0], y2: -knob[1], class: "heading-line" }, vg);
    const sq = el("rect", { x: veh.cg[0] - r, y: -veh.cg[1] - r, width: 2 * r, height: 2 * r, class: "handle cg-handle", "data-vehicle": veh.vehicle }, vg);
    sq.addEventListener("pointerdown", (e) => dragGeometry(e, sq, (p) => ({ vehicle: veh.vehicle, at: p })));
    const kn = el("circle", { cx: knob[0], cy: -knob[1], r: r * 0.8, class: "handle heading-handle", "data-vehicle": veh.vehicle }, vg);
    kn.addEventListener("pointerdown", (e) => dragGeometry(e, kn, (p) => ({
      vehicle: veh.vehicle, heading: (Math.atan2(p[1] - veh.cg[1], p[0] - veh.cg[0]) * 180) / Math.PI,
    })));
  }
  const imp = a.plan.impact;
  if (!imp) return;
  const c = imp.centre, n = (imp.normal * Math.PI) / 180, len = 42 / px;
  const end = [c[0] + len * Math.cos(n), c[1] + len * Math.sin(n)];
  el("line", { x1: c[0], y1: -c[1], x2: end[0], y2: -end[1], class: "normal-line" }, g);
  const dm = el("path", { d: `M${c[0]} ${-c[1] - r * 1.3}l${r * 1.3} ${r * 1.3}l${-r * 1.3} ${r * 1.3}l${-r * 1.3} ${-r * 1.3}z`, class: "handle centre-handle" }, g);
  dm.addEventListener("pointerdown", (e) => dragGeometry(e, dm, (p) => ({ centre: p })));
  const nk = el("circle", { cx: end[0], cy: -end[1], r: r * 0.8, class: "handle normal-handle" }, g);
  nk.addEventListener("pointerdown", (e) => dragGeometry(e, nk, (p) => ({
    normal: (Math.atan2(p[1] - c[1], p[0] - c[0]) * 180) / Math.PI,
  })));
}

// The knob that turns a rest given as its CG and heading: on a line from the CG along the
// heading, beyond the outline; dragged, the rest's heading follows the pointer about the CG.
function restKnob(g, vehicle, gr) {
  const px = pxPerUnit(), r = 6 / px;
  const reach = Math.max(...gr.outline.map(([h, v]) => Math.hypot(h - gr.at[0], v - gr.at[1]))) + 16 / px;
  const t = (gr.heading * Math.PI) / 180;
  const knob = [gr.at[0] + reach * Math.cos(t), gr.at[1] + reach * Math.sin(t)];
  el("line", { x1: gr.at[0], y1: -gr.at[1], x2: knob[0], y2: -knob[1], class: "heading-line" }, g);
  const kn = el("circle", { cx: knob[0], cy: -knob[1], r: r * 0.8, class: "rest-knob", "data-vehicle": vehicle }, g);
  kn.addEventListener("pointerdown", (e) => dragGeometry(e, kn, (p) => ({
    vehicle, rest_heading: (Math.atan2(p[1] - gr.at[1], p[0] - gr.at[0]) * 180) / Math.PI,
  })));
}

// Each vehicle's skid up to contact ([pre_impact.vehicleN] skid): a line that long behind
// its CG at contact, against its heading, with its length beside it.
function drawSkids(svg, a) {
  const px = pxPerUnit();
  for (const veh of a.plan.vehicles) {
    if (!veh.skid || !veh.cg) continue;
    const t = (veh.heading * Math.PI) / 180;
    const from = [veh.cg[0] - veh.skid * Math.cos(t), veh.cg[1] - veh.skid * Math.sin(t)];
    const g = el("g", { class: `skid v${veh.vehicle}`, "data-vehicle": veh.vehicle }, svg);
    el("line", { x1: from[0], y1: -from[1], x2: veh.cg[0], y2: -veh.cg[1], class: "skid-line" }, g);
    const label = el("text", { x: from[0], y: -from[1], class: "skid-label", style: `font-size: ${12 / px}px` }, g);
    label.textContent = `skid ${veh.skid.toFixed(1)} ${a.plan.length_label}`;
  }
}

// A skid set by a click behind a vehicle (the Skid tool): the vehicle whose line behind its CG
// passes nearest, the length the click's distance behind the CG along its heading, both
// asked to confirm.
async function placeSkid(click) {
  const p = [click.x, -click.y];
  let best = null;
  for (const v of state.answer.plan.vehicles) {
    if (!v.cg) continue;
    const t = (v.heading * Math.PI) / 180, dx = v.cg[0] - p[0], dy = v.cg[1] - p[1];
    const along = dx * Math.cos(t) + dy * Math.sin(t), across = Math.abs(-dx * Math.sin(t) + dy * Math.cos(t));
    if (along > 0 && (!best || across < best.across)) best = { vehicle: v.vehicle, along, across };
  }
  if (!best) { status("click behind a vehicle's CG at contact: no skid placed"); render(); return; }
  const answer = window.prompt(`Skid of vehicle (1 or 2) up to contact, its length (${state.answer.plan.length_label}):`,
    `${best.vehicle} ${best.along.toFixed(2)}`);
  const [vehicle, length] = (answer || "").trim().split(/[\s,]+/).map(Number);
  if (!(vehicle === 1 || vehicle === 2) || !(length > 0)) { status("no skid placed"); render(); return; }
  await edited("/api/skid", { vehicle, length });
}

// A drag of a contact handle: the handle follows the pointer; the change the pointer's page
// point makes (`changeAt`) is sent live while the server keeps up, and once more on release.
function dragGeometry(e, handle, changeAt) {
  const svg = $("plan");
  const from = svgPoint(e);
  let last = null;
  grab(e, { geometry: true }, (ev) => {
    const p = svgPoint(ev);
    last = changeAt([p.x, -p.y]);
    for (const h of svg.querySelectorAll(".dragging")) h.setAttribute("transform", `translate(${p.x - from.x} ${p.y - from.y})`);
    if (!state.busy && !state.inFlight) {
      state.inFlight = true;
      editQueued(last, true).finally(() => { state.inFlight = false; });
    }
  }, () => {
    const s = last && last.centre && surveySnap(last.centre);
    if (s) editQueued({ centre: s.at, point: s.id }, false);
    else if (last) editQueued(last, false); else render();
  }, handle);
}

// Edits of the geometry run one after the other, as moves of a rest do.
function editQueued(change, live) {
  state.moves = (state.moves || 0) + 1;
  state.moving = (state.moving || Promise.resolve())
    .then(() => edited("/api/contact", change, live))
    .finally(() => { state.moves -= 1; });
  return state.moving;
}

// The case's background image: pixel (u, v) lands at at + per_pixel R(rotation) ((u, v) -
// pixels[0]) on the page (the SVG's y is the page's down, as the image's v).
function backgroundTransform(b) {
  const [u1, v1] = b.pixels[0];
  return `translate(${b.at[0]} ${-b.at[1]}) rotate(${-b.rotation}) scale(${b.per_pixel}) translate(${-u1} ${-v1})`;
}

function drawBackground(svg) {
  const b = state.answer.plan.background;
  if (!b) return;
  const size = state.sizes[b.image];
  const href = `/api/image?path=${encodeURIComponent(b.image)}`;
  if (!size) {
    const img = new Image();
    // Once its size is known the scene is fitted again, the image in it.
    img.onload = () => { state.sizes[b.image] = [img.naturalWidth, img.naturalHeight]; state.view = null; render(); };
    img.src = href;
    return;
  }
  el("image", {
    href, x: 0, y: 0, width: size[0], height: size[1], class: "background",
    preserveAspectRatio: "none", transform: backgroundTransform(b),
  }, svg);
  if (state.tool !== "move-image" || b.locked) return;
  // Turning: a knob on a line from the image's first scale point along its rotation.
  const px = pxPerUnit(), t = (b.rotation * Math.PI) / 180, len = 70 / px;
  const end = [b.at[0] + len * Math.cos(t), b.at[1] + len * Math.sin(t)];
  el("line", { x1: b.at[0], y1: -b.at[1], x2: end[0], y2: -end[1], class: "normal-line" }, svg);
  const knob = el("circle", { cx: end[0], cy: -end[1], r: 6 / px, class: "handle rotate-image" }, svg);
  knob.addEventListener("pointerdown", (e) => dragImage(e, (p) => {
    b.rotation = (Math.atan2(p[1] - b.at[1], p[0] - b.at[0]) * 180) / Math.PI;
    return { rotation: b.rotation };
  }));
}

// A drag of the background (Move image): drawn where the pointer takes it, written into
// [background] on release.
function dragImage(e, changeAt) {
  let last = null;
  grab(e, { image: true }, (ev) => { const p = svgPoint(ev); last = changeAt([p.x, -p.y]); render(); }, () => {
    if (last) changeBackground(last); else render();
  });
}

// A point of the page's SVG on the background image, pixels.
function toPixels(b, p) {
  const [u1, v1] = b.pixels[0], r = (b.rotation * Math.PI) / 180;
  const dx = (p.x - b.at[0]) / b.per_pixel, dy = (p.y + b.at[1]) / b.per_pixel;
  return [u1 + Math.cos(r) * dx - Math.sin(r) * dy, v1 + Math.sin(r) * dx + Math.cos(r) * dy];
}

// The clicks of a tool and the last measurement, on top of the plan.
function drawClicks(svg) {
  const r = 5 / pxPerUnit();
  const pts = state.clicks.length ? state.clicks : state.measured ? state.measured.points : [];
  for (const p of pts) el("circle", { cx: p.x, cy: p.y, r, class: "click" }, svg);
  if (["zone", "trace", "tyres"].includes(state.tool) && pts.length > 1) el("polyline", { points: pts.map((p) => `${p.x},${p.y}`).join(" "), class: "click" }, svg);
  else if (pts.length === 2) el("line", { x1: pts[0].x, y1: pts[0].y, x2: pts[1].x, y2: pts[1].y, class: "click" }, svg);
}

function useTool(tool) {
  const bg = state.answer && state.answer.plan.background;
  if ((tool === "scale" || tool === "move-image") && !bg) {
    status("no background: choose one first");
    return;
  }
  if (tool === "move-image" && bg.locked && state.tool !== tool) {
    status("the background is locked: untick locked to move or turn it");
    return;
  }
  state.tool = state.tool === tool ? null : tool;
  state.clicks = [];
  $("plan").classList.toggle("picking", !!state.tool);
  status(!state.tool ? "" : state.tool === "mark" ? "click where the tyre mark lies"
    : state.tool === "rest" ? "click where a vehicle's CG came to rest (a survey point's square takes its place and id)"
    : state.tool === "skid" ? "click where the skid begins, behind the vehicle"
    : state.tool === "zone" ? "click the zone's corners in order, the first again to close it"
    : state.tool === "trace" ? "click points along the tyre's mark in order, the last again to end"
    : state.tool === "tyres" ? "click the tyres or corners measured at rest, the last again to end"
    : state.tool === "move-image" ? "drag the image to move it, its knob to turn it; Move image again to end"
    : "click two points on the plan");
  $("move-image").classList.toggle("active", state.tool === "move-image");
  render();
}

async function toolClick(e) {
  if (!state.tool || state.tool === "move-image") return;
  if (state.tool === "zone") { await zoneClick(svgPoint(e)); return; }
  if (state.tool === "trace") { await traceClick(svgPoint(e)); return; }
  if (state.tool === "tyres") { await tyresClick(svgPoint(e)); return; }
  state.clicks.push(svgPoint(e));
  render();
  // A mark, a rest or a skid takes one click, a distance two; then the tool ends.
  if (state.clicks.length < (["mark", "skid", "rest"].includes(state.tool) ? 1 : 2)) return;
  const clicks = state.clicks, tool = state.tool;
  state.tool = null; state.clicks = [];
  $("plan").classList.remove("picking");
  if (tool === "mark") { await placeMark(clicks[0]); return; }
  if (tool === "rest") { await placeRest(clicks[0]); return; }
  if (tool === "skid") { await placeSkid(clicks[0]); return; }
  const [a, b] = clicks;
  const label = state.answer.plan.length_label;
  if (tool === "measure") {
    const d = Math.hypot(b.x - a.x, b.y - a.y);
    state.measured = { distance: d, points: [a, b] };
    status(`measured ${d.toFixed(2)} ${label}`);
    render();
    return;
  }
  const bg = state.answer.plan.background;
  const answer = window.prompt(`The distance between the two points (${label}):`, bg.distance.toFixed(2));
  const distance = answer === null ? NaN : +answer;
  if (!(distance > 0)) { status("scale not set"); render(); return; }
  await changeBackground({ pixels: [toPixels(bg, a), toPixels(bg, b)], distance, at: [a.x, -a.y] });
}

// The vehicle whose path passes nearest the page point p (page coordinates).
function nearestVehicle(p) {
  let best = { vehicle: 1, d: Infinity };
  for (const v of state.answer.plan.vehicles) {
    for (const [h, u] of v.path) {
      const d = Math.hypot(h - p[0], u - p[1]);
      if (d < best.d) best = { vehicle: v.vehicle, d };
    }
  }
  return best.vehicle;
}

// A tyre mark where the plan was clicked: the vehicle (the one whose path passes nearest) and
// the mark's standard deviation asked, then written into the TOML (not saved) and solved.
async function placeMark(click) {
  const s = surveySnap([click.x, -click.y]);
  const at = s ? s.at : [click.x, -click.y];
  const who = askWhoseMark(s ? `Tyre mark on survey point ${s.id}` : "Tyre mark", "a point of the CG's path", at, "cg");
  if (!who) { status("no mark placed"); render(); return; }
  await edited("/api/mark", { at, ...who, point: s ? s.id : undefined });
}

// Whose mark at the page point `at` (`what`: its kind; `cg`: what a CG mark is), asked: the
// vehicle (the one whose path passes nearest offered), the standard deviation (0.15 m in the
// display unit offered) and the tyre that left it (`wheel` offered); null when not given.
function askWhoseMark(what, cg, at, wheel) {
  const plan = state.answer.plan;
  const sigma = Math.round((0.15 / plan.metres) * 100) / 100;
  const answer = window.prompt(`${what}: the vehicle (1 or 2), its standard deviation (${plan.length_label}) `
    + `and the tyre that left it (fl, fr, rl, rr for front left ... rear right; cg: ${cg}):`,
    `${nearestVehicle(at)} ${sigma} ${wheel === "cg" ? "cg" : "fl"}`);
  const words = (answer || "").trim().toLowerCase().split(/[\s,]+/);
  const [vehicle, s] = words.slice(0, 2).map(Number);
  const tyres = { fl: "front_left", fr: "front_right", rl: "rear_left", rr: "rear_right" };
  if (!(vehicle === 1 || vehicle === 2) || !(s > 0)) return null;
  return { vehicle, sigma: s, wheel: tyres[words[2]] || words[2] || wheel };
}

// A point of a traced mark: added, or with two or more a click within 8 screen pixels of the
// last ends it; the vehicle, the standard deviation and the tyre asked, then written into the
// TOML (not saved) and solved.
// A click of a tool that takes two or more points, the last clicked again (within 8 screen
// pixels) to end: the points once ended (the tool then off), else null.
function pointsEnded(p) {
  const c = state.clicks, near = 8 / pxPerUnit(), last = c[c.length - 1];
  if (!(c.length >= 2 && Math.hypot(p.x - last.x, p.y - last.y) <= near)) {
    c.push(p);
    render();
    return null;
  }
  state.tool = null; state.clicks = [];
  $("plan").classList.remove("picking");
  return c;
}

async function traceClick(p) {
  const c = pointsEnded(p);
  if (!c) return;
  const points = c.map((q) => [q.x, -q.y]);
  const who = askWhoseMark("Traced mark", "the CG's path", points[0], "front_left");
  if (!who) { status("no trace placed"); render(); return; }
  await edited("/api/trace", { points, ...who });
}

// A corner of a friction zone: added, or with three or more a click within 8 screen pixels of
// the first closes it; its friction (and a name) asked, then written into the TOML (not saved).
async function zoneClick(p) {
  const c = state.clicks, near = 8 / pxPerUnit();
  if (!(c.length >= 3 && Math.hypot(p.x - c[0].x, p.y - c[0].y) <= near)) {
    c.push(p);
    render();
    return;
  }
  state.tool = null; state.clicks = [];
  $("plan").classList.remove("picking");
  const answer = window.prompt("Friction zone: its friction, and a name if you like (e.g. 0.45 grass verge):", "0.45");
  const [first, ...rest] = (answer || "").trim().split(/\s+/);
  const friction = +first;
  if (!(friction > 0)) { status("no zone placed"); render(); return; }
  const corners = c.map((q) => [q.x, -q.y]);
  await edited("/api/zone", { corners, friction, name: rest.join(" ") || undefined });
}

async function changeBackground(change) {
  await edited("/api/background", change);
}

// Asks the server for the text with an edit (`url`, `change`), shows it and solves it (`live`:
// following the last answer, while a handle is dragged); a refused edit is shown and leaves
// the text as it was.
async function edited(url, change, live = false) {
  try {
    const { data } = await api("POST", url, { path: state.path, text: state.text, units: state.units, ...change });
    state.text = data.text;
    $("toml").value = data.text;
    await solve(live);
  } catch (e) {
    $("error").hidden = false;
    $("error").textContent = e.message;
    render();
  }
}

// Chooses an image of the folder for the background: placed at the origin, 20 pixels to the
// length unit until its scale is set.
async function chooseBackground() {
  const list = state.images.join(", ") || "(none in this folder)";
  const image = window.prompt(`An image of the folder served for the background: ${list}`, state.images[0] || "");
  if (!image) return;
  const folder = state.path.includes("/") ? state.path.replace(/[^/]*$/, "") : "";
  const relative = image.startsWith(folder) ? image.slice(folder.length) : image;
  await changeBackground({ image: relative, pixels: [[0, 0], [20, 0]], distance: 1, at: [0, 0] });
}

// A photo of the folder made into a plan: the photo shown over the plan, each click on it a
// point whose place on the scene is asked (x y in the case's frame and the display unit), then
// Rectify writes the plan-view image beside the photo and sets it as the background.
async function startPhotoPlan() {
  const photos = state.images.filter((i) => /\.(png|jpe?g)$/i.test(i));
  const photo = window.prompt(`A photo of the folder to make into a plan: ${photos.join(", ") || "(none listed)"}`, photos[0] || "");
  if (!photo) return;
  state.photo = { path: photo, points: [] };
  for (const m of [...document.querySelectorAll(".photo-point")]) m.remove();
  $("photo-img").src = `/api/image?path=${encodeURIComponent(photo)}`;
  $("photo-pane").hidden = false;
  photoBar();
}

function photoBar() {
  const n = state.photo ? state.photo.points.length : 0;
  $("photo-count").textContent = `${n} point${n === 1 ? "" : "s"} (four or more, no three in line): click a point of the ground whose place you know`;
  $("photo-rectify").disabled = n < 4;
}

function photoClick(e) {
  if (!state.photo) return;
  const img = $("photo-img"), r = img.getBoundingClientRect();
  const pixel = [(e.clientX - r.left) * img.naturalWidth / r.width, (e.clientY - r.top) * img.naturalHeight / r.height];
  const plan = state.answer.plan;
  const answer = window.prompt(`Where this point lies on the scene: x y (${plan.length_label}, the case's frame)`, "");
  const xy = (answer || "").trim().split(/[\s,]+/).map(Number);
  if (xy.length !== 2 || !xy.every(Number.isFinite)) { status("no point taken"); return; }
  state.photo.points.push({ pixel, at: xy });
  const m = document.createElement("div");
  m.className = "photo-point";
  m.style.left = `${e.clientX - r.left + img.offsetLeft}px`;
  m.style.top = `${e.clientY - r.top + img.offsetTop}px`;
  m.textContent = state.photo.points.length;
  $("photo-wrap").appendChild(m);
  photoBar();
}

function closePhoto() {
  state.photo = null;
  $("photo-pane").hidden = true;
}

async function rectifyPhoto() {
  const p = state.photo;
  try {
    const { data } = await api("POST", "/api/photo-plan", { path: state.path, text: state.text, units: state.units || undefined, photo: p.path, points: p.points });
    closePhoto();
    state.photoResult = data;
    if (!state.images.includes(data.image)) state.images.push(data.image);
    state.text = data.text;
    $("toml").value = data.text;
    await solve();
    const worst = Math.max(...data.residuals);
    status(`${data.image} written (${data.size[0]} by ${data.size[1]} pixels); the points met within ${worst.toFixed(2)} ${state.answer.plan.length_label}`);
  } catch (e) {
    $("error").hidden = false;
    $("error").textContent = e.message;
    status("not rectified");
  }
}

function svgPoint(e) {
  const svg = $("plan");
  const p = svg.createSVGPoint(); p.x = e.clientX; p.y = e.clientY;
  return p.matrixTransform(svg.getScreenCTM().inverse());
}

// A drag from the press `e` on the plan: `move(ev)` at each move of the pointer once it has left
// the pixel it was pressed on, `end(moved)` once when it is let go or the browser cancels it.
// The browser's own moves under a still pointer (after the plan is drawn again beneath it) are
// not moves: a press and release in place drags nothing.
function capture(e, move, end) {
  const svg = $("plan");
  svg.setPointerCapture(e.pointerId);
  let moved = false;
  const go = (ev) => {
    moved ||= Math.hypot(ev.clientX - e.clientX, ev.clientY - e.clientY) >= 0.5;
    if (moved) move(ev);
  };
  const up = () => {
    svg.removeEventListener("pointermove", go);
    svg.removeEventListener("pointerup", up);
    svg.removeEventListener("pointercancel", up);
    end(moved);
  };
  svg.addEventListener("pointermove", go);
  svg.addEventListener("pointerup", up);
  svg.addEventListener("pointercancel", up);
}

// Whether a click tool (a mark, a skid, the scale, a measure) is waiting for its click: the
// plan's handles then leave the press to it.
function picking() {
  return !!state.tool && state.tool !== "move-image";
}

// [`capture`] of a handle's press as the drag `dragging` (`state.dragging` until it ends, the
// `handle`, if given, drawn as dragged): the plan under it neither pans nor has its text
// selected; `end(moved, dragging)` once the drag is cleared. Nothing is grabbed while a click
// tool waits for its click.
function grab(e, dragging, move, end, handle) {
  if (picking()) return;
  e.stopPropagation();
  e.preventDefault();
  if (handle) handle.classList.add("dragging");
  state.dragging = dragging;
  capture(e, move, (moved) => {
    const d = state.dragging;
    state.dragging = null;
    end(moved, d);
  });
}

// A drag of a rest (`target` {vehicle}) or a tyre mark ({vehicle, mark}): the handle follows the
// pointer; the case is moved and solved again whenever the last answer is in (while dragging),
// and once more on release.
function startDrag(e, target, at, group, handle) {
  const from = svgPoint(e);
  grab(e, { ...target, group, base: at, to: at }, (ev) => {
    const p = svgPoint(ev);
    const d = state.dragging;
    d.to = [at[0] + p.x - from.x, at[1] - (p.y - from.y)];
    follow(d);
    if (!state.busy && !state.inFlight) {
      state.inFlight = true;
      moveTo(target, d.to, true).finally(() => { state.inFlight = false; });
    }
  }, (moved, d) => {
    // A rest given by tyre points moves whole: its tyres are placed on survey points in the TOML.
    const veh = state.answer.plan.vehicles.find((v) => v.vehicle === target.vehicle);
    const byTyres = target.mark == null && veh && veh.given_rest && (veh.given_rest.tyres || []).length;
    const s = moved && !byTyres && surveySnap(d.to);
    if (s) moveTo({ ...target, point: s.id }, s.at);
    else if (moved) moveTo(target, d.to); else render();
  }, handle);
}

// The dragged rest drawn where the pointer is (its group drawn at `base`).
function follow(d) {
  d.group.setAttribute("transform", `translate(${d.to[0] - d.base[0]} ${-(d.to[1] - d.base[1])})`);
}

// Moves run one after the other (each edits the text the one before left).
function moveTo(target, at, live = false) {
  state.moves = (state.moves || 0) + 1;
  state.moving = (state.moving || Promise.resolve())
    .then(() => move(target, at, live))
    .finally(() => { state.moves -= 1; });
  return state.moving;
}

async function move(target, at, live) {
  try {
    const { data } = await api("POST", "/api/move", { path: state.path, text: state.text, ...target, at, units: state.units });
    state.text = data.text;
    $("toml").value = data.text;
    await solve(live);
  } catch (e) {
    $("error").hidden = false;
    $("error").textContent = e.message;
  }
}

function panAndZoom() {
  const svg = $("plan");
  svg.addEventListener("wheel", (e) => {
    if (!state.view) return;
    e.preventDefault();
    const p = svgPoint(e), k = Math.exp(e.deltaY * 0.0015), v = state.view;
    state.view = { x: p.x - (p.x - v.x) * k, y: p.y - (p.y - v.y) * k, w: v.w * k, h: v.h * k };
    render();
  }, { passive: false });
  svg.addEventListener("click", toolClick);
  svg.addEventListener("pointerdown", (e) => {
    if (state.tool === "move-image" && state.view && !state.dragging) {
      const b = state.answer.plan.background, from = svgPoint(e), at0 = b.at.slice();
      dragImage(e, (p) => {
        b.at = [at0[0] + p[0] - from.x, at0[1] + p[1] + from.y];
        return { at: b.at };
      });
      return;
    }
    if (!state.view || state.dragging || state.tool) return;
    svg.classList.add("panning");
    const start = { x: e.clientX, y: e.clientY, view: { ...state.view } };
    capture(e, (ev) => {
      const k = state.view.w / svg.clientWidth;
      state.view = { ...start.view, x: start.view.x - (ev.clientX - start.x) * k, y: start.view.y - (ev.clientY - start.y) * k };
      render();
    }, () => svg.classList.remove("panning"));
  });
}

// Saves the text over the version of the file it was made from. The server refuses (409)
// when the file changed on disk meanwhile (another editor, another page, pim set): nothing is
// lost, and the page offers to reload the file, to compare the two, or to save its own text
// over the file as it is now.
async function save(over) {
  try {
    const version = over || state.version;
    const create = !!state.fresh;
    const { data } = await api("POST", "/api/save", { path: state.path, text: state.text, version, create });
    state.saved = state.text; state.version = data.version; state.fresh = false;
    if (create) await listCases(state.path);
    state.conflict = null; $("conflict").hidden = true;
    status(`saved ${data.saved} (${data.bytes} bytes)`);
  } catch (e) {
    if (e.status === 409 && e.data && e.data.conflict) { showConflict(e.data.conflict, e.message); status("not saved: changed on disk"); return; }
    $("error").hidden = false;
    $("error").textContent = e.message;
    status("not saved");
  }
}

// The file changed on disk (`disk`: its text and version now): said, with the three ways on.
function showConflict(disk, message) {
  state.conflict = disk;
  $("conflict-message").textContent = message ||
    `${state.path} changed on disk since it was opened (by another editor, another page or pim set).`;
  $("conflict-compare").hidden = true;
  $("conflict").hidden = false;
}

// The two texts side by side, each line that differs marked.
function compareConflict() {
  const mine = state.text.split("\n"), disk = state.conflict.text.split("\n");
  for (const [id, lines, other] of [["conflict-disk", disk, mine], ["conflict-mine", mine, disk]]) {
    const pre = $(id);
    pre.innerHTML = "";
    const others = new Set(other);
    for (const line of lines) {
      const span = document.createElement("span");
      span.textContent = line + "\n";
      if (!others.has(line)) span.className = "changed";
      pre.appendChild(span);
    }
  }
  $("conflict-compare").hidden = false;
}

async function reloadFromDisk(disk = state.conflict) {
  state.text = state.saved = disk.text; state.version = disk.version;
  state.conflict = null; $("conflict").hidden = true;
  $("toml").value = disk.text;
  await solve();
  status("reloaded from disk");
}

// On coming back to the page: a file changed on disk meanwhile is reloaded when the page
// holds no unsaved change, and said (as a conflict) when it does.
async function checkDisk() {
  if (!state.path || state.conflict || state.opening) return;
  let data;
  try { ({ data } = await api("GET", `/api/case?path=${encodeURIComponent(state.path)}`)); } catch (e) { return; }
  if (data.version === state.version) return;
  if (state.text === state.saved) {
    await reloadFromDisk({ text: data.text, version: data.version });
    status("reloaded: the file changed on disk");
  } else {
    showConflict({ text: data.text, version: data.version });
  }
}

// The report of the text as it stands (saved or not), in a new tab.
// The plan for CAD (`scene.dxf` of `pim fit --out`) of the page's text, in its display units,
// downloaded as the case's name.
async function exportDxf() {
  status("drawing the plan for CAD…");
  const res = await fetch("/api/dxf", {
    method: "POST", headers: { "content-type": "application/json" },
    body: JSON.stringify({ path: state.path, text: state.text, units: state.units || undefined }),
  });
  if (!res.ok) {
    const e = await res.json().catch(() => ({ error: res.statusText }));
    $("error").hidden = false; $("error").textContent = e.error;
    status("no DXF");
    return;
  }
  const a = document.createElement("a");
  a.href = URL.createObjectURL(await res.blob());
  a.download = `${(state.path || "plan").replace(/\.toml$/, "").split("/").pop()}.dxf`;
  document.body.appendChild(a); a.click(); a.remove();
  status("plan for CAD written");
}

async function openReport() {
  const tab = window.open("", "_blank");
  status("making the report…");
  const res = await fetch("/api/report", {
    method: "POST", headers: { "content-type": "application/json" },
    body: JSON.stringify({ path: state.path, text: state.text }),
  });
  if (!res.ok) {
    const e = await res.json().catch(() => ({ error: res.statusText }));
    if (tab) tab.close();
    $("error").hidden = false; $("error").textContent = e.error;
    status("no report");
    return;
  }
  const url = URL.createObjectURL(new Blob([await res.text()], { type: "text/html" }));
  if (tab) tab.location = url; else window.open(url, "_blank");
  status("report opened");
}

// The plan as drawn, a standalone SVG (the page's drawing rules inlined).
function exportSvg() {
  const m = state.answer && state.answer.plan.motion;
  const at = m && state.playT != null ? `_t${Math.min(Math.max(state.playT, m.start), m.end).toFixed(2)}s` : "";
  download(standalonePlan(), at);
}

// The plan as a standalone SVG document: its drawing, the rules it is drawn with, white behind.
function standalonePlan() {
  const svg = $("plan").cloneNode(true);
  svg.setAttribute("xmlns", NS);
  svg.setAttribute("width", $("plan").clientWidth);
  svg.setAttribute("height", $("plan").clientHeight);
  const rules = [...document.styleSheets].flatMap((sh) => [...sh.cssRules].map((r) => r.cssText))
    .filter((t) => /^\.(grid|axis|v1|v2|path|outline|sigma|handle|mark|label|zone)/.test(t));
  const style = document.createElementNS(NS, "style");
  style.textContent = rules.join("\n");
  svg.insertBefore(style, svg.firstChild);
  const bg = document.createElementNS(NS, "rect");
  const v = state.view;
  for (const [k, x] of Object.entries({ x: v.x, y: v.y, width: v.w, height: v.h, fill: "#fff" })) bg.setAttribute(k, x);
  svg.insertBefore(bg, style.nextSibling);
  return svg;
}

// `svg` downloaded as the case's name with `suffix` (`_t1.20s`, `_motion`, or none).
function download(svg, suffix) {
  const text = new XMLSerializer().serializeToString(svg);
  const a = document.createElement("a");
  a.href = URL.createObjectURL(new Blob([text], { type: "image/svg+xml" }));
  const name = (state.path || "plan").replace(/\.toml$/, "").split("/").pop();
  a.download = `${name}${suffix}.svg`;
  document.body.appendChild(a); a.click(); a.remove();
}

let typing = null;
$("toml").addEventListener("input", () => {
  clearTimeout(typing);
  typing = setTimeout(() => { state.text = $("toml").value; solve(); }, 300);
});
$("cases").addEventListener("change", (e) => openCase(e.target.value));
$("fit").addEventListener("click", fitView);
// Display units: the plan, the speeds and the table in them (the case and its document keep
// theirs); the view is fitted again.
$("units").addEventListener("change", (e) => { state.units = e.target.value; state.view = null; solve(); });
$("save").addEventListener("click", () => save());
$("conflict-reload").addEventListener("click", () => reloadFromDisk());
$("conflict-compare-button").addEventListener("click", compareConflict);
$("conflict-overwrite").addEventListener("click", () => save(state.conflict.version));
window.addEventListener("focus", checkDisk);
document.addEventListener("visibilitychange", () => { if (!document.hidden) checkDisk(); });
$("study-start").addEventListener("click", startStudy);
$("report").addEventListener("click", openReport);
$("export").addEventListener("click", exportSvg);
$("export-dxf").addEventListener("click", exportDxf);
$("play").addEventListener("click", togglePlay);
$("time").addEventListener("input", () => { state.playT = +$("time").value; render(); });
$("export-motion").addEventListener("click", exportMotion);
$("background").addEventListener("click", chooseBackground);
$("photo-plan").addEventListener("click", startPhotoPlan);
$("photo-img").addEventListener("click", photoClick);
$("photo-rectify").addEventListener("click", rectifyPhoto);
$("photo-cancel").addEventListener("click", closePhoto);
$("set-scale").addEventListener("click", () => useTool("scale"));
$("measure").addEventListener("click", () => useTool("measure"));
$("add-mark").addEventListener("click", () => useTool("mark"));
$("add-rest").addEventListener("click", () => useTool("rest"));
$("batch-start").addEventListener("click", startBatch);
$("batch-cancel").addEventListener("click", cancelBatch);
$("add-skid").addEventListener("click", () => useTool("skid"));
$("add-zone").addEventListener("click", () => useTool("zone"));
$("add-trace").addEventListener("click", () => useTool("trace"));
$("add-tyres").addEventListener("click", () => useTool("tyres"));
$("move-image").addEventListener("click", () => useTool("move-image"));
$("lock-image").addEventListener("change", (e) => {
  if (state.tool === "move-image") useTool("move-image");
  changeBackground({ locked: e.target.checked });
});
$("study-cancel").addEventListener("click", cancelStudy);
window.addEventListener("resize", () => state.view && fitView());
panAndZoom();
loadCases().catch((e) => { $("error").hidden = false; $("error").textContent = e.message; });
