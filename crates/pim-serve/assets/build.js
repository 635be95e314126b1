// pim serve: a case built in the page. New case… names a file of the folder and its frame
// and units (nothing is written until Save, which creates it); Forms offers each section the
// text does not write yet, added with starting values to edit in its form. Until the text is a
// case that answers, the plan shows what it gives so far (its background, its survey).
"use strict";

function openNewDialog() {
  $("new-error").textContent = "";
  $("new-dialog").showModal();
}

async function startNewCase(e) {
  e.preventDefault();
  if (state.text !== state.saved && !window.confirm(`${state.path} has changes not saved: leave them?`)) return;
  const body = {
    name: $("new-name").value.trim(), title: $("new-title").value.trim() || undefined,
    units: $("new-units").value, convention: $("new-convention").value,
  };
  try {
    const { data } = await api("POST", "/api/new", body);
    $("new-dialog").close();
    state.path = data.path; state.text = data.text; state.saved = ""; state.version = null;
    state.fresh = true; state.view = null; state.answer = null; state.off = [];
    state.study = null; state.measured = null; state.conflict = null; $("conflict").hidden = true;
    const sel = $("cases");
    const o = document.createElement("option");
    o.value = data.path; o.textContent = `${data.path} (new)`;
    sel.appendChild(o); sel.value = data.path;
    $("toml").value = data.text;
    $("forms-box").open = true;
    await solve();
    status(`new case ${data.path}: add its sections (Forms), then Save`);
  } catch (err) {
    $("new-error").textContent = err.message;
  }
}

// The sections the text does not write yet, in the Forms' menu.
async function refreshSections() {
  if (state.sectionsText === state.text) return;
  state.sectionsText = state.text;
  let sections = [];
  try {
    ({ data: { sections } } = await api("POST", "/api/sections", { path: state.path, text: state.text }));
  } catch (e) { /* not TOML: the TOML's own mark says why */ }
  const sel = $("add-section");
  sel.innerHTML = "";
  for (const s of sections) {
    const o = document.createElement("option");
    o.value = s.name; o.textContent = `[${s.name}] ${s.what}`;
    sel.appendChild(o);
  }
  $("add-section-bar").hidden = !sections.length;
}

// The section chosen added to the text (not saved), its form opened, and solved.
async function addSection() {
  const name = $("add-section").value;
  if (!name) return;
  try {
    const { data } = await api("POST", "/api/section", { path: state.path, text: state.text, name });
    state.text = data.text;
    $("toml").value = data.text;
    await solve();
    const d = $("forms").querySelector(`details[data-section="${CSS.escape(name)}"]`);
    if (d) d.open = true;
  } catch (e) {
    $("error").hidden = false;
    $("error").textContent = e.message;
  }
}

// A rest where the plan was clicked (on a survey point: at the point, its id kept): the
// vehicle, its heading as the case writes headings and the standard deviation asked.
async function placeRest(click) {
  const s = surveySnap([click.x, -click.y]);
  const at = s ? s.at : [click.x, -click.y];
  const plan = state.answer.plan;
  const sigma = Math.round((0.3 / plan.metres) * 100) / 100;
  const clockwise = plan.frame === "sae" ? "clockwise from north" : "counter-clockwise from east";
  const answer = window.prompt(`Rest${s ? ` on survey point ${s.id}` : ""}: the vehicle (1 or 2), its heading `
    + `(deg ${clockwise}; - if not measured) and the standard deviation of its position (${plan.length_label}):`,
    `${state.answer.sketch ? 1 : nearestVehicle(at)} - ${sigma}`);
  const [v, h, sd] = (answer || "").trim().split(/[\s,]+/);
  const vehicle = +v, sdv = +sd, heading = h === "-" || h === undefined ? undefined : +h;
  if (!(vehicle === 1 || vehicle === 2) || !(sdv > 0) || (heading !== undefined && !Number.isFinite(heading))) {
    status("no rest placed"); render(); return;
  }
  await edited("/api/rest", { vehicle, at, heading, sigma: sdv, point: s ? s.id : undefined });
}

// A point of a rest measured by its tyres or corners: added, or with two or more a click
// within 8 screen pixels of the last ends it; then the vehicle, the sd and each point's name
// are asked, and the rest written as rest_tyres (its CG rest replaced).
const TYRE_NAMES = { fl: "front_left", fr: "front_right", rl: "rear_left", rr: "rear_right" };

async function tyresClick(p) {
  const c = pointsEnded(p);
  if (!c) return;
  const placed = c.map((q) => surveySnap([q.x, -q.y]) || { at: [q.x, -q.y] });
  const plan = state.answer.plan;
  const sigma = Math.round((0.1 / plan.metres) * 100) / 100;
  const on = placed.map((q) => q.id || "-").join(" ");
  const answer = window.prompt(`Rest by ${placed.length} points (survey points: ${on}): the vehicle (1 or 2), `
    + `the standard deviation of each point (${plan.length_label}), then each point's name in the order clicked: `
    + "fl fr rl rr for a tyre's contact point, cfl cfr crl crr for a corner of the outline",
    `${state.answer.sketch ? 1 : nearestVehicle(placed[0].at)} ${sigma} ${["fl", "rl", "fr", "rr"].slice(0, placed.length).join(" ")}`);
  const [v, sd, ...names] = (answer || "").trim().split(/[\s,]+/);
  const vehicle = +v, sdv = +sd;
  const named = names.map((n) => {
    const corner = n.startsWith("c") && TYRE_NAMES[n.slice(1)];
    return { name: corner || TYRE_NAMES[n], corner: !!corner };
  });
  if (!(vehicle === 1 || vehicle === 2) || !(sdv > 0) || named.length !== placed.length || named.some((n) => !n.name)) {
    status("no rest placed: give the vehicle, the sd and a name for each point"); render(); return;
  }
  const points = placed.map((q, i) => ({ at: q.at, ...named[i], point: q.id }));
  await edited("/api/rest-tyres", { vehicle, sigma: sdv, points });
}

$("new-case").addEventListener("click", openNewDialog);
$("new-form").addEventListener("submit", startNewCase);
$("new-cancel").addEventListener("click", () => $("new-dialog").close());
$("add-section-button").addEventListener("click", addSection);

// A section removed from the case's text (not saved), after asking; the forms and the answer
// follow.
async function removeSection(name) {
  if (!confirm(`Remove [${name}] from the case?`)) return;
  try {
    const { data } = await api("POST", "/api/section/remove", { path: state.path, text: state.text, name });
    state.text = data.text;
    $("toml").value = data.text;
    await solve();
    status(`[${name}] removed`);
  } catch (e) {
    status(e.message);
  }
}
