//! The same answer on every machine: a reconstruction whose refinements end on their budget of
//! work gives the same document, byte for byte, on an idle machine and on a busy one (its
//! budget counts run-out evaluations and impact-fit work, never time).
mod common;
use common::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

#[test]
fn a_reconstruction_is_the_same_on_a_busy_machine() {
    let text =
        std::fs::read_to_string(repo().join("examples/cases/reconstruction_us.toml")).unwrap();
    // The sedan's rest 865 ft off: evidence no impact reaches, whose refinements run to the
    // end of their budget.
    let from = "rest = { x = 11.9, y = 2.9, heading = 144.0 }";
    assert!(text.contains(from));
    let case = scratch_file(
        "determinism",
        "far_rest.toml",
        text.replace(from, "rest = { x = 11.9, y = -862.13, heading = 144.0 }"),
    );
    let idle = pim(&["fit", &case, "--format", "json"]);
    let doc: serde_json::Value = serde_json::from_slice(&idle.stdout).unwrap();
    let work = doc["work"].as_u64().unwrap();
    assert!(
        work > pim_reconstruct::REFINE_WORK,
        "the budget must end this reconstruction: {work}"
    );
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
