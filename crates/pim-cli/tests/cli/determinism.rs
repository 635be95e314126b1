//! The same answer on every machine: a reconstruction with much work to do gives the same
//! document, byte for byte, on an idle machine and on a busy one (its refinements end on their
//! convergence or their budget of work, which counts run-out evaluations and impact-fit work,
//! never time).
use crate::common;
use common::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

#[test]
fn a_reconstruction_is_the_same_on_a_busy_machine() {
    let text =
        std::fs::read_to_string(repo().join("examples/cases/reconstruction_us.toml")).unwrap();
    // The example with its EDR moved 8 mph and without its [estimates]: a scene whose
    // refinements fit the impact many times on the grid route (about 3.2 million units of work).
    let mut case_text = text.replace("speed = 27.5, time = 0.5", "speed = 35.5, time = 0.5");
    for l in [
        "[estimates.initial]\nvehicle1 = { omega = 0.0 }\nvehicle2 = { omega = 0.0 }\n",
        "[sigma.initial]\nvehicle1 = { omega = 5.0 }          # deg/s\nvehicle2 = { omega = 5.0 }\n",
    ] {
        assert!(case_text.contains(l), "{l}");
        case_text = case_text.replace(l, "");
    }
    let case = scratch_file("determinism", "heavy.toml", case_text);
    let idle = pim(&["fit", &case, "--format", "json"]);
    let doc: serde_json::Value = serde_json::from_slice(&idle.stdout).unwrap();
    let work = doc["work"].as_u64().unwrap();
    assert!(work > 2_000_000, "a scene with much work to do: {work}");
    // No stop of the search depends on the clock.
    let undetermined = doc["undetermined"].to_string();
    assert!(!undetermined.contains("time"), "{undetermined}");
    // Every core busy while the same reconstruction runs again.
    let stop = Arc::new(AtomicBool::new(false));
    let burners: Vec<_> = (0..4)
        .map(|_| {
            let stop = Arc::clone(&stop);
            std::thread::spawn(move || {
                let mut x = 0u64;
                while !stop.load(Ordering::Relaxed) {
                    x = x.wrapping_mul(6364136223846793005).wrapping_add(1);
                }
                x
            })
        })
        .collect();
    let busy = pim(&["fit", &case, "--format", "json"]);
    stop.store(true, Ordering::Relaxed);
    for b in burners {
        b.join().unwrap();
    }
    assert_eq!(idle.status.code(), busy.status.code());
    assert!(idle.stdout == busy.stdout, "the documents differ");
}
