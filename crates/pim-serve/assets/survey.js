// pim serve: a survey's points on the plan. A CSV (id, x, y, code, description) is imported
// into the case's [survey] (placed by its unit, the point made the origin and a turn); its
// points are drawn with their ids, and a rest, a mark or the impact centre dropped within a
// few pixels of one is placed on it: written at the point's own coordinates, its id kept.
"use strict";

// The survey point within `px` screen pixels of the page point p, the nearest: {id, at}.
function surveySnap(p, px = 10) {
  const pts = (state.answer && state.answer.plan.survey) || [];
  const near = px / pxPerUnit();
  let best = null;
  for (const s of pts) {
    const d = Math.hypot(s.at[0] - p[0], s.at[1] - p[1]);
    if (d <= near && (!best || d < best.d)) best = { id: s.id, at: s.at, d };
  }
  return best;
}

// The survey's points: a small square, the id beside it (its code and description as the
// title); drawn under the evidence.
function drawSurvey(svg) {
  const pts = (state.answer && state.answer.plan.survey) || [];
  if (!pts.length) return;
  const px = pxPerUnit(), r = 3 / px;
  const g = el("g", { class: "survey" }, svg);
  for (const s of pts) {
    const pg = el("g", { class: "survey-point", "data-point": s.id }, g);
    el("rect", { x: s.at[0] - r, y: -s.at[1] - r, width: 2 * r, height: 2 * r }, pg);
    const label = el("text", { x: s.at[0] + 1.6 * r, y: -s.at[1] - 1.6 * r, style: `font-size: ${10 / px}px` }, pg);
    label.textContent = s.id;
    const title = el("title", {}, pg);
    title.textContent = [s.id, s.code, s.description].filter(Boolean).join(" · ");
  }
}

function openSurveyDialog() {
  if (!state.path) { status("open or create a case first"); return; }
  const d = $("survey-dialog");
  $("survey-unit").value = "";
  $("survey-error").textContent = "";
  d.showModal();
}

// The CSV chosen imported into the case's text (not saved) and solved; a refusal (a bad line,
// an origin the survey lacks) is shown in the dialog, which stays open.
async function importSurvey(e) {
  e.preventDefault();
  const file = $("survey-file").files[0];
  if (!file) { $("survey-error").textContent = "choose the survey's CSV file"; return; }
  const csv = await file.text();
  const body = {
    path: state.path, text: state.text, csv, source: file.name,
    unit: $("survey-unit").value || undefined,
    origin: $("survey-origin").value.trim() || undefined,
    rotation: +$("survey-rotation").value || 0,
  };
  try {
    const { data } = await api("POST", "/api/survey", body);
    $("survey-dialog").close();
    state.text = data.text;
    $("toml").value = data.text;
    state.view = null; // the plan refitted to show the survey
    await solve();
    status(`survey of ${(state.answer && state.answer.plan.survey.length) || 0} points imported`);
  } catch (err) {
    $("survey-error").textContent = err.message;
  }
}

$("survey").addEventListener("click", openSurveyDialog);
$("survey-form").addEventListener("submit", importSurvey);
$("survey-cancel").addEventListener("click", () => $("survey-dialog").close());
