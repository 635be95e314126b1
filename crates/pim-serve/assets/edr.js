// An event data recorder's pre-crash table pasted into the case, and the speeds before contact
// drawn beside it (the answer's history, the EDR's rows and records).

// The answer's speed_history.svg under the speeds, when a vehicle has an EDR.
function speedHistory(a) {
  const box = $("speed-history-box");
  const svg = a && !a.sketch && a.plan && a.plan.speed_history;
  box.hidden = !svg;
  $("speed-history").innerHTML = svg ? svg.replace(/^<\?xml[^>]*>\s*/, "") : "";
}

function openEdrDialog() {
  if (!state.path) { status("open or create a case first"); return; }
  $("edr-error").textContent = "";
  $("edr-dialog").showModal();
}

// The pasted table imported into the case's text (not saved) and solved; a refusal (a row
// that is not a number, a brake neither on nor off) is shown in the dialog, which stays open.
async function importEdr(e) {
  e.preventDefault();
  const sigma = $("edr-sigma").value.trim();
  const body = {
    path: state.path, text: state.text, table: $("edr-table").value,
    vehicle: +$("edr-vehicle").value,
    unit: $("edr-unit").value || undefined,
    sigma: sigma === "" ? undefined : +sigma,
    record: $("edr-record").checked,
  };
  try {
    const { data } = await api("POST", "/api/edr", body);
    $("edr-dialog").close();
    state.text = data.text;
    $("toml").value = data.text;
    await solve();
    status(`EDR table of vehicle ${body.vehicle} imported`);
  } catch (err) {
    $("edr-error").textContent = err.message;
  }
}

$("edr").addEventListener("click", openEdrDialog);
$("edr-form").addEventListener("submit", importEdr);
$("edr-cancel").addEventListener("click", () => $("edr-dialog").close());
