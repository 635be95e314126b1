//! A reconstruction started also from an earlier answer (`pim fit --from result.json`): the
//! answer of the case before an edit, or of a neighbouring case, read from its JSON document
//! (the reconstruction then runs with [`crate::reconstruct::reconstruct_searching`]).

use crate::documents::DocumentError;
use pim_core::VehicleId;
pub use pim_reconstruct::{Earlier, EarlierState};

/// Each scene vehicle's separation state and count of turns in a reconstruction's JSON document
/// (`kind = "reconstruction"`, as `pim fit --format json` prints it and `--out` writes it as
/// `result.json`), and the fitted frictions its run-outs ran on (`best.frictions`; a document
/// without them starts on the stated frictions): the starts of
/// [`crate::reconstruct::reconstruct_searching`]. `file` names the document in messages.
///
/// # Errors
/// Text that is not JSON, a document of another kind, or one without an answer.
pub fn earlier_states(file: &str, text: &str) -> Result<Earlier, DocumentError> {
    let bad = |what: String| DocumentError::Input(format!("{file}: {what}"));
    let doc: serde_json::Value =
        serde_json::from_str(text).map_err(|e| bad(format!("not a JSON document: {e}")))?;
    match doc.get("kind").and_then(|k| k.as_str()) {
        Some("reconstruction") => {}
        Some(other) => {
            return Err(bad(format!(
                "a document of kind \"{other}\", not a reconstruction's (the JSON `pim fit` \
                 writes for a case with scene evidence)"
            )))
        }
        None => {
            return Err(bad(
                "no `kind`: not a document `pim fit` wrote (its --format json or --out \
                 result.json)"
                    .into(),
            ))
        }
    }
    let scene: Vec<u64> = doc
        .get("scene_vehicles")
        .and_then(|s| s.as_array())
        .map(|a| a.iter().filter_map(serde_json::Value::as_u64).collect())
        .unwrap_or_default();
    let Some(vehicles) = doc.pointer("/best/vehicles").and_then(|v| v.as_array()) else {
        return Err(bad(
            "best: no answer to start from (the earlier reconstruction found none)".into(),
        ));
    };
    let frictions = match doc.pointer("/best/frictions") {
        None => None,
        Some(f) => Some(
            f.as_array()
                .and_then(|a| {
                    a.iter()
                        .map(|x| x.as_f64().filter(|x| x.is_finite() && *x > 0.0))
                        .collect::<Option<Vec<f64>>>()
                })
                .ok_or_else(|| bad("best.frictions: expected a list of positive numbers".into()))?,
        ),
    };
    let mut out = Vec::new();
    for (i, v) in vehicles.iter().enumerate() {
        let field = |name: &str| format!("best.vehicles[{i}].{name}");
        let number = v.get("vehicle").and_then(serde_json::Value::as_u64);
        let vehicle = match number {
            Some(1) => VehicleId::One,
            Some(2) => VehicleId::Two,
            _ => return Err(bad(format!("{}: expected 1 or 2", field("vehicle")))),
        };
        if !scene.contains(&number.unwrap_or(0)) {
            continue;
        }
        let component = |name: &str| {
            v.pointer(&format!("/separation/{name}"))
                .and_then(serde_json::Value::as_f64)
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    bad(format!(
                        "{}: expected a number",
                        field(&format!("separation.{name}"))
                    ))
                })
        };
        out.push(EarlierState {
            vehicle,
            turns: v.get("turns").and_then(serde_json::Value::as_i64),
            velocity: [component("vx")?, component("vy")?, component("yaw_rate")?],
        });
    }
    Ok(Earlier {
        states: out,
        frictions,
    })
}
